//! `tracksim list`: the bundled vehicles and scenarios.

use super::Failure;

/// List the bundled vehicles and scenarios (usable by name from anywhere) with their
/// descriptions.
#[derive(clap::Args)]
pub struct ListArgs {}

/// `tracksim list`.
pub fn list(_a: ListArgs) -> Result<(), Failure> {
    use tracksim::bundled::Kind;
    for (kind, title) in [(Kind::Vehicle, "vehicles"), (Kind::Scenario, "scenarios")] {
        out!("{title}:");
        for f in tracksim::bundled::list()
            .into_iter()
            .filter(|f| f.kind == kind)
        {
            out!("  {:<36} {}", f.name, f.description);
        }
    }
    out!();
    out!("Run a scenario by name from anywhere (`tracksim run packbot_flat`), or write them all");
    out!("into a folder to edit with `tracksim export DIR`.");
    Ok(())
}
