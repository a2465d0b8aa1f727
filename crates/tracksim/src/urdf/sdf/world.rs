//! A `<world>`'s terrain: every `<static>` model's collision shapes (nested static models
//! included) as tracksim terrain entries in the world frame. A box becomes a box (its
//! rotation as yaw and pitch after swapping its axes if need be; a roll no swap removes is
//! refused), a plane facing up the ground, a mesh a mesh (STL or OBJ, turned about z only,
//! scaled uniformly), a heightmap a height field (a PNG, turned about z only; row 0 at +y and
//! white at `<size>` z above the base are assumed to be gz-sim's, not checked). Cylinders and
//! spheres are kept apart ([`WorldSolid`]: `tracksim import` writes each as a mesh) and
//! capsules refused: tracksim's terrain has no such entry. Non-static models
//! (the robot, loose objects) are not terrain and are skipped; `<include>` is refused.

use super::file::{Ctx, Node, child, children, is_static};
use super::geometry::{Shape, shape};
use super::pose::{Frames, pose_of};
use crate::error::SpecIssue;
use crate::spec::{BoxSpec, GroundSpec, HeightFieldSpec, MeshSpec, TerrainSpec, UpAxis};
use glam::{DAffine3, DMat3, DQuat, DVec3, EulerRot};

/// Friction of a terrain entry whose collision has no `<surface><friction><ode><mu>`
/// (tracksim's default; gz-sim's would be 1).
const DEFAULT_FRICTION: f64 = 0.6;

/// How far (rad, and in a rotation matrix's entries) a rotation may be from a yaw and a pitch
/// and still be read as one: SDF files write 1.5708 for pi/2 (3.7e-6 rad off), and 1e-4 rad
/// moves a corner of a 1 m box by 0.1 mm.
pub const ROTATION_TOLERANCE: f64 = 1e-4;

/// The yaw and pitch (rad, `R = Rz(yaw) Ry(pitch)`) and the full sizes (m, permuted) of a box
/// of `size` turned by `r`, when a swap of the box's axes makes `r` a yaw and a pitch.
pub(super) fn box_yaw_pitch(r: DMat3, size: [f64; 3]) -> Option<(f64, f64, [f64; 3])> {
    for perm in [
        [0, 1, 2],
        [1, 0, 2],
        [0, 2, 1],
        [2, 1, 0],
        [1, 2, 0],
        [2, 0, 1],
    ] {
        for signs in 0..8u32 {
            let s = |k: u32| if signs & (1 << k) == 0 { 1.0 } else { -1.0 };
            // Column i of P: the box axis perm[i], signed.
            let cols: Vec<DVec3> = (0..3)
                .map(|i| {
                    let mut v = DVec3::ZERO;
                    v[perm[i]] = s(i as u32);
                    v
                })
                .collect();
            let p = DMat3::from_cols(cols[0], cols[1], cols[2]);
            if p.determinant() < 0.0 {
                continue;
            }
            let q = r * p;
            let (yaw, pitch, roll) = DQuat::from_mat3(&q).to_euler(EulerRot::ZYX);
            if roll.abs() < ROTATION_TOLERANCE {
                let rebuilt = DMat3::from_quat(DQuat::from_euler(EulerRot::ZYX, yaw, pitch, 0.0));
                if (rebuilt - q)
                    .to_cols_array()
                    .iter()
                    .all(|v| v.abs() < ROTATION_TOLERANCE)
                {
                    return Some((yaw, pitch, perm.map(|k| size[k])));
                }
            }
        }
    }
    None
}

/// The yaw (rad) of `r` when it turns about z only.
fn yaw_only(r: DMat3) -> Option<f64> {
    let (yaw, pitch, roll) = DQuat::from_mat3(&r).to_euler(EulerRot::ZYX);
    (pitch.abs() < ROTATION_TOLERANCE && roll.abs() < ROTATION_TOLERANCE).then_some(yaw)
}

/// `<surface><friction><ode><mu>` of a collision.
fn friction(ctx: &Ctx, c: Node) -> Result<f64, SpecIssue> {
    match child(c, "surface")
        .and_then(|s| child(s, "friction"))
        .and_then(|s| child(s, "ode"))
        .and_then(|s| child(s, "mu"))
    {
        Some(mu) => Ok(super::file::numbers(ctx, mu, &[1])?[0]),
        None => Ok(DEFAULT_FRICTION),
    }
}

/// A cylinder or sphere of a static model: tracksim's terrain has no such entry, but a caller
/// can make it a mesh ([`super::WorldTerrain::solids`]).
#[derive(Clone, Debug)]
pub struct WorldSolid {
    /// Radius, m.
    pub radius: f64,
    /// Length along its z axis, m (`None`: a sphere).
    pub length: Option<f64>,
    /// Its frame in the world (a cylinder's axis is its z), m.
    pub pose: DAffine3,
    /// Friction coefficient.
    pub friction: f64,
    /// Why the terrain itself cannot hold it, with the element and line.
    pub issue: SpecIssue,
}

/// Adds collision `c` (its frame `x` in the world) to `t`, or its cylinder or sphere to
/// `solids`.
fn add(
    ctx: &Ctx,
    c: Node,
    x: DAffine3,
    t: &mut TerrainSpec,
    solids: &mut Vec<WorldSolid>,
) -> Result<(), SpecIssue> {
    let g = child(c, "geometry").ok_or_else(|| ctx.issue(c, "has no <geometry>"))?;
    let friction = friction(ctx, c)?;
    let refuse = |what: &str| {
        Err(ctx.issue(
            c,
            format!(
                "a {what}: tracksim's terrain has no {what} entry; replace it with boxes or a \
                 mesh"
            ),
        ))
    };
    match shape(ctx, g)? {
        Shape::Box(size) => {
            let (yaw, pitch, size) = box_yaw_pitch(x.matrix3, size).ok_or_else(|| {
                ctx.issue(
                    c,
                    "a box turned about its own axes in a way a yaw and a pitch cannot give \
                     (tracksim's terrain boxes turn about z and y only)",
                )
            })?;
            t.boxes.push(BoxSpec {
                centre_m: x.translation.to_array(),
                size_m: size,
                yaw_deg: yaw.to_degrees(),
                pitch_deg: pitch.to_degrees(),
                friction,
                soil: None,
                color: None,
            });
        }
        Shape::Plane(n) => {
            if (x.matrix3 * n).z < 1.0 - 1e-9 {
                return Err(ctx.issue(c, "a plane that does not face up (+z) cannot be the ground"));
            }
            if t.ground.is_some() {
                return Err(ctx.issue(c, "a second ground plane: tracksim has one ground"));
            }
            t.ground = Some(GroundSpec {
                friction,
                z_m: x.translation.z,
                soil: None,
                color: None,
            });
        }
        Shape::Mesh { file, scale } => {
            let yaw = yaw_only(x.matrix3)
                .ok_or_else(|| ctx.issue(c, "a terrain mesh may be turned about z only"))?;
            if scale
                .iter()
                .any(|s| (s - scale[0]).abs() > 1e-12 * scale[0].abs())
                || scale[0] <= 0.0
            {
                return Err(ctx.issue(
                    c,
                    format!("a terrain mesh takes one positive scale; got {scale:?}"),
                ));
            }
            let lower = file.to_ascii_lowercase();
            if !(lower.ends_with(".stl") || lower.ends_with(".obj"))
                || file.starts_with("package://")
            {
                return Err(ctx.issue(c, format!("{file}: a terrain mesh is an STL or OBJ file")));
            }
            t.meshes.push(MeshSpec {
                file: file.into(),
                scale: scale[0],
                translation_m: x.translation.to_array(),
                yaw_deg: yaw.to_degrees(),
                up_axis: UpAxis::Z,
                friction,
                color: None,
            });
        }
        Shape::Heightmap { file, size, pos } => {
            let yaw = yaw_only(x.matrix3)
                .ok_or_else(|| ctx.issue(c, "a heightmap may be turned about z only"))?;
            if !file
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("png"))
            {
                return Err(ctx.issue(c, "a heightmap is read from a PNG image only"));
            }
            let centre = x.transform_point3(DVec3::from_array(pos));
            t.heightfields.push(HeightFieldSpec {
                file,
                size_x_m: size[0],
                size_y_m: size[1],
                min_z_m: centre.z,
                max_z_m: centre.z + size[2],
                centre_m: [centre.x, centre.y],
                yaw_deg: yaw.to_degrees(),
                friction,
                color: None,
            });
        }
        Shape::Empty => {}
        Shape::Cylinder { radius, length } => solids.push(WorldSolid {
            radius,
            length: Some(length),
            pose: x,
            friction,
            issue: refuse("cylinder").unwrap_err(),
        }),
        Shape::Sphere(radius) => solids.push(WorldSolid {
            radius,
            length: None,
            pose: x,
            friction,
            issue: refuse("sphere").unwrap_err(),
        }),
        Shape::Capsule { .. } => return refuse("capsule"),
    }
    Ok(())
}

/// Adds the collisions of static model `m` (its frame `x` in the world) and of its nested
/// models to `t`; what cannot be added goes to `left_out`.
fn add_model(
    ctx: &Ctx,
    m: Node,
    x: DAffine3,
    t: &mut TerrainSpec,
    solids: &mut Vec<WorldSolid>,
    left_out: &mut Vec<SpecIssue>,
) {
    let frames = Frames::read(ctx, m, left_out);
    for l in children(m, "link") {
        let name = l.attribute("name").unwrap_or_default();
        for c in children(l, "collision") {
            let placed =
                pose_of(ctx, c).and_then(|p| frames.place(&p, name).map_err(|e| ctx.issue(c, e)));
            match placed.and_then(|p| add(ctx, c, x * p, t, solids)) {
                Ok(()) => {}
                Err(e) => left_out.push(e),
            }
        }
    }
    for n in children(m, "model") {
        match pose_of(ctx, n) {
            Ok(p) if p.relative_to.is_none() => add_model(ctx, n, x * p.x, t, solids, left_out),
            Ok(_) => left_out.push(ctx.issue(n, "a nested model's pose relative_to is not read")),
            Err(e) => left_out.push(e),
        }
    }
    for n in children(m, "include") {
        left_out.push(include(ctx, n));
    }
}

/// The problem of an `<include>`.
pub(super) fn include(ctx: &Ctx, n: Node) -> SpecIssue {
    let uri = child(n, "uri").map(super::file::text).unwrap_or_default();
    let web = uri.to_ascii_lowercase().starts_with("http");
    ctx.issue(
        n,
        format!(
            "an <include> ({}) is not read{}: expand it, e.g. `gz sdf -p {} > expanded.sdf`",
            crate::check::echoed(uri),
            if web {
                " (a Fuel model: nothing is downloaded at run time)"
            } else {
                ""
            },
            ctx.file()
        ),
    )
}

/// What a world's static models give: terrain entries, cylinders and spheres, and what could
/// not be read.
pub(super) type Read = (TerrainSpec, Vec<WorldSolid>, Vec<SpecIssue>);

/// The terrain of the first `<world>` of the parsed file, its solids, and what could not be
/// read.
pub(super) fn terrain(ctx: &Ctx) -> Result<Read, Vec<SpecIssue>> {
    let root = ctx.doc.root_element();
    let Some(w) = child(root, "world") else {
        return Err(vec![SpecIssue::new(
            ctx.key,
            format!("{} has no <world>", ctx.path.display()),
        )]);
    };
    let mut t = TerrainSpec::default();
    let mut solids = Vec::new();
    let mut left_out = Vec::new();
    for n in w.children().filter(|n| n.is_element()) {
        match n.tag_name().name() {
            "include" => left_out.push(include(ctx, n)),
            "model" if is_static(n) => match pose_of(ctx, n) {
                Ok(p) if p.relative_to.as_deref().is_none_or(|r| r == "world") => {
                    add_model(ctx, n, p.x, &mut t, &mut solids, &mut left_out)
                }
                Ok(_) => left_out.push(ctx.issue(
                    n,
                    "its <pose relative_to> names another frame: a terrain model's pose is read \
                     in the world frame only",
                )),
                Err(e) => left_out.push(e),
            },
            _ => {}
        }
    }
    Ok((t, solids, left_out))
}
