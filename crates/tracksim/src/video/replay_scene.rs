//! A finished run as a [`RenderScene`]: [`ReplayWorld`] holds what `scene.json` describes, built
//! once (the terrain's boxes, cylinders and meshes, the flat ground, each robot's chassis, flipper
//! arms, belts and grouser shapes, conveyors and loose boxes), and [`ReplayWorld::scene`] places
//! the moving parts at one time's state ([`RobotState`]: body pose, flipper angles, belt
//! positions, loose boxes' poses) into a [`ReplayScene`] the tracer renders.
//!
//! Shapes: boxes and cylinders use the closed forms of [`crate::render::shapes`], the ground is
//! a plane, every mesh (terrain meshes and height fields, the chassis hull, flipper arms,
//! grousers) is a parry [`TriMesh`]. A belt is drawn as its loop's outer surface (a ribbon of
//! the belt's width along the sampled path) closed by its two flat sides (the loop's area), in
//! the tracks' colour; grousers ride on it at their arc lengths, moved by the belt's position.

use super::record::{MeshIn, Recording, RobotState, SceneIn, TrackIn, color_or};
use crate::render::{Candidate, Hit, RenderScene, Rgb, palette, shapes};
use glam::{DMat3, DQuat, DVec3, Mat3, Quat, Vec3};
use rapier3d::parry::query::{Ray, RayCast};
use rapier3d::parry::shape::TriMesh;
use std::sync::Arc;

/// A shape in its own frame.
#[derive(Clone)]
enum Geom {
    /// Half extents, m.
    Box(Vec3),
    /// Axis y: half height, radius, m.
    Cylinder(f32, f32),
    /// The plane z = 0, normal +z (the ground).
    Plane,
    /// Triangles.
    Mesh(Arc<TriMesh>),
}

impl Geom {
    /// Bounding box in the shape's frame (the plane's is set per frame).
    fn local_box(&self) -> (Vec3, Vec3) {
        match self {
            Geom::Box(h) => (-*h, *h),
            Geom::Cylinder(hh, r) => (Vec3::new(-r, -hh, -r), Vec3::new(*r, *hh, *r)),
            Geom::Plane => (Vec3::ZERO, Vec3::ZERO),
            Geom::Mesh(m) => {
                let b = m.local_aabb();
                (b.mins, b.maxs)
            }
        }
    }
}

/// A rigid transform (f64 while composing frames).
#[derive(Clone, Copy, Debug)]
struct Tf {
    r: DQuat,
    t: DVec3,
}

impl Tf {
    const ID: Tf = Tf {
        r: DQuat::IDENTITY,
        t: DVec3::ZERO,
    };

    fn mul(self, o: Tf) -> Tf {
        Tf {
            r: (self.r * o.r).normalize(),
            t: self.t + self.r * o.t,
        }
    }
}

/// A shape placed in the world for one frame.
#[derive(Clone)]
struct Item {
    geom: Geom,
    rot: Quat,
    inv: Quat,
    pos: Vec3,
    color: Rgb,
}

/// A belt's loop and its grousers, in its parent frame.
struct TrackParts {
    parent: i64,
    shell: Option<Arc<TriMesh>>,
    grousers: Vec<Arc<TriMesh>>,
    count: usize,
    offset: f64,
    pitch: f64,
    length: f64,
    points: Vec<DVec3>,
    normals: Vec<DVec3>,
    laterals: Vec<DVec3>,
}

impl TrackParts {
    fn new(t: &TrackIn) -> TrackParts {
        let n = t.points_m.len() / 3;
        let v3 = |a: &[f64], i: usize| DVec3::new(a[3 * i], a[3 * i + 1], a[3 * i + 2]);
        let lateral = DVec3::from_array(t.lateral);
        let points: Vec<DVec3> = (0..n).map(|i| v3(&t.points_m, i)).collect();
        let normals: Vec<DVec3> = (0..n.min(t.normals.len() / 3))
            .map(|i| v3(&t.normals, i))
            .collect();
        let laterals: Vec<DVec3> = match &t.laterals {
            Some(l) if l.len() >= 3 * n => (0..n).map(|i| v3(l, i)).collect(),
            _ => vec![lateral; n],
        };
        let (grousers, count, offset, pitch) = match &t.grousers {
            Some(g) => (
                g.shapes.iter().filter_map(mesh).collect(),
                g.count,
                g.offset_m,
                g.pitch_m,
            ),
            None => (Vec::new(), 0, 0.0, 0.0),
        };
        TrackParts {
            parent: t.parent,
            shell: belt_shell(&points, &laterals, t.width_m, t.laterals.is_none()),
            grousers,
            count,
            offset,
            pitch,
            length: t.length_m,
            points,
            normals,
            laterals,
        }
    }

    /// Each grouser's transform in the parent frame at belt position `s` (m).
    fn grouser_frames(&self, s: f64) -> Vec<(usize, Tf)> {
        let n = self.points.len();
        if self.grousers.is_empty() || n < 2 || self.normals.len() < n || self.length <= 0.0 {
            return Vec::new();
        }
        (0..self.count)
            .map(|k| {
                let a = (self.offset + k as f64 * self.pitch + s).rem_euclid(self.length);
                let f = a / self.length * n as f64;
                let i = (f.floor() as usize) % n;
                let j = (i + 1) % n;
                let w = f - f.floor();
                let p = self.points[i].lerp(self.points[j], w);
                let nr = self.normals[i].lerp(self.normals[j], w).normalize_or_zero();
                let l = self.laterals[i]
                    .lerp(self.laterals[j], w)
                    .normalize_or_zero();
                let tan = l.cross(nr).normalize_or_zero();
                let r = DQuat::from_mat3(&DMat3::from_cols(tan, l, nr)).normalize();
                (k % self.grousers.len(), Tf { r, t: p })
            })
            .collect()
    }
}

/// The belt's outer surface (a ribbon along the loop) and, for a planar loop, its two sides
/// (fans from the loop's centroid).
fn belt_shell(points: &[DVec3], lats: &[DVec3], width: f64, planar: bool) -> Option<Arc<TriMesh>> {
    let n = points.len();
    if n < 3 {
        return None;
    }
    let mut v: Vec<Vec3> = Vec::with_capacity(2 * n + 2);
    for (p, l) in points.iter().zip(lats) {
        v.push((*p + *l * (width / 2.0)).as_vec3());
        v.push((*p - *l * (width / 2.0)).as_vec3());
    }
    let mut idx = Vec::with_capacity(4 * n);
    for i in 0..n {
        let j = (i + 1) % n;
        let (ai, bi, aj, bj) = (
            2 * i as u32,
            2 * i as u32 + 1,
            2 * j as u32,
            2 * j as u32 + 1,
        );
        idx.push([ai, bi, aj]);
        idx.push([aj, bi, bj]);
    }
    if planar {
        let c = points.iter().copied().sum::<DVec3>() / n as f64;
        let l = lats[0] * (width / 2.0);
        let (ca, cb) = (v.len() as u32, v.len() as u32 + 1);
        v.push((c + l).as_vec3());
        v.push((c - l).as_vec3());
        for i in 0..n {
            let j = (i + 1) % n;
            idx.push([ca, 2 * i as u32, 2 * j as u32]);
            idx.push([cb, 2 * j as u32 + 1, 2 * i as u32 + 1]);
        }
    }
    TriMesh::new(v, idx).ok().map(Arc::new)
}

/// A parry mesh of `scene.json`'s triangles (`None`: no triangles).
fn mesh(m: &MeshIn) -> Option<Arc<TriMesh>> {
    let v: Vec<Vec3> = m
        .vertices_m
        .chunks_exact(3)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect();
    let nv = v.len() as u32;
    let idx: Vec<[u32; 3]> = m
        .triangles
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .filter(|t| t.iter().all(|&i| i < nv))
        .collect();
    if idx.is_empty() {
        return None;
    }
    TriMesh::new(v, idx).ok().map(Arc::new)
}

/// One robot's parts (body frame).
struct RobotParts {
    body: Option<Arc<TriMesh>>,
    /// Pivot, unit axis, arm.
    flippers: Vec<(DVec3, DVec3, Option<Arc<TriMesh>>)>,
    tracks: Vec<TrackParts>,
    /// Body, tracks, flippers.
    colors: [Rgb; 3],
}

impl RobotParts {
    fn new(s: &SceneIn) -> RobotParts {
        RobotParts {
            body: mesh(&s.vehicle.body),
            flippers: s
                .vehicle
                .flippers
                .iter()
                .map(|f| {
                    (
                        DVec3::from_array(f.pivot_m),
                        DVec3::from_array(f.axis).normalize_or_zero(),
                        f.mesh.as_ref().and_then(mesh),
                    )
                })
                .collect(),
            tracks: s.vehicle.tracks.iter().map(TrackParts::new).collect(),
            colors: s.vehicle_colors(),
        }
    }
}

/// Everything `scene.json` describes, built once for every frame of a video.
pub struct ReplayWorld {
    fixed: Vec<Item>,
    ground: Option<(f32, Rgb)>,
    robots: Vec<RobotParts>,
    conveyors: Vec<(Tf, TrackParts)>,
    loose: Vec<(Vec3, Rgb)>,
}

fn item(geom: Geom, tf: Tf, color: Rgb) -> Item {
    let rot = tf.r.as_quat().normalize();
    Item {
        geom,
        rot,
        inv: rot.inverse(),
        pos: tf.t.as_vec3(),
        color,
    }
}

impl ReplayWorld {
    /// The world of `runs` (the first's terrain, conveyors and loose boxes; every run's robot).
    pub fn new(runs: &[Recording]) -> ReplayWorld {
        let s = &runs[0].scene;
        let t = &s.terrain;
        let mut fixed = Vec::new();
        for b in &t.boxes {
            let q = b.quat_xyzw;
            let tf = Tf {
                r: DQuat::from_xyzw(q[0], q[1], q[2], q[3]).normalize(),
                t: DVec3::from_array(b.centre_m),
            };
            let c = color_or(b.color.as_deref(), palette::BOX);
            fixed.push(item(
                Geom::Box(DVec3::from_array(b.half_m).as_vec3()),
                tf,
                c,
            ));
        }
        for c in &t.cylinders {
            let tf = Tf {
                r: DQuat::from_rotation_z(c.yaw_rad),
                t: DVec3::from_array(c.centre_m),
            };
            let col = color_or(c.color.as_deref(), palette::NOSING);
            fixed.push(item(
                Geom::Cylinder(c.half_length_m as f32, c.radius_m as f32),
                tf,
                col,
            ));
        }
        for (i, m) in t.meshes.iter().enumerate() {
            if let Some(m) = mesh(m) {
                let c = color_or(t.mesh_colors.get(i).map(String::as_str), palette::MESH);
                fixed.push(item(Geom::Mesh(m), Tf::ID, c));
            }
        }
        ReplayWorld {
            fixed,
            ground: t.ground_z_m.map(|z| {
                (
                    z as f32,
                    color_or(t.ground_color.as_deref(), palette::GROUND),
                )
            }),
            robots: runs.iter().map(|r| RobotParts::new(&r.scene)).collect(),
            conveyors: s
                .conveyors
                .iter()
                .map(|c| {
                    (
                        Tf {
                            r: DQuat::from_rotation_z(c.yaw_rad),
                            t: DVec3::from_array(c.centre_m),
                        },
                        TrackParts::new(&c.track),
                    )
                })
                .collect(),
            loose: s
                .loose_boxes
                .iter()
                .map(|b| {
                    (
                        DVec3::from_array(b.half_m).as_vec3(),
                        color_or(b.color.as_deref(), palette::LOOSE_BOX),
                    )
                })
                .collect(),
        }
    }

    /// The scene at the robots' `states` (one per robot, in [`Self::new`]'s order; the first's
    /// conveyors and loose boxes) for a camera at `eye` seeing `reach` m; `hide`: a robot left
    /// out of the primary rays (an onboard camera's own; it still casts shadows).
    pub fn scene(
        &self,
        states: &[RobotState],
        eye: DVec3,
        reach: f64,
        hide: Option<usize>,
    ) -> ReplayScene {
        let mut items = self.fixed.clone();
        let mut owner: Vec<Option<usize>> = vec![None; items.len()];
        for (ri, (parts, st)) in self.robots.iter().zip(states).enumerate() {
            let start = items.len();
            robot_items(parts, st, &mut items);
            owner.resize(owner.len() + items.len() - start, Some(ri));
        }
        if let Some(st) = states.first() {
            for (i, (tf, tr)) in self.conveyors.iter().enumerate() {
                let s = st.conveyors.get(i).copied().unwrap_or(0.0);
                track_items(tr, *tf, s, palette::CONVEYOR, &mut items);
            }
            for ((half, c), (p, q)) in self.loose.iter().zip(&st.boxes) {
                items.push(item(Geom::Box(*half), Tf { r: *q, t: *p }, *c));
            }
        }
        owner.resize(items.len(), None);
        let mut primary = Vec::with_capacity(items.len() + 1);
        let mut casters = Vec::with_capacity(items.len());
        for (i, it) in items.iter().enumerate() {
            let (mins, maxs) = world_box(it);
            let c = Candidate {
                mins,
                maxs,
                id: i as u32,
            };
            if hide.is_none() || owner[i] != hide {
                primary.push(c);
            }
            casters.push(c);
        }
        if let Some((z, color)) = self.ground {
            let e = eye.as_vec3();
            let r = reach as f32;
            primary.push(Candidate {
                mins: Vec3::new(e.x - r, e.y - r, z - 0.01),
                maxs: Vec3::new(e.x + r, e.y + r, z),
                id: items.len() as u32,
            });
            items.push(item(
                Geom::Plane,
                Tf {
                    r: DQuat::IDENTITY,
                    t: DVec3::new(0.0, 0.0, z as f64),
                },
                color,
            ));
        }
        ReplayScene {
            items,
            primary,
            casters,
        }
    }
}

/// The robot's parts at state `st`.
fn robot_items(p: &RobotParts, st: &RobotState, out: &mut Vec<Item>) {
    let body = Tf {
        r: st.rotation,
        t: st.position,
    };
    let [cb, ct, cf] = p.colors;
    if let Some(m) = &p.body {
        out.push(item(Geom::Mesh(m.clone()), body, cb));
    }
    let flip: Vec<Tf> = p
        .flippers
        .iter()
        .enumerate()
        .map(|(i, (pivot, axis, _))| {
            let a = st.flippers.get(i).copied().unwrap_or(0.0);
            let r = if axis.length_squared() > 0.0 {
                DQuat::from_axis_angle(*axis, a)
            } else {
                DQuat::IDENTITY
            };
            // x' = pivot + R (x - pivot).
            body.mul(Tf {
                r,
                t: *pivot - r * *pivot,
            })
        })
        .collect();
    for ((_, _, arm), tf) in p.flippers.iter().zip(&flip) {
        if let Some(m) = arm {
            out.push(item(Geom::Mesh(m.clone()), *tf, cf));
        }
    }
    for (i, tr) in p.tracks.iter().enumerate() {
        let parent = usize::try_from(tr.parent)
            .ok()
            .and_then(|f| flip.get(f).copied())
            .unwrap_or(body);
        let s = st.belts.get(i).copied().unwrap_or(0.0);
        track_items(tr, parent, s, ct, out);
    }
}

/// A belt and its grousers at belt position `s`, its parent frame at `parent`.
fn track_items(tr: &TrackParts, parent: Tf, s: f64, color: Rgb, out: &mut Vec<Item>) {
    if let Some(m) = &tr.shell {
        out.push(item(Geom::Mesh(m.clone()), parent, color));
    }
    for (k, tf) in tr.grouser_frames(s) {
        out.push(item(
            Geom::Mesh(tr.grousers[k].clone()),
            parent.mul(tf),
            color,
        ));
    }
}

/// The world bounding box of a placed shape.
fn world_box(it: &Item) -> (Vec3, Vec3) {
    let (lo, hi) = it.geom.local_box();
    let (c, h) = ((lo + hi) / 2.0, (hi - lo) / 2.0);
    let m = Mat3::from_quat(it.rot);
    let abs = Mat3::from_cols(m.x_axis.abs(), m.y_axis.abs(), m.z_axis.abs());
    let wc = it.pos + it.rot * c;
    let wh = abs * h + Vec3::splat(1e-4);
    (wc - wh, wc + wh)
}

/// The shapes of one frame of a replay.
pub struct ReplayScene {
    items: Vec<Item>,
    primary: Vec<Candidate>,
    casters: Vec<Candidate>,
}

impl ReplayScene {
    /// Shapes in the frame (the ground counted).
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// Whether the frame holds no shape.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    fn local_hit(&self, id: u32, origin: Vec3, dir: Vec3, max: f32) -> Option<(f32, Vec3)> {
        let it = &self.items[id as usize];
        let o = it.inv * (origin - it.pos);
        let d = it.inv * dir;
        let hit = match &it.geom {
            Geom::Box(h) => shapes::ray_box(*h, o, d, max),
            Geom::Cylinder(hh, r) => shapes::ray_cylinder(*hh, *r, o, d, max),
            Geom::Plane => {
                if d.z == 0.0 {
                    return None;
                }
                let t = -o.z / d.z;
                ((0.0..=max).contains(&t)).then_some((t, Vec3::Z))
            }
            Geom::Mesh(m) => m
                .cast_local_ray_and_get_normal(&Ray::new(o, d), max, true)
                .map(|i| (i.time_of_impact, i.normal)),
        };
        hit.map(|(t, n)| (t, it.rot * n))
    }
}

impl RenderScene for ReplayScene {
    fn primary(&self) -> &[Candidate] {
        &self.primary
    }

    fn shadow_casters(&self) -> &[Candidate] {
        &self.casters
    }

    fn cast(&self, id: u32, origin: Vec3, dir: Vec3, max: f32) -> Option<Hit> {
        self.local_hit(id, origin, dir, max)
            .map(|(t, normal)| Hit { t, normal })
    }

    fn meets(&self, id: u32, origin: Vec3, dir: Vec3, max: f32) -> bool {
        self.local_hit(id, origin, dir, max).is_some()
    }

    fn color(&self, id: u32) -> Rgb {
        self.items[id as usize].color
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_belt_shell_is_closed_over_its_loop() {
        // A square loop in the x-z plane, lateral y.
        let pts = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(0.0, 0.0, 1.0),
        ];
        let lats = [DVec3::Y; 4];
        let m = belt_shell(&pts, &lats, 0.2, true).unwrap();
        // A ray along y through the loop's middle meets a side; one along x meets the belt.
        let side = m.cast_local_ray(&Ray::new(Vec3::new(0.5, -1.0, 0.5), Vec3::Y), 10.0, true);
        assert!((side.unwrap() - 0.9).abs() < 1e-5);
        let belt = m.cast_local_ray(&Ray::new(Vec3::new(-1.0, 0.0, 0.5), Vec3::X), 10.0, true);
        assert!((belt.unwrap() - 1.0).abs() < 1e-5);
    }
}
