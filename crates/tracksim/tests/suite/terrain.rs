//! Terrain descriptions compile into the surfaces they describe: heights measured by raycasts
//! against the Rapier colliders (`height_at`) match the geometry, files load in every
//! supported format, and bad inputs name the key and the file.

use glam::DVec3;
use std::path::{Path, PathBuf};
use tracksim::SpecIssue;
use tracksim::spec::TerrainSpec;
use tracksim::terrain::{TerrainModel, compile_terrain};

/// Raycasts run in f32 (Rapier) from 1 m above the highest surface: about 1e-6 m resolution
/// near the origin.
const TOL: f64 = 1e-5;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A fresh, empty folder for files written by one test.
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracksim-terrain-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn compile_in(toml_text: &str, base: &Path) -> (TerrainModel, Vec<SpecIssue>) {
    let spec: TerrainSpec = toml::from_str(toml_text).expect("terrain snippet parses");
    let mut issues = Vec::new();
    let t = compile_terrain(&spec, base, &mut issues);
    (t, issues)
}

fn compile_ok(toml_text: &str, base: &Path) -> TerrainModel {
    let (t, issues) = compile_in(toml_text, base);
    assert!(issues.is_empty(), "unexpected issues: {issues:?}");
    t
}

fn compile(toml_text: &str) -> TerrainModel {
    compile_ok(toml_text, &root().join("scenarios"))
}

/// The issues' `key: message` lines, joined.
fn errors(toml_text: &str, base: &Path) -> String {
    let (_, issues) = compile_in(toml_text, base);
    assert!(!issues.is_empty(), "expected issues for {toml_text}");
    issues
        .iter()
        .map(|i| i.to_string())
        .collect::<Vec<_>>()
        .join("\n")
}

fn assert_height(t: &TerrainModel, x: f64, y: f64, want: f64) {
    assert_height_within(t, x, y, want, TOL);
}

fn assert_height_within(t: &TerrainModel, x: f64, y: f64, want: f64, tol: f64) {
    let h = t.height_at(x, y);
    assert!(
        h.is_some_and(|h| (h - want).abs() < tol),
        "height at ({x}, {y}): got {h:?}, want {want}"
    );
}

fn write_png(path: &Path, w: u32, h: u32, depth: png::BitDepth, color: png::ColorType, d: &[u8]) {
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut enc = png::Encoder::new(file, w, h);
    enc.set_color(color);
    enc.set_depth(depth);
    let mut wr = enc.write_header().unwrap();
    wr.write_image_data(d).unwrap();
}

fn write_png16(path: &Path, w: u32, h: u32, vals: &[u16]) {
    let d: Vec<u8> = vals.iter().flat_map(|v| v.to_be_bytes()).collect();
    write_png(
        path,
        w,
        h,
        png::BitDepth::Sixteen,
        png::ColorType::Grayscale,
        &d,
    );
}

#[test]
fn staircase_treads_are_at_whole_rises() {
    let (x0, rise, run, n) = (1.0, 0.17, 0.28, 4);
    let t = compile(&format!(
        "[[staircases]]\nx_m = {x0}\nrise_m = {rise}\nrun_m = {run}\ncount = {n}\n\
         width_m = 1.0\nlanding_m = 0.5\nfriction = 0.8"
    ));
    assert_eq!(t.boxes.len(), n);
    assert!(t.boxes.iter().all(|b| b.friction == 0.8));
    for k in 1..=n {
        let centre = x0 + (k as f64 - 0.5) * run;
        assert_height(&t, centre, 0.3, k as f64 * rise);
    }
    // The landing extends the top tread by 0.5 m; beyond it and before the stairs is nothing.
    assert_height(&t, x0 + n as f64 * run + 0.45, 0.0, n as f64 * rise);
    assert_eq!(t.height_at(x0 + n as f64 * run + 0.55, 0.0), None);
    assert_eq!(t.height_at(x0 - 0.01, 0.0), None);
    assert_eq!(
        t.height_at(x0 + 0.1, 0.51),
        None,
        "1 m wide, centred on y = 0"
    );
}

#[test]
fn staircase_with_yaw_and_nosing() {
    // Climbing towards +y (yaw 90), from (2, -1) on a floor at z = 0.5, 20 mm nosings.
    let (rise, run, r) = (0.2, 0.3, 0.02f64);
    let t = compile(&format!(
        "[[staircases]]\nx_m = 2.0\ny_m = -1.0\nz_m = 0.5\nyaw_deg = 90\nrise_m = {rise}\n\
         run_m = {run}\ncount = 3\nwidth_m = 0.8\nnosing_radius_m = {r}"
    ));
    assert_eq!(t.cylinders.len(), 3);
    for k in 1..=3 {
        let front = -1.0 + (k as f64 - 1.0) * run;
        let top = 0.5 + k as f64 * rise;
        assert_height(&t, 2.0, front + 0.5 * run, top);
        // On the rounded edge, half a radius behind the riser: a circle of radius r.
        let dz = (r * r - (0.5 * r) * (0.5 * r)).sqrt();
        // (Rapier casts rays on cylinders iteratively: 0.1 mm tolerance.)
        assert_height_within(&t, 2.0, front + 0.5 * r, top - r + dz, 1e-4);
    }
    // Width 0.8 m runs along x.
    assert_eq!(t.height_at(2.41, -1.0 + 0.5 * run), None);
}

#[test]
fn incline_height_is_distance_times_tan_angle() {
    let (x0, a_deg, len) = (0.5, 20.0f64, 2.0);
    let t = compile(&format!(
        "[[inclines]]\nx_m = {x0}\nangle_deg = {a_deg}\nlength_m = {len}\nwidth_m = 1.0"
    ));
    let tan = a_deg.to_radians().tan();
    for d in [0.05, 0.5, 1.0, 1.8] {
        assert_height(&t, x0 + d, 0.2, d * tan);
    }
    assert_eq!(
        t.height_at(x0 - 0.01, 0.0),
        None,
        "no lip before the lower edge"
    );
    // Same at yaw 90 from (0, 0, 0.1): rises towards +y.
    let t = compile(&format!(
        "[[inclines]]\nx_m = 0\nz_m = 0.1\nyaw_deg = 90\nangle_deg = {a_deg}\n\
         length_m = {len}\nwidth_m = 1.0"
    ));
    assert_height(&t, 0.3, 1.0, 0.1 + tan);
}

#[test]
fn png_16bit_heights_map_to_min_max_north_up() {
    let dir = temp_dir("png16");
    // 5 columns x 4 rows; interior pixel (row 1, col 1) white, (row 2, col 3) mid grey.
    let (w, h) = (5usize, 4usize);
    let mut vals = vec![0u16; w * h];
    vals[w + 1] = 65535;
    vals[2 * w + 3] = 32768;
    vals[2 * w + 2] = 1; // one 16-bit step above black
    write_png16(&dir.join("map.png"), w as u32, h as u32, &vals);
    let (min_z, max_z) = (-0.2, 0.8);
    let t = compile_ok(
        &format!(
            "[[heightfields]]\nfile = \"map.png\"\nsize_x_m = 4.0\nsize_y_m = 3.0\n\
             min_z_m = {min_z}\nmax_z_m = {max_z}\ncentre_m = [10.0, 20.0]\nfriction = 0.9"
        ),
        &dir,
    );
    let hf = &t.heightfields[0];
    assert_eq!((hf.rows, hf.cols), (h, w));
    assert_eq!(hf.heights[0], min_z);
    assert_eq!(hf.heights[w + 1], max_z);
    assert_eq!(hf.friction, 0.9);
    // Cells are 1 m (x) by 1 m (y); row 0 is the +y edge, column 0 the -x edge.
    let at = |r: usize, c: usize| (8.0 + c as f64, 21.5 - r as f64);
    assert_eq!(hf.vertex(1, 1), DVec3::new(9.0, 20.5, max_z));
    let (x, y) = at(1, 1);
    assert_height(&t, x, y, max_z);
    let (x, y) = at(2, 3);
    assert_height(&t, x, y, min_z + (max_z - min_z) * 32768.0 / 65535.0);
    let (x, y) = at(1, 3); // mirror of the white pixel about x
    assert_height(&t, x, y, min_z);
    let (x, y) = at(2, 1); // mirror of the white pixel about y
    assert_height(&t, x, y, min_z);
    // A single 16-bit step is resolved in the compiled heights (1/65535 of 1 m ~ 15 um).
    assert!((hf.heights[2 * w + 2] - (min_z + 1.0 / 65535.0)).abs() < 1e-12);
    // Off the map: nothing.
    assert_eq!(t.height_at(5.0, 20.0), None);
    let (lo, hi) = t.bounds().unwrap();
    assert!((lo - DVec3::new(8.0, 18.5, min_z)).abs().max_element() < 1e-12);
    assert!((hi - DVec3::new(12.0, 21.5, max_z)).abs().max_element() < 1e-12);
}

#[test]
fn png_8bit_and_grey_alpha_work() {
    let dir = temp_dir("png8");
    let vals = [0u8, 0, 0, 0, 255, 51, 0, 0, 0];
    write_png(
        &dir.join("g8.png"),
        3,
        3,
        png::BitDepth::Eight,
        png::ColorType::Grayscale,
        &vals,
    );
    let ga: Vec<u8> = vals.iter().flat_map(|v| [*v, 255]).collect();
    write_png(
        &dir.join("ga8.png"),
        3,
        3,
        png::BitDepth::Eight,
        png::ColorType::GrayscaleAlpha,
        &ga,
    );
    for file in ["g8.png", "ga8.png"] {
        let t = compile_ok(
            &format!(
                "[[heightfields]]\nfile = \"{file}\"\nsize_x_m = 2.0\nsize_y_m = 2.0\n\
                 min_z_m = 0.0\nmax_z_m = 0.5"
            ),
            &dir,
        );
        assert_height(&t, 0.0, 0.0, 0.5);
        assert!(
            (t.heightfields[0].heights[5] - 0.1).abs() < 1e-12,
            "51/255 of 0.5 m"
        );
        // Halfway between the centre vertex and its neighbours: linear in between.
        assert_height(&t, -0.5, 0.0, 0.25);
    }
}

#[test]
fn bundled_png_asset_loads_at_full_range() {
    let t = compile(
        "[[heightfields]]\nfile = \"assets/bumps_128_16bit.png\"\nsize_x_m = 6.4\n\
         size_y_m = 6.4\nmin_z_m = 0.0\nmax_z_m = 0.15",
    );
    let hf = &t.heightfields[0];
    assert_eq!((hf.rows, hf.cols), (128, 128));
    let max = hf.heights.iter().cloned().fold(f64::MIN, f64::max);
    let min = hf.heights.iter().cloned().fold(f64::MAX, f64::min);
    assert_eq!((min, max), (0.0, 0.15));
    // The border is black (meets flat ground at min_z_m).
    assert!(hf.heights[..128].iter().all(|z| *z == 0.0));
    // Every vertex height is what the raycast sees (interior sample).
    let pts: Vec<(usize, usize)> = (10..118)
        .step_by(27)
        .flat_map(|r| (10..118).step_by(31).map(move |c| (r, c)))
        .collect();
    let hs = t.heights_at(
        &pts.iter()
            .map(|&(r, c)| {
                let v = hf.vertex(r, c);
                (v.x, v.y)
            })
            .collect::<Vec<_>>(),
    );
    for (&(r, c), h) in pts.iter().zip(hs) {
        let want = hf.vertex(r, c).z;
        assert!(
            h.is_some_and(|h| (h - want).abs() < TOL),
            "({r}, {c}): {h:?} vs {want}"
        );
    }
}

fn rough(seed: u64, extra: &str) -> TerrainModel {
    compile(&format!(
        "[[rough]]\nseed = {seed}\nsize_m = [4.0, 3.0]\ncell_m = 0.05\ncorrelation_m = 0.15\n\
         centre_m = [1.0, 0.0]\n{extra}"
    ))
}

#[test]
fn rough_field_is_repeatable_and_has_the_asked_amplitude() {
    let a = rough(42, "rms_height_m = 0.03");
    let b = rough(42, "rms_height_m = 0.03");
    let c = rough(43, "rms_height_m = 0.03");
    let (ha, hb, hc) = (&a.heightfields[0], &b.heightfields[0], &c.heightfields[0]);
    assert_eq!((ha.rows, ha.cols), (61, 81));
    let bits = |h: &[f64]| h.iter().map(|z| z.to_bits()).collect::<Vec<_>>();
    assert_eq!(
        bits(&ha.heights),
        bits(&hb.heights),
        "same seed: bit-identical"
    );
    let differing = ha
        .heights
        .iter()
        .zip(&hc.heights)
        .filter(|(x, y)| x != y)
        .count();
    assert!(
        differing > ha.heights.len() * 9 / 10,
        "another seed: other heights"
    );
    // rms about mean_z_m (0) is exact up to rounding (tolerance 1e-9 relative).
    let rms = |h: &[f64]| (h.iter().map(|z| z * z).sum::<f64>() / h.len() as f64).sqrt();
    assert!((rms(&ha.heights) - 0.03).abs() < 0.03 * 1e-9);
    assert!((rms(&hc.heights) - 0.03).abs() < 0.03 * 1e-9);
    // Correlated: neighbouring vertices are far closer than independent ones would be.
    let d1: f64 = ha
        .heights
        .windows(2)
        .map(|w| (w[1] - w[0]).powi(2))
        .sum::<f64>()
        / (ha.heights.len() - 1) as f64;
    assert!(
        d1.sqrt() < 0.3 * 0.03 * 2f64.sqrt(),
        "rms step {}",
        d1.sqrt()
    );
    // The collider is the grid: a raycast at an interior vertex sees its height.
    let v = ha.vertex(30, 40);
    assert_height(&a, v.x, v.y, v.z);
    assert_eq!(v.x, 1.0);
    // Peak amplitude with a tapered edge around a mean height.
    let p = rough(
        7,
        "peak_height_m = 0.05\nmean_z_m = 0.2\nedge_taper_m = 0.5",
    );
    let hp = &p.heightfields[0];
    let peak = hp
        .heights
        .iter()
        .map(|z| (z - 0.2).abs())
        .fold(0.0, f64::max);
    assert!((peak - 0.05).abs() < 1e-12);
    assert!(
        hp.heights[..hp.cols]
            .iter()
            .all(|z| (z - 0.2).abs() < 1e-12),
        "edge at mean"
    );
    // Uncorrelated (correlation 0) works too.
    let u = compile("[[rough]]\nsize_m = [1.0, 1.0]\ncorrelation_m = 0\nrms_height_m = 0.01");
    assert_eq!(u.heightfields[0].rows, 21);
}

#[test]
fn obj_asset_mesh_loads_with_right_heights() {
    let t = compile("[[meshes]]\nfile = \"assets/ramp_mound.obj\"\nfriction = 0.7");
    let m = &t.meshes[0];
    assert!(m.triangles.len() > 100 && m.triangles.len() < 500);
    assert_eq!(m.friction, 0.7);
    assert_height(&t, 1.25, 0.0, 0.2); // plateau
    assert_height(&t, 0.5, 0.2, 0.1); // half-way up the 1 m ramp
    assert_height(&t, 3.5, 0.0, 0.15); // mound apex
    let (lo, hi) = t.bounds().unwrap();
    assert!((lo.x - 0.0).abs() < 1e-9 && (hi.x - 4.1).abs() < 1e-6 && (hi.z - 0.2).abs() < 1e-9);
    // Scaled, y-up file convention off, yawed 90 and translated.
    let t = compile(
        "[[meshes]]\nfile = \"assets/ramp_mound.obj\"\nscale = 2.0\nyaw_deg = 90\n\
         translation_m = [1.0, 2.0, 0.5]",
    );
    // Plateau point (1.25, 0, 0.2) -> scaled (2.5, 0, 0.4) -> yawed (0, 2.5, 0.4) -> + t.
    assert_height(&t, 1.0, 4.5, 0.9);
}

/// A 1 m square at z = 0.3 (two triangles) with a y-up variant.
fn square_tris() -> Vec<[[f32; 3]; 3]> {
    vec![
        [[0.0, 0.0, 0.3], [1.0, 0.0, 0.3], [1.0, 1.0, 0.3]],
        [[0.0, 0.0, 0.3], [1.0, 1.0, 0.3], [0.0, 1.0, 0.3]],
    ]
}

#[test]
fn stl_binary_and_ascii_load() {
    let dir = temp_dir("stl");
    let tris = square_tris();
    let mut bin = vec![0u8; 80];
    bin.extend((tris.len() as u32).to_le_bytes());
    for t in &tris {
        bin.extend([0u8; 12]); // normal (ignored)
        for v in t {
            for c in v {
                bin.extend(c.to_le_bytes());
            }
        }
        bin.extend([0u8; 2]);
    }
    std::fs::write(dir.join("sq.stl"), &bin).unwrap();
    let mut ascii = String::from("solid square\n");
    for t in &tris {
        ascii += "facet normal 0 0 1\n outer loop\n";
        for v in t {
            ascii += &format!("  vertex {} {} {}\n", v[0], v[1], v[2]);
        }
        ascii += " endloop\nendfacet\n";
    }
    ascii += "endsolid square\n";
    std::fs::write(dir.join("sq_ascii.STL"), ascii).unwrap();
    for file in ["sq.stl", "sq_ascii.STL"] {
        let t = compile_ok(&format!("[[meshes]]\nfile = \"{file}\""), &dir);
        assert_eq!(t.meshes[0].triangles.len(), 2, "{file}");
        assert_height(&t, 0.3, 0.6, 0.3);
        assert_height(&t, 0.7, 0.2, 0.3);
        assert_eq!(t.height_at(1.2, 0.5), None);
    }
    // up_axis = "y": file +y becomes +z.
    let obj = "v 0 0.3 0\nv 1 0.3 0\nv 1 0.3 -1\nv 0 0.3 -1\nf 1 2 3 4\n";
    std::fs::write(dir.join("yup.obj"), obj).unwrap();
    let t = compile_ok("[[meshes]]\nfile = \"yup.obj\"\nup_axis = \"y\"", &dir);
    assert_height(&t, 0.5, 0.5, 0.3);
}

#[test]
fn stepfield_posts_are_whole_steps() {
    // Row 0 is the +y row, column 0 the entry (-x) column; 0 leaves the floor bare.
    let t = compile(
        "[ground]\nz_m = -1.0\n[[stepfields]]\nx_m = 1.0\npattern = [[1, 2], [3, 0]]\n\
         step_m = 0.15",
    );
    assert_eq!(t.boxes.len(), 3);
    assert_height(&t, 1.05, 0.05, 0.15);
    assert_height(&t, 1.15, 0.05, 0.30);
    assert_height(&t, 1.05, -0.05, 0.45);
    assert_height(&t, 1.15, -0.05, -1.0);
    // Default: a 12 x 12 symmetric hill of 1..4 steps of 0.1 m posts 0.1 m wide.
    let t = compile("[[stepfields]]\nx_m = 0.0\nyaw_deg = 0");
    assert_eq!(t.boxes.len(), 144);
    assert_height(&t, 0.55, 0.05, 0.4); // centre
    assert_height(&t, 0.05, 0.55, 0.1); // corner
    assert_height(&t, 1.15, -0.55, 0.1); // opposite corner
    let (lo, hi) = t.bounds().unwrap();
    assert!((lo - DVec3::new(0.0, -0.6, 0.0)).abs().max_element() < 1e-12);
    assert!((hi - DVec3::new(1.2, 0.6, 0.4)).abs().max_element() < 1e-12);
    // Seeded random: repeatable, heights 1..=max_steps.
    let spec = "[[stepfields]]\nx_m = 0.0\nseed = 5\nrows = 6\ncolumns = 8\nmax_steps = 3";
    let (a, b) = (compile(spec), compile(spec));
    assert_eq!(a.boxes.len(), 48);
    let tops = |t: &TerrainModel| t.boxes.iter().map(|b| 2.0 * b.half.z).collect::<Vec<_>>();
    assert_eq!(tops(&a), tops(&b));
    let steps: Vec<i64> = tops(&a).iter().map(|h| (h / 0.1).round() as i64).collect();
    assert!(steps.iter().all(|s| (1..=3).contains(s)));
    assert!(
        (1..=3).all(|k| steps.contains(&k)),
        "all heights used: {steps:?}"
    );
}

#[test]
fn pitch_and_roll_ramps_slope_at_their_angle() {
    let tan = 15f64.to_radians().tan();
    let p = 1.2;
    let t = compile("[[pitch_roll_ramps]]\nx_m = 2.0\norientation = \"pitch\"");
    assert_eq!(t.boxes.len(), 4);
    assert_height(&t, 2.0 + 0.25 * p, 0.0, 0.25 * p * tan); // panel 0 rises
    assert_height(&t, 2.0 + 0.99 * p, 1.0, 0.99 * p * tan);
    assert_height(&t, 2.0 + 1.25 * p, -1.0, 0.75 * p * tan); // panel 1 falls
    assert_height(&t, 2.0 + 2.5 * p, 0.0, 0.5 * p * tan);
    assert_eq!(t.height_at(2.0 + 0.5 * p, 1.25), None, "2 lanes of 1.2 m");
    // Roll: lanes slope across; lane 0 (+y side) rises towards +y from a valley at y = 0.
    let t = compile(
        "[[pitch_roll_ramps]]\nx_m = 0.0\norientation = \"roll\"\nangle_deg = 10\n\
         panel_m = 1.0\ncount = 3\nlanes = 2",
    );
    let tan10 = 10f64.to_radians().tan();
    assert_eq!(t.boxes.len(), 2);
    assert_height(&t, 1.5, 0.75, 0.75 * tan10);
    assert_height(&t, 0.2, -0.25, 0.25 * tan10);
    assert_height(&t, 2.9, -0.9, 0.9 * tan10);
}

#[test]
fn hurdle_and_gap_have_their_heights() {
    let t = compile(
        "[[hurdles]]\nx_m = 1.0\nheight_m = 0.3\nthickness_m = 0.2\n\
         [[gaps]]\nx_m = 5.0\ngap_width_m = 0.4\nheight_m = 0.25\nz_m = 0.1",
    );
    assert_height(&t, 1.1, 0.0, 0.3);
    assert_height(&t, 1.1, 0.55, 0.3);
    assert_eq!(t.height_at(1.25, 0.0), None);
    assert_eq!(t.height_at(0.95, 0.0), None);
    assert_height(&t, 4.5, 0.0, 0.35);
    assert_eq!(t.height_at(5.2, 0.0), None, "the gap");
    assert_height(&t, 5.45, 0.0, 0.35);
    assert_height(&t, 6.55, 0.0, 0.35);
    assert_eq!(t.height_at(6.65, 0.0), None, "1.2 m platforms");
    let (lo, hi) = t.bounds().unwrap();
    assert!((lo - DVec3::new(1.0, -0.6, 0.0)).abs().max_element() < 1e-12);
    assert!((hi - DVec3::new(6.6, 0.6, 0.35)).abs().max_element() < 1e-12);
}

#[test]
fn everything_combines_and_ground_makes_bounds_infinite() {
    let t = compile(
        "[ground]\nfriction = 0.5\n\
         [[boxes]]\ncentre_m = [0, 0, 0.05]\nsize_m = [1, 1, 0.1]\n\
         [[staircases]]\nx_m = 3\nrise_m = 0.1\nrun_m = 0.3\ncount = 2\nwidth_m = 1\n\
         [[inclines]]\nx_m = -3\nangle_deg = 10\nlength_m = 1\nwidth_m = 1\n\
         [[rough]]\ncentre_m = [0, 5]\nsize_m = [2, 2]\nrms_height_m = 0.02\n\
         [[heightfields]]\nfile = \"assets/bumps_128_16bit.png\"\ncentre_m = [0, -8]\n\
         size_x_m = 6.4\nsize_y_m = 6.4\nmin_z_m = 0\nmax_z_m = 0.15\n\
         [[meshes]]\nfile = \"assets/ramp_mound.obj\"\ntranslation_m = [10, 0, 0]\n\
         [[stepfields]]\nx_m = 15\n[[pitch_roll_ramps]]\nx_m = 20\n\
         [[hurdles]]\nx_m = 27\nheight_m = 0.2\n[[gaps]]\nx_m = 30\ngap_width_m = 0.3\nheight_m = 0.2",
    );
    assert_eq!(t.bounds(), None);
    assert_eq!(t.heightfields.len(), 2);
    let hs = t.heights_at(&[
        (0.0, 0.0),
        (3.15, 0.0),
        (11.25, 0.0),
        (27.05, 0.0),
        (40.0, 40.0),
    ]);
    let want = [0.1, 0.1, 0.2, 0.2, 0.0];
    for (h, w) in hs.iter().zip(want) {
        assert!(h.is_some_and(|h| (h - w).abs() < TOL), "{hs:?}");
    }
}

#[test]
fn bad_files_name_the_key_and_the_file() {
    let dir = temp_dir("bad");
    std::fs::write(dir.join("garbage.png"), b"this is not a png").unwrap();
    std::fs::write(dir.join("empty.obj"), "# only vertices\nv 0 0 0\nv 1 0 0\n").unwrap();
    std::fs::write(dir.join("flat.obj"), "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap();
    std::fs::write(dir.join("bad.obj"), "v 0 0 0\nf 1 2 3\n").unwrap();
    std::fs::write(dir.join("model.ply"), "ply\n").unwrap();
    std::fs::write(dir.join("junk.stl"), [0xffu8, 0xfe, 0x00, 0x01]).unwrap();
    write_png(
        &dir.join("rgb.png"),
        2,
        2,
        png::BitDepth::Eight,
        png::ColorType::Rgb,
        &[0; 12],
    );
    let hf = |file: &str| {
        format!(
            "[[heightfields]]\nfile = \"{file}\"\nsize_x_m = 1\nsize_y_m = 1\nmin_z_m = 0\n\
             max_z_m = 1"
        )
    };
    let cases = [
        (
            hf("garbage.png"),
            "terrain.heightfields[0].file",
            "garbage.png",
            "not a readable PNG",
        ),
        (
            hf("missing.png"),
            "terrain.heightfields[0].file",
            "missing.png",
            "cannot read",
        ),
        (
            hf("rgb.png"),
            "terrain.heightfields[0].file",
            "rgb.png",
            "greyscale",
        ),
        (
            "[[meshes]]\nfile = \"empty.obj\"".into(),
            "terrain.meshes[0].file",
            "empty.obj",
            "no triangles",
        ),
        (
            "[[meshes]]\nfile = \"flat.obj\"".into(),
            "terrain.meshes[0].file",
            "flat.obj",
            "no triangles",
        ),
        (
            "[[meshes]]\nfile = \"bad.obj\"".into(),
            "terrain.meshes[0].file",
            "bad.obj",
            "line 2",
        ),
        (
            "[[meshes]]\nfile = \"model.ply\"".into(),
            "terrain.meshes[0].file",
            "model.ply",
            ".stl",
        ),
        (
            "[[meshes]]\nfile = \"junk.stl\"".into(),
            "terrain.meshes[0].file",
            "junk.stl",
            "STL",
        ),
        (
            "[[meshes]]\nfile = \"gone.stl\"".into(),
            "terrain.meshes[0].file",
            "gone.stl",
            "cannot read",
        ),
    ];
    for (spec, key, file, what) in cases {
        let e = errors(&spec, &dir);
        assert!(e.contains(&format!("{key}: ")), "{e}");
        assert!(e.contains(&dir.join(file).display().to_string()), "{e}");
        assert!(e.contains(what), "{e}");
        assert!(!e.contains("nothing to drive on"), "{e}");
    }
}

#[test]
fn bad_values_name_the_key() {
    let base = root().join("scenarios");
    let cases = [
        (
            "[[staircases]]\nx_m = 0\nrise_m = -0.1\nrun_m = 0.3\ncount = 2\nwidth_m = 1",
            "terrain.staircases[0].rise_m: must be a finite number > 0 m, got -0.1",
        ),
        (
            "[[staircases]]\nx_m = nan\nrise_m = 0.1\nrun_m = 0.3\ncount = 0\nwidth_m = 1",
            "terrain.staircases[0].x_m: must be finite numbers, got [NaN]",
        ),
        (
            "[[staircases]]\nx_m = 0\nrise_m = 0.1\nrun_m = 0.3\ncount = 0\nwidth_m = 1",
            "terrain.staircases[0].count: must be a whole number from 1",
        ),
        (
            "[[staircases]]\nx_m = 0\nrise_m = 0.1\nrun_m = 0.3\ncount = 2\nwidth_m = 1\n\
             nosing_radius_m = 0.2",
            "terrain.staircases[0].nosing_radius_m: must not exceed",
        ),
        (
            "[[inclines]]\nx_m = 0\nangle_deg = 95\nlength_m = 1\nwidth_m = 1",
            "terrain.inclines[0].angle_deg: must be a finite angle",
        ),
        (
            "[[inclines]]\nx_m = 0\nangle_deg = 10\nlength_m = nan\nwidth_m = 1",
            "terrain.inclines[0].length_m: must be a finite number > 0 m, got NaN",
        ),
        (
            "[[heightfields]]\nfile = \"assets/bumps_128_16bit.png\"\nsize_x_m = -1\n\
             size_y_m = 1\nmin_z_m = 0\nmax_z_m = 1",
            "terrain.heightfields[0].size_x_m: must be a finite number > 0 m, got -1",
        ),
        (
            "[[heightfields]]\nfile = \"assets/bumps_128_16bit.png\"\nsize_x_m = 1\n\
             size_y_m = 1\nmin_z_m = 1\nmax_z_m = 0",
            "terrain.heightfields[0].max_z_m: must be >= min_z_m",
        ),
        (
            "[[rough]]\nsize_m = [1, -2]\nrms_height_m = 0.1",
            "terrain.rough[0].size_m[1]: must be a finite number > 0 m, got -2",
        ),
        (
            "[[rough]]\nsize_m = [1, 1]\nrms_height_m = 0.1\npeak_height_m = 0.2",
            "terrain.rough[0]: give exactly one of rms_height_m",
        ),
        (
            "[[rough]]\nsize_m = [100, 100]\ncell_m = 0.001\nrms_height_m = 0.1",
            "terrain.rough[0]: the grid would need",
        ),
        (
            "[[meshes]]\nfile = \"assets/ramp_mound.obj\"\nscale = 0",
            "terrain.meshes[0].scale: must be a finite number > 0",
        ),
        (
            "[[stepfields]]\nx_m = 0\npattern = [[1, 2], [3]]",
            "terrain.stepfields[0].pattern[1]: has 1 entries but row 0 has 2",
        ),
        (
            "[[stepfields]]\nx_m = 0\npattern = [[1]]\nseed = 3",
            "terrain.stepfields[0].seed: give either pattern or seed",
        ),
        (
            "[[pitch_roll_ramps]]\nx_m = 0\nlanes = 0",
            "terrain.pitch_roll_ramps[0].lanes: must be a whole number from 1",
        ),
        (
            "[[hurdles]]\nx_m = 0\nheight_m = 0",
            "terrain.hurdles[0].height_m: must be a finite number > 0 m, got 0",
        ),
        (
            "[[gaps]]\nx_m = 0\nheight_m = 0.2\ngap_width_m = -0.3",
            "terrain.gaps[0].gap_width_m: must be a finite number > 0 m, got -0.3",
        ),
        ("", "terrain: nothing to drive on"),
    ];
    for (spec, want) in cases {
        let e = errors(spec, &base);
        assert!(e.contains(want), "want {want:?} in:\n{e}");
    }
    // Unknown keys and wrong enum values are parse errors.
    assert!(toml::from_str::<TerrainSpec>("[[hurdles]]\nx_m = 0\nheight_m = 0.1\nh = 1").is_err());
    assert!(
        toml::from_str::<TerrainSpec>("[[pitch_roll_ramps]]\nx_m = 0\norientation = \"yaw\"")
            .is_err()
    );
}
