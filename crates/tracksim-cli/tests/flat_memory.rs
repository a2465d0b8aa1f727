//! Issue 45: a run's memory does not grow with its length. The samples go to a spill file on
//! disk as the run goes (`tracksim::run::SampleLog`) and every output is written from them a
//! row at a time, so a run twelve times longer (as 2 hours are to 10 minutes) peaks at the
//! same resident memory.
//!
//! Accelerated: PackBot on flat ground sampled at every 1 ms step (100 times the default
//! rate), so 25 s and 300 s of simulated time hold 25,001 and 300,001 samples, as 4 min and
//! 50 min at the default 100 Hz output do. Both are past every bounded buffer (the 8,192
//! samples kept in memory, the plots' 20,000 points). Before the spill, each sample held about
//! 870 bytes in memory and the trajectory's text as much again: the long run would have
//! peaked about 480 MB higher.

use std::path::Path;
use std::process::Command;

/// Runs `tracksim run` on `file` for `duration_s` into `out`; returns its peak resident set
/// size, bytes (the kernel's `ru_maxrss` of the child, from `wait4`).
#[expect(
    clippy::zombie_processes,
    reason = "the child is reaped by wait4, which also gives its peak memory"
)]
fn peak_rss(file: &Path, out: &Path, duration_s: f64) -> u64 {
    let child = Command::new(env!("CARGO_BIN_EXE_tracksim"))
        .arg("run")
        .arg(file)
        .arg("--out")
        .arg(out)
        .args(["--duration", &duration_s.to_string()])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::inherit())
        .spawn()
        .expect("tracksim starts");
    let mut status = 0;
    // SAFETY: an all-zero rusage is a valid value of the plain C struct wait4 fills in.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: waits for our own child by its pid, with valid pointers to the two outputs.
    let pid = unsafe { libc::wait4(child.id() as i32, &mut status, 0, &mut usage) };
    assert_eq!(pid, child.id() as i32, "wait4");
    assert!(
        libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
        "tracksim run exited with status {status}"
    );
    // Linux reports ru_maxrss in kilobytes.
    usage.ru_maxrss as u64 * 1024
}

#[test]
fn a_run_twelve_times_longer_peaks_at_the_same_memory() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let vehicle = root
        .join("vehicles/packbot510.toml")
        .canonicalize()
        .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("long.toml");
    std::fs::write(
        &file,
        format!(
            "[vehicle]\nfile = {:?}\n[terrain.ground]\nfriction = 0.6\n\
             [simulation]\ndt_s = 0.001\noutput_interval_s = 0.001\nduration_s = 25.0\n\
             [[commands]]\nt_s = 0.0\nbelt_speed_mps = 0.3\n",
            vehicle.display().to_string()
        ),
    )
    .unwrap();
    let (short, long) = (dir.path().join("short"), dir.path().join("long"));
    let a = peak_rss(&file, &short, 25.0);
    let b = peak_rss(&file, &long, 300.0);
    // Every sample reached the files: a header and 300,001 rows (t = 0 to 300 s).
    let rows = |d: &Path, f: &str| std::fs::read_to_string(d.join(f)).unwrap().lines().count();
    assert_eq!(rows(&short, "trajectory.csv"), 25_002);
    assert_eq!(rows(&long, "trajectory.csv"), 300_002);
    assert_eq!(rows(&long, "belts.csv"), 300_002);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(long.join("summary.json")).unwrap()).unwrap();
    let x = summary["final_pose"]["x"].as_f64().unwrap();
    assert!((85.0..91.0).contains(&x), "300 s at 0.3 m/s: x = {x} m");
    let (ma, mb) = (a as f64 / 1e6, b as f64 / 1e6);
    println!(
        "peak RSS: 25 s {ma:.1} MB, 300 s {mb:.1} MB ({:+.1} %)",
        100.0 * (mb / ma - 1.0)
    );
    assert!(
        mb <= 1.10 * ma,
        "the 300 s run peaked at {mb:.1} MB, the 25 s run at {ma:.1} MB: memory grows with the run"
    );
}
