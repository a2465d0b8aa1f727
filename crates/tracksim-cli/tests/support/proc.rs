//! A `tracksim` process started by a test, its output lines read as they come (a thread per
//! stream, so a server that prints a lot never blocks). Shared by the tests that start a server
//! (`school.rs`, `servers.rs`), each including it with `#[path = "support/proc.rs"] mod proc;`.

#![allow(dead_code)] // each test uses a part: servers.rs the memory, school.rs the token

use std::io::{BufRead, BufReader, Read};
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{Receiver, channel};
use std::time::{Duration, Instant};

/// The repository's root (the bundled scenarios are relative to it).
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A `tracksim` process, its output lines as they come.
pub struct Proc {
    pub child: Child,
    pub stdout: Receiver<String>,
    pub stderr: Receiver<String>,
    /// The stdout lines read so far.
    pub seen: Vec<String>,
}

fn lines(r: impl Read + Send + 'static) -> Receiver<String> {
    let (tx, rx) = channel();
    std::thread::spawn(move || {
        for l in BufReader::new(r).lines().map_while(Result::ok) {
            let _ = tx.send(l);
        }
    });
    rx
}

/// Starts `tracksim ARGS` in the repository's root.
pub fn spawn(args: &[&str]) -> Proc {
    let mut child = Command::new(env!("CARGO_BIN_EXE_tracksim"))
        .current_dir(root())
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stdout = lines(child.stdout.take().unwrap());
    let stderr = lines(child.stderr.take().unwrap());
    Proc {
        child,
        stdout,
        stderr,
        seen: Vec::new(),
    }
}

impl Proc {
    /// The first stdout line holding `what`, waited for at most 30 s (every line read kept in
    /// `seen`).
    pub fn line_with(&mut self, what: &str) -> String {
        let t0 = Instant::now();
        while t0.elapsed() < Duration::from_secs(30) {
            if let Ok(l) = self.stdout.recv_timeout(Duration::from_millis(100)) {
                self.seen.push(l.clone());
                if l.contains(what) {
                    return l;
                }
            }
        }
        panic!("no line with {what:?} in {:?}", self.seen);
    }

    /// The server's address and the session's token, as `drive` prints them.
    pub fn address_and_token(&mut self) -> (SocketAddr, String) {
        let url = self.line_with("http://");
        let addr: SocketAddr = url
            .split("http://")
            .nth(1)
            .and_then(|r| r.split('/').next())
            .unwrap()
            .parse()
            .unwrap();
        let token = self.line_with("session token");
        let token = token
            .split_whitespace()
            .skip_while(|w| *w != "token")
            .nth(1)
            .unwrap()
            .to_string();
        (addr, token)
    }

    /// The instructor's token, from the instructor's URL `drive` prints (`?instructor=TOKEN`).
    pub fn instructor_token(&mut self) -> String {
        let line = match self.seen.iter().find(|l| l.contains("?instructor=")) {
            Some(l) => l.clone(),
            None => self.line_with("?instructor="),
        };
        line.split("?instructor=")
            .nth(1)
            .and_then(|r| r.split_whitespace().next())
            .unwrap()
            .to_string()
    }

    /// Its resident memory, kB (`VmRSS`).
    pub fn rss_kb(&self) -> u64 {
        let status = std::fs::read_to_string(format!("/proc/{}/status", self.child.id())).unwrap();
        status
            .lines()
            .find_map(|l| l.strip_prefix("VmRSS:"))
            .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
            .expect("VmRSS")
    }

    /// Waits for the end (killed and failed past `limit`): the exit code and every stdout
    /// line (those already read first) and stderr line.
    pub fn finish(mut self, limit: Duration) -> (i32, Vec<String>, Vec<String>) {
        let t0 = Instant::now();
        let code = loop {
            if let Some(s) = self.child.try_wait().unwrap() {
                break s.code().unwrap_or(-1);
            }
            if t0.elapsed() > limit {
                let _ = self.child.kill();
                panic!("did not end within {limit:?}");
            }
            std::thread::sleep(Duration::from_millis(50));
        };
        let mut out = self.seen;
        out.extend(self.stdout.iter());
        let err = self.stderr.iter().collect();
        (code, out, err)
    }
}
