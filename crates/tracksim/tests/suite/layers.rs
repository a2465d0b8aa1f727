//! The library's layers import only downward (issue 10): for every top-level module, the
//! `crate::<module>` paths in its code (comments excluded) name only modules of lower layers.
//! This is how "no import circles" is checked: a circle needs an upward edge.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Top-level modules from the bottom layer up; modules in one inner list are one layer and must
/// not import each other.
const LAYERS: &[&[&str]] = &[
    &["error"],
    &["check", "files", "rosmsg"],
    &["spec"],
    &["geometry"],
    &["terrain"],
    &["model"],
    &["tracks"],
    &["world"],
    &["sensors"],
    &["run"],
    &["output"],
    &["cases"],
    &["ensemble"],
    &[
        "bench", "validate", "env", "sweep", "compare", "bundled", "sessions",
    ],
    &["sensor_bench"],
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

fn rank(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

fn rust_files(p: &Path, out: &mut Vec<PathBuf>) {
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

/// The sibling files a file of a folder module names through `super::` (or
/// `crate::<module>::`), `mod.rs` excluded (it declares and re-exports them all).
fn sibling_imports(dir: &Path, module: &str, file: &Path) -> BTreeSet<String> {
    let text = std::fs::read_to_string(file).unwrap();
    let siblings: BTreeSet<String> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            let stem = p.file_stem()?.to_str()?.to_string();
            (stem != "mod" && (p.is_dir() || p.extension().is_some_and(|x| x == "rs")))
                .then_some(stem)
        })
        .collect();
    let me = file.file_stem().unwrap().to_str().unwrap().to_string();
    let mut found = BTreeSet::new();
    let in_tests = |code: &str| code.contains("mod tests");
    let mut tests = false;
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        tests |= in_tests(code);
        if tests {
            // A unit-test module's `super::` is its own file.
            continue;
        }
        for prefix in ["super::".to_string(), format!("crate::{module}::")] {
            for (i, _) in code.match_indices(&prefix) {
                let name: String = code[i + prefix.len()..]
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if siblings.contains(&name) && name != me {
                    found.insert(name);
                }
            }
        }
    }
    found
}

/// Inside every folder module, its files import each other without a circle (issue 24: four
/// files of `output/` went round through `SideLine`).
#[test]
fn no_import_circle_inside_a_folder() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut folders = Vec::new();
    for e in std::fs::read_dir(&src).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            folders.push(p);
        }
    }
    let mut circles = Vec::new();
    for dir in folders {
        let module = dir.file_name().unwrap().to_str().unwrap().to_string();
        let mut graph = std::collections::BTreeMap::new();
        for e in std::fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "rs") && p.file_stem().unwrap() != "mod" {
                let name = p.file_stem().unwrap().to_str().unwrap().to_string();
                graph.insert(name, sibling_imports(&dir, &module, &p));
            }
        }
        // Depth-first search for a back edge.
        fn visit(
            n: &str,
            g: &std::collections::BTreeMap<String, BTreeSet<String>>,
            path: &mut Vec<String>,
            done: &mut BTreeSet<String>,
            out: &mut Vec<String>,
        ) {
            if let Some(i) = path.iter().position(|p| p == n) {
                out.push(path[i..].join(" -> ") + " -> " + n);
                return;
            }
            if done.contains(n) {
                return;
            }
            path.push(n.to_string());
            for m in g.get(n).into_iter().flatten() {
                visit(m, g, path, done, out);
            }
            path.pop();
            done.insert(n.to_string());
        }
        let mut done = BTreeSet::new();
        for n in graph.keys() {
            let mut found = Vec::new();
            visit(n, &graph, &mut Vec::new(), &mut done, &mut found);
            circles.extend(found.into_iter().map(|c| format!("{module}/: {c}")));
        }
    }
    assert!(circles.is_empty(), "import circles: {circles:#?}");
}
