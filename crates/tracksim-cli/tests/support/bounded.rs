//! The binary run under a time limit (killed past it: a hang fails the test) and, if given, an
//! address-space limit (`ulimit -v`), its standard error and output read to the end so that a
//! long message cannot block it. Shared by the bad-input tests (`bad_inputs.rs`,
//! `bad_urdf.rs`), each including it with `#[path = "support/bounded.rs"] mod bounded;`.

#![allow(dead_code)] // each test uses a part: bad_inputs.rs the time, bad_urdf.rs the signal

use std::os::unix::process::ExitStatusExt;
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How a bounded command ended.
pub struct Ran {
    /// Exit code (`None`: ended by a signal).
    pub code: Option<i32>,
    /// The signal that ended it, if one did.
    pub signal: Option<i32>,
    /// Standard error, then standard output.
    pub text: String,
    /// Wall time.
    pub took: Duration,
}

/// Runs the tracksim binary with `args` under `limit` and, with `memory_kib`, that address
/// space; panics (fails the test) if it had to be killed for time.
pub fn run_bounded(args: &[&str], limit: Duration, memory_kib: Option<u64>) -> Ran {
    let bin = env!("CARGO_BIN_EXE_tracksim");
    let t0 = Instant::now();
    let mut cmd = match memory_kib {
        Some(kib) => {
            let mut c = Command::new("sh");
            c.arg("-c")
                .arg(format!("ulimit -v {kib} && exec \"$0\" \"$@\""))
                .arg(bin);
            c
        }
        None => Command::new(bin),
    };
    let child = cmd
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let pid = child.id().to_string();
    let done = Arc::new(AtomicBool::new(false));
    let killed = Arc::new(AtomicBool::new(false));
    let watchdog = {
        let (done, killed) = (done.clone(), killed.clone());
        std::thread::spawn(move || {
            while !done.load(Ordering::SeqCst) {
                if t0.elapsed() > limit {
                    killed.store(true, Ordering::SeqCst);
                    let _ = Command::new("kill").args(["-KILL", &pid]).status();
                    return;
                }
                std::thread::sleep(Duration::from_millis(10));
            }
        })
    };
    let o = child.wait_with_output().unwrap();
    done.store(true, Ordering::SeqCst);
    watchdog.join().unwrap();
    assert!(
        !killed.load(Ordering::SeqCst),
        "{args:?} took more than {limit:?}: a hang"
    );
    Ran {
        code: o.status.code(),
        signal: o.status.signal(),
        text: String::from_utf8_lossy(&o.stderr).into_owned() + &String::from_utf8_lossy(&o.stdout),
        took: t0.elapsed(),
    }
}
