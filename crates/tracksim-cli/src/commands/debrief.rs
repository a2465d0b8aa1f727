//! `tracksim debrief`: a run folder's printable debrief (`debrief.html`: score, events, the
//! path on the course map, key plots) written again, or written for a folder of runs.

use super::Failure;
use std::path::PathBuf;

/// Write debrief.html into a run folder (or into every run folder under a folder, searched 3
/// levels deep as `tracksim sessions` does): a printable page of the session, its score table,
/// events with their times, the path on the course map and the key plots; self-contained
/// (open it in a browser, print it to PDF). `run` and `drive` write it for every course.
#[derive(clap::Args)]
pub struct DebriefArgs {
    /// A run folder (holding summary.json and trajectory.csv) or a folder of run folders.
    pub dir: PathBuf,
}

/// `tracksim debrief`.
pub fn debrief(a: DebriefArgs) -> Result<(), Failure> {
    if a.dir.join("summary.json").is_file() {
        let p = tracksim::output::debrief::write_debrief(&a.dir)?;
        out!("wrote      {}", p.display());
        return Ok(());
    }
    let table = tracksim::sessions::scan_sessions(&a.dir)?;
    for w in &table.warnings {
        eprintln!("{w}");
    }
    if table.rows.is_empty() {
        // Names what is missing and how to get it.
        tracksim::output::debrief::write_debrief(&a.dir)?;
    }
    let mut failed = 0;
    for row in &table.rows {
        let dir = a.dir.join(&row.folder);
        match tracksim::output::debrief::write_debrief(&dir) {
            Ok(p) => out!("wrote      {}", p.display()),
            Err(e) => {
                eprintln!("warning: {}: no debrief: {e}", dir.display());
                failed += 1;
            }
        }
    }
    if failed > 0 {
        eprintln!(
            "{failed} of {} run folders have no debrief (see the warnings)",
            table.rows.len()
        );
        return Err(Failure::Reported);
    }
    Ok(())
}
