//! Seeded sensor noise: white Gaussian noise and bias random walks from a PCG generator (one per
//! sensor, seeded from the run's seed and the sensor's index, so a run is reproducible and two
//! sensors never share a stream).

use rand_core::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_pcg::Pcg64Mcg;

/// A sensor's noise source.
#[derive(Clone, Debug)]
pub struct Noise {
    rng: Pcg64Mcg,
}

impl Noise {
    /// The generator of sensor `index` in a run with `seed`.
    pub fn new(seed: u64, index: usize) -> Self {
        let mix = seed ^ (0x9E37_79B9_7F4A_7C15u64.wrapping_mul(index as u64 + 1));
        Noise {
            rng: Pcg64Mcg::seed_from_u64(mix),
        }
    }

    /// A sample of a zero-mean Gaussian with standard deviation `sigma` (0: exactly 0, and no
    /// number drawn).
    pub fn gaussian(&mut self, sigma: f64) -> f64 {
        if sigma == 0.0 {
            return 0.0;
        }
        let z: f64 = StandardNormal.sample(&mut self.rng);
        sigma * z
    }
}
