//! The running world as a [`RenderScene`]: [`WorldShapes`] gathers, once per frame through
//! the broad phase the step built, the colliders a camera's primary rays may hit (those its
//! groups see, within its reach) and those that may cast shadows into its view (every
//! collider within reach plus the shadow rays' length, the robots included: a robot casts its
//! shadow), each with its bounding box and its colour ([`crate::world::Appearance`]).
//! [`WorldScene`] answers the tracer's exact tests with the colliders' own shapes. Also the
//! chase camera's frame of a robot ([`render_chase`]).

use crate::render::{
    self, CameraPose, Candidate, ChaseCamera, Frame, Hit, Light, RenderScene, Rgb, shapes,
};
use crate::world::Simulation;
use glam::{DQuat, DVec3, Vec3};
use rapier3d::parry::bounding_volume::Aabb;
use rapier3d::prelude::*;

/// A gathered collider's shape, with what its closed-form ray test needs (no collider lookup
/// per ray).
#[derive(Clone, Copy)]
enum Prim {
    /// A box not turned in the world (the ground tile, most terrain boxes): centre and half
    /// extents, m.
    AxisBox(Vec3, Vec3),
    /// A box: half extents, m.
    Cuboid(Vec3),
    /// A cylinder along its local y: half height and radius, m.
    Cylinder(f32, f32),
    /// Any other shape: through parry.
    Other,
}

/// The colliders of one frame (buffers reused between frames).
#[derive(Default)]
pub struct WorldShapes {
    handles: Vec<ColliderHandle>,
    prims: Vec<(Prim, Pose)>,
    colors: Vec<Rgb>,
    primary: Vec<Candidate>,
    casters: Vec<Candidate>,
}

fn v(p: Vec3) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

fn g(p: Vector) -> Vec3 {
    Vec3::new(p.x, p.y, p.z)
}

impl WorldShapes {
    /// Gathers the colliders of `sim` for a camera at `centre` (Rapier world, m) seeing
    /// `reach` m with `groups`, and shadow rays of `shadow_range` m (0: no shadows).
    pub fn gather(
        &mut self,
        sim: &Simulation,
        centre: DVec3,
        reach: f64,
        groups: InteractionGroups,
        shadow_range: f64,
    ) {
        self.handles.clear();
        self.prims.clear();
        self.colors.clear();
        self.primary.clear();
        self.casters.clear();
        let r = (reach + shadow_range) as f32;
        let c = Vector::new(centre.x as f32, centre.y as f32, centre.z as f32);
        let (lo, hi) = (
            c - Vector::splat(reach as f32),
            c + Vector::splat(reach as f32),
        );
        let qp = sim.world.query_pipeline();
        for (h, co) in
            qp.intersect_aabb_conservative(Aabb::new(c - Vector::splat(r), c + Vector::splat(r)))
        {
            let bb = co.compute_aabb();
            let cand = Candidate {
                mins: g(bb.mins),
                maxs: g(bb.maxs),
                id: self.handles.len() as u32,
            };
            let seen = co.collision_groups().test(groups)
                && bb.maxs.cmpge(lo).all()
                && bb.mins.cmple(hi).all();
            if !(seen || shadow_range > 0.0) {
                continue;
            }
            self.handles.push(h);
            let pose = *co.position();
            let prim = if let Some(b) = co.shape().as_cuboid() {
                if pose.rotation == glam::Quat::IDENTITY {
                    Prim::AxisBox(pose.translation, b.half_extents)
                } else {
                    Prim::Cuboid(b.half_extents)
                }
            } else if let Some(c) = co.shape().as_cylinder() {
                Prim::Cylinder(c.half_height, c.radius)
            } else {
                Prim::Other
            };
            self.prims.push((prim, pose));
            self.colors.push(sim.appearance().color(h));
            if seen {
                self.primary.push(cand);
            }
            if shadow_range > 0.0 {
                self.casters.push(cand);
            }
        }
    }
}

/// The world seen by one camera for one frame.
pub struct WorldScene<'a> {
    /// The world.
    pub sim: &'a Simulation,
    /// Its colliders gathered for the frame.
    pub shapes: &'a WorldShapes,
}

impl RenderScene for WorldScene<'_> {
    fn primary(&self) -> &[Candidate] {
        &self.shapes.primary
    }

    fn shadow_casters(&self) -> &[Candidate] {
        &self.shapes.casters
    }

    fn cast(&self, id: u32, origin: Vec3, dir: Vec3, max: f32) -> Option<Hit> {
        let (prim, pose) = &self.shapes.prims[id as usize];
        let local = || {
            (
                pose.inverse_transform_point(origin),
                pose.inverse_transform_vector(dir),
            )
        };
        let closed = |hit: Option<(f32, Vec3)>| {
            hit.map(|(t, n)| Hit {
                t,
                normal: pose.rotation * n,
            })
        };
        match *prim {
            Prim::AxisBox(c, half) => {
                shapes::ray_box(half, origin - c, dir, max).map(|(t, normal)| Hit { t, normal })
            }
            Prim::Cuboid(half) => {
                let (o, d) = local();
                closed(shapes::ray_box(half, o, d, max))
            }
            Prim::Cylinder(hh, r) => {
                let (o, d) = local();
                closed(shapes::ray_cylinder(hh, r, o, d, max))
            }
            Prim::Other => {
                let co = &self.sim.world.colliders[self.shapes.handles[id as usize]];
                let i = co.shape().cast_ray_and_get_normal(
                    pose,
                    &Ray::new(v(origin), v(dir)),
                    max,
                    true,
                )?;
                Some(Hit {
                    t: i.time_of_impact,
                    normal: g(i.normal),
                })
            }
        }
    }

    fn meets(&self, id: u32, origin: Vec3, dir: Vec3, max: f32) -> bool {
        let (prim, pose) = &self.shapes.prims[id as usize];
        if let Prim::AxisBox(c, half) = *prim {
            return shapes::ray_box(half, origin - c, dir, max).is_some();
        }
        if let Prim::Cuboid(half) = *prim {
            let (o, d) = (
                pose.inverse_transform_point(origin),
                pose.inverse_transform_vector(dir),
            );
            return shapes::ray_box(half, o, d, max).is_some();
        }
        let co = &self.sim.world.colliders[self.shapes.handles[id as usize]];
        co.shape()
            .intersects_ray(pose, &Ray::new(v(origin), v(dir)), max)
    }

    fn convex(&self, id: u32) -> bool {
        !matches!(self.shapes.prims[id as usize].0, Prim::Other)
    }

    fn color(&self, id: u32) -> Rgb {
        self.shapes.colors[id as usize]
    }
}

/// The position (Rapier world, m) and orientation of the selected robot's chassis.
pub fn body_frame(sim: &Simulation) -> (DVec3, DQuat) {
    let p = sim.world.bodies[sim.body_handle()].position();
    let r = p.rotation;
    (
        DVec3::new(
            p.translation.x as f64,
            p.translation.y as f64,
            p.translation.z as f64,
        ),
        DQuat::from_xyzw(r.x as f64, r.y as f64, r.z as f64, r.w as f64).normalize(),
    )
}

/// How far a chase camera sees, m.
pub const CHASE_RANGE_M: f32 = 30.0;

/// Renders the selected robot of `sim` seen by `chase` (the robot itself in view, shadows on)
/// into `frame` (of the chase camera's size), reusing `shapes` between frames.
pub fn render_chase(
    sim: &Simulation,
    chase: &ChaseCamera,
    shapes: &mut WorldShapes,
    frame: &mut Frame,
) {
    let (p, q) = body_frame(sim);
    let pose: CameraPose = chase.pose(p, q);
    let light = Light::default();
    let i = chase.intrinsics;
    let corner = i.corner_factor();
    shapes.gather(
        sim,
        pose.position,
        CHASE_RANGE_M as f64 * corner,
        InteractionGroups::all(),
        light.shadow_range as f64,
    );
    let scene = WorldScene { sim, shapes };
    let rays = i.pixel_rays_f32();
    render::render(
        &scene,
        &i,
        &rays,
        &pose,
        &light,
        0.0,
        CHASE_RANGE_M,
        None,
        frame,
    );
}
