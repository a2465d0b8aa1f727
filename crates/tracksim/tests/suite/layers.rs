//! The library's layers import only downward (issue 10): for every top-level module, the
//! `crate::<module>` paths in its code (comments excluded) name only modules of lower layers.
//! A circle between top-level modules needs an upward edge; circles inside a folder are checked
//! on the file graph (`module_graph.rs`).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Top-level modules from the bottom layer up; modules in one inner list are one layer and must
/// not import each other.
pub(crate) const LAYERS: &[&[&str]] = &[
    &["error"],
    &["check", "files", "spill", "rosmsg", "render"],
    &["spec"],
    &["geometry"],
    &["terrain", "urdf"],
    &["model"],
    &["import"],
    &["tracks"],
    &["world"],
    &["sensors"],
    &["run"],
    &["output"],
    &["cases"],
    &["ensemble"],
    &[
        "bench",
        "validate",
        "env",
        "sweep",
        "compare",
        "bundled",
        "sessions",
        "team_bench",
        "video",
    ],
    &["sensor_bench"],
    &["camera_bench"],
    &["live"],
    &["ros"],
];

/// Items re-exported at the crate root, by the module that defines them.
const ROOT_ITEMS: &[(&str, &str)] = &[
    ("Error", "error"),
    ("Result", "error"),
    ("SpecIssue", "error"),
    ("Controls", "model"),
    ("Scenario", "model"),
    ("ScenarioTemplate", "model"),
    ("VehicleModel", "model"),
    ("load_vehicle", "model"),
    ("Method", "model"),
    ("Simulation", "world"),
    ("compile_scenario", "model"),
    ("load_scenario", "model"),
    ("load_scenario_with", "model"),
    ("Overrides", "model"),
    ("load_template", "model"),
    ("Outcome", "run"),
    ("RunOptions", "run"),
    ("RunResult", "run"),
    ("Scripted", "run"),
    ("Runner", "run"),
    ("Summary", "run"),
    ("Timeline", "run"),
    ("run_scenario", "run"),
    ("run_scenario_with", "run"),
];

pub(crate) fn rank(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

/// Every `.rs` file under `p` (sub-folders included).
pub(crate) fn rust_files(p: &Path, out: &mut Vec<PathBuf>) {
    if p.is_dir() {
        for e in std::fs::read_dir(p).unwrap() {
            rust_files(&e.unwrap().path(), out);
        }
    } else if p.extension().is_some_and(|e| e == "rs") {
        out.push(p.to_path_buf());
    }
}

/// The modules a top-level module's code names through `crate::`.
fn imports(src: &Path, module: &str) -> BTreeSet<String> {
    let mut files = Vec::new();
    let dir = src.join(module);
    let file = src.join(format!("{module}.rs"));
    rust_files(if dir.is_dir() { &dir } else { &file }, &mut files);
    assert!(!files.is_empty(), "module {module} has no files");
    let mut found = BTreeSet::new();
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        for line in text.lines() {
            let code = line.split("//").next().unwrap_or("");
            for (i, _) in code.match_indices("crate::") {
                let name: String = code[i + 7..]
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                let target = if rank(&name).is_some() {
                    name
                } else {
                    ROOT_ITEMS
                        .iter()
                        .find(|(item, _)| *item == name)
                        .map(|(_, m)| m.to_string())
                        .unwrap_or_else(|| {
                            panic!("{}: unknown crate path crate::{name}", f.display())
                        })
                };
                if target != module {
                    found.insert(target);
                }
            }
        }
    }
    found
}

#[test]
fn every_layer_imports_only_lower_layers() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    // Every top-level module of lib.rs is placed in a layer.
    let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap();
    for line in lib.lines() {
        let line = line.trim();
        if let Some(rest) = line
            .strip_prefix("pub mod ")
            .or(line.strip_prefix("pub(crate) mod "))
        {
            let m = rest.trim_end_matches(';');
            assert!(rank(m).is_some(), "module {m} is in no layer of this test");
        }
    }
    let mut upward = Vec::new();
    for layer in LAYERS {
        for m in *layer {
            for dep in imports(&src, m) {
                if rank(&dep) >= rank(m) {
                    upward.push(format!("{m} imports {dep}"));
                }
            }
        }
    }
    assert!(
        upward.is_empty(),
        "imports that go up or sideways: {upward:?}"
    );
}
