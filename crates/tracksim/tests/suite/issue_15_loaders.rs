//! Property test of the loaders (issue 15): any mutation of a bundled scenario or vehicle file
//! (a number replaced by any f64 or i64 - NaN, infinities, 1e300, 1e-300, 2^63 - 1 included -,
//! a fixed array given an extra entry, a table written as an array of its values) either is
//! refused with an `Error` naming a key or the file, or builds a world whose first steps are
//! finite or reported unstable. Never a panic, and never NaN in a sample of an accepted file.

use proptest::prelude::*;
use std::path::{Path, PathBuf};
use toml::Value;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Paths (keys and indices) to every value of `v`.
#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

fn walk(v: &Value, at: &mut Vec<Step>, out: &mut Vec<(Vec<Step>, Value)>) {
    match v {
        Value::Table(t) => {
            for (k, x) in t {
                if k == "description" {
                    continue;
                }
                at.push(Step::Key(k.clone()));
                out.push((at.clone(), x.clone()));
                walk(x, at, out);
                at.pop();
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                at.push(Step::Index(i));
                out.push((at.clone(), x.clone()));
                walk(x, at, out);
                at.pop();
            }
        }
        _ => {}
    }
}

fn get_mut<'a>(v: &'a mut Value, path: &[Step]) -> &'a mut Value {
    path.iter().fold(v, |v, s| match s {
        Step::Key(k) => v.get_mut(k.as_str()).unwrap(),
        Step::Index(i) => v.get_mut(*i).unwrap(),
    })
}

#[derive(Clone, Debug)]
enum Mutation {
    Float(f64),
    Int(i64),
    ExtraEntry,
    TableAsArray,
}

fn extreme_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(1e300),
        Just(-1e300),
        Just(1e-300),
        Just(1e39),
        Just(1e154),
        Just(0.0),
        Just(-1.0),
        any::<f64>(),
        -1e6..1e6f64,
    ]
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => extreme_f64().prop_map(Mutation::Float),
        2 => prop_oneof![Just(i64::MAX), Just(-1i64), Just(1_000_000i64), any::<i64>()]
            .prop_map(Mutation::Int),
        1 => Just(Mutation::ExtraEntry),
        1 => Just(Mutation::TableAsArray),
    ]
}

/// Applies `m` to the `pick`-th value it fits; false when nothing fits.
fn apply(doc: &mut Value, m: &Mutation, pick: prop::sample::Index) -> bool {
    let mut all = Vec::new();
    walk(doc, &mut Vec::new(), &mut all);
    let fits = |v: &Value| match m {
        Mutation::Float(_) => v.is_float(),
        Mutation::Int(_) => v.is_integer(),
        Mutation::ExtraEntry => v.as_array().is_some_and(|a| {
            (2..=3).contains(&a.len()) && a.iter().all(|x| x.is_float() || x.is_integer())
        }),
        Mutation::TableAsArray => v
            .as_table()
            .is_some_and(|t| !t.is_empty() && t.values().all(|x| x.is_float() || x.is_integer())),
    };
    let cands: Vec<_> = all.into_iter().filter(|(_, v)| fits(v)).collect();
    if cands.is_empty() {
        return false;
    }
    let (path, v) = pick.get(&cands).clone();
    *get_mut(doc, &path) = match m {
        Mutation::Float(x) => Value::Float(*x),
        Mutation::Int(i) => Value::Integer(*i),
        Mutation::ExtraEntry => {
            let mut a = v.as_array().unwrap().clone();
            a.push(Value::Float(99.0));
            Value::Array(a)
        }
        Mutation::TableAsArray => Value::Array(v.as_table().unwrap().values().cloned().collect()),
    };
    true
}

const SCENARIOS: &[&str] = &[
    "scenarios/packbot_flat.toml",
    "scenarios/packbot_step.toml",
    "scenarios/packbot_stairs.toml",
    "scenarios/quince_flat.toml",
];

/// Loads, builds and steps the (mutated) scenario; panics only on a broken property.
fn check_one(scenario: usize, in_vehicle: bool, m: Mutation, pick: prop::sample::Index) {
    let src = root().join(SCENARIOS[scenario]);
    let mut sdoc: Value = toml::from_str(&std::fs::read_to_string(&src).unwrap()).unwrap();
    let vfile = src
        .parent()
        .unwrap()
        .join(sdoc["vehicle"]["file"].as_str().unwrap());
    let mut vdoc: Value = toml::from_str(&std::fs::read_to_string(&vfile).unwrap()).unwrap();
    let tmp = std::env::temp_dir().join(format!(
        "tracksim-loaders-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::create_dir_all(&tmp).unwrap();
    sdoc["vehicle"]["file"] = Value::String("v.toml".into());
    sdoc["simulation"]["duration_s"] = Value::Float(0.05);
    let target = if in_vehicle { &mut vdoc } else { &mut sdoc };
    if !apply(target, &m, pick) {
        return;
    }
    std::fs::write(tmp.join("v.toml"), toml::to_string(&vdoc).unwrap()).unwrap();
    let s = tmp.join("s.toml");
    std::fs::write(&s, toml::to_string(&sdoc).unwrap()).unwrap();
    match tracksim::load_scenario(&s) {
        Err(e) => {
            let msg = e.to_string();
            assert!(
                msg.contains("s.toml") || msg.contains("v.toml"),
                "error names no file: {msg}"
            );
            assert!(msg.len() < 4000, "message of {} bytes", msg.len());
        }
        Ok(sc) => match tracksim::Simulation::new(&sc) {
            Err(e) => assert!(!e.to_string().is_empty()),
            Ok(mut sim) => {
                for _ in 0..20 {
                    if sim.step().is_err() {
                        return; // reported unstable: exit 3, allowed
                    }
                }
                let p = sim.body_pose();
                assert!(
                    [p.x, p.y, p.z, p.roll, p.pitch, p.yaw]
                        .iter()
                        .all(|x| x.is_finite()),
                    "accepted ({m:?}) but the pose is not finite and not reported: {p:?}"
                );
            }
        },
    }
}

proptest! {
    // 256 cases: each is a load (milliseconds) and at most 20 steps; the whole test takes a
    // few seconds. Failures are shrunk and printed with the mutation.
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]
    #[test]
    fn a_mutated_file_is_refused_with_a_message_or_runs_finite(
        scenario in 0..SCENARIOS.len(),
        in_vehicle in any::<bool>(),
        m in mutation(),
        pick in any::<prop::sample::Index>(),
    ) {
        check_one(scenario, in_vehicle, m, pick);
    }
}
