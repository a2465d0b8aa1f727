//! What a run on soil shows (issue 30): per track, the mean and largest sinkage, the mean soil
//! thrust and compaction resistance, and the rut grid's memory at the end.

use crate::world::{RutGridStats, Simulation};
use serde::Serialize;

/// One track on soil.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct TrackSoilSummary {
    /// Track name.
    pub track: String,
    /// Mean load-weighted sinkage over the samples on soil, m.
    pub mean_sinkage_m: f64,
    /// Largest sinkage of a loaded patch, m.
    pub max_sinkage_m: f64,
    /// Mean soil thrust along the chassis's x over the samples on soil, N.
    pub mean_thrust_n: f64,
    /// Mean compaction resistance, N.
    pub mean_compaction_n: f64,
    /// Mean soil normal load, N.
    pub mean_normal_n: f64,
}

/// A run on soil.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SoilSummary {
    /// Per track, in track order.
    pub tracks: Vec<TrackSoilSummary>,
    /// The rut grid at the end: tiles held, bytes, tiles forgotten, the bound.
    pub rut_grid: RutGridStats,
}

/// The soil summary of a run (None without soil).
pub fn soil_summary(sim: &Simulation, samples: &crate::run::SampleLog) -> Option<SoilSummary> {
    let rut_grid = sim.rut_grid_stats()?;
    let tracks = sim
        .track_names()
        .iter()
        .enumerate()
        .map(|(i, name)| {
            // One pass (the samples may be on disk); sums from -0.0 in order, as
            // `Iterator::sum` adds.
            let (mut count, mut max_sinkage) = (0usize, 0.0f64);
            let mut sums = [-0.0f64; 4];
            for g in samples
                .iter()
                .filter_map(|s| s.soil.get(i).copied())
                .filter(|g| g.normal_n > 0.0)
            {
                count += 1;
                max_sinkage = max_sinkage.max(g.max_sinkage_m);
                for (sum, v) in
                    sums.iter_mut()
                        .zip([g.sinkage_m, g.thrust_n, g.compaction_n, g.normal_n])
                {
                    *sum += v;
                }
            }
            let n = count.max(1) as f64;
            TrackSoilSummary {
                track: name.clone(),
                mean_sinkage_m: sums[0] / n,
                max_sinkage_m: max_sinkage,
                mean_thrust_n: sums[1] / n,
                mean_compaction_n: sums[2] / n,
                mean_normal_n: sums[3] / n,
            }
        })
        .collect();
    Some(SoilSummary { tracks, rut_grid })
}
