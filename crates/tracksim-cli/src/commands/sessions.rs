//! `tracksim sessions`: the run folders under a folder tabulated (trainee, course, score,
//! date), sorted, as text or CSV.

use super::{Failure, bad_arg};
use std::path::PathBuf;
use tracksim::sessions::{SortKey, scan_sessions, sort_rows, table_csv, table_text};

/// Tabulate the sessions (run folders with summary.json) in a folder and its subfolders:
/// trainee, scenario, course, repetitions, time, faults, penalties, score, outcome, date.
#[derive(clap::Args)]
pub struct SessionsArgs {
    /// Folder holding run folders (searched 3 levels deep).
    pub dir: PathBuf,
    /// Sort by: trainee, scenario, course, repetitions, time, faults, penalty, score (most
    /// repetitions, then lowest time plus penalties), outcome, date or folder.
    #[arg(long, default_value = "date")]
    pub sort: String,
    /// Reverse the order.
    #[arg(long)]
    pub reverse: bool,
    /// Write CSV instead of the aligned table.
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
    let text = if a.csv {
        table_csv(&table.rows)
    } else {
        table_text(&table.rows) + "\n"
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
