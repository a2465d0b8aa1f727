//! A run folder's kept earlier attempts, read back (issue 43): a reset ends an attempt, which
//! is written to `attempts/N/` inside the folder of the run (a drive session's, or a robot's
//! of a team run); the folder itself holds the last attempt. `tracksim view` and `tracksim
//! video` replay a reset robot of a team run over the whole session from them.

use std::path::{Path, PathBuf};

/// Most earlier attempts a reader takes.
pub const MAX_ATTEMPTS: usize = 100;

/// The folders of `dir`'s earlier attempts in order (`attempts/1`, `attempts/2`, ... while
/// they exist; at most [`MAX_ATTEMPTS`]); empty without any. `None` when one of them was not
/// written to its end (its `INCOMPLETE` mark): it must not be replayed as if it had been.
pub fn kept_attempts(dir: &Path) -> Option<Vec<PathBuf>> {
    let mut out = Vec::new();
    for n in 1..=MAX_ATTEMPTS {
        let sub = dir.join(crate::run::attempt_folder(n));
        if !sub.is_dir() {
            break;
        }
        if super::incomplete::is_incomplete(&sub) {
            return None;
        }
        out.push(sub);
    }
    Some(out)
}

/// The time of the first sample of the CSV text `csv` (its first column, after the header),
/// s; `None` without a sample.
pub fn first_time(csv: &[u8]) -> Option<f64> {
    let text = std::str::from_utf8(csv).ok()?;
    let row = text.lines().nth(1)?;
    row.split(',').next()?.trim().parse().ok()
}
