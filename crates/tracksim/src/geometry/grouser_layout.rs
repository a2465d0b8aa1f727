//! The grouser pattern: N grousers spaced L/N apart along a path ([`GrouserLayout`]).

use super::{Frame, TrackPath};

/// N grousers spaced L/N apart along a path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrouserLayout {
    /// Number of grousers on the loop (>= 1).
    pub count: usize,
    /// Arc length of grouser 0's footprint from the loop start, m.
    pub offset: f64,
}

impl GrouserLayout {
    /// Pitch L/N, m.
    pub fn pitch(&self, path: &TrackPath) -> f64 {
        path.length() / self.count as f64
    }

    /// Arc length of grouser k's footprint, wrapped into [0, L), m.
    pub fn footprint_s(&self, path: &TrackPath, k: usize) -> f64 {
        (self.offset + k as f64 * self.pitch(path)).rem_euclid(path.length())
    }

    /// Footprint frames of all grousers with the segment each belongs to at rest.
    pub fn footprints(&self, path: &TrackPath) -> Vec<(usize, Frame)> {
        (0..self.count)
            .map(|k| {
                let s = self.footprint_s(path, k);
                (path.segment_at(s), path.frame_at(s))
            })
            .collect()
    }
}
