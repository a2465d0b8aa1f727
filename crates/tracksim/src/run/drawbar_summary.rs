//! The steady state of a drawbar-pull run (`[drawbar]`, issue 14.5), for `summary.json`: one
//! point of the drawbar-pull / slip curve.

use crate::model::Scenario;
use crate::world::Sample;
use serde::Serialize;

/// Drawbar pull, slip and speed averaged over the steady window: the second half of the time
/// after the pull has fully risen.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct DrawbarSummary {
    /// The window averaged over (start, end), s.
    pub window_s: [f64; 2],
    /// Mean drawbar pull, N.
    pub mean_pull_n: f64,
    /// Mean slip ratio over the tracks (`1 - ground speed / belt speed` per track).
    pub mean_slip: f64,
    /// Mean forward traction summed over the tracks, N.
    pub mean_traction_n: f64,
    /// Mean forward speed of the chassis along its start heading, m/s.
    pub mean_speed_mps: f64,
}

/// The drawbar summary of a run of `sc` (None without `[drawbar]` or without samples in the
/// window).
pub fn drawbar_summary(sc: &Scenario, samples: &super::SampleLog) -> Option<DrawbarSummary> {
    let d = sc.drawbar.as_ref()?;
    let end = samples.last()?.t;
    let risen = d.start + d.ramp;
    let from = risen + 0.5 * (end - risen).max(0.0);
    let w = || samples.iter().filter(|s| s.t >= from);
    let first = w().next()?;
    let n = w().count() as f64;
    let (c, s) = (sc.start_yaw.cos(), sc.start_yaw.sin());
    let mean = |f: &dyn Fn(&Sample) -> f64| w().map(|s| f(&s)).sum::<f64>() / n;
    let tracks = first.slip.len().max(1) as f64;
    Some(DrawbarSummary {
        window_s: [from, end],
        mean_pull_n: mean(&|s| s.drawbar_n.unwrap_or(0.0)),
        mean_slip: mean(&|s| s.slip.iter().sum::<f64>() / tracks),
        mean_traction_n: mean(&|s| s.loads.iter().map(|l| l.traction_n).sum()),
        mean_speed_mps: mean(&|x| x.linvel[0] * c + x.linvel[1] * s),
    })
}
