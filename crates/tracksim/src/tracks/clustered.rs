//! Clustered grousers (`okada2020_clustered`, issue 16.2): the paper's segment links with
//! every [`GROUSERS_PER_COMPOUND`] consecutive grousers of a link in one compound collider, and
//! Rapier's contact clustering on.
//!
//! Rapier solves each contact manifold as one constraint, and the manifolds of one body one
//! after the other (they share the body): with one collider per grouser the bottom run of a
//! PackBot track is 13 manifolds of 4 points on one body, most of what the paper's method pays
//! per step (BENCHMARKS.md, the contact floor). In a compound, contact clustering merges the
//! manifolds whose normals agree within ~5 deg into one of at most 4 points
//! (`rapier3d::geometry::contact_clustering`): on flat ground a group of grousers stands on the
//! outer corners of its first and last grouser, the support the group's 16 points spanned.
//! Where the grousers meet a step edge, a riser or a tread, each contact plane is its own
//! cluster: the grousers' edges still hook.
//!
//! Three settings come with it (`world_settings`), each measured (tests/suite/issue_16_clustered.rs,
//! BENCHMARKS.md):
//! - groups, not whole links: 4 points for a whole bottom run cannot carry the pressure
//!   distribution along the track that skid steering turns against (the PackBot's spin turn
//!   nearly stopped: 0.53 rad in 6 s); groups of 4 grousers turn as single grousers do;
//! - Rapier's contacts are soft, a spring per solver point whose stiffness is proportional to
//!   the point's effective mass (`SpringCoefficients::cfm_coeff`): the same load on 4 times
//!   fewer points sinks deeper, so both contact natural frequencies are raised by
//!   [`CONTACT_FREQUENCY_SCALE`] = sqrt(4) (stiffness goes as its square);
//! - Coulomb friction (a friction row per point) instead of Rapier's default twist model, whose
//!   one twist row per manifold resisted the turn of a cluster much more than Coulomb friction.

use rapier3d::prelude::*;

/// Consecutive grousers of a link in one compound collider (on flat ground one cluster of at
/// most 4 points where they had 4 each). Groups of 3, 4 and 6 turned the PackBot in place at
/// 0.77, 0.76 and 0.77 of the no-slip rate (1 per compound 0.79, a whole link nearly not at
/// all; springs stiffened x4 in that sweep, x2 as shipped: 0.76 for 4); 4 ran faster than 3,
/// as fast as 6.
pub const GROUSERS_PER_COMPOUND: usize = 4;

/// Factor on Rapier's contact natural frequencies (30 Hz against dynamic bodies, 60 Hz against
/// fixed ones) under this method: sqrt([`GROUSERS_PER_COMPOUND`]) keeps the contact stiffness
/// of the grousers' points with one cluster's (the PackBot's flat ride height within 0.01 mm).
pub const CONTACT_FREQUENCY_SCALE: f32 = 2.0;

/// The world settings the method needs: contact clustering on, Coulomb friction, stiffer
/// contact springs.
pub fn world_settings(ip: &mut IntegrationParameters) {
    ip.contact_clustering = true;
    ip.friction_model = FrictionModel::Coulomb;
    ip.contact_softness.natural_frequency *= CONTACT_FREQUENCY_SCALE;
    ip.static_contact_softness.natural_frequency *= CONTACT_FREQUENCY_SCALE;
}

/// Puts a segment's grouser slots `parts` (pose, slot k of `n` on the loop) in their order
/// along the segment, so that groups hold neighbours: the slots of one segment are a run of
/// consecutive k, which wraps past `n - 1` to 0 on the segment holding the loop's first slot.
pub fn order_along_segment(parts: &mut [(Pose, usize)], n: usize) {
    parts.sort_by_key(|p| p.1);
    // A wrapped run (e.g. 38, 39, 0, 1 of 40) sorts as 0, 1, 38, 39: start after the gap.
    let wraps =
        parts.first().is_some_and(|p| p.1 == 0) && parts.last().is_some_and(|p| p.1 + 1 == n);
    if let Some(i) = parts
        .windows(2)
        .position(|w| w[1].1 > w[0].1 + 1)
        .filter(|_| wraps)
    {
        parts.rotate_left(i + 1);
    }
}

/// The compound of a link's grousers: `parts` (pose on the link, shape), for every phase of
/// a pattern of `m` shapes in turn: entry `w` holds grouser slot k with shape
/// `(k - w) mod m` (`SegmentLinks::reassign_shapes`'s rule). One entry for a single shape.
pub fn compounds(parts: &[(Pose, usize)], shapes: &[SharedShape]) -> Vec<SharedShape> {
    let m = shapes.len().max(1);
    (0..m)
        .map(|w| {
            SharedShape::compound(
                parts
                    .iter()
                    .map(|&(pose, k)| (pose, shapes[(k + m - w % m) % m].clone()))
                    .collect(),
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_segment_holding_the_first_slot_is_grouped_in_its_order_along_the_loop() {
        let mut parts: Vec<(Pose, usize)> = [0, 1, 38, 39, 2]
            .iter()
            .map(|&k| (Pose::IDENTITY, k))
            .collect();
        order_along_segment(&mut parts, 40);
        let ks: Vec<usize> = parts.iter().map(|p| p.1).collect();
        assert_eq!(ks, [38, 39, 0, 1, 2]);
        let mut plain: Vec<(Pose, usize)> =
            [5, 3, 4].iter().map(|&k| (Pose::IDENTITY, k)).collect();
        order_along_segment(&mut plain, 40);
        assert_eq!(plain.iter().map(|p| p.1).collect::<Vec<_>>(), [3, 4, 5]);
    }

    #[test]
    fn each_phase_gives_every_slot_the_shape_the_separate_grousers_would_have() {
        let shapes = [SharedShape::cuboid(0.1, 0.1, 0.1), SharedShape::ball(0.2)];
        let parts: Vec<(Pose, usize)> = (3..7)
            .map(|k| (Pose::from_translation(Vector::new(k as f32, 0.0, 0.0)), k))
            .collect();
        let phases = compounds(&parts, &shapes);
        assert_eq!(phases.len(), 2);
        for (w, c) in phases.iter().enumerate() {
            let c = c.as_compound().unwrap();
            for ((_, part), &(_, k)) in c.shapes().iter().zip(&parts) {
                // SegmentLinks::reassign_shapes: slot k gets shape (k - wraps) mod m.
                let want = (k + 2 - w % 2) % 2;
                assert_eq!(part.as_ball().is_some(), want == 1, "phase {w}, slot {k}");
            }
        }
    }
}
