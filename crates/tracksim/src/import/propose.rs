//! A track path proposed from a track link's collision shapes: cylinders whose axis is the
//! link's y (its axles) are pulleys, and the belt is the convex hull of their circles in the
//! link's x-z plane; a link with boxes only (or a mesh's hull) gets the stadium of its x-z
//! extent. Every choice is written down ([`ProposedTrack::guesses`]).

use super::hull::circles_on_hull;
use crate::geometry::{CollisionShape, Pulley, TrackPath};
use crate::spec::{GrouserShapeSpec, GrouserSpec};
use crate::urdf::ImportedLink;
use glam::{DAffine3, DVec3};

/// Belt mass as a fraction of the track link's mass when the model does not give the belt's
/// own (the belt is added on top: the link's mass stays in the body it is part of).
pub const BELT_MASS_FRACTION: f64 = 0.1;
/// The smallest belt mass proposed, kg (a belt of a massless link).
pub const MIN_BELT_MASS_KG: f64 = 0.05;
/// Default grouser pitch when the model has no pattern, m.
pub const DEFAULT_GROUSER_PITCH_M: f64 = 0.05;
/// Default grouser (a box) length along the belt, m.
pub const DEFAULT_GROUSER_LENGTH_M: f64 = 0.01;
/// Default grouser height, m (it raises the robot by as much above the model's belt).
pub const DEFAULT_GROUSER_HEIGHT_M: f64 = 0.005;

/// The shape of a proposed path, in the track link's frame.
#[derive(Clone, Debug, PartialEq)]
pub enum ProposedPath {
    /// Pulleys the belt wraps (`[tracks.path] pulleys`), in order around the loop.
    Pulleys(Vec<Pulley>),
    /// One full circle (`[tracks.path] wheel`): a lugged wheel.
    Wheel(Pulley),
}

/// One track proposed for a vehicle file.
#[derive(Clone, Debug)]
pub struct ProposedTrack {
    /// The track's name in the vehicle file and in commands.
    pub name: String,
    /// The URDF link that carries it (`tracks.link`).
    pub link: String,
    /// Why this link is a track.
    pub why: String,
    /// The path, in the link's frame.
    pub path: ProposedPath,
    /// y of the track's mid-plane in the link's frame, m.
    pub plane_y: f64,
    /// y of the mid-plane in the chassis frame (arms at angle 0), m.
    pub chassis_y: f64,
    /// Belt width, m.
    pub width: f64,
    /// Belt mass, kg.
    pub belt_mass: f64,
    /// Belt friction coefficient (`None`: tracksim's default, 0.6).
    pub friction: Option<f64>,
    /// Sprocket pitch radius, m.
    pub sprocket_pitch_radius: Option<f64>,
    /// Grousers.
    pub grousers: Option<GrouserSpec>,
    /// The shapes or segments the path was made from, one line each.
    pub sources: Vec<String>,
    /// Every guess made, one line each.
    pub guesses: Vec<String>,
}

impl ProposedTrack {
    /// The loop's length at the grouser footprints, m (`None` if tracksim refuses the path).
    pub fn perimeter(&self) -> Option<f64> {
        match &self.path {
            ProposedPath::Pulleys(p) => TrackPath::from_pulleys(p, self.plane_y)
                .ok()
                .map(|t| t.length()),
            ProposedPath::Wheel(w) => Some(std::f64::consts::TAU * w.radius),
        }
    }

    /// The path's extent in z (its height, pulleys' rims included), m.
    pub fn height(&self) -> f64 {
        let rims: Vec<(f64, f64)> = match &self.path {
            ProposedPath::Pulleys(p) => {
                p.iter().map(|q| (q.z - q.radius, q.z + q.radius)).collect()
            }
            ProposedPath::Wheel(w) => vec![(w.z - w.radius, w.z + w.radius)],
        };
        let lo = rims.iter().map(|r| r.0).fold(f64::MAX, f64::min);
        let hi = rims.iter().map(|r| r.1).fold(f64::MIN, f64::max);
        hi - lo
    }
}

/// What the link's shapes give, in its frame.
#[derive(Default)]
struct Parts {
    /// Circles of y-axis cylinders: (pulley, y of its centre, its length).
    circles: Vec<(Pulley, f64, f64)>,
    /// Points of boxes, meshes and other shapes.
    points: Vec<DVec3>,
    /// True when a mesh hull (or a turned box) gave points.
    hull: bool,
    /// One line per shape.
    sources: Vec<String>,
}

fn collect(s: &CollisionShape, to_link: DAffine3, out: &mut Parts) {
    match s {
        CollisionShape::Cylinder {
            radius,
            half_length,
            centre,
            rotation,
        } => {
            let c = to_link.transform_point3(*centre);
            let axis = to_link.transform_vector3(*rotation * DVec3::Z);
            if axis.y.abs() > 0.999 {
                out.circles.push((
                    Pulley {
                        x: c.x,
                        z: c.z,
                        radius: *radius,
                    },
                    c.y,
                    2.0 * half_length,
                ));
                out.sources.push(format!(
                    "cylinder r {radius:.4} m, length {:.4} m, axis y at x {:.4}, z {:.4} m: a pulley",
                    2.0 * half_length,
                    c.x,
                    c.z
                ));
            } else {
                let (lo, hi) = s.bounds();
                out.points
                    .extend([lo, hi].map(|p| to_link.transform_point3(p)));
                out.sources.push(format!(
                    "cylinder r {radius:.4} m across the belt's plane: its bounds only"
                ));
            }
        }
        CollisionShape::Box { half, centre } => {
            for k in 0..8 {
                let sgn = DVec3::new(
                    if k & 1 == 0 { -1.0 } else { 1.0 },
                    if k & 2 == 0 { -1.0 } else { 1.0 },
                    if k & 4 == 0 { -1.0 } else { 1.0 },
                );
                out.points
                    .push(to_link.transform_point3(*centre + *half * sgn));
            }
            out.sources.push(format!(
                "box {:.4} x {:.4} x {:.4} m",
                2.0 * half.x,
                2.0 * half.y,
                2.0 * half.z
            ));
        }
        CollisionShape::Convex(p) => {
            out.points
                .extend(p.iter().map(|q| to_link.transform_point3(*q)));
            out.hull = true;
            out.sources.push(format!(
                "convex hull of {} points (a mesh or a turned box)",
                p.len()
            ));
        }
        CollisionShape::Sphere { radius, centre } => {
            out.points.extend(
                [-1.0, 1.0].map(|s| to_link.transform_point3(*centre + DVec3::splat(s * radius))),
            );
            out.sources
                .push(format!("sphere r {radius:.4} m: its bounds only"));
        }
        CollisionShape::Compound(v) => v.iter().for_each(|s| collect(s, to_link, out)),
    }
}

/// The stadium of the x-z extent of `points` (two pulleys of half the height at the ends).
fn stadium(points: &[DVec3]) -> Option<(Vec<Pulley>, f64, f64)> {
    let lo = points.iter().fold(DVec3::splat(f64::MAX), |a, p| a.min(*p));
    let hi = points.iter().fold(DVec3::splat(f64::MIN), |a, p| a.max(*p));
    let r = (hi.z - lo.z) / 2.0;
    let zc = (hi.z + lo.z) / 2.0;
    if !(r > 1e-4 && hi.x - lo.x > 2.0 * r + 1e-4) {
        return None;
    }
    Some((
        vec![
            Pulley {
                x: lo.x + r,
                z: zc,
                radius: r,
            },
            Pulley {
                x: hi.x - r,
                z: zc,
                radius: r,
            },
        ],
        (lo.y + hi.y) / 2.0,
        hi.y - lo.y,
    ))
}

/// The default grousers of a model that has none: small boxes at [`DEFAULT_GROUSER_PITCH_M`].
pub fn default_grousers(perimeter: f64) -> GrouserSpec {
    GrouserSpec {
        count: ((perimeter / DEFAULT_GROUSER_PITCH_M).round() as usize).max(8),
        offset_m: 0.0,
        shapes: vec![GrouserShapeSpec::Box {
            length_m: DEFAULT_GROUSER_LENGTH_M,
            height_m: DEFAULT_GROUSER_HEIGHT_M,
            width_m: None,
            shift_m: 0.0,
        }],
    }
}

/// Proposes the track of `link` from its collision shapes and those of `wheels`, the links
/// turning inside it on continuous joints (road wheels, sprockets, idlers: gz-sim's
/// `track_drive` has only these) (`Err`: why none can be).
pub fn from_shapes(
    name: &str,
    link: &ImportedLink,
    wheels: &[&ImportedLink],
    why: String,
) -> Result<ProposedTrack, String> {
    let to_link = link.pose.inverse();
    let mut parts = Parts::default();
    for s in link
        .shapes
        .iter()
        .chain(wheels.iter().flat_map(|w| &w.shapes))
    {
        collect(s, to_link, &mut parts);
    }
    let mut guesses = Vec::new();
    if !wheels.is_empty() {
        guesses.push(format!(
            "shapes: the link's own and those of the {} link(s) turning inside it on continuous \
             joints ({})",
            wheels.len(),
            wheels
                .iter()
                .map(|w| w.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    let circles: Vec<Pulley> = parts.circles.iter().map(|c| c.0).collect();
    let on_hull = circles_on_hull(&circles);
    let (pulleys, plane_y, width) = if on_hull.len() >= 2 {
        let n = parts.circles.len() as f64;
        let y = parts.circles.iter().map(|c| c.1).sum::<f64>() / n;
        let w = parts.circles.iter().map(|c| c.2).fold(0.0, f64::max);
        guesses.push(format!(
            "path: the convex hull of the {} y-axis cylinder(s) in the link's x-z plane ({} on \
             the hull); boxes and other shapes are not part of the path",
            parts.circles.len(),
            on_hull.len()
        ));
        guesses.push(format!("width: the longest pulley cylinder, {w:.4} m"));
        (on_hull, y, w)
    } else if let Some((p, y, w)) = stadium(&parts.points) {
        guesses.push(format!(
            "path: a stadium round the x-z extent of the link's {} (ends of radius half its \
             height){}",
            if parts.hull { "hull(s)" } else { "box(es)" },
            if parts.hull {
                "; a GUESS: the mesh's outline is not fitted, only its extent"
            } else {
                ""
            }
        ));
        guesses.push(format!("width: the shapes' y extent, {w:.4} m"));
        (p, y, w)
    } else {
        return Err(format!(
            "link {} has no shape a belt can be made from (y-axis cylinders, or a box or mesh \
             longer than it is high): {}",
            link.name,
            if parts.sources.is_empty() {
                "no collision shapes".to_string()
            } else {
                parts.sources.join("; ")
            }
        ));
    };
    let belt_mass = (BELT_MASS_FRACTION * link.mass).max(MIN_BELT_MASS_KG);
    guesses.push(format!(
        "belt mass: {:.0} % of the link's {:.3} kg = {belt_mass:.3} kg (at least {MIN_BELT_MASS_KG} \
         kg), added on top of the link's mass",
        BELT_MASS_FRACTION * 100.0,
        link.mass
    ));
    let chassis_y = link.pose.transform_point3(DVec3::new(0.0, plane_y, 0.0)).y;
    let mut t = ProposedTrack {
        name: name.to_string(),
        link: link.name.clone(),
        why,
        path: ProposedPath::Pulleys(pulleys),
        plane_y,
        chassis_y,
        width,
        belt_mass,
        friction: None,
        sprocket_pitch_radius: None,
        grousers: None,
        sources: parts.sources,
        guesses,
    };
    let perimeter = t
        .perimeter()
        .ok_or_else(|| format!("link {}: tracksim refuses the proposed pulleys", link.name))?;
    let g = default_grousers(perimeter);
    t.guesses.push(format!(
        "grousers: the model has none; {} boxes {DEFAULT_GROUSER_LENGTH_M} m long and \
         {DEFAULT_GROUSER_HEIGHT_M} m high (pitch {:.1} mm), which raise the robot by {} mm",
        g.count,
        perimeter / g.count as f64 * 1000.0,
        DEFAULT_GROUSER_HEIGHT_M * 1000.0
    ));
    t.grousers = Some(g);
    t.guesses
        .push("friction: tracksim's default 0.6 (the model gives none for this link)".into());
    Ok(t)
}
