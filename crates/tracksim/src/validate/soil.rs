//! Deformable soil against terramechanics (issue 30; docs/SOIL.md), PackBot 510 with 40
//! grousers per track on the soils of `terrain::soil::PRESETS`:
//!
//! - **static sinkage** (`soil/static/<preset>`): standing still, the tracks' mean sinkage
//!   against Bekker's `z = (W / (A (k_c / b + k_phi)))^(1/n)` with the load W and the contact
//!   area A the run measured;
//! - **drawbar pull against slip** (`soil/drawbar/<pull>N`): constant pulls on dry sand, the
//!   steady slip, and the pull against Wong's `F = (A c + W tan phi)(1 - K/(s l)(1 - e^(-s l /
//!   K)))` minus Bekker's compaction resistance, at the measured s, A, W and l;
//! - **grousers raise thrust** (`soil/smooth_belt`): the same pull with the belts without
//!   grousers, which shear at the belt-soil interface (`W tan delta`);
//! - **slope limit** (`soil/slope/<deg>deg`): lunar regolith, whose cohesion lets a track climb
//!   where Coulomb friction (0.6) would not: the steepest slope climbed against `W sin(theta) =
//!   A c + W cos(theta) tan(phi)`;
//! - **multi-pass sinkage** (`soil/multipass`): on snow, forward over fresh soil and back over
//!   the rut: the second pass sinks no deeper than the first (Bekker's memory: only the elastic
//!   `p / K_e` is added).

use super::compile::compile;
use super::jobs::{Jobs, Runs, pose_at};
use super::options::SolverSetting;
use super::report::{Case, ValidationReport};
use crate::error::Result;
use crate::model::{Scenario, VehicleModel};
use crate::run::RunResult;
use crate::terrain::SoilModel;
use std::path::Path;

/// Soils of the static sinkage case: those on which PackBot's grousers embed (their tips sink
/// their 8 mm height under the robot's weight).
const STATIC_PRESETS: [&str; 3] = ["dry_sand", "lunar_regolith", "snow"];
/// Speed of the sinkage case, m/s: slow, so fresh soil is loaded as the track rolls onto it.
const SINKAGE_SPEED_MPS: f64 = 0.1;
/// The sinkage case's window, s: from when the tracks have left the landing rut (0.69 m long
/// tracks at 0.1 m/s) to the end.
const SINKAGE_WINDOW_S: (f64, f64) = (8.0, 10.0);
/// Drawbar pulls of the pull-slip case, as fractions of the dry sand's Mohr-Coulomb limit.
const PULL_FRACTIONS: [f64; 6] = [0.5, 0.65, 0.8, 0.88, 0.93, 0.96];
/// Settling before the measurement windows, s.
const SETTLE_S: f64 = 3.0;
/// Measurement window, s.
const MEASURE_S: f64 = 3.0;
/// Slopes tried on lunar regolith, degrees.
const SLOPES_DEG: [f64; 7] = [32.0, 36.0, 38.0, 40.0, 42.0, 44.0, 46.0];
/// Allowed relative error of the static sinkage.
const SINKAGE_TOLERANCE: f64 = 0.15;
/// Allowed relative error of the drawbar pull against Wong's closed form.
const PULL_TOLERANCE: f64 = 0.15;
/// Allowed distance of the steepest slope climbed from the closed form, degrees.
const SLOPE_TOLERANCE_DEG: f64 = 4.0;
/// The contact area of the pulls' nominal Mohr-Coulomb limit, m^2: two tracks 0.075 m wide
/// loading 0.59 m of ground (the 0.51 m between the axles and the pulleys' grousers within
/// the sinkage, as the runs measure).
const NOMINAL_AREA_M2: f64 = 2.0 * 0.59 * 0.075;

/// The PackBot scenario text on soil `preset`, with `extra` appended.
fn text(preset: &str, method: &str, duration: f64, body: &str) -> String {
    format!(
        r#"
description = "PackBot 510 on {preset}"
[vehicle]
file = "../vehicles/packbot510.toml"
[terrain.ground]
[terrain.ground.soil]
preset = "{preset}"
[simulation]
duration_s = {duration}
method = "{method}"
[outcome]
fail_off_terrain = false
max_tilt_deg = 89.0
{body}
"#
    )
}

/// A preset by name (the names here are the presets').
fn soil(preset: &str) -> SoilModel {
    crate::terrain::soil::preset(preset).expect("a preset name")
}

/// PackBot's weight, N.
fn weight(packbot: &VehicleModel) -> f64 {
    let belts: f64 = packbot.tracks.iter().map(|t| t.belt_mass).sum();
    (packbot.body.mass + belts) * 9.81
}

/// Adds every soil run.
pub(super) fn add_jobs(
    jobs: &mut Jobs,
    packbot: &VehicleModel,
    root: &Path,
    setting: SolverSetting,
) -> Result<()> {
    let add = |jobs: &mut Jobs, name: String, t: String| -> Result<()> {
        jobs.add(name, compile(&t, packbot.clone(), root, setting)?)
    };
    let drive = "[[commands]]\nt_s = 0.0\nbelt_speed_mps = 0.3\n";
    let slow = format!("[[commands]]\nt_s = 0.0\nbelt_speed_mps = {SINKAGE_SPEED_MPS}\n");
    for preset in STATIC_PRESETS {
        add(
            jobs,
            format!("soil/static/{preset}"),
            text(preset, "okada2020", SINKAGE_WINDOW_S.1, &slow),
        )?;
    }
    let sand = soil("dry_sand");
    let f_max = NOMINAL_AREA_M2 * sand.cohesion + weight(packbot) * sand.phi.tan();
    for frac in PULL_FRACTIONS {
        let pull = (frac * f_max).round();
        let body = format!("[drawbar]\npull_n = {pull}\nstart_s = 0.5\nramp_s = 1.5\n{drive}");
        let d = SETTLE_S + MEASURE_S;
        add(
            jobs,
            format!("soil/drawbar/{pull:.0}N"),
            text("dry_sand", "okada2020", d, &body),
        )?;
    }
    let smooth_pull = smooth_pull(packbot, &sand);
    let body = format!("[drawbar]\npull_n = {smooth_pull}\nstart_s = 0.5\nramp_s = 1.5\n{drive}");
    for (name, method) in [
        ("soil/smooth_belt", "okada2020_no_grousers"),
        ("soil/grousers", "okada2020"),
    ] {
        add(
            jobs,
            name.into(),
            text("dry_sand", method, SETTLE_S + MEASURE_S, &body),
        )?;
    }
    for deg in SLOPES_DEG {
        jobs.add(
            format!("soil/slope/{deg:.0}deg"),
            slope_scenario(packbot, deg, root, setting)?,
        )?;
    }
    let body = "[[commands]]\nt_s = 0.0\nbelt_speed_mps = 0.3\n[[commands]]\nt_s = 6.0\nbelt_speed_mps = -0.3\n";
    add(
        jobs,
        "soil/multipass".into(),
        text("snow", "okada2020", 9.0, body),
    )?;
    Ok(())
}

/// The pull of the smooth-belt case: 1.5 times what a smooth belt can shear (`W tan delta`).
fn smooth_pull(packbot: &VehicleModel, sand: &SoilModel) -> f64 {
    (1.5 * weight(packbot) * sand.interface_phi.tan()).round()
}

/// PackBot on a plate of lunar regolith inclined at `deg` (surface through the origin), the
/// rigid slope case's plate with a soil.
fn slope_scenario(
    packbot: &VehicleModel,
    deg: f64,
    root: &Path,
    setting: SolverSetting,
) -> Result<Scenario> {
    let soil = "[terrain.boxes.soil]\npreset = \"lunar_regolith\"";
    let t = super::slope::plate_text(
        deg,
        0.6,
        crate::model::Method::Okada2020,
        SETTLE_S + MEASURE_S,
        soil,
    );
    compile(&t, packbot.clone(), root, setting)
}

/// Means over the samples in [t0, t1]: slip, pull, thrust, contact area, contact length (per
/// track), normal load, sinkage, compaction resistance.
#[derive(Clone, Copy, Debug, Default)]
struct Window {
    slip: f64,
    pull: f64,
    thrust: f64,
    area: f64,
    length: f64,
    normal: f64,
    sinkage: f64,
    compaction: f64,
}

fn window(r: &RunResult, t0: f64, t1: f64) -> Window {
    let mut w = Window::default();
    let mut n = 0.0;
    for s in r.samples.iter().filter(|s| s.t >= t0 && s.t <= t1) {
        let k = s.soil.len().max(1) as f64;
        w.slip += s.slip.iter().sum::<f64>() / s.slip.len().max(1) as f64;
        w.pull += s.drawbar_n.unwrap_or(0.0);
        w.thrust += s.soil.iter().map(|g| g.thrust_n).sum::<f64>();
        w.area += s.soil.iter().map(|g| g.contact_area_m2).sum::<f64>();
        w.length += s.soil.iter().map(|g| g.contact_length_m).sum::<f64>() / k;
        w.normal += s.soil.iter().map(|g| g.normal_n).sum::<f64>();
        w.sinkage += s.soil.iter().map(|g| g.sinkage_m).sum::<f64>() / k;
        w.compaction += s.soil.iter().map(|g| g.compaction_n).sum::<f64>();
        n += 1.0;
    }
    if n > 0.0 {
        for v in [
            &mut w.slip,
            &mut w.pull,
            &mut w.thrust,
            &mut w.area,
            &mut w.length,
            &mut w.normal,
            &mut w.sinkage,
            &mut w.compaction,
        ] {
            *v /= n;
        }
    }
    w
}

/// Fills the soil cases.
pub(super) fn assemble(report: &mut ValidationReport, runs: &mut Runs, packbot: &VehicleModel) {
    report.cases.push(static_case(runs));
    report.cases.push(drawbar_case(runs, packbot));
    report.cases.push(grouser_case(runs, packbot));
    report.cases.push(slope_case(runs));
    report.cases.push(multipass_case(runs));
}

fn case(name: &str, runs: Vec<String>) -> Case {
    Case {
        group: "soil".into(),
        name: name.into(),
        runs,
        outcome: String::new(),
        measured: String::new(),
        expected: String::new(),
        passed: false,
        note: String::new(),
        plot: String::new(),
    }
}

fn static_case(runs: &mut Runs) -> Case {
    let names: Vec<String> = STATIC_PRESETS
        .iter()
        .map(|p| format!("soil/static/{p}"))
        .collect();
    let mut c = case("Sinkage under the track's weight (Bekker)", names.clone());
    let mut ok = true;
    let mut measured = Vec::new();
    for (name, preset) in names.iter().zip(STATIC_PRESETS) {
        match runs.take(name).result {
            Ok(r) => {
                let w = window(&r, SINKAGE_WINDOW_S.0, SINKAGE_WINDOW_S.1);
                let s = soil(preset);
                let b = 0.075;
                let z = s.sinkage(w.normal / w.area.max(1e-9), b);
                let err = (w.sinkage - z).abs() / z;
                ok &= err <= SINKAGE_TOLERANCE;
                measured.push(format!(
                    "{preset}: {:.2} mm against {:.2} mm ({:+.0} %; W {:.0} N on {:.4} m^2)",
                    w.sinkage * 1e3,
                    z * 1e3,
                    100.0 * (w.sinkage - z) / z,
                    w.normal,
                    w.area
                ));
            }
            Err(e) => {
                ok = false;
                measured.push(format!("{preset}: {e}"));
            }
        }
    }
    c.outcome = format!("driving at {SINKAGE_SPEED_MPS} m/s onto fresh soil");
    c.measured = measured.join("; ");
    c.expected = format!(
        "within {:.0} % of Bekker's sinkage",
        SINKAGE_TOLERANCE * 100.0
    );
    c.passed = ok;
    c.note = format!(
        "PackBot drives slowly ({SINKAGE_SPEED_MPS} m/s) so that the soil under the tracks is loaded gradually, as the track rolls onto it: the tracks' mean sinkage (belt level, load-weighted over the loaded patches) over {}-{} s, after the tracks have left the rut of the landing (standing still keeps the plastic sinkage of the landing's peak load, as real soil does), against Bekker's z = (p / (k_c / b + k_phi))^(1/n), p = W / A with the soil's normal load W and the loaded patches' area A the run measured, b = 0.075 m (the track width). The soils are those on which PackBot's grousers embed. Tolerance: the pressure fluctuates by a few per cent as the grousers roll on and off the pulleys, and a ratchet keeps the largest.",
        SINKAGE_WINDOW_S.0, SINKAGE_WINDOW_S.1
    );
    c
}

/// Wong's thrust minus compaction resistance for a window, N.
fn wong(s: &SoilModel, w: &Window) -> f64 {
    let tracks = 2.0;
    let per_track = s.wong_thrust(
        w.area / tracks,
        w.normal / tracks,
        w.length,
        w.slip.max(1e-6),
    );
    tracks * (per_track - s.compaction_resistance(0.075, w.sinkage))
}

fn drawbar_case(runs: &mut Runs, packbot: &VehicleModel) -> Case {
    let sand = soil("dry_sand");
    let f_max = NOMINAL_AREA_M2 * sand.cohesion + weight(packbot) * sand.phi.tan();
    let names: Vec<String> = PULL_FRACTIONS
        .iter()
        .map(|f| format!("soil/drawbar/{:.0}N", (f * f_max).round()))
        .collect();
    let mut c = case("Drawbar pull against slip (Wong)", names.clone());
    let mut ok = true;
    let mut asserted = 0;
    let mut measured = Vec::new();
    for name in &names {
        match runs.take(name).result {
            Ok(r) => {
                let w = window(&r, SETTLE_S, SETTLE_S + MEASURE_S);
                let f = wong(&sand, &w);
                let err = (w.pull - f) / f;
                let in_range = (0.05..=0.8).contains(&w.slip);
                if in_range {
                    asserted += 1;
                    ok &= err.abs() <= PULL_TOLERANCE;
                }
                measured.push(format!(
                    "pull {:.0} N at slip {:.3}{}: Wong {:.0} N ({:+.0} %)",
                    w.pull,
                    w.slip,
                    if in_range { "" } else { " (outside 0.05-0.8)" },
                    f,
                    100.0 * err
                ));
            }
            Err(e) => {
                ok = false;
                measured.push(format!("{name}: {e}"));
            }
        }
    }
    c.outcome = format!(
        "{} constant pulls, {asserted} at slips 0.05-0.8",
        names.len()
    );
    c.measured = measured.join("; ");
    ok &= asserted >= 4;
    c.expected = format!(
        "at least 4 points at slips 0.05-0.8, each pull within {:.0} % of Wong's thrust minus compaction resistance at the measured slip",
        PULL_TOLERANCE * 100.0
    );
    c.passed = ok;
    c.note = format!(
        "Dry sand (Wong: c = {:.2} kPa, phi = {:.0} deg, K = {} m). PackBot drives at 0.3 m/s against a constant horizontal pull; over {SETTLE_S}-{} s the mean pull and slip give one point of the curve, compared with F = (A c + W tan phi)(1 - K/(s l)(1 - exp(-s l / K))) - b k z^(n+1)/(n+1) per track at the measured slip s, contact area A, load W, contact length l and sinkage z. Tolerance: the simulation accumulates the shear displacement per patch of ground (j = s x / (1 - s)) where Wong counts it per track element (j = s x), the patches are one grouser pitch (39 mm, against K = 25 mm) and the pulleys' grousers enter the soil over a few centimetres.",
        sand.cohesion / 1e3,
        sand.phi.to_degrees(),
        sand.shear_k,
        SETTLE_S + MEASURE_S
    );
    c
}

fn grouser_case(runs: &mut Runs, packbot: &VehicleModel) -> Case {
    let sand = soil("dry_sand");
    let pull = smooth_pull(packbot, &sand);
    let mut c = case(
        "Grousers raise thrust on loose sand",
        vec!["soil/smooth_belt".into(), "soil/grousers".into()],
    );
    let smooth = runs.take("soil/smooth_belt").result;
    let grousers = runs.take("soil/grousers").result;
    match (smooth, grousers) {
        (Ok(s), Ok(g)) => {
            let (ws, wg) = (
                window(&s, SETTLE_S, SETTLE_S + MEASURE_S),
                window(&g, SETTLE_S, SETTLE_S + MEASURE_S),
            );
            let limit = ws.normal * sand.interface_phi.tan();
            let (vs, vg) = (progress(&s), progress(&g));
            c.passed =
                vs < 0.05 && vg > 0.2 && wg.slip < 0.3 && (ws.thrust - limit).abs() <= 0.15 * limit;
            c.measured = format!(
                "pull {pull:.0} N: without grousers {vs:+.3} m/s forwards (thrust {:.1} N, limit W tan delta {limit:.1} N); with grousers {vg:+.3} m/s at slip {:.3}",
                ws.thrust, wg.slip
            );
        }
        (a, b) => {
            c.measured = format!(
                "{:?} / {:?}",
                a.err().map(|e| e.to_string()),
                b.err().map(|e| e.to_string())
            );
        }
    }
    c.outcome = "two runs".into();
    c.expected = "without grousers the belt shears at the interface and cannot pull (its thrust is W tan delta within 15 %); with grousers it drives on (slip < 0.3)".into();
    c.note = format!(
        "Dry sand; pull 1.5 W tan delta, delta = 2/3 phi = {:.1} deg. Without grousers (`okada2020_no_grousers`) the belt slides on the sand at the interface friction angle and has no cohesion (Wong's smooth track); with grousers the soil between them moves with the belt and shears at the grousers' tips with c and phi.",
        sand.interface_phi.to_degrees()
    );
    c
}

/// Mean forward speed over the measurement window, m/s.
fn progress(r: &RunResult) -> f64 {
    let p1 = pose_at(r, SETTLE_S);
    let p2 = pose_at(r, SETTLE_S + MEASURE_S);
    (p2.x - p1.x) / MEASURE_S
}

fn slope_case(runs: &mut Runs) -> Case {
    let names: Vec<String> = SLOPES_DEG
        .iter()
        .map(|d| format!("soil/slope/{d:.0}deg"))
        .collect();
    let mut c = case("Slope limit on lunar regolith", names.clone());
    let regolith = soil("lunar_regolith");
    let mut climbed = Vec::new();
    let mut area_load = Vec::new();
    let mut words = Vec::new();
    for (name, deg) in names.iter().zip(SLOPES_DEG) {
        match runs.take(name).result {
            Ok(r) => {
                let th = deg.to_radians();
                let p1 = pose_at(&r, SETTLE_S);
                let p2 = pose_at(&r, SETTLE_S + MEASURE_S);
                let along = ((p2.x - p1.x) * th.cos() + (p2.z - p1.z) * th.sin()) / MEASURE_S;
                let w = window(&r, SETTLE_S, SETTLE_S + MEASURE_S);
                let up = along >= 0.05;
                if up && w.area > 0.0 {
                    area_load.push(w.area);
                }
                if up {
                    climbed.push(deg);
                }
                words.push(format!("{deg:.0} deg {along:+.2} m/s"));
            }
            Err(e) => words.push(format!("{deg:.0} deg: {e}")),
        }
    }
    let area = area_load.iter().sum::<f64>() / area_load.len().max(1) as f64;
    // W sin(t) = A c + W cos(t) tan(phi), W the weight.
    let w = 127.5;
    let limit = (0..9000)
        .map(|i| i as f64 * 0.01)
        .find(|d| {
            let t = d.to_radians();
            w * t.sin() > area * regolith.cohesion + w * t.cos() * regolith.phi.tan()
        })
        .unwrap_or(90.0);
    let highest = climbed.iter().copied().fold(f64::NAN, f64::max);
    c.passed = highest.is_finite() && (highest - limit).abs() <= SLOPE_TOLERANCE_DEG;
    c.outcome = format!("climbed {} of {}", climbed.len(), SLOPES_DEG.len());
    c.measured = format!("steepest climbed {highest:.0} deg ({})", words.join(", "));
    c.expected = format!(
        "within {SLOPE_TOLERANCE_DEG:.0} deg of the Mohr-Coulomb limit {limit:.1} deg (A = {area:.3} m^2), where Coulomb friction 0.6 would stop at 31 deg"
    );
    c.note = "Lunar regolith (c = 0.17 kPa, phi = 35 deg) on a plate at each slope, PackBot driving uphill at 0.3 m/s; climbed: at least 0.05 m/s up the slope over 3-6 s. The limit solves W sin(theta) = A c + W cos(theta) tan(phi) with the contact area A the climbing runs measured (full mobilisation; the simulation climbs at finite slip, where Janosi's law mobilises less, and its tracks sink more at the rear, hence a limit a few degrees lower is expected).".into();
    c
}

fn multipass_case(runs: &mut Runs) -> Case {
    let mut c = case("Multi-pass sinkage (snow)", vec!["soil/multipass".into()]);
    match runs.take("soil/multipass").result {
        Ok(r) => {
            let first = window(&r, 4.0, 5.0);
            let second = window(&r, 7.5, 8.5);
            let snow = soil("snow");
            let elastic = second.normal / second.area.max(1e-9) / snow.elastic_stiffness;
            c.passed = second.sinkage <= first.sinkage * 1.1 + elastic
                && second.sinkage >= 0.5 * first.sinkage;
            c.measured = format!(
                "first pass {:.2} mm, second pass over the rut {:.2} mm",
                first.sinkage * 1e3,
                second.sinkage * 1e3
            );
        }
        Err(e) => c.measured = e.to_string(),
    }
    c.outcome = "forwards 6 s, back 3 s".into();
    c.expected =
        "the second pass sinks no deeper than the first (within 10 %, plus the elastic p / K_e)"
            .into();
    c.note = "Snow (Chrono SCM's soft soil, k_phi = 0.2 MPa/m^1.1). PackBot drives 1.8 m forwards and reverses over its own ruts; load-weighted mean sinkage over t = 4-5 s (first pass, on fresh snow, clear of the landing's rut) and 7.5-8.5 s (second pass, over the ruts of the first at steady state). Bekker's law with plastic memory: under the load that made the rut the soil answers elastically (K_e), so the second pass adds only p / K_e.".into();
    c
}
