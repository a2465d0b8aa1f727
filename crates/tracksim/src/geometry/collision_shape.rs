//! A compiled collision shape in its owner's frame ([`CollisionShape`]): a box, a convex
//! hull, a ball, a cylinder or several of them.

use glam::{DQuat, DVec3};

/// A compiled collision shape in its owner's frame.
#[derive(Clone, Debug, PartialEq)]
pub enum CollisionShape {
    /// Box with half extents, centred at `centre`, m.
    Box {
        /// Half extents, m.
        half: DVec3,
        /// Centre, m.
        centre: DVec3,
    },
    /// Convex hull of points, m.
    Convex(Vec<DVec3>),
    /// A ball (URDF `<sphere>`).
    Sphere {
        /// Radius, m.
        radius: f64,
        /// Centre, m.
        centre: DVec3,
    },
    /// A cylinder along the z axis of its frame (URDF `<cylinder>`).
    Cylinder {
        /// Radius, m.
        radius: f64,
        /// Half the length, m.
        half_length: f64,
        /// Centre, m.
        centre: DVec3,
        /// Orientation of its frame (its axis is `rotation * z`).
        rotation: DQuat,
    },
    /// Several shapes on one body (a URDF link's collisions, fixed links merged in).
    Compound(Vec<CollisionShape>),
}

impl CollisionShape {
    /// Axis-aligned bounds (min, max), m.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let empty = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
        match self {
            CollisionShape::Box { half, centre } => (*centre - *half, *centre + *half),
            CollisionShape::Convex(p) => {
                p.iter().fold(empty, |(lo, hi), q| (lo.min(*q), hi.max(*q)))
            }
            CollisionShape::Sphere { radius, centre } => (*centre - *radius, *centre + *radius),
            CollisionShape::Cylinder {
                radius,
                half_length,
                centre,
                rotation,
            } => {
                let a = *rotation * DVec3::Z;
                let e = (a * *half_length).abs()
                    + DVec3::new(
                        (1.0 - a.x * a.x).max(0.0).sqrt(),
                        (1.0 - a.y * a.y).max(0.0).sqrt(),
                        (1.0 - a.z * a.z).max(0.0).sqrt(),
                    ) * *radius;
                (*centre - e, *centre + e)
            }
            CollisionShape::Compound(parts) => parts.iter().fold(empty, |(lo, hi), p| {
                let (a, b) = p.bounds();
                (lo.min(a), hi.max(b))
            }),
        }
    }

    /// Points whose convex hull is the shape (a ball and a cylinder sampled: 24 around, for
    /// drawing), m; empty for a compound (see [`CollisionShape::parts`]).
    pub fn hull_points(&self) -> Vec<DVec3> {
        const AROUND: usize = 24;
        let ring = |k: usize| {
            let a = std::f64::consts::TAU * k as f64 / AROUND as f64;
            (a.cos(), a.sin())
        };
        match self {
            CollisionShape::Box { half, centre } => (0..8)
                .map(|i| {
                    let s = |b: usize| if i & b != 0 { 1.0 } else { -1.0 };
                    *centre + DVec3::new(s(1) * half.x, s(2) * half.y, s(4) * half.z)
                })
                .collect(),
            CollisionShape::Convex(p) => p.clone(),
            CollisionShape::Sphere { radius, centre } => {
                let mut pts = vec![*centre + DVec3::Z * *radius, *centre - DVec3::Z * *radius];
                for lat in 1..AROUND / 2 {
                    let phi = std::f64::consts::PI * lat as f64 / (AROUND / 2) as f64;
                    for k in 0..AROUND {
                        let (c, s) = ring(k);
                        pts.push(
                            *centre + DVec3::new(c * phi.sin(), s * phi.sin(), phi.cos()) * *radius,
                        );
                    }
                }
                pts
            }
            CollisionShape::Cylinder {
                radius,
                half_length,
                centre,
                rotation,
            } => (0..AROUND)
                .flat_map(|k| {
                    let (c, s) = ring(k);
                    [-1.0, 1.0].map(|z| {
                        *centre + *rotation * DVec3::new(c * radius, s * radius, z * half_length)
                    })
                })
                .collect(),
            CollisionShape::Compound(_) => Vec::new(),
        }
    }

    /// The simple shapes it is made of (itself, or a compound's parts).
    pub fn parts(&self) -> Vec<&CollisionShape> {
        match self {
            CollisionShape::Compound(p) => p.iter().flat_map(|s| s.parts()).collect(),
            s => vec![s],
        }
    }
}
