//! A run's samples at a bounded memory however long it runs ([`SampleLog`], issue 45): a
//! [`SpillLog`] of [`Sample`]s, the recent ones in memory, the older ones on disk. A 10-hour
//! paced session at 100 samples a second holds at most `2 * SPILL_CHUNK` samples in memory
//! (about 7 MB for PackBot), as a 10-minute one does.

pub use crate::spill::{SPILL_CHUNK, SampleIter, SpillLog};
use crate::world::Sample;

/// A run's samples in order, the first at t = 0 ([`SpillLog`] of [`Sample`]).
pub type SampleLog = SpillLog<Sample>;

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field of a sample, spilled and read back, is the same bits (so a run's outputs
    /// are the same bytes whether its samples were spilled or not).
    #[test]
    fn spilled_samples_read_back_bit_for_bit() {
        let sample = |i: usize| Sample {
            t: i as f64 * 0.01 + 1e-17,
            belt_speed: vec![i as f64 / 3.0, -0.1],
            slip: vec![f64::MIN_POSITIVE, 1.0 / 7.0],
            icr: i.is_multiple_of(3).then_some([0.1, i as f64]),
            drive: vec![None, Some(crate::world::DriveSample::default())],
            drawbar_n: Some(-0.0),
            soil: vec![crate::world::TrackSoil::default()],
            ..Sample::default()
        };
        let n = 3 * SPILL_CHUNK + 5;
        let log: SampleLog = (0..n).map(sample).collect();
        assert!(log.spilled() > 0);
        assert!(log.iter().enumerate().all(|(i, s)| *s == sample(i)));
        assert!(log.get(7).unwrap().drawbar_n.unwrap().is_sign_negative());
    }
}
