//! The seeds of many environments stepped together ([`Seeds`]): environment `i` reset with
//! `base + i`, or one seed each; after an episode ends its environment's next episode takes
//! [`next_seed`] of its seed, so each environment's episodes follow from the seed it was reset
//! with, whatever the others do.

use crate::error::{Error, Result};

/// The seed of the episode after one with `seed` (SplitMix64): each environment's episodes
/// follow from the seed it was reset with.
pub fn next_seed(seed: u64) -> u64 {
    let mut z = seed.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Each environment's seed.
#[derive(Clone, Debug, PartialEq)]
pub struct Seeds(Vec<u64>);

impl Seeds {
    /// `n` environments, environment `i` with `base + i` (wrapping).
    pub fn from_base(n: usize, base: u64) -> Seeds {
        Seeds((0..n as u64).map(|i| base.wrapping_add(i)).collect())
    }

    /// Environment `i` with `base + i` from now on.
    pub fn rebase(&mut self, base: u64) {
        *self = Seeds::from_base(self.0.len(), base);
    }

    /// One seed per environment (`unit` names one in the error: "environment", "world").
    pub fn replace(&mut self, seeds: &[u64], unit: &str) -> Result<()> {
        if seeds.len() != self.0.len() {
            return Err(Error::setting(
                "reset",
                "seeds",
                format!(
                    "expected {} seeds (one per {unit}), got {}",
                    self.0.len(),
                    seeds.len()
                ),
            ));
        }
        self.0 = seeds.to_vec();
        Ok(())
    }

    /// The seeds after the episodes that `ended` (by environment): theirs advanced by
    /// [`next_seed`], the others' kept.
    pub fn after(&self, ended: &[bool]) -> Seeds {
        Seeds(
            self.0
                .iter()
                .zip(ended)
                .map(|(s, e)| if *e { next_seed(*s) } else { *s })
                .collect(),
        )
    }

    /// The seeds, by environment.
    pub fn as_slice(&self) -> &[u64] {
        &self.0
    }
}
