//! The terrain under a validation figure's side view.

use crate::model::Scenario;
use crate::output::{SideLine, side_view_terrain};
use crate::run::RunResult;

/// [`side_view_terrain`], with the ground profile extended under the whole drawing (runs and
/// terrain outlines), so the floor reaches the step.
pub(super) fn full_side_view(sc: &Scenario, runs: &[&RunResult]) -> (SideLine, Vec<SideLine>) {
    let (_, outlines) = side_view_terrain(sc, runs);
    let xs = runs
        .iter()
        .flat_map(|r| r.samples.iter().map(|s| s.pose.x))
        .chain(outlines.iter().flatten().map(|p| p.0));
    let (lo, hi) = xs.fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
    if lo > hi {
        return (Vec::new(), outlines);
    }
    let (lo, hi) = (lo - 0.5, hi);
    let n = 600;
    let pts: Vec<(f64, f64)> = (0..=n)
        .map(|i| (lo + (hi - lo) * i as f64 / n as f64, 0.0))
        .collect();
    let profile = pts
        .iter()
        .zip(sc.terrain.heights_at(&pts))
        .filter_map(|(p, z)| z.map(|z| (p.0, z)))
        .collect();
    (profile, outlines)
}
