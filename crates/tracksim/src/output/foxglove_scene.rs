//! The Foxglove scene of `run.mcap` (issue 42): `foxglove.SceneUpdate` messages (JSON, the
//! `jsonschema` encoding Foxglove reads beside the recording's CDR channels) on `/scene`, once
//! at t = 0:
//! - entity `terrain` in `map`: the ground plane (a 200 x 200 m slab under its surface), every
//!   box and cylinder as cubes and cylinders, height fields and meshes as triangle lists (a
//!   height field at most 128 x 128 vertices: larger ones are sampled with a stride);
//! - entity `robot/...` per link, each in its own frame with `frame_locked`, so that the tf
//!   tree (`/tf`) moves it: the chassis's shapes in `base_link`, each flipper's in
//!   `<flipper>_flipper_link`, each track's path outline (24 thin boxes) in its parent's frame.
//!
//! And on a soil run `/soil` (JSON, one message per sample): each track's sinkage (m) and
//! thrust (N), plottable as `/soil.tracks[0].sinkage_m`.

use super::ros_messages::{BASE_FRAME, flipper_frame};
use super::ros_names::Namespace;
use crate::model::{CollisionShape, Parent, Scenario};
use crate::render::Rgb;
use crate::world::Sample;
use glam::{DQuat, DVec3};
use serde_json::{Value, json};

/// The schema name Foxglove draws as a 3-D scene.
pub const SCENE_SCHEMA: &str = "foxglove.SceneUpdate";
/// The topic of the scene.
pub const SCENE_TOPIC: &str = "/scene";
/// The topic of the soil figures.
pub const SOIL_TOPIC: &str = "/soil";
/// The schema name of the soil figures.
pub const SOIL_SCHEMA: &str = "tracksim.TrackSoil";
/// Most height-field vertices along a side in the scene.
const MAX_GRID: usize = 128;
/// Boxes per track outline.
const TRACK_BOXES: usize = 24;

/// A JSON schema of `foxglove.SceneUpdate` (the fields this file writes).
pub fn scene_schema() -> String {
    let vec3 = json!({"type": "object", "properties": {"x": {"type": "number"}, "y": {"type": "number"}, "z": {"type": "number"}}});
    let quat = json!({"type": "object", "properties": {"x": {"type": "number"}, "y": {"type": "number"}, "z": {"type": "number"}, "w": {"type": "number"}}});
    let pose = json!({"type": "object", "properties": {"position": vec3, "orientation": quat}});
    let color = json!({"type": "object", "properties": {"r": {"type": "number"}, "g": {"type": "number"}, "b": {"type": "number"}, "a": {"type": "number"}}});
    let time = json!({"type": "object", "properties": {"sec": {"type": "integer"}, "nsec": {"type": "integer"}}});
    let prim =
        json!({"type": "object", "properties": {"pose": pose, "size": vec3, "color": color}});
    let cyl = json!({"type": "object", "properties": {"pose": pose, "size": vec3, "bottom_scale": {"type": "number"}, "top_scale": {"type": "number"}, "color": color}});
    let tri = json!({"type": "object", "properties": {"pose": pose, "points": {"type": "array", "items": vec3}, "color": color, "colors": {"type": "array", "items": color}, "indices": {"type": "array", "items": {"type": "integer"}}}});
    let entity = json!({"type": "object", "properties": {
        "timestamp": time, "frame_id": {"type": "string"}, "id": {"type": "string"},
        "lifetime": time, "frame_locked": {"type": "boolean"},
        "metadata": {"type": "array"}, "arrows": {"type": "array"},
        "cubes": {"type": "array", "items": prim}, "spheres": {"type": "array", "items": prim},
        "cylinders": {"type": "array", "items": cyl}, "lines": {"type": "array"},
        "triangles": {"type": "array", "items": tri}, "texts": {"type": "array"},
        "models": {"type": "array"}}});
    json!({"title": SCENE_SCHEMA, "type": "object", "properties": {
        "deletions": {"type": "array"}, "entities": {"type": "array", "items": entity}}})
    .to_string()
}

/// A JSON schema of the soil figures.
pub fn soil_schema() -> String {
    json!({"title": SOIL_SCHEMA, "type": "object", "properties": {
        "t_s": {"type": "number"},
        "tracks": {"type": "array", "items": {"type": "object", "properties": {
            "name": {"type": "string"}, "sinkage_m": {"type": "number"},
            "max_sinkage_m": {"type": "number"}, "thrust_n": {"type": "number"},
            "normal_n": {"type": "number"}}}}}})
    .to_string()
}

fn v3(v: DVec3) -> Value {
    json!({"x": v.x, "y": v.y, "z": v.z})
}

fn pose(at: DVec3, q: DQuat) -> Value {
    json!({"position": v3(at), "orientation": {"x": q.x, "y": q.y, "z": q.z, "w": q.w}})
}

fn rgba(c: Rgb, a: f64) -> Value {
    let [r, g, b] = c.0;
    json!({"r": r as f64 / 255.0, "g": g as f64 / 255.0, "b": b as f64 / 255.0, "a": a})
}

/// Primitives of one entity.
#[derive(Default)]
struct Prims {
    cubes: Vec<Value>,
    spheres: Vec<Value>,
    cylinders: Vec<Value>,
    triangles: Vec<Value>,
}

impl Prims {
    fn cube(&mut self, at: DVec3, q: DQuat, size: DVec3, c: &Value) {
        self.cubes
            .push(json!({"pose": pose(at, q), "size": v3(size), "color": c}));
    }

    fn cylinder(&mut self, at: DVec3, q: DQuat, radius: f64, length: f64, c: &Value) {
        self.cylinders.push(json!({"pose": pose(at, q),
            "size": v3(DVec3::new(2.0 * radius, 2.0 * radius, length)),
            "bottom_scale": 1.0, "top_scale": 1.0, "color": c}));
    }

    /// A collision shape shifted by `-offset`.
    fn shape(&mut self, s: &CollisionShape, offset: DVec3, c: &Value) {
        match s {
            CollisionShape::Box { half, centre } => {
                self.cube(*centre - offset, DQuat::IDENTITY, *half * 2.0, c)
            }
            CollisionShape::Convex(points) => {
                if let Some(first) = points.first() {
                    let (lo, hi) = points
                        .iter()
                        .fold((*first, *first), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
                    self.cube(0.5 * (lo + hi) - offset, DQuat::IDENTITY, hi - lo, c);
                }
            }
            CollisionShape::Sphere { radius, centre } => self.spheres.push(json!({
                "pose": pose(*centre - offset, DQuat::IDENTITY),
                "size": v3(DVec3::splat(2.0 * radius)), "color": c})),
            CollisionShape::Cylinder {
                radius,
                half_length,
                centre,
                rotation,
            } => self.cylinder(*centre - offset, *rotation, *radius, 2.0 * half_length, c),
            CollisionShape::Compound(parts) => {
                for p in parts {
                    self.shape(p, offset, c);
                }
            }
        }
    }

    fn entity(self, id: &str, frame: &str, locked: bool) -> Value {
        let zero = json!({"sec": 0, "nsec": 0});
        json!({"timestamp": zero, "frame_id": frame, "id": id, "lifetime": zero,
            "frame_locked": locked, "metadata": [], "arrows": [], "cubes": self.cubes,
            "spheres": self.spheres, "cylinders": self.cylinders, "lines": [],
            "triangles": self.triangles, "texts": [], "models": []})
    }
}

/// The terrain as one entity in `map`.
fn terrain(sc: &Scenario, map: &str) -> Value {
    let t = &sc.terrain;
    let mut p = Prims::default();
    if let Some((h, _)) = t.ground {
        let c = rgba(t.ground_color, 1.0);
        p.cube(
            DVec3::new(0.0, 0.0, h - 0.05),
            DQuat::IDENTITY,
            DVec3::new(200.0, 200.0, 0.1),
            &c,
        );
    }
    for b in &t.boxes {
        p.cube(b.centre, b.rotation(), b.half * 2.0, &rgba(b.color, 1.0));
    }
    for c in &t.cylinders {
        // Its axis is y turned by its yaw; Foxglove's cylinder's is z.
        let q =
            DQuat::from_rotation_z(c.yaw) * DQuat::from_rotation_x(-std::f64::consts::FRAC_PI_2);
        p.cylinder(
            c.centre,
            q,
            c.radius,
            2.0 * c.half_length,
            &rgba(c.color, 1.0),
        );
    }
    for h in &t.heightfields {
        let stride = |n: usize| n.div_ceil(MAX_GRID).max(1);
        let rows: Vec<usize> = (0..h.rows)
            .step_by(stride(h.rows))
            .chain([h.rows - 1])
            .collect();
        let cols: Vec<usize> = (0..h.cols)
            .step_by(stride(h.cols))
            .chain([h.cols - 1])
            .collect();
        let mut rows = rows;
        rows.dedup();
        let mut cols = cols;
        cols.dedup();
        let mut points = Vec::new();
        for w in rows.windows(2) {
            for k in cols.windows(2) {
                let (a, b) = (h.vertex(w[0], k[0]), h.vertex(w[0], k[1]));
                let (c, d) = (h.vertex(w[1], k[0]), h.vertex(w[1], k[1]));
                for q in [a, b, c, b, d, c] {
                    points.push(v3(q));
                }
            }
        }
        p.triangles
            .push(json!({"pose": pose(DVec3::ZERO, DQuat::IDENTITY),
            "points": points, "color": rgba(h.color, 1.0), "colors": [], "indices": []}));
    }
    for m in &t.meshes {
        let points: Vec<Value> = m
            .triangles
            .iter()
            .flat_map(|tri| tri.iter().map(|&i| v3(m.vertices[i as usize])))
            .collect();
        p.triangles
            .push(json!({"pose": pose(DVec3::ZERO, DQuat::IDENTITY),
            "points": points, "color": rgba(m.color, 1.0), "colors": [], "indices": []}));
    }
    p.entity("terrain", map, false)
}

/// The robot's links as entities, each in its frame (in namespace `ns`, whose name prefixes the
/// entities' ids).
fn robot(sc: &Scenario, ns: &Namespace) -> Vec<Value> {
    let frame = |f: &str| ns.frame(f);
    let prefix = ns.name().map_or(String::new(), |n| format!("{n}/"));
    let v = &sc.vehicle;
    let body_c = rgba(v.colors.body, 1.0);
    let dark = rgba(Rgb([40, 40, 40]), 1.0);
    let mut out = Vec::new();
    let mut body = Prims::default();
    body.shape(&v.body.shape, DVec3::ZERO, &body_c);
    out.push(body.entity(&format!("{prefix}robot/body"), &frame(BASE_FRAME), true));
    for f in &v.flippers {
        let mut p = Prims::default();
        if let Some(s) = &f.shape {
            p.shape(s, f.pivot, &body_c);
        }
        let id = format!("{prefix}robot/flipper/{}", f.name);
        out.push(p.entity(&id, &frame(&flipper_frame(&f.name)), true));
    }
    for t in &v.tracks {
        let (parent, offset) = match t.parent {
            Parent::Body => (BASE_FRAME.to_string(), DVec3::ZERO),
            Parent::Flipper(i) => (flipper_frame(&v.flippers[i].name), v.flippers[i].pivot),
        };
        let mut p = Prims::default();
        let len = t.path.length();
        for k in 0..TRACK_BOXES {
            let s0 = len * k as f64 / TRACK_BOXES as f64;
            let s1 = len * (k + 1) as f64 / TRACK_BOXES as f64;
            let (a, b) = (t.path.frame_at(s0).origin, t.path.frame_at(s1).origin);
            let mid = t.path.frame_at(0.5 * (s0 + s1));
            let size = DVec3::new(a.distance(b).max(1e-4), t.width, t.belt_thickness.max(1e-3));
            p.cube(0.5 * (a + b) - offset, mid.rotation(), size, &dark);
        }
        let id = format!("{prefix}robot/track/{}", t.name);
        out.push(p.entity(&id, &frame(&parent), true));
    }
    out
}

/// The `/scene` message at t = 0 of `robots` (each robot's scenario and namespace) in a world
/// whose terrain is the first robot's, in frame `map`.
pub fn scene_update(robots: &[(&Scenario, Namespace)], map: &str) -> Value {
    let mut entities = Vec::new();
    if let Some((sc, _)) = robots.first() {
        entities.push(terrain(sc, map));
    }
    for (sc, ns) in robots {
        entities.extend(robot(sc, ns));
    }
    json!({"deletions": [], "entities": entities})
}

/// The `/soil` message of sample `s` (tracks named `names`), if the run has soil.
pub fn soil_message(s: &Sample, names: &[String]) -> Option<Value> {
    if s.soil.is_empty() {
        return None;
    }
    let tracks: Vec<Value> = s
        .soil
        .iter()
        .zip(names)
        .map(|(g, n)| {
            json!({"name": n, "sinkage_m": g.sinkage_m, "max_sinkage_m": g.max_sinkage_m,
                "thrust_n": g.thrust_n, "normal_n": g.normal_n})
        })
        .collect();
    Some(json!({"t_s": s.t, "tracks": tracks}))
}
