//! `tracksim merge`: sweep folders (shards) merged into one.

use super::Failure;
use std::path::PathBuf;

/// Merge sweep folders (shards) into one: their runs and one manifest.jsonl.
#[derive(clap::Args)]
pub struct MergeArgs {
    /// Sweep output folders.
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Merged sweep folder (may be one of DIRS: shards that wrote into one folder).
    #[arg(long)]
    pub out: PathBuf,
}

/// `tracksim merge`.
pub fn merge(a: MergeArgs) -> Result<(), Failure> {
    let lines = tracksim::sweep::merge(&a.dirs, &a.out)?;
    out!(
        "{} runs merged into {}",
        lines.len(),
        a.out.join("manifest.jsonl").display()
    );
    Ok(())
}
