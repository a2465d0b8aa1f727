//! `tracksim import`: a vehicle file and a flat-ground scenario from a robot model as it is
//! found (issue 42); the logic is `tracksim::import`.

use super::Failure;
use std::path::PathBuf;

/// Write a vehicle file that runs (tracks proposed from the model's track plugin or collision
/// shapes) and a flat-ground scenario beside it, from a URDF robot; print every guess.
#[derive(clap::Args)]
pub struct ImportArgs {
    /// The robot model (URDF, or SDF: a model or a world holding it).
    pub model: PathBuf,
    /// The SDF `<model>` to import when the file holds several (default: the one with a
    /// tracked-vehicle plugin, else the only non-static one).
    #[arg(long)]
    pub sdf_model: Option<String>,
    /// Folder to write into (created if need be); default `imported/<model stem>`.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Overwrite files that exist already.
    #[arg(long)]
    pub force: bool,
}

/// `tracksim import`: exits 2 if the model cannot be read or has no tracks.
pub fn import(a: ImportArgs) -> Result<(), Failure> {
    let out = a.out.unwrap_or_else(|| {
        let stem = a
            .model
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "robot".into());
        PathBuf::from("imported").join(stem)
    });
    let done = tracksim::import::import_model(&a.model, a.sdf_model.as_deref(), &out, a.force)?;
    for l in done.report.lines() {
        out!("{l}");
    }
    out!();
    out!("wrote {}", done.vehicle.display());
    out!("wrote {}", done.scenario.display());
    if let Some(w) = &done.world {
        out!(
            "wrote {} (the SDF world's terrain; what it could not hold is listed on top)",
            w.display()
        );
    }
    out!("try: tracksim run {}", done.scenario.display());
    Ok(())
}
