//! Issue 45, part 1: every bound on a URDF/SDF robot and its meshes, each by a case just
//! inside it (loads) and one beyond it (refused, the file and element named): XML nesting
//! depth, element, link, joint and collision counts, the file size, the magnitudes of the
//! TOML checker on every number, mesh vertices after their scale, a binary STL's header
//! against its length, COLLADA counts against their data, degenerate hulls, and a mesh named
//! by many collisions read once. The CLI-level corpus and the seeded mutator are in
//! `crates/tracksim-cli/tests/bad_urdf.rs`.

use crate::common::root;
use std::path::{Path, PathBuf};
use tracksim::urdf::{self, UrdfRobot};

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracksim-issue45-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn corpus() -> PathBuf {
    root().join("crates/tracksim/tests/bad_urdf")
}

fn bundled() -> String {
    std::fs::read_to_string(root().join("vehicles/urdf/packbot510_flippers.urdf")).unwrap()
}

/// Replaces the first `old` (which must occur) by `new`.
fn edit(text: &str, old: &str, new: &str) -> String {
    assert!(text.contains(old), "{old:?} not in the text");
    text.replacen(old, new, 1)
}

/// Loads `text` written as `dir/robot.urdf`: the robot, or its problems as one string.
fn load(dir: &Path, text: &str) -> Result<UrdfRobot, String> {
    let p = dir.join("robot.urdf");
    std::fs::write(&p, text).unwrap();
    UrdfRobot::load(&p).map_err(|issues| {
        issues
            .iter()
            .map(|i| format!("{}: {}", i.key, i.message))
            .collect::<Vec<_>>()
            .join("\n")
    })
}

fn loads(dir: &Path, what: &str, text: &str) -> UrdfRobot {
    load(dir, text).unwrap_or_else(|e| panic!("{what}: refused:\n{e}"))
}

fn refused(dir: &Path, what: &str, text: &str, expect: &str) {
    match load(dir, text) {
        Ok(_) => panic!("{what}: accepted"),
        Err(e) => {
            assert!(e.contains(expect), "{what}: lacks {expect:?}:\n{e}");
            assert!(e.contains("robot.urdf"), "{what}: names no file:\n{e}");
        }
    }
}

const ROBOT: &str = "<robot name=\"packbot510_flippers\">";
const BASE: &str = "<link name=\"base_link\">";
const BOX: &str =
    "<collision>\n      <geometry><box size=\"0.50 0.25 0.10\"/></geometry>\n    </collision>";

fn nested(n: usize) -> String {
    "<x>".repeat(n) + &"</x>".repeat(n)
}

#[test]
fn xml_nesting_is_bounded_at_64_levels() {
    let d = scratch("depth");
    let u = bundled();
    assert_eq!(urdf::MAX_XML_DEPTH, 64);
    // <robot> is level 1: 63 levels inside it reach 64.
    loads(
        &d,
        "64 deep",
        &edit(&u, ROBOT, &format!("{ROBOT}{}", nested(63))),
    );
    let e = "elements nested 65 deep";
    refused(
        &d,
        "65 deep",
        &edit(&u, ROBOT, &format!("{ROBOT}{}", nested(64))),
        e,
    );
    // <link> is level 2.
    loads(
        &d,
        "64 deep in a link",
        &edit(&u, BASE, &format!("{BASE}{}", nested(62))),
    );
    refused(
        &d,
        "100,000 deep",
        &edit(&u, BASE, &format!("{BASE}{}", nested(100_000))),
        e,
    );
}

fn extra_links(n: usize) -> String {
    (0..n)
        .map(|i| {
            format!(
                "<link name=\"x{i}\"/><joint name=\"jx{i}\" type=\"fixed\"><parent \
                 link=\"base_link\"/><child link=\"x{i}\"/></joint>"
            )
        })
        .collect()
}

#[test]
fn links_joints_collisions_and_elements_are_counted() {
    let d = scratch("counts");
    let u = bundled();
    // Links: the bundled robot has 5.
    assert_eq!(urdf::MAX_LINKS, 1000);
    let r = loads(
        &d,
        "1000 links",
        &edit(&u, "</robot>", &format!("{}</robot>", extra_links(995))),
    );
    assert_eq!(r.links.len(), 1000);
    let big = edit(&u, "</robot>", &format!("{}</robot>", extra_links(996)));
    refused(&d, "1001 links", &big, "more than 1000 <link> elements");
    // Joints: 4, and more inside a <gazebo> block (not the robot's, but counted).
    let joints = |n: usize| -> String {
        let j: String = (0..n).map(|i| format!("<joint name=\"g{i}\"/>")).collect();
        edit(&u, "</robot>", &format!("<gazebo>{j}</gazebo></robot>"))
    };
    loads(&d, "1000 joints", &joints(996));
    refused(
        &d,
        "1001 joints",
        &joints(997),
        "more than 1000 <joint> elements",
    );
    // Collisions: 5.
    assert_eq!(urdf::MAX_COLLISIONS, 10_000);
    let boxes = |n: usize| edit(&u, BOX, &BOX.repeat(n + 1));
    let r = loads(&d, "10,000 collisions", &boxes(9_995));
    assert!(
        r.links[0].shapes.len() == 9_996,
        "{}",
        r.links[0].shapes.len()
    );
    refused(
        &d,
        "10,001 collisions",
        &boxes(9_996),
        "more than 10000 <collision>",
    );
    // Elements: every element of the file, counted as roxmltree does.
    let doc = roxmltree::Document::parse(&u).unwrap();
    let have = doc.descendants().filter(|n| n.is_element()).count();
    let padded = |n: usize| edit(&u, "</robot>", &format!("{}</robot>", "<x/>".repeat(n)));
    loads(
        &d,
        "100,000 elements",
        &padded(urdf::MAX_XML_ELEMENTS - have),
    );
    refused(
        &d,
        "100,001 elements",
        &padded(urdf::MAX_XML_ELEMENTS - have + 1),
        "more than 100000 elements",
    );
}

#[test]
fn a_robot_file_is_at_most_16_mib() {
    let d = scratch("size");
    let u = bundled();
    let max = urdf::MAX_URDF_BYTES as usize;
    let pad = |n: usize| format!("{u}<!--{}-->", "x".repeat(n - u.len() - 7));
    let at = pad(max);
    assert_eq!(at.len(), max);
    loads(&d, "16 MiB", &at);
    refused(
        &d,
        "16 MiB + 1",
        &pad(max + 1),
        "more than the limit of 16777216 bytes",
    );
}

/// (what, the text replaced, a value just inside, a value beyond, the element named).
const MAGNITUDES: &[(&str, &str, &str, &str, &str)] = &[
    (
        "joint origin",
        "<origin xyz=\"0 0.1625 0\" rpy=\"0 0 0\"/>",
        "<origin xyz=\"99999 0.1625 0\" rpy=\"0 0 0\"/>",
        "<origin xyz=\"100001 0.1625 0\" rpy=\"0 0 0\"/>",
        "<joint name=\"left_track_joint\"> (robot.urdf line",
    ),
    (
        "joint rpy",
        "<origin xyz=\"0 0.1625 0\" rpy=\"0 0 0\"/>",
        "<origin xyz=\"0 0.1625 0\" rpy=\"0 0 1e9\"/>",
        "<origin xyz=\"0 0.1625 0\" rpy=\"0 0 1.1e9\"/>",
        "<origin rpy>",
    ),
    (
        "inertial origin",
        "<origin xyz=\"0.15 0 0\" rpy=\"0 0 0\"/>\n      <mass",
        "<origin xyz=\"-99999 0 0\" rpy=\"0 0 0\"/>\n      <mass",
        "<origin xyz=\"-100001 0 0\" rpy=\"0 0 0\"/>\n      <mass",
        "<inertial> <origin xyz>",
    ),
    (
        "collision origin",
        "<collision>\n      <origin xyz=\"0.15 0 0\" rpy=\"0 0 0\"/>",
        "<collision>\n      <origin xyz=\"0.15 0 -99999\" rpy=\"0 0 0\"/>",
        "<collision>\n      <origin xyz=\"0.15 0 -100001\" rpy=\"0 0 0\"/>",
        "<collision> 1 <origin xyz>",
    ),
    (
        "smallest moment of inertia",
        "ixx=\"0.01\"",
        "ixx=\"1e-12\"",
        "ixx=\"9e-13\"",
        "<inertia ixx>",
    ),
    (
        "largest moment of inertia",
        "ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"",
        "ixx=\"1e6\" ixy=\"0\" ixz=\"0\" iyy=\"1e6\" iyz=\"0\" izz=\"1e6\"",
        "ixx=\"1.1e6\" ixy=\"0\" ixz=\"0\" iyy=\"1.1e6\" iyz=\"0\" izz=\"1.1e6\"",
        "<inertia>",
    ),
    (
        "joint limit",
        "lower=\"-1.5708\"",
        "lower=\"-1e9\"",
        "lower=\"-1.1e9\"",
        "<limit lower>",
    ),
    (
        "largest effort",
        "effort=\"60\"",
        "effort=\"1e7\"",
        "effort=\"1.1e7\"",
        "<limit effort>",
    ),
    (
        "smallest effort",
        "effort=\"60\"",
        "effort=\"1e-6\"",
        "effort=\"9e-7\"",
        "<limit effort>",
    ),
    (
        "axis",
        "<axis xyz=\"0 -1 0\"/>",
        "<axis xyz=\"0 -1e9 0\"/>",
        "<axis xyz=\"0 -1.1e9 0\"/>",
        "<axis xyz>",
    ),
    (
        "friction",
        "<mu1>0.6</mu1>",
        "<mu1>1e4</mu1>",
        "<mu1>1.1e4</mu1>",
        "<gazebo reference=\"base_link\"><mu1> (robot.urdf)",
    ),
    (
        "tracks_separation",
        "<tracks_separation>0.325</tracks_separation>",
        "<tracks_separation>1e5</tracks_separation>",
        "<tracks_separation>1.1e5</tracks_separation>",
        "<plugin><tracks_separation>",
    ),
];

#[test]
fn every_number_is_held_to_the_toml_checkers_bounds() {
    let d = scratch("magnitudes");
    let u = bundled();
    for (what, old, inside, beyond, element) in MAGNITUDES {
        loads(&d, what, &edit(&u, old, inside));
        refused(&d, what, &edit(&u, old, beyond), element);
    }
    for (what, old, new, element) in [
        (
            "NaN rpy",
            "rpy=\"0 0 0\"",
            "rpy=\"nan 0 0\"",
            "<origin rpy>",
        ),
        (
            "1e308 axis",
            "<axis xyz=\"0 -1 0\"/>",
            "<axis xyz=\"1e308 1e308 0\"/>",
            "<axis xyz>",
        ),
        (
            "zero axis",
            "<axis xyz=\"0 -1 0\"/>",
            "<axis xyz=\"0 0 0\"/>",
            "is a zero vector",
        ),
        (
            "1e308 limit",
            "upper=\"1.5708\"",
            "upper=\"1e308\"",
            "<limit upper>",
        ),
        (
            "1e-100 inertia",
            "iyy=\"0.01\"",
            "iyy=\"1e-100\"",
            "<inertia iyy>",
        ),
        (
            "1e300 inertia",
            "iyy=\"0.01\"",
            "iyy=\"1e300\"",
            "<inertia>",
        ),
        (
            "empty mu1",
            "<mu1>0.6</mu1>",
            "<mu1></mu1>",
            "<mu1> (robot.urdf)",
        ),
        (
            "1e30 m offset",
            "xyz=\"0.255 0.225 0\"",
            "xyz=\"1e30 0.225 0\"",
            "<origin xyz>",
        ),
    ] {
        refused(&d, what, &edit(&u, old, new), element);
    }
    // Each origin within 1e5 m, but their sum along a chain beyond it.
    let chain = edit(
        &edit(&u, "xyz=\"0.255 0.225 0\"", "xyz=\"90000 0.225 0\""),
        "<origin xyz=\"0.15 0 0\" rpy=\"0 0 0\"/>\n      <geometry",
        "<origin xyz=\"90000 0 0\" rpy=\"0 0 0\"/>\n      <geometry",
    );
    refused(&d, "a chain beyond 1e5 m", &chain, "beyond 1e5 m (the f32");
}

/// The bundled robot with its chassis box replaced by `copies` collisions of mesh `file`.
fn with_mesh(file: &str, scale: &str, copies: usize) -> String {
    let m = format!(
        "<collision><geometry><mesh filename=\"{file}\" scale=\"{scale}\"/></geometry></collision>"
    );
    edit(&bundled(), BOX, &m.repeat(copies))
}

/// A binary STL of `tris`, its header claiming `count` triangles.
fn stl(tris: &[[[f32; 3]; 3]], count: u32) -> Vec<u8> {
    let mut d = vec![b' '; 80];
    d.extend_from_slice(&count.to_le_bytes());
    for t in tris {
        for v in [[0.0, 0.0, 1.0], t[0], t[1], t[2]] {
            for c in v {
                d.extend_from_slice(&c.to_le_bytes());
            }
        }
        d.extend_from_slice(&[0, 0]);
    }
    d
}

/// A tetrahedron with its edges along the axes, `x` m long.
fn tetra(x: f32) -> Vec<[[f32; 3]; 3]> {
    let p = [[0.0, 0.0, 0.0], [x, 0.0, 0.0], [0.0, x, 0.0], [0.0, 0.0, x]];
    vec![
        [p[0], p[1], p[2]],
        [p[0], p[1], p[3]],
        [p[0], p[2], p[3]],
        [p[1], p[2], p[3]],
    ]
}

#[test]
fn mesh_vertices_are_bounded_after_their_scale() {
    let d = scratch("vertices");
    std::fs::write(d.join("t.stl"), stl(&tetra(0.1), 4)).unwrap();
    std::fs::write(d.join("near.stl"), stl(&tetra(99_999.0), 4)).unwrap();
    std::fs::write(d.join("far.stl"), stl(&tetra(100_001.0), 4)).unwrap();
    loads(
        &d,
        "a vertex at 99999 m",
        &with_mesh("near.stl", "1 1 1", 1),
    );
    refused(
        &d,
        "a vertex at 100001 m",
        &with_mesh("far.stl", "1 1 1", 1),
        "far.stl: vertex 1",
    );
    loads(
        &d,
        "scaled to 99999 m",
        &with_mesh("t.stl", "999990 999990 999990", 1),
    );
    refused(
        &d,
        "scaled past 1e5 m",
        &with_mesh("t.stl", "1000010 1 1", 1),
        "t.stl: vertex 1",
    );
    std::fs::write(d.join("tiny.stl"), stl(&tetra(1e-5), 4)).unwrap();
    loads(
        &d,
        "a scale of 1e9",
        &with_mesh("tiny.stl", "1e9 1e9 1e9", 1),
    );
    refused(
        &d,
        "a scale of 1.1e9",
        &with_mesh("t.stl", "1 1.1e9 1", 1),
        "<mesh scale>",
    );
    refused(
        &d,
        "a scale of 1e300",
        &with_mesh("t.stl", "1e300 1 1", 1),
        "<mesh scale>",
    );
    let c = corpus();
    for (file, expect) in [
        ("far_1e38.obj", "far_1e38.obj: vertex"),
        ("far_3e38.stl", "far_3e38.stl: vertex 0"),
    ] {
        let u = with_mesh(c.join(file).to_str().unwrap(), "1 1 1", 1);
        refused(&d, file, &u, expect);
    }
}

#[test]
fn a_binary_stl_header_must_match_the_file() {
    let d = scratch("stl");
    std::fs::write(d.join("ok.stl"), stl(&tetra(0.1), 4)).unwrap();
    loads(&d, "4 triangles", &with_mesh("ok.stl", "1 1 1", 1));
    let mut nl = stl(&tetra(0.1), 4);
    nl.push(b'\n');
    std::fs::write(d.join("nl.stl"), nl).unwrap();
    loads(
        &d,
        "a line end after the triangles",
        &with_mesh("nl.stl", "1 1 1", 1),
    );
    for (name, count) in [("five.stl", 5), ("lie.stl", 2_000_000)] {
        std::fs::write(d.join(name), stl(&tetra(0.1), count)).unwrap();
        let expect = format!("{name}: its binary STL header says {count} triangles");
        refused(&d, name, &with_mesh(name, "1 1 1", 1), &expect);
    }
    // At the triangle bound and past it (sparse files of the right length: zero triangles).
    let sparse = |name: &str, n: u64| {
        let f = std::fs::File::create(d.join(name)).unwrap();
        f.set_len(84 + 50 * n).unwrap();
        use std::io::{Seek, Write};
        let mut f = f;
        f.seek(std::io::SeekFrom::Start(80)).unwrap();
        f.write_all(&(n as u32).to_le_bytes()).unwrap();
    };
    let max = urdf::MAX_MESH_TRIANGLES;
    sparse("max.stl", max);
    sparse("over.stl", max + 1);
    let e = "more than the 2000000 a collision mesh may have";
    refused(&d, "2,000,001", &with_mesh("over.stl", "1 1 1", 1), e);
    // Within the bound it is read: its zero triangles are all at one point.
    let at = load(&d, &with_mesh("max.stl", "1 1 1", 1)).unwrap_err();
    assert!(
        !at.contains(e) && at.contains("all its vertices are at one point"),
        "{at}"
    );
    // Past the size bound: refused before it is read.
    let f = std::fs::File::create(d.join("huge.stl")).unwrap();
    f.set_len(urdf::MAX_ROBOT_MESH_BYTES + 1).unwrap();
    refused(
        &d,
        "128 MiB + 1",
        &with_mesh("huge.stl", "1 1 1", 1),
        "more than the limit of",
    );
}

#[test]
fn collada_counts_are_checked_against_their_data() {
    let d = scratch("collada");
    let c = corpus();
    let r = loads(
        &d,
        "tetra.dae",
        &with_mesh(c.join("tetra.dae").to_str().unwrap(), "1 1 1", 1),
    );
    assert_eq!(r.meshes_read, 1);
    for (file, expect) in [
        (
            "count_huge.dae",
            "<float_array count=\"4294967295\"> needs 4294967295 but 12 values it holds",
        ),
        (
            "triangles_count.dae",
            "<triangles count=\"4294967295\"> needs 12884901885 but 12 indices of its <p>",
        ),
        // mesh-loader panics on it: caught at the call, a message instead.
        (
            "index_past.dae",
            "index_past.dae: reading the mesh failed inside a dependency",
        ),
    ] {
        refused(
            &d,
            file,
            &with_mesh(c.join(file).to_str().unwrap(), "1 1 1", 1),
            expect,
        );
    }
    // An input offset of 10^6: 10^6 indices per vertex announced, 12 given.
    let tetra = std::fs::read_to_string(c.join("tetra.dae")).unwrap();
    let wide = edit(&tetra, "offset=\"0\"/>", "offset=\"999999\"/>");
    std::fs::write(d.join("wide.dae"), wide).unwrap();
    let e = "<triangles count=\"4\"> needs 12000000 but 12 indices";
    refused(&d, "wide.dae", &with_mesh("wide.dae", "1 1 1", 1), e);
    // An OBJ's faces are counted before it is parsed.
    let faces = "v 0 0 0\nv 1 0 0\nv 0 1 0\n".to_string() + &"f 1 2 3\n".repeat(2_000_001);
    std::fs::write(d.join("faces.obj"), faces).unwrap();
    let e = "faces.obj: 2000001 faces, more than the 2000000";
    refused(&d, "faces.obj", &with_mesh("faces.obj", "1 1 1", 1), e);
    let deep = format!(
        "<?xml version=\"1.0\"?><COLLADA version=\"1.4.1\"><library_visual_scenes>\
         <visual_scene id=\"s\">{}{}</visual_scene></library_visual_scenes></COLLADA>",
        "<node>".repeat(100_000),
        "</node>".repeat(100_000)
    );
    std::fs::write(d.join("deep.dae"), deep).unwrap();
    refused(
        &d,
        "deep.dae",
        &with_mesh("deep.dae", "1 1 1", 1),
        "deep.dae: elements nested 65",
    );
}

#[test]
fn degenerate_meshes_are_refused_before_the_hull() {
    let d = scratch("degenerate");
    let c = corpus();
    for (file, expect) in [
        ("all_equal.stl", "all its vertices are at one point"),
        ("line.stl", "its vertices are on one line"),
        ("coplanar.stl", "its vertices are in one plane"),
    ] {
        let u = with_mesh(c.join(file).to_str().unwrap(), "1 1 1", 1);
        refused(&d, file, &u, &format!("{file}: {expect}"));
    }
    let t = c.join("tetra.stl");
    let t = t.to_str().unwrap();
    loads(&d, "a tetrahedron", &with_mesh(t, "1 1 1", 1));
    loads(
        &d,
        "a tetrahedron of 1 mm",
        &with_mesh(t, "0.01 0.01 0.01", 1),
    );
    refused(
        &d,
        "scaled to a point",
        &with_mesh(t, "1e-12 1e-12 1e-12", 1),
        "at one point",
    );
    refused(
        &d,
        "scaled flat",
        &with_mesh(t, "1 1 1e-9", 1),
        "in one plane",
    );
}

#[test]
fn a_mesh_named_by_many_collisions_is_read_and_hulled_once() {
    let d = scratch("cache");
    let t = corpus().join("tetra.stl");
    let t = t.to_str().unwrap();
    let r = loads(&d, "200 collisions", &with_mesh(t, "1 1 1", 200));
    assert_eq!(r.meshes_read, 1);
    assert_eq!(r.links[0].shapes.len(), 200);
    let two = format!(
        "{}<collision><geometry><mesh filename=\"{t}\" scale=\"2 2 2\"/></geometry></collision>",
        "<collision><geometry><mesh filename=\"TETRA\" scale=\"1 1 1\"/></geometry></collision>"
            .replace("TETRA", t)
    );
    let r = loads(&d, "two scales", &edit(&bundled(), BOX, &two));
    assert_eq!(r.meshes_read, 2);
    // A refused mesh is told once, at its first collision.
    let bad = corpus().join("all_equal.stl");
    let e = load(&d, &with_mesh(bad.to_str().unwrap(), "1 1 1", 200)).unwrap_err();
    assert_eq!(
        e.matches("all its vertices are at one point").count(),
        1,
        "{e}"
    );
    assert_eq!(e.lines().count(), urdf::MAX_REPORTED_ISSUES + 1, "{e}");
}

const SDF: &str = "<?xml version=\"1.0\"?>
<sdf version=\"1.9\"><model name=\"m\"><link name=\"base\"><pose>POSE</pose>
<inertial><mass>1</mass><inertia><ixx>0.1</ixx><iyy>0.1</iyy><izz>0.1</izz></inertia></inertial>
<collision name=\"c\"><geometry><box><size>0.5 0.3 0.1</size></box></geometry></collision>
</link></model></sdf>
";

#[test]
fn sdf_poses_are_bounded_and_a_nan_quaternion_refused() {
    let d = scratch("sdf");
    let p = d.join("robot.sdf");
    let load = |pose: &str| {
        let text = SDF.replace("<pose>POSE", &format!("<pose{pose}"));
        std::fs::write(&p, text).unwrap();
        UrdfRobot::load(&p).map_err(|i| format!("{i:?}"))
    };
    let q = " rotation_format=\"quat_xyzw\">";
    load(">99999 0 0 0 0 1e9").unwrap();
    load(&format!("{q}0 0 0 0 0 0 1")).unwrap();
    for (pose, expect) in [
        (">100001 0 0 0 0 0", "beyond the f32 engine's bounds"),
        (">0 0 0 0 0 1.1e9", "beyond the f32 engine's bounds"),
        (
            &format!("{q}0 0 0 1e308 1e308 1e308 1e308") as &str,
            "beyond the f32 engine's bounds",
        ),
        (&format!("{q}0 0 0 nan 0 0 1"), "robot.sdf"),
    ] {
        let e = load(pose).expect_err(pose);
        assert!(e.contains(expect) && e.contains("robot.sdf"), "{pose}: {e}");
    }
}
