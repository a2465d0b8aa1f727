//! The tracer: [`RenderScene`] (the shapes a frame may hit, each with its bounding box, and the
//! exact ray test of one shape) and [`render`], which fills a [`Frame`] with one primary ray
//! per pixel and, where the hit faces the sun, one shadow ray.
//!
//! Work is done by tiles of [`TILE`] x [`TILE`] pixels. For each tile, the shapes whose boxes
//! meet the tile's frustum (four planes through the camera) are kept; each pixel's ray is then
//! tested against those boxes only (a slab test) and cast against the shapes whose box it
//! crosses, nearest first wins. The tile's shadow rays start at its lit hit points and are
//! parallel: a shape can shadow them only if its box, seen along the sun, overlaps those
//! points and lies between the nearest of them and the farthest plus the shadow range; the
//! tree is walked with that test and only those shapes are tried. A scene of a few hundred
//! shapes costs a few tests per ray. Tiles are independent, so a rayon
//! pool renders rows of tiles in parallel into the same bytes as one thread.

use super::camera::{CameraPose, Intrinsics};
use super::color::Rgb;
use super::light::Light;
use glam::{DVec3, Mat3, Vec3};
use rapier3d::parry::bounding_volume::Aabb;
use rapier3d::parry::partitioning::{Bvh, BvhBuildStrategy};
use rayon::prelude::*;

/// Side of a tile, pixels.
pub const TILE: usize = 8;

/// A shape of the scene: its bounding box (scene frame, m) and its number for
/// [`RenderScene`]'s tests.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Candidate {
    /// Lower corner of the box, m.
    pub mins: Vec3,
    /// Upper corner of the box, m.
    pub maxs: Vec3,
    /// The shape's number in its scene.
    pub id: u32,
}

/// What a ray hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Time of impact, in units of the ray direction's length.
    pub t: f32,
    /// Unit surface normal at the hit, scene frame (either side: the tracer turns it towards
    /// the viewer).
    pub normal: Vec3,
}

/// A scene for one frame: its shapes, in one frame (m).
pub trait RenderScene: Sync {
    /// The shapes primary rays may hit.
    fn primary(&self) -> &[Candidate];
    /// The shapes that may cast shadows (`[]`: no shadows).
    fn shadow_casters(&self) -> &[Candidate];
    /// Ray `origin + s * dir`, `0 <= s <= max`, against shape `id` (solid).
    fn cast(&self, id: u32, origin: Vec3, dir: Vec3, max: f32) -> Option<Hit>;
    /// Whether ray `origin + s * dir`, `0 <= s <= max`, meets shape `id`.
    fn meets(&self, id: u32, origin: Vec3, dir: Vec3, max: f32) -> bool;
    /// The colour of shape `id`.
    fn color(&self, id: u32) -> Rgb;
    /// Whether shape `id` is convex: a ray leaving its surface outwards cannot meet it again,
    /// so it cannot shadow itself (default false: it is tested).
    fn convex(&self, _id: u32) -> bool {
        false
    }
}

/// An image and its depth, row-major from the top-left pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Red, green, blue per pixel (`3 * width * height` bytes).
    pub rgb: Vec<u8>,
    /// Depth along the optical axis, m (`+inf`: nothing within range; `-inf`: nearer than the
    /// minimum range, REP 117).
    pub depth: Vec<f32>,
}

impl Frame {
    /// A black frame of `width` x `height` pixels.
    pub fn new(width: usize, height: usize) -> Frame {
        Frame {
            width,
            height,
            rgb: vec![0; 3 * width * height],
            depth: vec![f32::INFINITY; width * height],
        }
    }
}

/// A hit facing the sun, waiting for its shadow ray.
struct Lit {
    /// Its pixel in the band.
    pixel: usize,
    /// Where the shadow ray starts (the hit, raised along the normal), m.
    point: Vec3,
    /// The surface normal, towards the viewer.
    normal: Vec3,
    /// The surface's colour.
    color: Rgb,
    /// The shape hit.
    id: u32,
}

/// Offset of a shadow ray's origin along the surface normal, m (clears f32 rounding of the
/// hit point a few metres from the origin).
const SHADOW_BIAS_M: f32 = 1e-3;

/// A camera for one frame: where it is, its pixel rays (camera frame) and their rotation
/// into the scene, its range, and the scene's boxes in a tree each.
struct View<'a> {
    origin: Vec3,
    rays: &'a [Vec3],
    rotation: Mat3,
    width: usize,
    primary: Bvh,
    casters: Bvh,
    corner: Box<dyn Fn(f64, f64) -> Vec3 + Sync + 'a>,
    min: f32,
    max: f32,
}

/// Renders `scene` seen from `pose` through a camera of `intrinsics` (`rays`: its
/// [`Intrinsics::pixel_rays`] in f32) into `frame` (of its size), with depth in `min..max` m.
/// `pool`: render rows of tiles on these threads (the same bytes as without).
#[allow(clippy::too_many_arguments)]
pub fn render(
    scene: &dyn RenderScene,
    intrinsics: &Intrinsics,
    rays: &[Vec3],
    pose: &CameraPose,
    light: &Light,
    min: f32,
    max: f32,
    pool: Option<&rayon::ThreadPool>,
    frame: &mut Frame,
) {
    let f = intrinsics.focal_px();
    let (w, h) = (intrinsics.width as f64, intrinsics.height as f64);
    let rot = pose.rotation;
    let tree = |c: &[Candidate]| {
        let boxes: Vec<Aabb> = c.iter().map(|c| Aabb::new(c.mins, c.maxs)).collect();
        Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes)
    };
    let view = View {
        origin: pose.position.as_vec3(),
        rays,
        rotation: Mat3::from_quat(rot.as_quat()),
        width: intrinsics.width,
        primary: tree(scene.primary()),
        casters: tree(scene.shadow_casters()),
        corner: Box::new(move |u, v| {
            (rot * DVec3::new(1.0, -(u - w / 2.0) / f, -(v - h / 2.0) / f)).as_vec3()
        }),
        min,
        max,
    };
    let band = |(tv, (rgb, depth)): (usize, (&mut [u8], &mut [f32]))| {
        band_of_tiles(scene, &view, light, tv * TILE, rgb, depth);
    };
    let wpx = frame.width;
    match pool {
        None => frame
            .rgb
            .chunks_mut(3 * wpx * TILE)
            .zip(frame.depth.chunks_mut(wpx * TILE))
            .enumerate()
            .for_each(band),
        Some(p) => p.install(|| {
            frame
                .rgb
                .par_chunks_mut(3 * wpx * TILE)
                .zip(frame.depth.par_chunks_mut(wpx * TILE))
                .enumerate()
                .for_each(band)
        }),
    }
}

/// The tiles of one band of rows starting at row `v0` (`rgb`, `depth`: the band's pixels).
fn band_of_tiles(
    scene: &dyn RenderScene,
    view: &View,
    light: &Light,
    v0: usize,
    rgb: &mut [u8],
    depth: &mut [f32],
) {
    let w = view.width;
    let rows = depth.len() / w;
    let mut near: Vec<Candidate> = Vec::new();
    let mut casters: Vec<Candidate> = Vec::new();
    let mut hits: Vec<Lit> = Vec::new();
    for u0 in (0..w).step_by(TILE) {
        let u1 = (u0 + TILE).min(w);
        let planes = frustum(view, u0, u1, v0, v0 + rows);
        near.clear();
        let all = scene.primary();
        near.extend(
            view.primary
                .leaves(|n| {
                    let b = n.aabb();
                    planes
                        .iter()
                        .all(|&p| meets_half_space(p, view.origin, b.mins, b.maxs))
                })
                .map(|leaf| all[leaf as usize]),
        );
        hits.clear();
        for r in 0..rows {
            for u in u0..u1 {
                let i = r * w + u;
                let d = view.rotation * view.rays[(v0 + r) * w + u];
                let Some((id, hit)) = nearest(scene, &near, view.origin, d, view.max) else {
                    rgb[3 * i..3 * i + 3].copy_from_slice(&Light::background(d.normalize()));
                    depth[i] = f32::INFINITY;
                    continue;
                };
                let n = if hit.normal.dot(d) > 0.0 {
                    -hit.normal
                } else {
                    hit.normal
                };
                depth[i] = if hit.t < view.min {
                    f32::NEG_INFINITY
                } else {
                    hit.t
                };
                let color = scene.color(id);
                // Facing the sun: lit unless a shadow ray says otherwise (below).
                let facing = n.dot(light.sun) > 0.0;
                rgb[3 * i..3 * i + 3]
                    .copy_from_slice(&Light::apply(color, light.factor(n, facing)));
                if facing {
                    let p = view.origin + d * hit.t + n * SHADOW_BIAS_M;
                    hits.push(Lit {
                        pixel: i,
                        point: p,
                        normal: n,
                        color,
                        id,
                    });
                }
            }
        }
        shade_shadows(scene, &view.casters, light, &hits, &mut casters, rgb);
    }
}

/// Darkens the hits of a tile that a shadow ray finds in shadow.
fn shade_shadows(
    scene: &dyn RenderScene,
    tree: &Bvh,
    light: &Light,
    hits: &[Lit],
    casters: &mut Vec<Candidate>,
    rgb: &mut [u8],
) {
    if hits.is_empty() || scene.shadow_casters().is_empty() {
        return;
    }
    // The tile's hits seen along the sun: their bounds across it (`e1`, `e2`) and along it.
    let sun = light.sun;
    let (e1, e2) = sun.any_orthonormal_pair();
    let axes = [e1, e2, sun];
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for h in hits {
        for k in 0..3 {
            let x = h.point.dot(axes[k]);
            lo[k] = lo[k].min(x);
            hi[k] = hi[k].max(x);
        }
    }
    hi[2] += light.shadow_range;
    casters.clear();
    let all = scene.shadow_casters();
    casters.extend(
        tree.leaves(|n| {
            // A box can shadow a hit only if it overlaps the hits across the sun and lies
            // between the nearest hit and the farthest one plus the shadow range along it.
            let b = n.aabb();
            let (c, h) = ((b.mins + b.maxs) / 2.0, (b.maxs - b.mins) / 2.0);
            (0..3).all(|k| {
                let (x, r) = (c.dot(axes[k]), h.dot(axes[k].abs()));
                x + r >= lo[k] && x - r <= hi[k]
            })
        })
        .map(|leaf| all[leaf as usize]),
    );
    if casters.is_empty() {
        return;
    }
    for h in hits {
        let own = scene.convex(h.id).then_some(h.id);
        let (p, s, r) = (h.point, light.sun, light.shadow_range);
        let shadowed = casters
            .iter()
            .any(|c| Some(c.id) != own && slab(c, p, s, r).is_some() && scene.meets(c.id, p, s, r));
        if shadowed {
            let i = h.pixel;
            rgb[3 * i..3 * i + 3]
                .copy_from_slice(&Light::apply(h.color, light.factor(h.normal, false)));
        }
    }
}

/// The nearest shape of `near` along `origin + s * d`, `0 <= s <= max`.
fn nearest(
    scene: &dyn RenderScene,
    near: &[Candidate],
    origin: Vec3,
    d: Vec3,
    max: f32,
) -> Option<(u32, Hit)> {
    let mut best: Option<(u32, Hit)> = None;
    for c in near {
        let lim = best.map_or(max, |b| b.1.t);
        if slab(c, origin, d, lim).is_none() {
            continue;
        }
        if let Some(h) = scene.cast(c.id, origin, d, lim)
            && best.is_none_or(|b| h.t < b.1.t)
        {
            best = Some((c.id, h));
        }
    }
    best
}

/// Entry time of ray `o + s * d` into box `c` within `0..=max`, if it enters.
fn slab(c: &Candidate, o: Vec3, d: Vec3, max: f32) -> Option<f32> {
    let inv = d.recip();
    let t0 = (c.mins - o) * inv;
    let t1 = (c.maxs - o) * inv;
    let lo = t0.min(t1);
    let hi = t0.max(t1);
    // NaN (0 * inf, a ray in a box's face plane) counts as inside that slab: `f32::max` and
    // `f32::min` return the other operand.
    let enter = lo.x.max(lo.y).max(lo.z).max(0.0);
    let exit = hi.x.min(hi.y).min(hi.z).min(max);
    (enter <= exit).then_some(enter)
}

/// The four inward normals of the planes bounding pixels `u0..u1` x `v0..v1` (pixel edges)
/// through the camera.
fn frustum(view: &View, u0: usize, u1: usize, v0: usize, v1: usize) -> [Vec3; 4] {
    let c = |u: usize, v: usize| (view.corner)(u as f64, v as f64);
    let (a, b, cc, d) = (c(u0, v0), c(u1, v0), c(u1, v1), c(u0, v1));
    let centre = a + b + cc + d;
    [a.cross(b), b.cross(cc), cc.cross(d), d.cross(a)]
        .map(|n| if n.dot(centre) < 0.0 { -n } else { n })
}

/// Whether the box `mins..maxs` reaches the side of the plane through `o` that normal `n`
/// points to.
fn meets_half_space(n: Vec3, o: Vec3, mins: Vec3, maxs: Vec3) -> bool {
    let p = Vec3::new(
        if n.x >= 0.0 { maxs.x } else { mins.x },
        if n.y >= 0.0 { maxs.y } else { mins.y },
        if n.z >= 0.0 { maxs.z } else { mins.z },
    );
    n.dot(p - o) >= 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slab_enters_boxes_it_crosses_only() {
        let c = Candidate {
            mins: Vec3::new(1.0, -1.0, -1.0),
            maxs: Vec3::new(2.0, 1.0, 1.0),
            id: 0,
        };
        assert_eq!(slab(&c, Vec3::ZERO, Vec3::X, 10.0), Some(1.0));
        assert_eq!(slab(&c, Vec3::ZERO, Vec3::X, 0.5), None);
        assert_eq!(slab(&c, Vec3::ZERO, -Vec3::X, 10.0), None);
        assert_eq!(slab(&c, Vec3::new(0.0, 2.0, 0.0), Vec3::X, 10.0), None);
        // Starting inside: enters at 0.
        assert_eq!(slab(&c, Vec3::new(1.5, 0.0, 0.0), Vec3::Y, 10.0), Some(0.0));
    }
}
