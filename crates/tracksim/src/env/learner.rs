//! The learner's observation (`observation = "learner"`): named float32 entries, each with its
//! shape, unit and bounds ([`LearnerEntry`]), computed once per control period into buffers
//! allocated when the episode starts ([`LearnerObs`]). In order (entries of length 0, e.g. the
//! flippers of a vehicle without any, are left out):
//!
//! | entry | shape | unit | bounds | what |
//! |---|---|---|---|---|
//! | `roll_pitch_rad` | 2 | rad | ±pi | roll and pitch of the body (first, as in the state vector, so a reward reading entries 0 and 1 works in both) |
//! | `orientation_xyzw` | 4 | 1 | ±1 | the body's orientation quaternion in the world (x, y, z, w) |
//! | `linear_velocity_mps` | 3 | m/s | ±inf | the body origin's velocity in the body frame (x forward, y left, z up) |
//! | `angular_velocity_rad_s` | 3 | rad/s | ±inf | the body's angular velocity in the body frame |
//! | `goal_m` | 3 | m | ±inf | the goal relative to the body origin, in the body frame |
//! | `flipper_angle_rad` | flippers | rad | ±2 pi | flipper angles relative to the body |
//! | `flipper_velocity_rad_s` | flippers | rad/s | ±inf | their rates |
//! | `track_slip` | tracks | 1 | ±2 | slip ratio per track (`world::Sample::slip`) |
//! | `track_traction_n` | tracks | N | ±inf | the terrain's force on each track along the body's x axis (`world::TrackLoad::traction_n`) |
//! | `track_contacts` | tracks | count | 0..inf | solver contact points between each track and the terrain (`world::TrackLoad::contacts`) |
//! | `elevation_map_m` | rows, columns | m | see below | terrain heights around the body |
//!
//! The goal: `goal_xy_m` if set; else, with `outcome.success_x_m`, the point of that line
//! level with the start (x = success_x_m, y = the start's y); else the point
//! [`DEFAULT_GOAL_AHEAD_M`] ahead of the start along its heading. Its height is
//! `outcome.success_z_m` if set, else the body's (the entry's world z offset is then 0).
//!
//! The elevation map is a [`crate::sensors::ElevationMap`] (the same ray casts as the sensor,
//! through its gathered colliders): with the vehicle's first `elevation_map` sensor when it
//! has one (its mount, cells, resolution, reach and occlusion, updated at its `rate_hz` as
//! the sensor would be), else one on the body origin, `map_shape` cells of
//! `map_resolution_m`, looking from `map_reach_m` above to `map_reach_m` below, updated every
//! control period. Cell `[i, j]` is ahead `(i + 0.5 - rows / 2) * resolution` and left
//! `(j + 0.5 - columns / 2) * resolution` of the map's origin along its heading (level, turned
//! with the body's yaw only); heights are relative to the map's origin, clamped to
//! `[-depth below, height above]`; a cell without terrain reads `no_terrain_m` (the bounds
//! include it).
//!
//! Slip, traction and contacts are the CLI's figures (`trajectory.csv`, `summary.json`), by the
//! same functions ([`Simulation::slip_into`], [`Simulation::track_loads_mean_into`]: the
//! loads' mean over the last output interval).

use super::EnvConfig;
use crate::model::{ElevationMapModel, Mount, Scenario, SensorKind, SensorModel};
use crate::sensors::{ElevationMap, Sensor};
use crate::world::{PoseRpy, Simulation, TrackLoad};
use glam::{DQuat, DVec3};
use std::f64::consts::PI;
use std::time::Instant;

/// How far ahead of the start along its heading the goal is when neither `goal_xy_m` nor
/// `outcome.success_x_m` gives it, m.
pub const DEFAULT_GOAL_AHEAD_M: f64 = 10.0;

/// One entry of the learner's observation.
#[derive(Clone, Debug, PartialEq)]
pub struct LearnerEntry {
    /// The entry's key (its unit in the name).
    pub name: &'static str,
    /// Shape (row-major).
    pub shape: Vec<usize>,
    /// Least value an entry can take.
    pub low: f64,
    /// Greatest value an entry can take.
    pub high: f64,
}

impl LearnerEntry {
    /// Number of values.
    pub fn len(&self) -> usize {
        self.shape.iter().product()
    }

    /// No values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The learner's observation of one episode: its layout and buffers, filled by
/// [`LearnerObs::update`] without allocating.
pub struct LearnerObs {
    entries: Vec<LearnerEntry>,
    map: ElevationMap,
    /// The vehicle's sensor's rate, Hz (`None`: every control period).
    map_rate_hz: Option<f64>,
    map_updates: u64,
    map_low: f64,
    map_high: f64,
    no_terrain: f64,
    loads: Vec<TrackLoad>,
    slip: Vec<f64>,
    /// Goal (world x, y, and z if the outcome gives one), m (Rapier-world-independent).
    goal: (f64, f64, Option<f64>),
    values: Vec<f32>,
    updates: u64,
    cost_s: f64,
}

/// The map: the vehicle's first elevation map sensor, else one on the body origin.
fn map_of(sc: &Scenario, cfg: &EnvConfig) -> (ElevationMap, Option<f64>, ElevationMapModel) {
    for m in &sc.vehicle.sensors {
        if let SensorKind::ElevationMap(p) = m.kind {
            return (ElevationMap::new(m.clone(), p), Some(m.rate_hz), p);
        }
    }
    let p = ElevationMapModel {
        cells: [cfg.map_shape.0, cfg.map_shape.1],
        resolution: cfg.map_resolution_m,
        height_above: cfg.map_reach_m,
        depth_below: cfg.map_reach_m,
        occlusion: false,
    };
    let m = SensorModel {
        name: "elevation_map_m".into(),
        mount: Mount::Body,
        position: DVec3::ZERO,
        rotation: DQuat::IDENTITY,
        rate_hz: f64::INFINITY,
        kind: SensorKind::ElevationMap(p),
        frame_id: None,
    };
    (ElevationMap::new(m, p), None, p)
}

/// The goal of [`LearnerObs`] (see the module's documentation).
fn goal_of(sc: &Scenario, cfg: &EnvConfig, start: &PoseRpy) -> (f64, f64, Option<f64>) {
    let (x, y) = match (cfg.goal_xy_m, sc.outcome.success_x) {
        (Some(g), _) => g,
        (None, Some(x)) => (x, start.y),
        (None, None) => (
            start.x + DEFAULT_GOAL_AHEAD_M * start.yaw.cos(),
            start.y + DEFAULT_GOAL_AHEAD_M * start.yaw.sin(),
        ),
    };
    (x, y, sc.outcome.success_z)
}

fn dv(v: rapier3d::prelude::Vector) -> DVec3 {
    DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

impl LearnerObs {
    /// The observation of an episode of `sim` (its scenario `sc`) that started at `start`,
    /// with its first values taken now.
    pub fn new(sim: &Simulation, sc: &Scenario, cfg: &EnvConfig, start: &PoseRpy) -> Self {
        let (map, map_rate_hz, p) = map_of(sc, cfg);
        let (nf, nt) = (sc.vehicle.flippers.len(), sc.vehicle.tracks.len());
        let map_low = (-p.depth_below).min(cfg.no_terrain_m);
        let map_high = p.height_above.max(cfg.no_terrain_m);
        let e = |name, shape: &[usize], low, high| LearnerEntry {
            name,
            shape: shape.to_vec(),
            low,
            high,
        };
        let inf = f64::INFINITY;
        let entries: Vec<LearnerEntry> = [
            e("roll_pitch_rad", &[2], -PI, PI),
            e("orientation_xyzw", &[4], -1.0, 1.0),
            e("linear_velocity_mps", &[3], -inf, inf),
            e("angular_velocity_rad_s", &[3], -inf, inf),
            e("goal_m", &[3], -inf, inf),
            e("flipper_angle_rad", &[nf], -2.0 * PI, 2.0 * PI),
            e("flipper_velocity_rad_s", &[nf], -inf, inf),
            e("track_slip", &[nt], -2.0, 2.0),
            e("track_traction_n", &[nt], -inf, inf),
            e("track_contacts", &[nt], 0.0, inf),
            e("elevation_map_m", &p.cells, map_low, map_high),
        ]
        .into_iter()
        .filter(|x| !x.is_empty())
        .collect();
        let len = entries.iter().map(LearnerEntry::len).sum();
        let mut o = LearnerObs {
            entries,
            map,
            map_rate_hz,
            map_updates: 0,
            map_low,
            map_high,
            no_terrain: cfg.no_terrain_m,
            loads: vec![TrackLoad::default(); nt],
            slip: vec![0.0; nt],
            goal: goal_of(sc, cfg, start),
            values: vec![0.0; len],
            updates: 0,
            cost_s: 0.0,
        };
        o.update(sim);
        o.updates = 0;
        o.cost_s = 0.0;
        o
    }

    /// The entries, in order.
    pub fn entries(&self) -> &[LearnerEntry] {
        &self.entries
    }

    /// Number of values of all entries.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// No values.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The values, entry after entry (each row-major).
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The goal, world x, y (m) and z if the scenario's outcome gives one.
    pub fn goal(&self) -> (f64, f64, Option<f64>) {
        self.goal
    }

    /// Updates since the episode started and their mean wall time, us.
    pub fn cost(&self) -> (u64, f64) {
        (self.updates, self.cost_s / self.updates.max(1) as f64 * 1e6)
    }

    /// The name of every value (`goal_m[0]`, `elevation_map_m[3,5]`, ...), in order.
    pub fn value_names(&self) -> Vec<String> {
        let mut n = Vec::with_capacity(self.len());
        for e in &self.entries {
            match e.shape.as_slice() {
                [k] => n.extend((0..*k).map(|i| format!("{}[{i}]", e.name))),
                [r, c] => {
                    for i in 0..*r {
                        n.extend((0..*c).map(|j| format!("{}[{i},{j}]", e.name)));
                    }
                }
                _ => n.extend((0..e.len()).map(|i| format!("{}[{i}]", e.name))),
            }
        }
        n
    }

    /// Takes the values of the state `sim` is in (after a control period).
    pub fn update(&mut self, sim: &Simulation) {
        let t0 = Instant::now();
        let t = sim.time();
        let due = match self.map_rate_hz {
            None => true,
            Some(rate) => t + 0.5 * sim.dt() >= self.map_updates as f64 / rate,
        };
        if due {
            self.map.update(sim, 0.0);
            self.map_updates += 1;
        }
        sim.slip_into(&mut self.slip);
        sim.track_loads_mean_into(&mut self.loads);
        let b = &sim.world.bodies[sim.body_handle()];
        let r = b.rotation();
        let q = DQuat::from_xyzw(r.x as f64, r.y as f64, r.z as f64, r.w as f64).normalize();
        let inv = q.inverse();
        let p = sim.body_pose();
        // The body origin's velocity (not its centre of mass's), as the sensors see it.
        let v = inv * dv(b.velocity_at_point(b.translation()));
        let w_body = dv(b.angvel());
        let w = inv * w_body;
        let (gx, gy, gz) = self.goal;
        let goal = inv * DVec3::new(gx - p.x, gy - p.y, gz.map_or(0.0, |z| z - p.z));
        let sc = sim.scenario();
        let mut k = 0;
        let vals = &mut self.values;
        let mut put = |x: f64, lo: f64, hi: f64| {
            vals[k] = x.clamp(lo, hi) as f32;
            k += 1;
        };
        let inf = f64::INFINITY;
        put(p.roll, -PI, PI);
        put(p.pitch, -PI, PI);
        for c in [q.x, q.y, q.z, q.w] {
            put(c, -1.0, 1.0);
        }
        for x in [v.x, v.y, v.z, w.x, w.y, w.z, goal.x, goal.y, goal.z] {
            put(x, -inf, inf);
        }
        let nf = sc.vehicle.flippers.len();
        for i in 0..nf {
            put(sim.flipper_angle(i), -2.0 * PI, 2.0 * PI);
        }
        for (i, fl) in sc.vehicle.flippers.iter().enumerate() {
            let wf = dv(sim.world.bodies[sim.flipper_body(i)].angvel());
            put((inv * (wf - w_body)).dot(fl.axis), -inf, inf);
        }
        for s in &self.slip {
            put(*s, -2.0, 2.0);
        }
        for l in &self.loads {
            put(l.traction_n, -inf, inf);
        }
        for l in &self.loads {
            put(l.contacts as f64, 0.0, inf);
        }
        let (lo, hi, none) = (self.map_low, self.map_high, self.no_terrain);
        let heights = &self.map.channels()[0].data;
        for h in heights {
            put(if h.is_nan() { none } else { *h }, lo, hi);
        }
        debug_assert_eq!(k, self.values.len());
        self.updates += 1;
        self.cost_s += t0.elapsed().as_secs_f64();
    }
}
