//! `tracksim view`: a finished run replayed in the 3-D page.

use super::{AccessArgs, Failure, access, bind_address};
use std::path::PathBuf;

/// Replay a finished run (of `run`, `drive` or `compare`) in the 3-D page; a `compare` folder
/// replays every method's run side by side, as ghosts on one terrain.
#[derive(clap::Args)]
pub struct ViewArgs {
    /// The run's output folder (holding scene.json, trajectory.csv, belts.csv), or the output
    /// folder of `tracksim compare` (one such subfolder per method).
    pub dir: PathBuf,
    /// TCP port of the page (0: any free port).
    #[arg(long, default_value_t = tracksim::live::DEFAULT_PORT)]
    pub port: u16,
    /// Address to listen on (default loopback only).
    #[arg(long)]
    pub bind: Option<std::net::IpAddr>,
    /// Who else may use the page (docs/LIVE.md, security).
    #[command(flatten)]
    pub access: AccessArgs,
}

/// `tracksim view`: serves until Ctrl-C or SIGTERM.
pub fn view(a: ViewArgs) -> Result<(), Failure> {
    use tracksim::live::{Mode, Server, ViewVideo};
    let files = tracksim::live::view_files(&a.dir)?;
    let video = ViewVideo::of(&a.dir);
    let server = Server::start_with(
        bind_address(a.bind),
        a.port,
        Mode::View { files, video },
        access(&a.access)?,
    )?;
    out!("view       open {} in a browser; Ctrl-C ends", server.url());
    let (tx, rx) = std::sync::mpsc::channel();
    super::on_stop(move || {
        let _ = tx.send(());
    });
    let _ = rx.recv();
    Ok(())
}
