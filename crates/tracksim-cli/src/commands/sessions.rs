//! `tracksim sessions`: the run folders under a folder tabulated (trainee, course, score,
//! date), sorted, as text or CSV.

use super::{Failure, bad_arg};
use std::path::PathBuf;
use tracksim::sessions::{
    SortKey, leaderboard, leaderboard_csv, leaderboard_text, scan_sessions, sort_rows, table_csv,
    table_text_by_course,
};

/// Tabulate the sessions (run folders with summary.json) in a folder and its subfolders, grouped
/// by course: trainee, scenario, course, status (completed, time limit, tipped over, failed,
/// ended, interrupted, ran to the end), repetitions, time, faults, penalties, score, outcome,
/// date, folder (relative to the folder given); or, with --leaderboard, each course's
/// trainees ranked by their best completed score, with their mean, spread and counts.
#[derive(clap::Args)]
pub struct SessionsArgs {
    /// Folder holding run folders (searched 3 levels deep).
    pub dir: PathBuf,
    /// Sort by: trainee, scenario, course, repetitions, time, faults, penalty, score (most
    /// repetitions, then lowest time plus penalties), outcome, date, folder or status.
    #[arg(long, default_value = "date")]
    pub sort: String,
    /// Reverse the order.
    #[arg(long)]
    pub reverse: bool,
    /// The leaderboard of every course instead of the sessions: per trainee the attempts, the
    /// completed ones, and the best, mean and standard deviation of their scores.
    #[arg(long)]
    pub leaderboard: bool,
    /// Write CSV instead of the aligned table (one table, with a course column).
    #[arg(long)]
    pub csv: bool,
    /// Write into this file instead of standard output.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// `tracksim sessions`.
pub fn sessions(a: SessionsArgs) -> Result<(), Failure> {
    let key = SortKey::parse(&a.sort).ok_or_else(|| {
        bad_arg(
            "--sort",
            format!(
                "must be one of {}, got {:?}",
                SortKey::NAMES.join(", "),
                a.sort
            ),
        )
    })?;
    let mut table = scan_sessions(&a.dir)?;
    for w in &table.warnings {
        eprintln!("{w}");
    }
    sort_rows(&mut table.rows, key, a.reverse);
    let text = match (a.leaderboard, a.csv) {
        (true, true) => leaderboard_csv(&leaderboard(&table.rows)),
        (true, false) => leaderboard_text(&leaderboard(&table.rows)) + "\n",
        (false, true) => table_csv(&table.rows),
        (false, false) => table_text_by_course(&table.rows) + "\n",
    };
    match &a.out {
        Some(p) => {
            tracksim::files::write_atomic(p, text.as_bytes())?;
            eprintln!("wrote {} ({} sessions)", p.display(), table.rows.len());
        }
        None => out!("{}", text.trim_end_matches('\n')),
    }
    Ok(())
}
