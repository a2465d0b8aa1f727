//! Compiling a [`ScenarioSpec`] with an already compiled vehicle into a [`Scenario`], in named
//! stages run in this order: vehicle overrides (`vehicle_overrides`), terrain
//! ([`crate::terrain::compile_terrain`]), simulation settings (`simulation`), commands
//! (`command`, `track_speeds`, `flipper_angles`), the track method and what it can model
//! (`method`), then the outcome (`outcome`). Every problem is reported with its key path, in that order, each once.

use super::compliance::compile_compliance;
use super::{
    Command, Controls, Method, MotorCommand, OutcomeModel, Scenario, ScenarioData, SolverSettings,
    VehicleModel,
};
use crate::check::Checker;
use crate::error::{Result, SpecIssue};
use crate::spec::{
    CommandSpec, OutcomeSpec, PerTrack, ScenarioSpec, SimulationSpec, VehicleRefSpec,
};
use std::path::Path;

/// Compiles a scenario whose vehicle is already loaded (files named by the scenario are found
/// relative to `base_dir`), reporting every problem with its key path at once.
pub fn compile_scenario(
    spec: &ScenarioSpec,
    mut vehicle: VehicleModel,
    base_dir: &Path,
) -> Result<Scenario, Vec<SpecIssue>> {
    let mut c = Checker::default();
    let v = &spec.vehicle;
    vehicle_overrides(&mut c, v, &mut vehicle);
    // Terrain.
    let terrain = crate::terrain::compile_terrain(&spec.terrain, base_dir, &mut c.issues);
    let conveyors = super::conveyor::compile_conveyors(&mut c, &spec.terrain.conveyors);
    let loose_boxes = super::conveyor::compile_loose_boxes(&mut c, &spec.terrain.loose_boxes);
    if c.issues.is_empty() {
        check_start_height(&mut c, v, &terrain);
    }
    let s = &spec.simulation;
    let solver = simulation(&mut c, s);
    let mut commands = Vec::new();
    let mut last_t = f64::NEG_INFINITY;
    for (i, cmd) in spec.commands.iter().enumerate() {
        commands.push(command(
            &mut c,
            &format!("commands[{i}]"),
            cmd,
            &vehicle,
            &mut last_t,
        ));
    }
    let method = match Method::parse("simulation.method", &s.method) {
        Ok(m) => {
            c.issues.extend(method_problems(m, &vehicle));
            unpowered_problems(&mut c, m, &commands);
            m
        }
        Err(issue) => {
            c.issues.push(issue);
            Method::Okada2020
        }
    };
    sensor_rates(&mut c, &vehicle, solver.dt);
    let outcome = outcome(&mut c, &spec.outcome);
    let expect = super::expect::compile_expect(&mut c, &spec.expect);
    let course = spec
        .course
        .as_ref()
        .map(|k| super::course::compile_course(&mut c, k));
    let drawbar = spec
        .drawbar
        .as_ref()
        .and_then(|d| super::drawbar::compile_drawbar(&mut c, d));
    if !c.issues.is_empty() {
        // One line per problem even where a value applies to every track.
        let mut seen = Vec::new();
        c.issues.retain(|i| {
            let new = !seen.contains(i);
            seen.push(i.clone());
            new
        });
        return Err(c.issues);
    }
    Ok(Scenario(ScenarioData {
        outcome,
        expect,
        course,
        drawbar,
        method,
        overridden: Vec::new(),
        seed: s.seed,
        record_mcap: spec.output.mcap,
        randomized: Default::default(),
        team: None,
        source: None,
        description: spec.description.clone(),
        vehicle,
        start_xy: (v.x_m, v.y_m),
        start_z: v.z_m,
        start_yaw: v.yaw_deg.to_radians(),
        start_pitch: v.pitch_deg.to_radians(),
        terrain,
        conveyors,
        loose_boxes,
        solver,
        duration: s.duration_s,
        output_interval: s.output_interval_s,
        commands,
    }))
}

/// A sensor updates at most once per physics step: its rate is at most `1 / dt`.
fn sensor_rates(c: &mut Checker, vehicle: &VehicleModel, dt: f64) {
    for (i, s) in vehicle.sensors.iter().enumerate() {
        if dt > 0.0 && s.rate_hz * dt > 1.0 + 1e-9 {
            c.push(
                format!("vehicle file: sensors[{i}].rate_hz"),
                format!(
                    "{} Hz is more than one update per physics step (dt_s = {dt} s allows at \
                     most {} Hz): lower rate_hz or simulation.dt_s",
                    s.rate_hz,
                    1.0 / dt
                ),
            );
        }
    }
}

/// What `method` cannot model on `vehicle`: a drive motor on a method other than the segment
/// links (only they feel the load at their joints), one problem per track, keyed by it.
pub fn method_problems(method: Method, vehicle: &VehicleModel) -> Vec<SpecIssue> {
    if method.models_motors() {
        return Vec::new();
    }
    vehicle
        .tracks
        .iter()
        .filter(|t| t.motor.is_some())
        .map(|t| {
            SpecIssue::new(
                format!("track {} motor", t.name),
                format!(
                    "a drive motor is modelled by okada2020 and okada2020_no_grousers only, not {method}: run with --method okada2020 or remove [tracks.motor]",
                ),
            )
        })
        .collect()
}

/// Compiles a list of `[[commands]]` (e.g. a `commands.toml` written by `tracksim drive`) for
/// `vehicle`, with the checks of a scenario's commands and their key paths.
pub fn compile_commands(
    specs: &[CommandSpec],
    vehicle: &VehicleModel,
) -> Result<Vec<Command>, Vec<SpecIssue>> {
    let mut c = Checker::default();
    let mut last_t = f64::NEG_INFINITY;
    let commands = specs
        .iter()
        .enumerate()
        .map(|(i, cmd)| command(&mut c, &format!("commands[{i}]"), cmd, vehicle, &mut last_t))
        .collect();
    if c.issues.is_empty() {
        Ok(commands)
    } else {
        Err(c.issues)
    }
}

/// Vehicle-override stage: checks the start pose and applies the scenario's overrides of track
/// friction, body mass (inertia scaled with it), belt mass, contact compliance and grouser
/// count to `vehicle`.
fn vehicle_overrides(c: &mut Checker, v: &VehicleRefSpec, vehicle: &mut VehicleModel) {
    c.finite("vehicle.x_m", &[v.x_m]);
    c.finite("vehicle.y_m", &[v.y_m]);
    c.finite("vehicle.yaw_deg", &[v.yaw_deg]);
    c.finite("vehicle.pitch_deg", &[v.pitch_deg]);
    if let Some(z) = v.z_m {
        c.finite("vehicle.z_m", &[z]);
    }
    if let Some(f) = v.track_friction {
        c.non_negative("vehicle.track_friction", f, "");
        for t in &mut vehicle.tracks {
            t.friction = f;
        }
    }
    if let Some(m) = v.body_mass_kg {
        c.positive("vehicle.body_mass_kg", m, "kg");
        vehicle.body.inertia *= m / vehicle.body.mass;
        vehicle.body.mass = m;
    }
    if let Some(m) = v.belt_mass_kg {
        c.positive("vehicle.belt_mass_kg", m, "kg");
        for t in &mut vehicle.tracks {
            t.belt_mass = m;
        }
    }
    if let Some(spec) = &v.compliance {
        let compliance = compile_compliance(c, "vehicle.compliance", spec);
        for t in &mut vehicle.tracks {
            t.compliance = compliance;
        }
    }
    if let Some(n) = v.grouser_count {
        if n > 0 && vehicle.tracks.iter().all(|t| t.grousers.is_none()) {
            c.push(
                "vehicle.grouser_count",
                "the vehicle's tracks have no grousers to count; add a [tracks.grousers] table to the vehicle file (0 is the only count that applies)",
            );
        }
        if n > super::MAX_GROUSERS {
            c.push(
                "vehicle.grouser_count",
                format!("must be at most {} per track, got {n}", super::MAX_GROUSERS),
            );
        }
        for t in &mut vehicle.tracks {
            if n == 0 {
                t.grousers = None;
            } else if let Some(g) = &mut t.grousers {
                if n % g.shapes.len() != 0 {
                    c.push(
                        "vehicle.grouser_count",
                        format!(
                            "must be a multiple of the {} grouser shapes",
                            g.shapes.len()
                        ),
                    );
                }
                g.layout.count = n;
            }
        }
    }
}

/// Checks that a run of `duration` s in steps of `dt` s stays within
/// [`crate::check::MAX_STEPS`] steps (reported at `key`).
fn check_steps(c: &mut Checker, key: &str, duration: f64, dt: f64) {
    if let Some(m) =
        duration_problem(duration, dt).filter(|_| duration.is_finite() && duration > 0.0)
    {
        c.push(key, m);
    }
}

/// What is wrong with a run of `duration` s in steps of `dt` s, if anything: it must be
/// finite, > 0, at most [`crate::check::MAX_DURATION_S`] (one day) and at most
/// [`crate::check::MAX_STEPS`] steps (for `--duration` and `simulation.duration_s`).
pub fn duration_problem(duration: f64, dt: f64) -> Option<String> {
    use crate::check::{MAX_DURATION_S, MAX_STEPS};
    if !(duration.is_finite() && duration > 0.0 && duration <= MAX_DURATION_S) {
        return Some(format!(
            "must be a number of seconds > 0 and at most {MAX_DURATION_S} (one day), got {}",
            crate::check::num(duration)
        ));
    }
    let steps = duration / dt;
    (dt > 0.0 && steps > MAX_STEPS).then(|| {
        format!(
            "{} s in steps of {} s is {steps:.3e} steps, more than the limit of \
             {MAX_STEPS:e}: shorten the run or lengthen the step",
            crate::check::num(duration),
            crate::check::num(dt)
        )
    })
}

/// Largest contact prediction distance, m.
const MAX_PREDICTION_M: f64 = 0.1;

/// Depth below the terrain surface at which a given start height `vehicle.z_m` of the body
/// origin is refused, m (the body origin lies inside the chassis, above the track bottoms).
const MAX_START_BELOW_TERRAIN_M: f64 = 0.05;

/// Refuses a start height `z` m of the body origin more than [`MAX_START_BELOW_TERRAIN_M`]
/// below the terrain at the start (x, y).
fn check_start_height(c: &mut Checker, v: &VehicleRefSpec, terrain: &crate::terrain::TerrainModel) {
    let Some(z) = v.z_m else { return };
    if let Some(h) = terrain.height_at(v.x_m, v.y_m)
        && z < h - MAX_START_BELOW_TERRAIN_M
    {
        c.push(
            "vehicle.z_m",
            format!(
                "{z} m is {:.3} m below the terrain surface at the start ({h:.3} m): the vehicle \
                 would start inside it; raise z_m or leave it out (placed just above the terrain)",
                h - z
            ),
        );
    }
}

/// Most inert colliders `simulation.order_salt` may ask for.
pub const MAX_ORDER_SALT: usize = 1024;

/// Simulation-settings stage: checks `[simulation]` and compiles the solver settings.
fn simulation(c: &mut Checker, s: &SimulationSpec) -> SolverSettings {
    use crate::check::MIN_DT_S;
    if !(s.dt_s.is_finite() && (MIN_DT_S..=0.01).contains(&s.dt_s)) {
        c.push(
            "simulation.dt_s",
            format!(
                "must be at least {MIN_DT_S:e} s and at most 0.01 s (tracks with grousers need \
                 1-2 ms), got {}",
                crate::check::num(s.dt_s)
            ),
        );
    }
    c.positive("simulation.duration_s", s.duration_s, "s");
    check_steps(c, "simulation.duration_s", s.duration_s, s.dt_s);
    c.positive("simulation.output_interval_s", s.output_interval_s, "s");
    c.non_negative("simulation.min_link_mass_kg", s.min_link_mass_kg, "kg");
    if !(s.prediction_distance_m.is_finite()
        && s.prediction_distance_m > 0.0
        && s.prediction_distance_m <= MAX_PREDICTION_M)
    {
        c.push(
            "simulation.prediction_distance_m",
            format!(
                "must be > 0 and at most {MAX_PREDICTION_M} m (contacts are predicted this far \
                 ahead; the default is 0.02), got {}",
                s.prediction_distance_m
            ),
        );
    }
    if !(s.contact_slop_m.is_finite() && (0.0..=0.02).contains(&s.contact_slop_m)) {
        c.push(
            "simulation.contact_slop_m",
            format!(
                "must be between 0 and 0.02 m (the paper's simulator used 0.01), got {}",
                s.contact_slop_m
            ),
        );
    }
    if s.stabilization_iterations > 16 {
        c.push(
            "simulation.stabilization_iterations",
            format!(
                "must be between 0 and 16 (Rapier's default 1; 0 leaves penetrations and joint errors uncorrected), got {}",
                s.stabilization_iterations
            ),
        );
    }
    if !(s.warmstart_coefficient.is_finite()
        && s.warmstart_coefficient > 0.0
        && s.warmstart_coefficient <= 1.0)
    {
        c.push(
            "simulation.warmstart_coefficient",
            format!(
                "must be in (0, 1] (the share of the last step's impulses the solver starts from; default Rapier's 1), got {}",
                s.warmstart_coefficient
            ),
        );
    }
    if s.order_salt > MAX_ORDER_SALT {
        c.push(
            "simulation.order_salt",
            format!(
                "must be between 0 and {MAX_ORDER_SALT} (inert colliders that change the solver's order; 0 = none), got {}",
                s.order_salt
            ),
        );
    }
    if let Some(z) = s.terrain_contact_damping_ratio
        && !(z.is_finite() && z > 0.0 && z <= 100.0)
    {
        c.push(
            "simulation.terrain_contact_damping_ratio",
            format!("must be in (0, 100] (1: critically damped; Rapier's default 10), got {z}"),
        );
    }
    if s.solver_iterations == 0 || s.solver_iterations > 100 {
        c.push(
            "simulation.solver_iterations",
            format!("must be between 1 and 100, got {}", s.solver_iterations),
        );
    }
    SolverSettings {
        dt: s.dt_s,
        iterations: s.solver_iterations,
        stabilization_iterations: s.stabilization_iterations,
        warmstart: s.warmstart_coefficient,
        contact_clustering: s.contact_clustering,
        min_link_mass: s.min_link_mass_kg,
        prediction_distance: s.prediction_distance_m,
        contact_slop: s.contact_slop_m,
        held_friction_in_bias_pass: s.held_friction_in_bias_pass,
        contact_recycling: s.contact_recycling,
        floating_origin: s.floating_origin,
        order_salt: s.order_salt,
        terrain_contact_damping_ratio: s.terrain_contact_damping_ratio,
        cull_speculative_contacts: s.cull_speculative_contacts,
    }
}

/// Command stage: checks one `[[commands]]` entry (key path `k`; `last_t` is the previous
/// entry's time, s) and resolves it to track and flipper indices.
fn command(
    c: &mut Checker,
    k: &str,
    cmd: &CommandSpec,
    vehicle: &VehicleModel,
    last_t: &mut f64,
) -> Command {
    if !(cmd.t_s.is_finite() && (0.0..=crate::check::MAX_DURATION_S).contains(&cmd.t_s)) {
        c.push(
            format!("{k}.t_s"),
            format!(
                "must be >= 0 s and at most {} s (the longest run), got {}",
                crate::check::MAX_DURATION_S,
                crate::check::num(cmd.t_s)
            ),
        );
    } else if cmd.t_s < *last_t {
        c.push(
            format!("{k}.t_s"),
            "commands must be listed in order of time",
        );
    }
    *last_t = cmd.t_s;
    let mut belt = track_speeds(c, k, cmd, vehicle);
    match (cmd.forward_mps, cmd.yaw_rate_rad_s) {
        (None, None) => {}
        (v_fwd, w) => {
            let (v_fwd, w) = (v_fwd.unwrap_or(0.0), w.unwrap_or(0.0));
            if cmd.belt_speed_mps.is_some() || cmd.sprocket_rad_s.is_some() {
                c.push(
                    k.to_string(),
                    "give forward_mps/yaw_rate_rad_s or per-track speeds, not both",
                );
            }
            let max = crate::check::MAX_SPEED_MPS;
            c.bounded(&format!("{k}.forward_mps"), v_fwd, max, "m/s");
            c.bounded(&format!("{k}.yaw_rate_rad_s"), w, max, "rad/s");
            belt = Controls::twist(vehicle, v_fwd, w).belt_speed;
        }
    }
    let flip = flipper_angles(c, k, cmd, vehicle);
    let motor = motor_commands(c, k, cmd, vehicle);
    if motor.iter().any(Option::is_some)
        && (belt.iter().any(Option::is_some)
            || cmd.forward_mps.is_some()
            || cmd.yaw_rate_rad_s.is_some())
    {
        c.push(
            k.to_string(),
            "give speeds (belt_speed_mps, sprocket_rad_s, forward_mps) or motor_duty / \
             motor_torque_nm in one command, not both",
        );
    }
    let faults = cmd
        .fault
        .as_ref()
        .map(|f| super::compile_faults(c, k, f, vehicle))
        .unwrap_or_default();
    Command {
        t: cmd.t_s,
        controls: Controls {
            belt_speed: belt,
            flipper_angle: flip,
            motor,
            faults,
            reset: cmd.reset == Some(true),
        },
    }
}

/// Duty and torque commands per track index from a command's `motor_duty` / `motor_torque_nm`;
/// each track named must have a drive motor (duty: the DC motor's line, not a curve).
fn motor_commands(
    c: &mut Checker,
    k: &str,
    cmd: &CommandSpec,
    vehicle: &VehicleModel,
) -> Vec<Option<MotorCommand>> {
    let mut out = vec![None; vehicle.tracks.len()];
    if cmd.motor_duty.is_some() && cmd.motor_torque_nm.is_some() {
        c.push(
            k.to_string(),
            "give motor_duty or motor_torque_nm, not both",
        );
    }
    let given = [
        ("motor_duty", &cmd.motor_duty, true),
        ("motor_torque_nm", &cmd.motor_torque_nm, false),
    ];
    for (key, values, duty) in given {
        let Some(values) = values else { continue };
        for (j, x, kk) in per_track_entries(c, k, key, values, vehicle) {
            let t = &vehicle.tracks[j];
            let Some(m) = &t.motor else {
                c.push(
                    kk,
                    format!(
                        "track \"{}\" has no [tracks.motor]; a duty or torque command needs one \
                         (or give belt_speed_mps)",
                        t.name
                    ),
                );
                continue;
            };
            if duty && !(x.is_finite() && (-1.0..=1.0).contains(&x)) {
                c.push(kk, format!("must be a duty cycle in [-1, 1], got {x}"));
            } else if duty && m.curve.is_some() {
                c.push(
                    kk,
                    "a duty cycle scales the DC motor's line: give the motor stall_torque_nm and \
                     no_load_speed_rad_s rather than torque_speed, or command a torque",
                );
            } else if !x.is_finite() {
                c.push(kk, format!("must be finite, got {x}"));
            } else {
                out[j] = Some(if duty {
                    MotorCommand::Duty(x)
                } else {
                    MotorCommand::Torque(x)
                });
            }
        }
    }
    out
}

/// The (track index, value, key path) entries of a per-track value `values` at `k.key`: one
/// for every track, or one per track name (unknown names reported).
fn per_track_entries(
    c: &mut Checker,
    k: &str,
    key: &str,
    values: &PerTrack,
    vehicle: &VehicleModel,
) -> Vec<(usize, f64, String)> {
    match values {
        PerTrack::All(x) => (0..vehicle.tracks.len())
            .map(|j| (j, *x, format!("{k}.{key}")))
            .collect(),
        PerTrack::ByName(m) => {
            let mut e = Vec::new();
            for (name, x) in m {
                match vehicle.track_index(name) {
                    Some(j) => e.push((j, *x, format!("{k}.{key}.{name}"))),
                    None => c.push(
                        format!("{k}.{key}.{name}"),
                        format!(
                            "no track called \"{name}\"; the vehicle has {}",
                            vehicle
                                .tracks
                                .iter()
                                .map(|t| format!("\"{}\"", t.name))
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    ),
                }
            }
            e
        }
    }
}

/// Belt speed per track index from a command's `belt_speed_mps` or `sprocket_rad_s` (times the
/// track's sprocket pitch radius), m/s.
fn track_speeds(
    c: &mut Checker,
    k: &str,
    cmd: &CommandSpec,
    vehicle: &VehicleModel,
) -> Vec<Option<f64>> {
    let nt = vehicle.tracks.len();
    let mut belt = vec![None; nt];
    if cmd.belt_speed_mps.is_some() && cmd.sprocket_rad_s.is_some() {
        c.push(
            k.to_string(),
            "give belt_speed_mps or sprocket_rad_s, not both",
        );
    }
    let given = [
        ("belt_speed_mps", &cmd.belt_speed_mps, false),
        ("sprocket_rad_s", &cmd.sprocket_rad_s, true),
    ];
    for (key, values, sprocket) in given {
        let Some(values) = values else { continue };
        let entries = per_track_entries(c, k, key, values, vehicle);
        for (j, x, kk) in entries {
            let scale = if sprocket {
                vehicle.tracks[j].sprocket_radius
            } else {
                Some(1.0)
            };
            let unit = if sprocket { "rad/s" } else { "m/s" };
            if !(x.is_finite() && x.abs() <= crate::check::MAX_SPEED_MPS) {
                c.bounded(&kk, x, crate::check::MAX_SPEED_MPS, unit);
            } else if let Some(f) = scale {
                belt[j] = Some(x * f);
            } else {
                c.push(
                    kk,
                    format!(
                        "track \"{}\" has no sprocket_pitch_radius_m; give belt_speed_mps instead or add the radius to the vehicle file",
                        vehicle.tracks[j].name
                    ),
                );
            }
        }
    }
    belt
}

/// Flipper target angle per flipper index from a command's `flipper_angle_deg`, rad.
fn flipper_angles(
    c: &mut Checker,
    k: &str,
    cmd: &CommandSpec,
    vehicle: &VehicleModel,
) -> Vec<Option<f64>> {
    let mut flip = vec![None; vehicle.flippers.len()];
    for (name, a) in &cmd.flipper_angle_deg {
        match vehicle.flipper_index(name) {
            Some(j) if a.is_finite() && a.abs() <= 3600.0 => flip[j] = Some(a.to_radians()),
            Some(_) => c.bounded(&format!("{k}.flipper_angle_deg.{name}"), *a, 3600.0, "deg"),
            None => c.push(
                format!("{k}.flipper_angle_deg.{name}"),
                format!("no flipper called \"{name}\""),
            ),
        }
    }
    flip
}

/// Outcome stage: checks `[outcome]` and compiles it (tilt limit to radians).
fn outcome(c: &mut Checker, o: &OutcomeSpec) -> OutcomeModel {
    if let Some(x) = o.success_x_m {
        c.finite("outcome.success_x_m", &[x]);
    }
    if let Some(z) = o.success_z_m {
        c.finite("outcome.success_z_m", &[z]);
    }
    // Meaningful with several robots only, but a wrong name is refused in any file.
    if let Err(issue) = super::TeamRule::parse(o.team.as_deref()) {
        c.issues.push(issue);
    }
    if !(o.max_tilt_deg.is_finite() && o.max_tilt_deg > 0.0 && o.max_tilt_deg <= 180.0) {
        c.push(
            "outcome.max_tilt_deg",
            format!("must be in (0, 180] degrees, got {}", o.max_tilt_deg),
        );
    }
    OutcomeModel {
        success_x: o.success_x_m,
        success_z: o.success_z_m,
        max_tilt: o.max_tilt_deg.to_radians(),
        fail_off_terrain: o.fail_off_terrain,
        stop: o.stop,
    }
}

/// A command that makes a track unpowered under a method that does not model it: refused with
/// its key path and the methods that do.
fn unpowered_problems(c: &mut Checker, method: Method, commands: &[Command]) {
    if super::models_unpowered(method) {
        return;
    }
    for (i, cmd) in commands.iter().enumerate() {
        if cmd.controls.faults.unpowers() {
            c.push(
                format!("commands[{i}].fault.track"),
                format!(
                    "an \"unpowered\" track is not modelled by method \"{method}\" (its belt is a \
                     speed imposed on its contacts, with no drive to let go); use okada2020 (any \
                     variant), wheelsK or plates, or \"stopped\""
                ),
            );
        }
    }
}
