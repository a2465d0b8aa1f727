//! Randomised scenarios: a file's `[randomize]` table checked and compiled into a
//! [`Randomizer`], which samples every parameter from a seed (each parameter from its own
//! stream, so adding one leaves the others' values unchanged) and writes the values into the
//! scenario document before it is compiled like any file ([`super::ScenarioTemplate`]).

use crate::error::SpecIssue;
use crate::spec::{RandomParamSpec, RandomTargetSpec};
use rand_core::{Rng, SeedableRng};
use std::collections::BTreeMap;

/// A distribution of one parameter.
#[derive(Clone, Debug, PartialEq)]
pub enum Distribution {
    /// Uniform real in `[low, high]`.
    Uniform(f64, f64),
    /// Uniform integer in `[low, high]`, both included.
    Integers(i64, i64),
    /// One of these values (numbers), each equally likely.
    Choice(Vec<toml::Value>),
}

/// One segment of a key path: a table key or an array index.
#[derive(Clone, Debug, PartialEq)]
enum Segment {
    Key(String),
    Index(usize),
}

/// Where a sampled value goes: a key path and `value * scale + offset`.
#[derive(Clone, Debug, PartialEq)]
pub struct Target {
    /// The key path as written (`terrain.boxes[0].size_m[2]`).
    pub key: String,
    path: Vec<Segment>,
    /// Factor applied to the value.
    pub scale: f64,
    /// Added after scaling, in the key's unit.
    pub offset: f64,
}

/// One randomised parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    /// Its name (`[randomize.NAME]`), reported with the sampled value.
    pub name: String,
    /// How it is drawn.
    pub dist: Distribution,
    /// The keys it writes.
    pub targets: Vec<Target>,
}

/// The compiled `[randomize]` table: parameters in name order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Randomizer {
    /// The parameters, sorted by name.
    pub params: Vec<Param>,
}

/// Sampled values by parameter name (name order), in the units of their keys.
pub type Sampled = BTreeMap<String, f64>;

/// Sampled values as a message names them: `friction = 0.5, gap = 0.7`.
pub fn sampled_text(values: &Sampled) -> String {
    values
        .iter()
        .map(|(k, v)| format!("{k} = {v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// 64-bit FNV-1a of a name: the stream of its parameter.
fn fnv1a(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Parses `a.b[0].c[2]` into segments.
fn parse_path(key: &str) -> Option<Vec<Segment>> {
    let mut out = Vec::new();
    for part in key.split('.') {
        let (name, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if name.is_empty() || !name.chars().all(|c| c.is_alphanumeric() || c == '_') {
            return None;
        }
        out.push(Segment::Key(name.to_string()));
        while !rest.is_empty() {
            let close = rest.find(']')?;
            if !rest.starts_with('[') {
                return None;
            }
            out.push(Segment::Index(rest[1..close].parse().ok()?));
            rest = &rest[close + 1..];
        }
    }
    Some(out)
}

/// The value at `path` in `doc`, and whether its parent exists (a missing last table key can
/// be added: it is an optional key the file left out).
fn lookup<'a>(doc: &'a toml::Table, path: &[Segment]) -> Result<Option<&'a toml::Value>, String> {
    let mut cur: Option<&toml::Value> = None;
    for (i, seg) in path.iter().enumerate() {
        let last = i + 1 == path.len();
        let next = match (cur, seg) {
            (None, Segment::Key(k)) => doc.get(k),
            (Some(toml::Value::Table(t)), Segment::Key(k)) => t.get(k),
            (Some(toml::Value::Array(a)), Segment::Index(j)) => a.get(*j),
            (Some(_), Segment::Key(k)) => {
                return Err(format!("`{k}` is inside a value that is not a table"));
            }
            (_, Segment::Index(j)) => {
                return Err(format!(
                    "index [{j}] applies to a value that is not an array"
                ));
            }
        };
        match next {
            Some(v) => cur = Some(v),
            None if last && matches!(seg, Segment::Key(_)) => return Ok(None),
            None => return Err(format!("the file has no `{}` here", seg_name(seg))),
        }
    }
    Ok(cur)
}

fn seg_name(s: &Segment) -> String {
    match s {
        Segment::Key(k) => k.clone(),
        Segment::Index(i) => format!("[{i}]"),
    }
}

/// Writes `v` at `path` (which [`lookup`] accepted).
fn write(doc: &mut toml::Table, path: &[Segment], v: toml::Value) {
    let mut table = doc;
    let mut i = 0;
    loop {
        let Segment::Key(k) = &path[i] else { return };
        i += 1;
        // Follow array indices after the key.
        if i == path.len() {
            table.insert(k.clone(), v);
            return;
        }
        let Some(mut cur) = table.get_mut(k) else {
            return;
        };
        while let Some(Segment::Index(j)) = path.get(i) {
            let toml::Value::Array(a) = cur else { return };
            let Some(next) = a.get_mut(*j) else { return };
            i += 1;
            if i == path.len() {
                *next = v;
                return;
            }
            cur = next;
        }
        let toml::Value::Table(t) = cur else { return };
        table = t;
    }
}

fn number(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Integer(i) => Some(*i as f64),
        toml::Value::Float(f) => Some(*f),
        _ => None,
    }
}

/// Checks a distribution; `None` with issues pushed if it is wrong.
fn distribution(
    key: &str,
    p: &RandomParamSpec,
    issues: &mut Vec<SpecIssue>,
) -> Option<Distribution> {
    let given = [
        p.uniform.is_some(),
        p.integers.is_some(),
        p.choice.is_some(),
    ];
    if given.iter().filter(|g| **g).count() != 1 {
        issues.push(SpecIssue::new(
            key,
            "give exactly one distribution: `uniform = [low, high]`, `integers = [low, high]` or `choice = [a, b, ...]`",
        ));
        return None;
    }
    let bad = |what: &str, msg: &str| SpecIssue::new(format!("{key}.{what}"), msg.to_string());
    if let Some(u) = &p.uniform {
        match u.as_slice() {
            [lo, hi] if lo.is_finite() && hi.is_finite() && lo <= hi => {
                return Some(Distribution::Uniform(*lo, *hi));
            }
            _ => issues.push(bad(
                "uniform",
                "must be [low, high] with finite low <= high",
            )),
        }
    } else if let Some(u) = &p.integers {
        match u.as_slice() {
            [lo, hi] if lo <= hi => return Some(Distribution::Integers(*lo, *hi)),
            _ => issues.push(bad("integers", "must be [low, high] with low <= high")),
        }
    } else if let Some(c) = &p.choice {
        if c.is_empty() || c.iter().any(|v| !number(v).is_some_and(f64::is_finite)) {
            issues.push(bad("choice", "must be a non-empty list of finite numbers"));
        } else {
            return Some(Distribution::Choice(c.clone()));
        }
    }
    None
}

impl Randomizer {
    /// Checks `[randomize]` against the scenario document `doc` (the file's table without
    /// `randomize`): every distribution, and every key path must exist in the file (or be a
    /// key its table may hold but the file left out). Issues name `randomize.NAME....`.
    pub fn compile(
        spec: &BTreeMap<String, RandomParamSpec>,
        doc: &toml::Table,
    ) -> Result<Randomizer, Vec<SpecIssue>> {
        let mut issues = Vec::new();
        let mut params = Vec::new();
        for (name, p) in spec {
            let key = format!("randomize.{name}");
            let dist = distribution(&key, p, &mut issues);
            let mut raw: Vec<(String, String, f64, f64)> = Vec::new();
            match (&p.key, &p.keys) {
                (Some(k), None) => raw.push((format!("{key}.key"), k.clone(), 1.0, 0.0)),
                (None, Some(ks)) if !ks.is_empty() => {
                    for (k, t) in ks {
                        let (scale, offset) = match t {
                            RandomTargetSpec::Scale(s) => (*s, 0.0),
                            RandomTargetSpec::Affine(a) => (a.scale, a.offset),
                        };
                        raw.push((format!("{key}.keys.\"{k}\""), k.clone(), scale, offset));
                    }
                }
                _ => issues.push(SpecIssue::new(
                    key.clone(),
                    "give `key = \"terrain.boxes[0].size_m[2]\"` (one key) or `keys = { \"a.b\" = 1.0, \"c.d\" = { scale = 0.5, offset = 0.1 } }`",
                )),
            }
            let mut targets = Vec::new();
            for (where_, k, scale, offset) in raw {
                if !(scale.is_finite() && offset.is_finite()) {
                    issues.push(SpecIssue::new(
                        where_.clone(),
                        "scale and offset must be finite",
                    ));
                }
                let Some(path) = parse_path(&k) else {
                    issues.push(SpecIssue::new(
                        where_,
                        format!("`{k}` is not a key path; write it as error messages do, e.g. `terrain.boxes[0].size_m[2]`"),
                    ));
                    continue;
                };
                if matches!(path.first(), Some(Segment::Key(f)) if f == "randomize") {
                    issues.push(SpecIssue::new(
                        where_,
                        "a randomised key cannot be inside [randomize]",
                    ));
                    continue;
                }
                match lookup(doc, &path) {
                    Err(e) => issues.push(SpecIssue::new(
                        where_,
                        format!("`{k}`: {e}; name a key the scenario file holds"),
                    )),
                    Ok(Some(v)) if number(v).is_none() => issues.push(SpecIssue::new(
                        where_,
                        format!(
                            "`{k}` holds {}, not a number; only numbers can be randomised",
                            v.type_str()
                        ),
                    )),
                    Ok(_) => targets.push(Target {
                        key: k,
                        path,
                        scale,
                        offset,
                    }),
                }
            }
            if let Some(dist) = dist {
                params.push(Param {
                    name: name.clone(),
                    dist,
                    targets,
                });
            }
        }
        if issues.is_empty() {
            Ok(Randomizer { params })
        } else {
            Err(issues)
        }
    }

    /// True without parameters.
    pub fn is_empty(&self) -> bool {
        self.params.is_empty()
    }

    /// Every parameter drawn from `seed`: parameter `NAME` from a PCG stream seeded with
    /// `seed ^ FNV-1a(NAME)`, so the same seed always gives the same values.
    pub fn sample(&self, seed: u64) -> Vec<toml::Value> {
        self.params
            .iter()
            .map(|p| {
                let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed ^ fnv1a(&p.name));
                match &p.dist {
                    Distribution::Uniform(lo, hi) => {
                        // 53 random bits -> [0, 1).
                        let u = (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
                        toml::Value::Float(lo + (hi - lo) * u)
                    }
                    Distribution::Integers(lo, hi) => {
                        let span = (*hi as i128 - *lo as i128 + 1) as u128;
                        toml::Value::Integer(
                            (*lo as i128 + uniform_below(&mut rng, span) as i128) as i64,
                        )
                    }
                    Distribution::Choice(c) => {
                        c[uniform_below(&mut rng, c.len() as u128) as usize].clone()
                    }
                }
            })
            .collect()
    }

    /// The lowest and highest value of every parameter (first and last for a choice): the
    /// extremes a file is checked at when it is loaded.
    pub fn extremes(&self) -> [Vec<toml::Value>; 2] {
        let pick = |hi: bool| {
            self.params
                .iter()
                .map(|p| match &p.dist {
                    Distribution::Uniform(a, b) => toml::Value::Float(if hi { *b } else { *a }),
                    Distribution::Integers(a, b) => toml::Value::Integer(if hi { *b } else { *a }),
                    Distribution::Choice(c) => c[if hi { c.len() - 1 } else { 0 }].clone(),
                })
                .collect()
        };
        [pick(false), pick(true)]
    }

    /// Writes `values` (one per parameter, as from [`Randomizer::sample`]) into a copy of
    /// `doc`, and returns it with the values by name.
    pub fn apply(&self, doc: &toml::Table, values: &[toml::Value]) -> (toml::Table, Sampled) {
        let mut out = doc.clone();
        let mut sampled = Sampled::new();
        for (p, v) in self.params.iter().zip(values) {
            let x = number(v).unwrap_or(f64::NAN);
            sampled.insert(p.name.clone(), x);
            for t in &p.targets {
                let w = if t.scale == 1.0 && t.offset == 0.0 {
                    v.clone()
                } else {
                    toml::Value::Float(x * t.scale + t.offset)
                };
                write(&mut out, &t.path, w);
            }
        }
        (out, sampled)
    }
}

/// Uniform integer in `[0, n)` by rejection (no modulo bias), `n >= 1`.
fn uniform_below(rng: &mut impl Rng, n: u128) -> u128 {
    if n > u64::MAX as u128 {
        return rng.next_u64() as u128;
    }
    let n = n as u64;
    let zone = u64::MAX - (u64::MAX - n + 1) % n;
    loop {
        let r = rng.next_u64();
        if r <= zone {
            return (r % n) as u128;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc() -> toml::Table {
        toml::from_str("[vehicle]\nx_m = 0.0\n[[terrain.boxes]]\nsize_m = [2.0, 3.0, 0.1]\n")
            .unwrap()
    }

    #[test]
    fn paths_write_into_arrays_and_new_keys() {
        let spec: BTreeMap<String, RandomParamSpec> = toml::from_str(
            "[h]\nuniform = [0.05, 0.15]\nkeys = { \"terrain.boxes[0].size_m[2]\" = 1.0, \"vehicle.yaw_deg\" = { scale = 10.0, offset = 1.0 } }\n",
        )
        .unwrap();
        let r = Randomizer::compile(&spec, &doc()).unwrap();
        let v = r.sample(3);
        let (out, s) = r.apply(&doc(), &v);
        let h = s["h"];
        assert!((0.05..=0.15).contains(&h));
        assert_eq!(out["terrain"]["boxes"][0]["size_m"][2].as_float(), Some(h));
        assert_eq!(out["vehicle"]["yaw_deg"].as_float(), Some(h * 10.0 + 1.0));
        assert_eq!(r.sample(3), v);
        assert_ne!(r.sample(4), v);
    }

    #[test]
    fn bad_tables_name_their_keys() {
        let spec: BTreeMap<String, RandomParamSpec> = toml::from_str(
            "[a]\nuniform = [1.0, 0.0]\nkey = \"vehicle.x_m\"\n[b]\nintegers = [0, 3]\nkey = \"terrain.boxes[4].size_m\"\n[c]\nchoice = [1]\n",
        )
        .unwrap();
        let e = Randomizer::compile(&spec, &doc()).unwrap_err();
        let keys: Vec<_> = e.iter().map(|i| i.key.as_str()).collect();
        assert_eq!(
            keys,
            ["randomize.a.uniform", "randomize.b.key", "randomize.c"]
        );
    }

    #[test]
    fn integers_cover_their_range_only() {
        let spec: BTreeMap<String, RandomParamSpec> =
            toml::from_str("[n]\nintegers = [2, 4]\nkey = \"vehicle.x_m\"\n").unwrap();
        let r = Randomizer::compile(&spec, &doc()).unwrap();
        let mut seen = std::collections::BTreeSet::new();
        for s in 0..200 {
            seen.insert(r.sample(s)[0].as_integer().unwrap());
        }
        assert_eq!(seen.into_iter().collect::<Vec<_>>(), [2, 3, 4]);
    }
}
