//! Validation (issue 6): the paper's Table IV with Quince, the slope limit and skid steering.

use std::path::Path;
use tracksim::model::TrackMethod;

fn root() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn explore() {
    let rep = tracksim::validate::run_validation(&root(), TrackMethod::Okada2020, |s| eprintln!("{s}")).unwrap();
    eprintln!("{}", rep.to_markdown());
    rep.write(Path::new("/tmp/val")).unwrap();
}
