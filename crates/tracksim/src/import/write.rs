//! The files `tracksim import` writes: the vehicle file (serialised from a [`VehicleSpec`] with
//! the `toml` crate, so it reads back as written; empty and default-empty keys left out; the
//! report as comments on top) and a flat-ground scenario beside it.

use super::propose::{ProposedPath, ProposedTrack};
use super::report::ImportReport;
use crate::geometry::Pulley;
use crate::spec::{JointSpec, PathSpec, PulleySpec, TrackSpec, VehicleSpec};
use std::path::{Component, Path, PathBuf};

/// Belt speed the flat-ground scenario commands, m/s.
pub const FLAT_BELT_SPEED_MPS: f64 = 0.3;
/// Length of the flat-ground scenario, s.
pub const FLAT_DURATION_S: f64 = 6.0;

fn pulley(p: &Pulley) -> PulleySpec {
    PulleySpec {
        x_m: p.x,
        z_m: p.z,
        radius_m: p.radius,
    }
}

fn track_spec(t: &ProposedTrack) -> TrackSpec {
    let (wheel, pulleys) = match &t.path {
        ProposedPath::Pulleys(v) => (None, Some(v.iter().map(pulley).collect())),
        ProposedPath::Wheel(w) => (Some(pulley(w)), None),
    };
    TrackSpec {
        name: t.name.clone(),
        mirror: None,
        mirror_parent: None,
        parent: "body".into(),
        link: Some(t.link.clone()),
        mirror_link: None,
        width_m: t.width,
        belt_thickness_m: 0.01,
        belt_mass_kg: t.belt_mass,
        friction: t.friction.unwrap_or(0.6),
        friction_combine: "min".into(),
        sprocket_pitch_radius_m: t.sprocket_pitch_radius,
        omit_segments: Vec::new(),
        no_contact_segments: Vec::new(),
        path: PathSpec {
            plane_y_m: Some(t.plane_y),
            wheel,
            pulleys,
            segments: None,
            spatial: false,
        },
        grousers: t.grousers.clone(),
        compliance: None,
        motor: None,
    }
}

/// The vehicle file's spec; `urdf` is the model's path relative to the vehicle file.
pub fn vehicle_spec(r: &ImportReport, urdf: &str) -> VehicleSpec {
    VehicleSpec {
        name: r.robot.clone(),
        description: format!("{} imported by tracksim import", r.robot),
        urdf: Some(urdf.to_string()),
        body_friction: None,
        joints: r
            .flippers
            .iter()
            .map(|j| {
                let ctl = JointSpec {
                    stiffness_nm_per_rad: Some(2000.0),
                    damping_nms_per_rad: Some(50.0),
                    ..JointSpec::default()
                };
                (j.clone(), ctl)
            })
            .collect(),
        body: None,
        flippers: Vec::new(),
        tracks: r.tracks.iter().map(track_spec).collect(),
        odometry: None,
        sensors: Vec::new(),
        colors: None,
        steering: None,
        rigid_joints: r.rigid.iter().map(|(j, _)| j.clone()).collect(),
        flipper_joints: None,
        sdf_model: r.sdf_model.clone(),
    }
}

/// Drops empty arrays, tables and strings (all of them serde defaults) from `v`, recursively,
/// and rounds lengths to the nanometre.
pub(super) fn prune(v: &mut toml::Value) {
    match v {
        toml::Value::Table(t) => {
            t.iter_mut().for_each(|(_, v)| prune(v));
            t.retain(|_, v| !is_empty(v));
        }
        toml::Value::Array(a) => a.iter_mut().for_each(prune),
        // Nanometres are enough: 0.02000000000000011 is written 0.02.
        toml::Value::Float(f) if f.abs() < 1e6 => *f = (*f * 1e9).round() / 1e9,
        _ => {}
    }
}

fn is_empty(v: &toml::Value) -> bool {
    match v {
        toml::Value::Table(t) => t.is_empty(),
        toml::Value::Array(a) => a.is_empty(),
        toml::Value::String(s) => s.is_empty(),
        _ => false,
    }
}

/// `lines` as TOML comments.
fn comments(lines: &[String]) -> String {
    lines.iter().map(|l| format!("# {l}\n")).collect()
}

/// The vehicle file's text: the report as comments, then the spec.
pub fn vehicle_text(r: &ImportReport, urdf: &str) -> Result<String, String> {
    let mut v = toml::Value::try_from(vehicle_spec(r, urdf)).map_err(|e| e.to_string())?;
    prune(&mut v);
    let body = toml::to_string(&v).map_err(|e| e.to_string())?;
    let mut head = vec![
        "Written by `tracksim import`: every guess below is the importer's; check them against \
         the robot."
            .to_string(),
    ];
    head.extend(r.lines());
    Ok(format!("{}\n{body}", comments(&head)))
}

/// The flat-ground scenario's text: the vehicle file `vehicle` (a name beside it) driven at
/// [`FLAT_BELT_SPEED_MPS`] for [`FLAT_DURATION_S`].
pub fn scenario_text(robot: &str, vehicle: &str) -> Result<String, String> {
    let mut t = toml::Table::new();
    t.insert(
        "description".into(),
        format!("{robot} (imported) drives at {FLAT_BELT_SPEED_MPS} m/s on flat ground").into(),
    );
    let mut veh = toml::Table::new();
    veh.insert("file".into(), vehicle.into());
    t.insert("vehicle".into(), veh.into());
    let mut ground = toml::Table::new();
    ground.insert("friction".into(), 0.6.into());
    let mut terrain = toml::Table::new();
    terrain.insert("ground".into(), ground.into());
    t.insert("terrain".into(), terrain.into());
    drive_for(&mut t, FLAT_DURATION_S);
    let body = toml::to_string(&t).map_err(|e| e.to_string())?;
    Ok(format!(
        "# Written by `tracksim import`: the imported robot on flat ground (friction 0.6), all \
         tracks at {FLAT_BELT_SPEED_MPS} m/s.\n{body}"
    ))
}

/// A written scenario's `[simulation]` (dt 1 ms, `duration` s) and its one command: every
/// track at [`FLAT_BELT_SPEED_MPS`] from t = 0.
pub(super) fn drive_for(t: &mut toml::Table, duration: f64) {
    let mut sim = toml::Table::new();
    sim.insert("dt_s".into(), 0.001.into());
    sim.insert("duration_s".into(), duration.into());
    t.insert("simulation".into(), sim.into());
    let mut cmd = toml::Table::new();
    cmd.insert("t_s".into(), 0.0.into());
    cmd.insert("belt_speed_mps".into(), FLAT_BELT_SPEED_MPS.into());
    t.insert("commands".into(), toml::Value::Array(vec![cmd.into()]));
}

/// `to` as a path relative to the folder `from` (both made absolute first), `/`-separated.
pub fn relative(from: &Path, to: &Path) -> PathBuf {
    let abs = |p: &Path| {
        std::fs::canonicalize(p).unwrap_or_else(|_| {
            std::env::current_dir()
                .map(|d| d.join(p))
                .unwrap_or_else(|_| p.to_path_buf())
        })
    };
    let (from, to) = (abs(from), abs(to));
    let a: Vec<Component> = from.components().collect();
    let b: Vec<Component> = to.components().collect();
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..a.len() {
        out.push("..");
    }
    for c in &b[common..] {
        out.push(c);
    }
    out
}
