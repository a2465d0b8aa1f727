//! What a run on soil shows (issue 30): per track, the mean and largest sinkage, the mean soil
//! thrust and compaction resistance, and the rut grid's memory at the end.

use crate::world::{RutGridStats, Sample, Simulation};
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
pub fn soil_summary(sim: &Simulation, samples: &[Sample]) -> Option<SoilSummary> {
    let rut_grid = sim.rut_grid_stats()?;
    let tracks = sim
        .track_names()
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let on: Vec<_> = samples
                .iter()
                .filter_map(|s| s.soil.get(i))
                .filter(|g| g.normal_n > 0.0)
                .collect();
            let n = on.len().max(1) as f64;
            TrackSoilSummary {
                track: name.clone(),
                mean_sinkage_m: on.iter().map(|g| g.sinkage_m).sum::<f64>() / n,
                max_sinkage_m: on.iter().map(|g| g.max_sinkage_m).fold(0.0, f64::max),
                mean_thrust_n: on.iter().map(|g| g.thrust_n).sum::<f64>() / n,
                mean_compaction_n: on.iter().map(|g| g.compaction_n).sum::<f64>() / n,
                mean_normal_n: on.iter().map(|g| g.normal_n).sum::<f64>() / n,
            }
        })
        .collect();
    Some(SoilSummary { tracks, rut_grid })
}
