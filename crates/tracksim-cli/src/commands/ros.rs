//! `tracksim ros`: the scenario as a ROS 2 node (pure-Rust DDS), recorded as a run.

use super::{Failure, bad_arg, check_duration, overrides, scenario_file};
use std::path::PathBuf;

/// Run a scenario as the ROS 2 node /tracksim (no ROS installation needed; docs/ROS2.md):
/// /cmd_vel in, /odom, /tf, /joint_states, /clock out; loopback only unless --network. A file
/// with several robots ([[vehicles]]) gives each its topics and frames under its name
/// (/<name>/cmd_vel, <name>/base_link; docs/TEAMS.md). On Ctrl-C, SIGTERM or --duration its
/// outputs go to --out, as `run` writes them.
#[derive(clap::Args)]
pub struct RosArgs {
    /// Scenario file (TOML), or the name of a bundled scenario.
    pub file: PathBuf,
    /// Output folder (as `run`, plus commands.toml).
    #[arg(long, default_value = "out/ros")]
    pub out: PathBuf,
    /// Step as fast as possible instead of at real time (other nodes follow /clock with
    /// use_sim_time).
    #[arg(long)]
    pub fast: bool,
    /// Also publish map -> odom on /tf from the true pose (perfect localisation), so that
    /// map -> base_link is the truth; leave it off when AMCL or a SLAM node publishes it.
    #[arg(long)]
    pub map_tf: bool,
    /// End the session at this simulated time, s (default: on Ctrl-C or SIGTERM).
    #[arg(long)]
    pub duration: Option<f64>,
    /// DDS domain (default: $ROS_DOMAIN_ID, else 0).
    #[arg(long)]
    pub domain_id: Option<u16>,
    /// Where the node can be reached: `localhost` (default: this machine only), `any` (every
    /// interface: anyone on the network can drive the robot) or interface addresses, e.g.
    /// 192.168.1.20 (comma-separated).
    #[arg(long, default_value = "localhost")]
    pub network: String,
    /// Track method, overriding the scenario's `simulation.method`.
    #[arg(long)]
    pub method: Option<String>,
    /// Do not write the plot files.
    #[arg(long)]
    pub no_plot: bool,
    /// Also write run.mcap.
    #[arg(long)]
    pub mcap: bool,
    /// Also publish colour cameras' raw sensor_msgs/Image (rgb8) on /<camera> (and record it
    /// in run.mcap with --mcap), besides CompressedImage (PNG) on /<camera>/compressed and
    /// CameraInfo on /<camera>/camera_info: for RViz's Image display and cv_bridge nodes
    /// (Foxglove shows the compressed topic).
    #[arg(long)]
    pub raw_images: bool,
    /// Namespace a one-robot file's topics and frames as a robot of several is named:
    /// /<NAME>/cmd_vel, /<NAME>/odom, tf <NAME>/odom -> <NAME>/base_link (/clock and /tf stay).
    #[arg(long, value_name = "NAME")]
    pub namespace: Option<String>,
    /// Play the file's [[commands]] until the robot's first ROS command (then ROS wins, and a
    /// line says so). Without it they are not played: ROS topics alone drive the robot.
    #[arg(long)]
    pub play_commands: bool,
}

/// The DDS domain: the flag, else `ROS_DOMAIN_ID`, else 0.
fn domain(flag: Option<u16>) -> Result<u16, Failure> {
    // RTPS ports are 7400 + 250 * domain + offsets: above 232 they leave the u16 port range.
    const MAX_DOMAIN: u16 = 232;
    let (key, d) = match flag {
        Some(d) => ("--domain-id", d),
        None => match std::env::var("ROS_DOMAIN_ID") {
            Ok(s) if !s.trim().is_empty() => (
                "ROS_DOMAIN_ID",
                s.trim().parse().map_err(|_| {
                    bad_arg(
                        "ROS_DOMAIN_ID",
                        format!("must be a domain number 0-{MAX_DOMAIN}, got {s:?}"),
                    )
                })?,
            ),
            _ => return Ok(0),
        },
    };
    if d > MAX_DOMAIN {
        return Err(bad_arg(
            key,
            format!("must be a domain number 0-{MAX_DOMAIN} (DDS ports run out above), got {d}"),
        ));
    }
    Ok(d)
}

/// `tracksim ros`.
pub fn ros(a: RosArgs) -> Result<(), Failure> {
    use tracksim::ros::{NetworkRange, RosOptions, WATCHDOG_TIMEOUT_S, run_ros};
    let file = scenario_file(&a.file)?;
    let sc = tracksim::load_scenario_with(&file, &overrides(a.method.as_deref(), None, None)?)?;
    let max_time = a
        .duration
        .map(|d| check_duration(d, sc.solver.dt))
        .transpose()?;
    let network = NetworkRange::parse(&a.network).map_err(|m| bad_arg("--network", m))?;
    let team = sc.robot_count() > 1;
    if let Some(n) = &a.namespace {
        if team {
            return Err(bad_arg(
                "--namespace",
                "names one robot's namespace; this file has several robots, each namespaced by \
                 its name: leave it out"
                    .into(),
            ));
        }
        if let Some(why) = tracksim::model::robot_name_problem(n) {
            return Err(bad_arg("--namespace", why));
        }
    }
    if !network.is_local() {
        eprintln!(
            "warning: the node is reachable on {network}: anyone who can reach it can drive the \
             robot"
        );
    }
    let opts = RosOptions {
        fast: a.fast,
        map_tf: a.map_tf,
        max_time,
        domain_id: domain(a.domain_id)?,
        raw_images: a.raw_images,
        network,
        interrupt: Some(&super::STOP),
        namespace: a.namespace.clone(),
        play_commands: a.play_commands,
    };
    super::on_stop(|| {});
    out!(
        "ros        node /tracksim, DDS domain {}, on {}; {} (cmd_vel watchdog {} s)",
        opts.domain_id,
        opts.network,
        if a.fast {
            "as fast as possible (/clock)"
        } else {
            "paced to real time"
        },
        WATCHDOG_TIMEOUT_S
    );
    out!(
        "           stop: Ctrl-C or SIGTERM (the run is written to {})",
        a.out.display()
    );
    tracksim::output::incomplete::mark_incomplete(&a.out)?;
    if team {
        return ros_team(&a, &file, &sc, &opts);
    }
    let session = run_ros(&sc, &opts, &mut |w| eprintln!("warning: {w}"))?;
    let written = session.write(&sc, &file, &a.out, !a.no_plot, (a.mcap, a.raw_images))?;
    tracksim::output::incomplete::mark_complete(&a.out)?;
    super::session_report(&session.result.summary);
    out!(
        "commands   {} received, {} problems (dropped or clamped), {} samples not of their \
         topic's type dropped, {} watchdog stops, {} resets",
        session.received,
        session.problems,
        session.undecodable,
        session.watchdog_stops,
        session.resets
    );
    for w in &written {
        out!("wrote      {}", w.display());
    }
    if matches!(session.result.outcome, tracksim::Outcome::Interrupted(_)) {
        return Err(Failure::Interrupted);
    }
    super::world_stopped(session.result.summary.stopped.as_deref(), &a.out)
}

/// `tracksim ros` of a file with several robots: each robot's topics under its name.
fn ros_team(
    a: &RosArgs,
    file: &std::path::Path,
    sc: &tracksim::Scenario,
    opts: &tracksim::ros::RosOptions,
) -> Result<(), Failure> {
    out!(
        "robots     {}: topics /<name>/cmd_vel, /<name>/odom, ...; frames <name>/odom, \
         <name>/base_link; one /clock and /tf",
        sc.robot_names().join(", ")
    );
    let session = tracksim::ros::run_ros_team(sc, opts, &mut |w| eprintln!("warning: {w}"))?;
    let written = session.write(sc, file, &a.out, !a.no_plot, (a.mcap, a.raw_images))?;
    tracksim::output::incomplete::mark_complete(&a.out)?;
    out!(
        "{}",
        tracksim::output::team::team_report_of(
            file,
            sc,
            &session.result,
            &a.out,
            Some("ROS 2 topics")
        )
    );
    for (name, _, c) in &session.robots {
        out!(
            "commands   {name}: {} received, {} problems (dropped or clamped), {} samples not \
             of their topic's type dropped, {} watchdog stops",
            c.received,
            c.problems,
            c.undecodable,
            c.watchdog_stops
        );
    }
    for w in &written {
        out!("wrote      {}", w.display());
    }
    if matches!(session.result.outcome, tracksim::Outcome::Interrupted(_)) {
        return Err(Failure::Interrupted);
    }
    super::world_stopped(session.result.stopped.as_deref(), &a.out)
}
