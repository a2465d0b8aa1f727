//! `tracksim export`: the bundled vehicles and scenarios written into a folder.

use super::Failure;
use std::path::PathBuf;

/// Write the bundled vehicles/ and scenarios/ (with their meshes and height maps) into a
/// folder, to edit or to run by path.
#[derive(clap::Args)]
pub struct ExportArgs {
    /// Folder to write into (created if needed; files holding other bytes are replaced).
    #[arg(default_value = "tracksim-data")]
    pub dir: PathBuf,
}

/// `tracksim export`.
pub fn export(a: ExportArgs) -> Result<(), Failure> {
    let written = tracksim::bundled::export(&a.dir)?;
    out!(
        "export     {} files written into {} ({} bundled files in all)",
        written.len(),
        a.dir.display(),
        tracksim::bundled::list().len()
    );
    out!(
        "           try: tracksim run {}",
        a.dir.join("scenarios/packbot_flat.toml").display()
    );
    Ok(())
}
