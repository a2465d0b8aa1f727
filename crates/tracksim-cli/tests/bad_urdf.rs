//! Issue 45: URDF robots and their meshes through the binary's `check` and a 0.05 s `run`,
//! each under 5 s and a 1 GiB address space (`ulimit -v`), as `bad_inputs.rs` does for TOML:
//! - the corpus `crates/tracksim/tests/bad_urdf/` (each URDF's first line is
//!   `<!-- expect: TEXT -->`, the text its refusal must contain; the meshes it names beside it)
//!   refused with exit 2 by `check` and `run` alike;
//! - what is too large to commit (100,000 nested elements, a COLLADA file 100,000 deep,
//!   10,000 links, a 200,000-triangle STL named by 200 collisions) generated here;
//! - seeded mutants of the bundled URDF PackBot (`TRACKSIM_URDF_MUTANTS`, default 100;
//!   `TRACKSIM_URDF_SEED`, default 45): every one exits 0 or 2 in `check` and `run` alike, a
//!   refusal naming the file, never a panic or a signal;
//! - `check` and `run` agree on a vehicle file whose 1000-pulley loop the link-mass floor
//!   refuses.

use rand_core::{Rng, SeedableRng};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn corpus() -> PathBuf {
    repo().join("crates/tracksim/tests/bad_urdf")
}

/// Time limit of one command: a refusal takes milliseconds, a 0.05 s run of the PackBot a few
/// tenths of a second; 5 s leaves room for a loaded 2-core machine and catches a hang.
const LIMIT: Duration = Duration::from_secs(5);

/// Address-space limit of one command, KiB (1 GiB).
const MEMORY_KIB: u64 = 1 << 20;

/// Longest message allowed for one bad file.
const MAX_MESSAGE: usize = 4_000;

#[path = "support/bounded.rs"]
mod bounded;
use bounded::Ran;

/// Runs the binary with `args` under [`LIMIT`] (killed past it: a hang fails the test).
fn run(args: &[&str]) -> Ran {
    bounded::run_bounded(args, LIMIT, Some(MEMORY_KIB))
}

/// Asserts that `r` ended cleanly (no panic, no signal) with exit 0 or 2.
fn clean(what: &str, r: &Ran) {
    assert!(!r.text.contains("panicked"), "{what}: panic:\n{}", r.text);
    assert_eq!(r.signal, None, "{what}: killed by a signal:\n{}", r.text);
    assert!(
        matches!(r.code, Some(0 | 2)),
        "{what}: exit {:?}:\n{}",
        r.code,
        r.text
    );
    assert!(
        r.text.len() <= MAX_MESSAGE || r.code == Some(0),
        "{what}: message of {} bytes:\n{}",
        r.text.len(),
        r.text.chars().take(1500).collect::<String>()
    );
}

/// Asserts that `r` is a clean refusal (exit 2) containing `expect`.
fn refused(what: &str, r: &Ran, expect: &str) {
    clean(what, r);
    assert_eq!(r.code, Some(2), "{what}: exit code, output:\n{}", r.text);
    assert!(
        r.text.contains(expect),
        "{what}: message lacks {expect:?}:\n{}",
        r.text
    );
}

/// Writes `dir/v_NAME.toml`, the bundled URDF PackBot's vehicle file with `urdf` naming
/// `urdf`, and `dir/s_NAME.toml`, a 0.05 s scenario on flat ground with it.
fn files_for(dir: &Path, name: &str, urdf: &Path) -> (PathBuf, PathBuf) {
    let v = std::fs::read_to_string(repo().join("vehicles/packbot510_urdf.toml"))
        .unwrap()
        .replace(
            "urdf = \"urdf/packbot510_flippers.urdf\"",
            &format!("urdf = {:?}", urdf.to_str().unwrap()),
        );
    let vp = dir.join(format!("v_{name}.toml"));
    std::fs::write(&vp, v).unwrap();
    let sp = dir.join(format!("s_{name}.toml"));
    std::fs::write(
        &sp,
        format!(
            "[vehicle]\nfile = {:?}\n[terrain.ground]\n[simulation]\nduration_s = 0.05\n",
            vp.to_str().unwrap()
        ),
    )
    .unwrap();
    (vp, sp)
}

/// `check VEHICLE` and `run SCENARIO` of the robot `urdf`.
fn check_and_run(dir: &Path, name: &str, urdf: &Path) -> (Ran, Ran) {
    let (v, s) = files_for(dir, name, urdf);
    let c = run(&["check", v.to_str().unwrap()]);
    let out = dir.join(format!("out_{name}"));
    let r = run(&[
        "run",
        s.to_str().unwrap(),
        "--quiet",
        "--no-plot",
        "--out",
        out.to_str().unwrap(),
    ]);
    (c, r)
}

fn expected_text(file: &Path) -> String {
    let text = std::fs::read_to_string(file).unwrap();
    text.lines()
        .next()
        .and_then(|l| l.strip_prefix("<!-- expect: "))
        .and_then(|l| l.strip_suffix(" -->"))
        .unwrap_or_else(|| panic!("{} lacks its `<!-- expect: TEXT -->` line", file.display()))
        .to_string()
}

#[test]
fn every_bad_urdf_of_the_corpus_is_refused_by_check_and_run_alike() {
    let tmp = tempfile::tempdir().unwrap();
    let mut files: Vec<PathBuf> = std::fs::read_dir(corpus())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "urdf"))
        .collect();
    files.sort();
    assert!(files.len() >= 25, "corpus has {} URDF files", files.len());
    for f in files {
        let expect = expected_text(&f);
        let name = f.file_stem().unwrap().to_string_lossy().into_owned();
        let (c, r) = check_and_run(tmp.path(), &name, &f);
        refused(&format!("check {name}"), &c, &expect);
        refused(&format!("run {name}"), &r, &expect);
        let file = f.file_name().unwrap().to_string_lossy().into_owned();
        assert!(
            c.text.contains(&file),
            "check {name} names no file:\n{}",
            c.text
        );
        assert!(
            !tmp.path().join(format!("out_{name}/summary.json")).exists(),
            "run {name} wrote a summary"
        );
    }
}

/// A binary STL of `triangles` (each three vertices).
fn binary_stl(triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut d = vec![b' '; 80];
    d.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
    for t in triangles {
        for v in [[0.0, 0.0, 1.0], t[0], t[1], t[2]] {
            for c in v {
                d.extend_from_slice(&c.to_le_bytes());
            }
        }
        d.extend_from_slice(&[0, 0]);
    }
    d
}

/// `n` triangles of points spread through a 0.4 x 0.2 x 0.1 m box, its corners among them:
/// a heavy mesh whose hull is the box (8 vertices).
fn box_cloud_stl(n: usize) -> Vec<u8> {
    let corner = |k: usize| {
        [
            if k & 1 == 0 { -0.2 } else { 0.2 },
            if k & 2 == 0 { -0.1 } else { 0.1 },
            if k & 4 == 0 { -0.05 } else { 0.05 },
        ]
    };
    let p = |k: usize| -> [f32; 3] {
        if k < 8 {
            return corner(k);
        }
        let f = |m: f32| ((k as f32 * m).fract() - 0.5) * 0.9;
        [0.4 * f(0.618_034), 0.2 * f(0.754_877), 0.1 * f(0.569_840)]
    };
    let tris: Vec<[[f32; 3]; 3]> = (0..n)
        .map(|k| [p(3 * k), p(3 * k + 1), p(3 * k + 2)])
        .collect();
    binary_stl(&tris)
}

/// The bundled URDF PackBot's text.
fn base_urdf() -> String {
    std::fs::read_to_string(repo().join("vehicles/urdf/packbot510_flippers.urdf")).unwrap()
}

/// The chassis' box collision of the bundled URDF.
const BOX: &str =
    "<collision>\n      <geometry><box size=\"0.50 0.25 0.10\"/></geometry>\n    </collision>";

/// `copies` collisions of mesh `file` with `scale`.
fn mesh_collisions(file: &str, scale: &str, copies: usize) -> String {
    format!(
        "<collision><geometry><mesh filename=\"{file}\" scale=\"{scale}\"/></geometry></collision>"
    )
    .repeat(copies)
}

/// `n` extra links with a box collision each, fixed to the chassis.
fn extra_links(n: usize) -> String {
    (0..n)
        .map(|i| {
            format!(
                "<link name=\"x{i}\"><collision><geometry><box size=\"0.01 0.01 0.01\"/>\
                 </geometry></collision></link><joint name=\"jx{i}\" type=\"fixed\"><parent \
                 link=\"base_link\"/><child link=\"x{i}\"/></joint>"
            )
        })
        .collect()
}

#[test]
fn generated_hostile_urdfs_are_refused_quickly_and_large_valid_ones_load() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let base = base_urdf();
    let write = |name: &str, text: &str| {
        let p = d.join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let deep = |n: usize| "<x>".repeat(n) + &"</x>".repeat(n);
    // 100,000 nested unknown elements inside <robot> and inside a <link>.
    let open = "<robot name=\"packbot510_flippers\">";
    let f = write(
        "deep_robot.urdf",
        &base.replace(open, &format!("{open}{}", deep(100_000))),
    );
    let (c, r) = check_and_run(d, "deep_robot", &f);
    refused(
        "check deep_robot",
        &c,
        "deep_robot.urdf: elements nested 65 deep",
    );
    refused(
        "run deep_robot",
        &r,
        "deep_robot.urdf: elements nested 65 deep",
    );
    let link = "<link name=\"base_link\">";
    let f = write(
        "deep_link.urdf",
        &base.replace(link, &format!("{link}{}", deep(100_000))),
    );
    let (c, _) = check_and_run(d, "deep_link", &f);
    refused(
        "check deep_link",
        &c,
        "deep_link.urdf: elements nested 65 deep",
    );
    // A COLLADA file 100,000 deep.
    let dae = format!(
        "<?xml version=\"1.0\"?><COLLADA version=\"1.4.1\"><library_visual_scenes>\
         <visual_scene id=\"s\">{}{}</visual_scene></library_visual_scenes></COLLADA>",
        "<node>".repeat(100_000),
        "</node>".repeat(100_000)
    );
    write("deep.dae", &dae);
    let f = write(
        "deep_dae.urdf",
        &base.replacen(BOX, &mesh_collisions("deep.dae", "1 1 1", 1), 1),
    );
    let (c, r) = check_and_run(d, "deep_dae", &f);
    refused("check deep_dae", &c, "deep.dae: elements nested 65 deep");
    refused("run deep_dae", &r, "deep.dae: elements nested 65 deep");
    // 10,000 extra links: refused by their count, in milliseconds.
    let f = write(
        "links_10000.urdf",
        &base.replace("</robot>", &format!("{}</robot>", extra_links(10_000))),
    );
    let (c, r) = check_and_run(d, "links_10000", &f);
    refused(
        "check links_10000",
        &c,
        "links_10000.urdf: more than 1000 <link>",
    );
    refused(
        "run links_10000",
        &r,
        "links_10000.urdf: more than 1000 <link>",
    );
    // 1000 links in all (5 + 995): within the bound, checked and run.
    let f = write(
        "links_1000.urdf",
        &base.replace("</robot>", &format!("{}</robot>", extra_links(995))),
    );
    let (c, r) = check_and_run(d, "links_1000", &f);
    assert_eq!(c.code, Some(0), "{}", c.text);
    assert_eq!(r.code, Some(0), "{}", r.text);
    assert!(c.text.contains("1000 links"), "{}", c.text);
    // One 200,000-triangle STL named by 200 collisions: read and hulled once.
    std::fs::write(d.join("big.stl"), box_cloud_stl(200_000)).unwrap();
    let f = write(
        "big_200.urdf",
        &base.replacen(BOX, &mesh_collisions("big.stl", "1 1 1", 200), 1),
    );
    let t0 = Instant::now();
    let (c, r) = check_and_run(d, "big_200", &f);
    assert_eq!(c.code, Some(0), "{}", c.text);
    assert_eq!(r.code, Some(0), "{}", r.text);
    eprintln!(
        "200 collisions of a 200k-triangle STL: check and run in {:?}",
        t0.elapsed()
    );
}

#[test]
fn check_and_run_agree_on_a_loop_that_the_link_mass_floor_refuses() {
    let tmp = tempfile::tempdir().unwrap();
    let v = std::fs::read_to_string(repo().join("vehicles/packbot510.toml")).unwrap();
    let old = "pulleys = [\n  { x_m = -0.255, z_m = 0.0, radius_m = 0.082 },\n  { x_m = 0.255, z_m = 0.0, radius_m = 0.082 },\n]";
    assert!(v.contains(old));
    let pulleys: Vec<String> = (0..1000)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 1000.0;
            format!(
                "  {{ x_m = {:.6}, z_m = {:.6}, radius_m = 0.01 }},",
                0.3 * a.cos(),
                0.1 * a.sin()
            )
        })
        .collect();
    let vp = tmp.path().join("pulleys_1000.toml");
    std::fs::write(
        &vp,
        v.replace(old, &format!("pulleys = [\n{}\n]", pulleys.join("\n"))),
    )
    .unwrap();
    let key = "simulation.min_link_mass_kg";
    let c = run(&["check", vp.to_str().unwrap()]);
    refused("check pulleys_1000", &c, key);
    assert!(c.text.contains("pulleys_1000.toml"), "{}", c.text);
    let sp = tmp.path().join("s.toml");
    std::fs::write(
        &sp,
        format!(
            "[vehicle]\nfile = {:?}\n[terrain.ground]\n[simulation]\nduration_s = 0.05\n",
            vp.to_str().unwrap()
        ),
    )
    .unwrap();
    let out = tmp.path().join("o");
    let r = run(&[
        "run",
        sp.to_str().unwrap(),
        "--quiet",
        "--no-plot",
        "--out",
        out.to_str().unwrap(),
    ]);
    refused("run pulleys_1000", &r, key);
    // The bundled vehicle files still pass `check` (built as `run` builds them).
    for f in ["packbot510.toml", "packbot510_urdf.toml", "quince.toml"] {
        let c = run(&["check", repo().join("vehicles").join(f).to_str().unwrap()]);
        assert_eq!(c.code, Some(0), "{f}: {}", c.text);
    }
}

// ---- The mutator -------------------------------------------------------------------------

/// Numbers a hostile or careless file holds (and a few ordinary ones).
const HOSTILE: &[&str] = &[
    "1e30", "-1e30", "nan", "inf", "-inf", "1e-100", "1e308", "0", "-1", "1e5", "100001", "1e-13",
    "", "abc", "1e9", "3.4e38", "-0", "1e-6", "2e5", "0.5", "0.02", "2", "0.3 0",
];

/// Mesh scales to try.
const SCALES: &[&str] = &[
    "1 1 1",
    "1e300 1 1",
    "1e-12 1e-12 1e-12",
    "0.001 0.001 0.001",
    "1000 1000 1000",
    "-1 1 1",
    "nan 1 1",
    "0 1 1",
    "1 1",
];

fn below(rng: &mut impl Rng, n: usize) -> usize {
    (rng.next_u64() % n as u64) as usize
}

fn pick<'a, T>(rng: &mut impl Rng, items: &'a [T]) -> &'a T {
    &items[below(rng, items.len())]
}

/// Byte ranges of the attribute values of `text` that are numbers or lists of numbers.
fn numeric_values(text: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut at = 0;
    while let Some(i) = text[at..].find("=\"") {
        let s = at + i + 2;
        let Some(len) = text[s..].find('"') else {
            break;
        };
        let v = &text[s..s + len];
        if !v.is_empty() && v.split_whitespace().all(|w| w.parse::<f64>().is_ok()) {
            out.push((s, s + len));
        }
        at = s + len + 1;
    }
    out
}

/// The meshes the mutants may name, written into `dir`.
fn write_meshes(dir: &Path) -> Vec<&'static str> {
    let tet = |s: f32, o: f32| -> Vec<[[f32; 3]; 3]> {
        let p = [[o, 0.0, 0.0], [o + s, 0.0, 0.0], [o, s, 0.0], [o, 0.0, s]];
        vec![
            [p[0], p[1], p[2]],
            [p[0], p[1], p[3]],
            [p[0], p[2], p[3]],
            [p[1], p[2], p[3]],
        ]
    };
    std::fs::write(dir.join("tetra.stl"), binary_stl(&tet(0.1, 0.0))).unwrap();
    std::fs::write(dir.join("point.stl"), binary_stl(&[[[1.0; 3]; 3]; 4])).unwrap();
    std::fs::write(dir.join("far.stl"), binary_stl(&tet(0.1, 3e38))).unwrap();
    let mut lie = binary_stl(&tet(0.1, 0.0));
    lie[80..84].copy_from_slice(&2_000_000u32.to_le_bytes());
    std::fs::write(dir.join("lie.stl"), lie).unwrap();
    std::fs::write(dir.join("cloud.stl"), box_cloud_stl(2_000)).unwrap();
    std::fs::write(
        dir.join("far.obj"),
        "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 1e38\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n",
    )
    .unwrap();
    for f in [
        "tetra.dae",
        "index_past.dae",
        "count_huge.dae",
        "triangles_count.dae",
        "coplanar.stl",
    ] {
        std::fs::copy(corpus().join(f), dir.join(f)).unwrap();
    }
    vec![
        "tetra.stl",
        "point.stl",
        "far.stl",
        "lie.stl",
        "cloud.stl",
        "far.obj",
        "tetra.dae",
        "index_past.dae",
        "count_huge.dae",
        "triangles_count.dae",
        "coplanar.stl",
        "missing.stl",
    ]
}

/// One mutant of `base` (one to three mutations).
fn mutate(rng: &mut impl Rng, base: &str, meshes: &[&str]) -> String {
    let mut t = base.to_string();
    for _ in 0..1 + below(rng, 3) {
        match below(rng, 10) {
            0 | 1 => {
                let spots = numeric_values(&t);
                if let Some(&(s, e)) = spots.get(below(rng, spots.len().max(1))) {
                    let mut words: Vec<String> =
                        t[s..e].split_whitespace().map(String::from).collect();
                    let k = below(rng, words.len());
                    words[k] = pick(rng, HOSTILE).to_string();
                    t.replace_range(s..e, &words.join(" "));
                }
            }
            2 => {
                let v = pick(rng, HOSTILE);
                t = t.replace("<mu1>0.6</mu1>", &format!("<mu1>{v}</mu1>"));
                if below(rng, 2) == 0 {
                    t = t.replace(
                        "<tracks_separation>0.325</tracks_separation>",
                        &format!("<tracks_separation>{v}</tracks_separation>"),
                    );
                }
            }
            3 => {
                let n = *pick(rng, &[10, 63, 64, 65, 1000, 100_000]);
                let at = *pick(
                    rng,
                    &[
                        "<robot name=\"packbot510_flippers\">",
                        "<link name=\"base_link\">",
                    ],
                );
                let deep = "<x>".repeat(n) + &"</x>".repeat(n);
                t = t.replacen(at, &format!("{at}{deep}"), 1);
            }
            4 => {
                let n = *pick(rng, &[1, 10, 500, 995, 996, 5_000, 10_000]);
                t = t.replace("</robot>", &format!("{}</robot>", extra_links(n)));
            }
            5 => {
                let m = *pick(rng, meshes);
                let copies = *pick(rng, &[1, 2, 200]);
                let scale = *pick(rng, SCALES);
                t = t.replacen(BOX, &mesh_collisions(m, scale, copies), 1);
            }
            6 => {
                let ty = pick(
                    rng,
                    &[
                        "fixed",
                        "continuous",
                        "prismatic",
                        "floating",
                        "planar",
                        "bogus",
                        "",
                    ],
                );
                let from = *pick(rng, &["type=\"revolute\"", "type=\"fixed\""]);
                t = t.replacen(from, &format!("type=\"{ty}\""), 1);
            }
            7 => {
                let lines: Vec<&str> = t.lines().collect();
                let k = below(rng, lines.len());
                let dup = below(rng, 2) == 0;
                let mut out: Vec<&str> = Vec::new();
                for (i, l) in lines.iter().enumerate() {
                    if i != k || dup {
                        out.push(l);
                    }
                    if i == k && dup {
                        out.push(l);
                    }
                }
                t = out.join("\n");
            }
            8 => {
                let mut cut = below(rng, t.len());
                while !t.is_char_boundary(cut) {
                    cut -= 1;
                }
                t.truncate(cut);
            }
            _ => {
                let names = [
                    "base_link",
                    "left_track",
                    "front_left_flipper",
                    "front_right_flipper",
                ];
                let (a, b) = (pick(rng, &names), pick(rng, &names));
                t = t.replacen(&format!("link=\"{a}\""), &format!("link=\"{b}\""), 1);
            }
        }
    }
    t
}

#[test]
fn seeded_mutants_of_the_urdf_packbot_exit_0_or_2_naming_the_file() {
    let n: usize = std::env::var("TRACKSIM_URDF_MUTANTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(100);
    let seed: u64 = std::env::var("TRACKSIM_URDF_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(45);
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let meshes = write_meshes(d);
    let base = base_urdf();
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed);
    let (mut accepted, mut refusals) = (0, 0);
    let t0 = Instant::now();
    for i in 0..n {
        let text = mutate(&mut rng, &base, &meshes);
        let name = format!("m{i}");
        let file = format!("{name}.urdf");
        let f = d.join(&file);
        std::fs::write(&f, &text).unwrap();
        let what = format!("mutant {i} (seed {seed}, {})", f.display());
        let (c, r) = check_and_run(d, &name, &f);
        clean(&format!("check {what}"), &c);
        clean(&format!("run {what}"), &r);
        assert_eq!(
            c.code, r.code,
            "{what}: check and run disagree:\n{}\n---\n{}",
            c.text, r.text
        );
        if c.code == Some(2) {
            refusals += 1;
            // The robot file, or a key of the vehicle file that binds to it (a track on a
            // link turned out of the x-z plane; the link-mass floor of a light chassis), in the
            // vehicle file named first.
            let names = |t: &str| {
                t.contains(&file)
                    || t.contains("  - tracks[")
                    || t.contains("  - simulation.min_link_mass_kg")
            };
            assert!(
                names(&c.text),
                "{what}: the refusal names no file:\n{}",
                c.text
            );
            assert!(
                names(&r.text),
                "{what}: the refusal names no file:\n{}",
                r.text
            );
        } else {
            accepted += 1;
        }
    }
    eprintln!(
        "{n} mutants (seed {seed}): {accepted} accepted, {refusals} refused, in {:?}",
        t0.elapsed()
    );
    assert!(
        refusals > n / 4,
        "{refusals} of {n} mutants refused: the mutator is too mild"
    );
}
