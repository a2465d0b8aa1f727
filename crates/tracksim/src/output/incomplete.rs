//! A run folder being written is marked as such ([`INCOMPLETE_MARKER`]) from the start of its
//! run until its files are complete, so that a folder left by a killed run (SIGKILL, a power
//! cut: nothing can clean up after those) is never read as a result, whatever an earlier run
//! left in it. `tracksim run`, `drive` and `ros` mark their `--out` folder before simulating
//! and clear the mark after the last file is written; `sessions` skips a marked folder with a
//! warning, and `view` and `video` refuse it naming the marker.

use crate::error::{Error, Result, SpecIssue};
use std::path::Path;

/// The marker file's name in a run folder.
pub const INCOMPLETE_MARKER: &str = "INCOMPLETE";

/// Marks `dir` (created if needed) as being written by this process.
pub fn mark_incomplete(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|source| Error::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let text = format!(
        "A tracksim run (process {}) is writing this folder. If no run is, it was stopped \
         before it finished: the other files here are not its result (they may be an earlier \
         run's). Run it again, or delete this folder.\n",
        std::process::id()
    );
    crate::files::write_atomic(&dir.join(INCOMPLETE_MARKER), text.as_bytes())
}

/// Clears the mark of `dir`: its files are complete.
pub fn mark_complete(dir: &Path) -> Result<()> {
    let p = dir.join(INCOMPLETE_MARKER);
    match std::fs::remove_file(&p) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(source) => Err(Error::Io { path: p, source }),
    }
}

/// Whether `dir` is marked as being written (or left by a killed run).
pub fn is_incomplete(dir: &Path) -> bool {
    dir.join(INCOMPLETE_MARKER).is_file()
}

/// An error naming the marker when `dir` is marked, for readers of run folders.
pub fn check_complete(dir: &Path) -> Result<()> {
    if !is_incomplete(dir) {
        return Ok(());
    }
    Err(Error::Invalid {
        path: dir.to_path_buf(),
        issues: vec![SpecIssue::new(
            INCOMPLETE_MARKER,
            "this run folder is still being written, or its run was killed before it \
             finished: its files are not a result. Wait for the run, or run it again",
        )],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_marked_folder_is_refused_until_cleared() {
        let dir = std::env::temp_dir().join(format!("tracksim-incomplete-{}", std::process::id()));
        mark_incomplete(&dir).unwrap();
        assert!(is_incomplete(&dir));
        let e = check_complete(&dir).unwrap_err().to_string();
        assert!(e.contains(INCOMPLETE_MARKER) && e.contains("killed"), "{e}");
        mark_complete(&dir).unwrap();
        assert!(!is_incomplete(&dir));
        check_complete(&dir).unwrap();
        mark_complete(&dir).unwrap(); // clearing twice is fine
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
