//! Issue 38.1-2: the order of a file's entries never matters. Permuted copies of every bundled
//! scenario (its terrain lists and its robots reversed or shuffled, `[randomize]` keys following
//! their entries, every track's pulley list reversed or rotated in its vehicle file) run to
//! their end with a trajectory byte-identical to the original's.

use crate::common::{self, root};
use rand_core::Rng;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use toml::{Table, Value};

/// How a copy is permuted.
#[derive(Clone, Copy, Debug)]
enum Permutation {
    /// Every terrain list and every pulley list reversed.
    Reversed,
    /// Every terrain list shuffled (seeded), every pulley list rotated by one.
    Shuffled(u64),
}

/// Copies a folder tree (the bundled scenarios and vehicles: small).
fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_tree(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}

/// The order the entries of a list of `n` take in the copy: `order[new] = old`.
fn order(n: usize, p: Permutation) -> Vec<usize> {
    let mut o: Vec<usize> = (0..n).collect();
    match p {
        Permutation::Reversed => o.reverse(),
        Permutation::Shuffled(seed) => {
            let mut rng =
                rand_pcg::Pcg64::new(seed as u128, 0xa02b_dbf7_bb3c_0a7a_c28f_a16a_64ab_f96d);
            for i in (1..n).rev() {
                let j = (rng.next_u64() % (i as u64 + 1)) as usize;
                o.swap(i, j);
            }
        }
    }
    o
}

/// Rewrites `terrain.LIST[i]` (or `vehicles[i]`, a robot) in a `[randomize]` key path to the
/// entry's index in the copy. `lists` holds each permuted list's key prefix (`terrain.boxes[`,
/// `vehicles[`) and its order.
fn remap_key(key: &str, lists: &[(String, Vec<usize>)]) -> String {
    for (prefix, o) in lists {
        if let Some(rest) = key.strip_prefix(prefix.as_str())
            && let Some((i, tail)) = rest.split_once(']')
            && let Ok(i) = i.parse::<usize>()
        {
            let new = o.iter().position(|&old| old == i).unwrap();
            return format!("{prefix}{new}]{tail}");
        }
    }
    key.to_string()
}

/// Remaps every key path in a `[randomize]` table (values `key = "..."`, and the keys of
/// `keys = { ... }` tables).
fn remap_randomize(v: &mut Value, lists: &[(String, Vec<usize>)]) {
    match v {
        Value::Table(t) => {
            let entries: Vec<(String, Value)> = std::mem::take(t).into_iter().collect();
            for (k, mut val) in entries {
                remap_randomize(&mut val, lists);
                let k = if is_list_key(&k) {
                    remap_key(&k, lists)
                } else {
                    k
                };
                t.insert(k, val);
            }
        }
        Value::String(s) if is_list_key(s) => *s = remap_key(s, lists),
        Value::Array(a) => a.iter_mut().for_each(|x| remap_randomize(x, lists)),
        _ => {}
    }
}

/// Whether a `[randomize]` key path starts in a list a copy permutes.
fn is_list_key(key: &str) -> bool {
    key.starts_with("terrain.") || key.starts_with("vehicles[")
}

/// The scenario document with its terrain lists and its robots permuted (key paths in
/// `[randomize]` follow).
fn permute_scenario(doc: &mut Table, p: Permutation) {
    let mut lists = Vec::new();
    if let Some(Value::Table(terrain)) = doc.get_mut("terrain") {
        for (name, v) in terrain.iter_mut() {
            if let Value::Array(a) = v
                && a.len() > 1
            {
                let o = order(a.len(), p);
                let old = std::mem::take(a);
                *a = o.iter().map(|&i| old[i].clone()).collect();
                lists.push((format!("terrain.{name}["), o));
            }
        }
    }
    // The robots of a world with several (issue 40).
    if let Some(Value::Array(a)) = doc.get_mut("vehicles")
        && a.len() > 1
    {
        let o = order(a.len(), p);
        let old = std::mem::take(a);
        *a = o.iter().map(|&i| old[i].clone()).collect();
        lists.push(("vehicles[".to_string(), o));
    }
    if let Some(r) = doc.get_mut("randomize") {
        remap_randomize(r, &lists);
    }
}

/// The vehicle document with every track's pulley list permuted.
fn permute_vehicle(doc: &mut Table, p: Permutation) -> usize {
    let mut n = 0;
    let Some(Value::Array(tracks)) = doc.get_mut("tracks") else {
        return 0;
    };
    for t in tracks {
        if let Some(Value::Array(pulleys)) = t.get_mut("path").and_then(|p| p.get_mut("pulleys")) {
            match p {
                Permutation::Reversed => pulleys.reverse(),
                Permutation::Shuffled(_) => pulleys.rotate_left(1),
            }
            n += 1;
        }
    }
    n
}

/// Writes the permuted copy of `scenario` (a file of the copied tree) beside it, with
/// a permuted copy of its vehicle file; returns its path and how many lists were permuted.
fn permuted_copy(scenario: &Path, p: Permutation, tag: &str) -> (PathBuf, usize) {
    let text = std::fs::read_to_string(scenario).unwrap();
    let mut doc: Table = toml::from_str(&text).unwrap();
    permute_scenario(&mut doc, p);
    let mut permuted = doc
        .get("terrain")
        .and_then(|t| t.as_table())
        .map_or(0, |t| {
            t.values()
                .filter(|v| v.as_array().is_some_and(|a| a.len() > 1))
                .count()
        })
        + doc
            .get("vehicles")
            .and_then(|v| v.as_array())
            .map_or(0, |a| usize::from(a.len() > 1));
    let dir = scenario.parent().unwrap();
    if let Some(file) = doc
        .get("vehicle")
        .and_then(|v| v.get("file"))
        .and_then(|f| f.as_str())
        .map(str::to_string)
    {
        let vpath = dir.join(&file);
        let mut vdoc: Table = toml::from_str(&std::fs::read_to_string(&vpath).unwrap()).unwrap();
        permuted += permute_vehicle(&mut vdoc, p);
        let vname = format!(
            "{}.{tag}.toml",
            vpath.file_stem().unwrap().to_string_lossy()
        );
        let vcopy = vpath.with_file_name(vname);
        std::fs::write(&vcopy, toml::to_string(&vdoc).unwrap()).unwrap();
        let rel = Path::new(&file).with_file_name(vcopy.file_name().unwrap());
        doc["vehicle"]["file"] = Value::String(rel.to_string_lossy().to_string());
    }
    let copy = scenario.with_file_name(format!(
        "{}.{tag}.toml",
        scenario.file_stem().unwrap().to_string_lossy()
    ));
    std::fs::write(&copy, toml::to_string(&doc).unwrap()).unwrap();
    (copy, permuted)
}

/// Runs a scenario to its end; the SHA-256 of its trajectory.csv and its outcome.
fn run_hash(path: &Path) -> (String, String) {
    let sc = tracksim::load_scenario(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    if sc.robot_count() > 1 {
        // Each robot's trajectory by its name (the outputs follow the file's order).
        let r = tracksim::run::run_team(&sc, Default::default()).unwrap_or_else(|e| panic!("{e}"));
        let mut runs: Vec<_> = r.robots.iter().collect();
        runs.sort_by(|a, b| a.0.cmp(&b.0));
        let text: String = runs
            .iter()
            .map(|(n, run)| format!("{n}\n{}", tracksim::output::trajectory_csv(run)))
            .collect();
        return (
            format!("{:x}", Sha256::digest(text.as_bytes())),
            format!("{:?}", r.outcome),
        );
    }
    let r = tracksim::run_scenario(&sc, |_, _| {}).unwrap_or_else(|e| panic!("{e}"));
    let text = tracksim::output::trajectory_csv(&r);
    (
        format!("{:x}", Sha256::digest(text.as_bytes())),
        format!("{:?}", r.outcome),
    )
}

#[test]
fn permuted_bundled_scenarios_run_byte_identical_to_their_end() {
    let tree = std::env::temp_dir().join(format!("tracksim_order_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tree);
    copy_tree(&root().join("scenarios"), &tree.join("scenarios"));
    copy_tree(&root().join("vehicles"), &tree.join("vehicles"));
    let files: Vec<PathBuf> = common::all_bundled_scenarios()
        .into_iter()
        .map(|f| tree.join(f.strip_prefix(root()).unwrap()))
        .collect();
    let mut cases = Vec::new();
    let mut lists = 0;
    for (i, f) in files.iter().enumerate() {
        for (p, tag) in [
            (Permutation::Reversed, "reversed"),
            (Permutation::Shuffled(38 + i as u64), "shuffled"),
        ] {
            let (copy, n) = permuted_copy(f, p, tag);
            lists += n;
            cases.push((f.clone(), copy));
        }
    }
    // Both cores: each worker takes every other case.
    let failures: Vec<String> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..2)
            .map(|w| {
                let cases = &cases;
                s.spawn(move || {
                    let mut bad = Vec::new();
                    for (orig, copy) in cases.iter().skip(w).step_by(2) {
                        let (a, oa) = run_hash(orig);
                        let (b, ob) = run_hash(copy);
                        if a != b {
                            bad.push(format!(
                                "{}: original {oa}, permuted copy {} {ob}",
                                orig.display(),
                                copy.display()
                            ));
                        }
                    }
                    bad
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap())
            .collect()
    });
    let _ = std::fs::remove_dir_all(&tree);
    // The test permutes something in most files (a scenario with a single terrain entry and a
    // vehicle without pulleys would test nothing).
    assert!(
        lists >= files.len(),
        "only {lists} lists permuted over {} files",
        files.len()
    );
    assert!(
        failures.is_empty(),
        "{} permuted copies ran differently:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// Every bundled scenario whose `[expect]` states ensemble bounds (the step and the stairs)
/// run as that ensemble (`tracksim run --ensemble`): its members agree as the file says.
#[test]
fn bundled_ensembles_meet_their_bounds() {
    let mut checked = Vec::new();
    let mut failed = Vec::new();
    for f in common::all_bundled_scenarios() {
        let sc = tracksim::load_scenario(&f).unwrap();
        let Some(e) = sc.expect.ensemble.clone() else {
            continue;
        };
        let mut opts = tracksim::ensemble::EnsembleOptions::new(e.members);
        opts.seed = 38;
        let t = tracksim::load_template(&f).unwrap();
        let r = tracksim::ensemble::run_ensemble(&t, &opts, |_, _| {}).unwrap();
        let misses = tracksim::ensemble::check_ensemble(&e, &r);
        let line = format!("{}: {}", f.display(), r.text());
        println!("{line}");
        if !misses.is_empty() {
            failed.push(format!("{line}    {}", misses.join("\n    ")));
        }
        checked.push(f.file_name().unwrap().to_string_lossy().to_string());
    }
    for must in ["packbot_step.toml", "packbot_stairs.toml"] {
        assert!(
            checked.iter().any(|c| c == must),
            "{must} states no ensemble bounds; checked {checked:?}"
        );
    }
    assert!(failed.is_empty(), "\n{}", failed.join("\n"));
}

/// The perturbation of the solver's order changes nothing physical but the order: a member
/// with inert colliders runs a different trajectory (else it would perturb nothing), and the
/// same member twice runs the same one (members are reproducible).
#[test]
fn order_salt_reorders_the_solver_and_members_are_reproducible() {
    let path = root().join("scenarios/packbot_step.toml");
    let sc = common::load_for("scenarios/packbot_step.toml", 2.0);
    let hash = |sc: &tracksim::Scenario| {
        let r = tracksim::run_scenario(sc, |_, _| {}).unwrap();
        format!(
            "{:x}",
            Sha256::digest(tracksim::output::trajectory_csv(&r).as_bytes())
        )
    };
    let base = hash(&sc);
    let salted = common::load_with(
        "scenarios/packbot_step.toml",
        tracksim::Overrides {
            duration_s: Some(2.0),
            order_salt: Some(3),
            ..Default::default()
        },
    );
    let a = hash(&salted);
    assert_ne!(base, a, "inert colliders left the solver's order unchanged");
    assert_eq!(a, hash(&salted));
    // A member is reproduced by its keys written into the file.
    let p = tracksim::ensemble::Perturbations::default();
    let m = p.member(38, 5);
    let two_seconds = tracksim::Overrides {
        duration_s: Some(2.0),
        ..Default::default()
    };
    let t = tracksim::ScenarioTemplate::load_with(&path, &two_seconds).unwrap();
    let msc = m.scenario(&t, &sc).unwrap();
    let mut text = std::fs::read_to_string(&path).unwrap();
    let mut doc: Table = toml::from_str(&text).unwrap();
    for (k, v) in m.keys(&sc) {
        let (table, key) = k.split_once('.').unwrap();
        let t = doc
            .entry(table)
            .or_insert(Value::Table(Table::new()))
            .as_table_mut()
            .unwrap();
        t.insert(
            key.into(),
            if key == "order_salt" {
                Value::Integer(v as i64)
            } else {
                Value::Float(v)
            },
        );
    }
    doc["simulation"]["duration_s"] = Value::Float(2.0);
    // The copy lives in a temporary folder: its vehicle file by absolute path.
    let vehicle = root()
        .join("scenarios")
        .join(doc["vehicle"]["file"].as_str().unwrap());
    doc["vehicle"]["file"] = Value::String(vehicle.to_string_lossy().to_string());
    text = toml::to_string(&doc).unwrap();
    let copy = std::env::temp_dir().join(format!("tracksim_member_{}.toml", std::process::id()));
    std::fs::write(&copy, text).unwrap();
    let from_file = tracksim::load_scenario(&copy);
    let _ = std::fs::remove_file(&copy);
    assert_eq!(hash(&from_file.unwrap()), hash(&msc));
}
