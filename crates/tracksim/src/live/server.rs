//! The page's server on plain `std::net` sockets: HTTP GET for the embedded assets and the
//! run's data (held in memory: no request path reaches the file system), and a WebSocket
//! (`/ws`, drive only) that streams the latest state and takes the driver's controls.
//!
//! One thread accepts; each connection has its own thread, so a slow or stuck client blocks
//! only itself. The simulation never waits for any of them: it publishes into the [`Hub`]
//! (a latest-value slot) and reads the latest control from it.

use super::access::Access;
use super::assets::asset;
use super::hub::Hub;
use crate::error::{Error, Result};
use crate::output::kept_attempts::{first_time, kept_attempts};
use std::io::{Read, Write};
use std::net::{IpAddr, SocketAddr, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

/// Largest request head read, bytes.
const MAX_HEAD: usize = 8192;

/// What the server serves besides the page.
pub enum Mode {
    /// A live session: `/scene.json` and the `/ws` WebSocket of the hub.
    Drive {
        /// The session's shared state.
        hub: Arc<Hub>,
        /// `scene.json` of the scenario: of each robot, in the hub's order
        /// ([`Hub::robots`]); `/scene.json?robot=NAME` gives robot `NAME`'s, `/scene.json`
        /// the first's.
        scene_json: Vec<String>,
    },
    /// A replay: the files of a finished run, read once at start.
    View {
        /// (URL path, content type, bytes), e.g. `/run/trajectory.csv`.
        files: Vec<(String, &'static str, Vec<u8>)>,
        /// The run's video, `/video.mp4` (`None`: not offered, e.g. a compare folder).
        video: Option<ViewVideo>,
    },
}

/// Longest run whose video the page renders, s of simulated time (a longer one: the page
/// names the `tracksim video` command instead).
pub const MAX_PAGE_VIDEO_S: f64 = 600.0;

/// A replay's video (`/video.mp4`): the run folder, rendered with the default settings
/// ([`crate::video::VideoOptions::default`]) on the first request and kept in memory;
/// requests meanwhile wait for it. Nothing is written into the folder.
pub struct ViewVideo {
    dir: std::path::PathBuf,
    made: std::sync::Mutex<Option<std::result::Result<Arc<Vec<u8>>, String>>>,
}

impl ViewVideo {
    /// The video of the run (or team run) in `dir`, if it is one a video can be made of.
    pub fn of(dir: &std::path::Path) -> Option<ViewVideo> {
        let run = dir.join("scene.json").is_file() && dir.join("trajectory.csv").is_file();
        (run || dir.join("team.json").is_file()).then(|| ViewVideo {
            dir: dir.to_path_buf(),
            made: std::sync::Mutex::new(None),
        })
    }

    /// The MP4's bytes, rendered on the first call; the error is the page's message.
    pub fn bytes(&self) -> std::result::Result<Arc<Vec<u8>>, String> {
        let mut made = self.made.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(r) = made.as_ref() {
            return r.clone();
        }
        let command = format!("tracksim video {}", self.dir.display());
        let said = |e: crate::error::Error| format!("{e} (`{command}` says the same)");
        let r = crate::video::Replay::open(&self.dir, None)
            .map_err(said)
            .and_then(|replay| {
                let f = replay.focus();
                let length = f.end_s() - f.start_s();
                if length > MAX_PAGE_VIDEO_S {
                    return Err(format!(
                        "the run lasts {length:.0} s, longer than the page renders ({MAX_PAGE_VIDEO_S:.0} s): run `{command}`"
                    ));
                }
                crate::video::render_video(&self.dir, &crate::video::VideoOptions::default())
                    .map(|(b, _)| Arc::new(b))
                    .map_err(said)
            });
        *made = Some(r.clone());
        r
    }
}

impl Mode {
    fn name(&self) -> &'static str {
        match self {
            Mode::Drive { .. } => "drive",
            Mode::View { .. } => "view",
        }
    }
}

/// A running server; dropping it (or [`Server::shutdown`]) stops accepting.
pub struct Server {
    addr: SocketAddr,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Server {
    /// Binds `bind:port` (port 0: any free port) and starts serving `mode` to its own pages
    /// only ([`Access::loopback`]: see [`super::access`]).
    pub fn start(bind: IpAddr, port: u16, mode: Mode) -> Result<Server> {
        Server::start_with(bind, port, mode, Access::loopback())
    }

    /// [`Server::start`], also answering the hosts and origins `access` allows.
    pub fn start_with(bind: IpAddr, port: u16, mode: Mode, access: Access) -> Result<Server> {
        let listener = TcpListener::bind((bind, port)).map_err(|source| Error::Io {
            path: format!("{bind}:{port} (--bind/--port: is the port in use? try another --port)")
                .into(),
            source,
        })?;
        let addr = listener.local_addr().map_err(|source| Error::Io {
            path: format!("{bind}:{port}").into(),
            source,
        })?;
        listener.set_nonblocking(true).map_err(|source| Error::Io {
            path: format!("{addr}").into(),
            source,
        })?;
        let stop = Arc::new(AtomicBool::new(false));
        let served = Arc::new((mode, access.bound(bind, addr.port())));
        let stop2 = stop.clone();
        let thread = std::thread::spawn(move || accept_loop(listener, served, stop2));
        Ok(Server {
            addr,
            stop,
            thread: Some(thread),
        })
    }

    /// The address it listens on.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// The page's URL.
    pub fn url(&self) -> String {
        format!("http://{}/", self.addr)
    }

    /// Stops accepting connections (open WebSockets end when their session stops).
    pub fn shutdown(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.shutdown();
    }
}

fn accept_loop(listener: TcpListener, served: Arc<(Mode, Access)>, stop: Arc<AtomicBool>) {
    while !stop.load(Ordering::Relaxed) {
        match listener.accept() {
            Ok((stream, _)) => {
                let served = served.clone();
                std::thread::spawn(move || {
                    let _ = handle(stream, &served.0, &served.1);
                });
            }
            Err(_) => std::thread::sleep(Duration::from_millis(10)),
        }
    }
}

/// Reads (peeks) the request head without consuming it, so that a WebSocket handshake can
/// read it again.
fn peek_head(stream: &TcpStream) -> std::io::Result<Vec<u8>> {
    let mut buf = vec![0u8; MAX_HEAD];
    for _ in 0..500 {
        let n = stream.peek(&mut buf)?;
        if n == 0 {
            break;
        }
        if let Some(end) = buf[..n].windows(4).position(|w| w == b"\r\n\r\n") {
            buf.truncate(end + 4);
            return Ok(buf);
        }
        if n == MAX_HEAD {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    Err(std::io::Error::new(
        std::io::ErrorKind::InvalidData,
        "no complete request head",
    ))
}

fn respond(stream: &mut TcpStream, status: &str, ctype: &str, body: &[u8]) -> std::io::Result<()> {
    respond_to(stream, true, status, ctype, body)
}

fn respond_to(
    stream: &mut TcpStream,
    with_body: bool,
    status: &str,
    ctype: &str,
    body: &[u8],
) -> std::io::Result<()> {
    let head = format!(
        "HTTP/1.1 {status}\r\nContent-Type: {ctype}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n",
        body.len()
    );
    stream.write_all(head.as_bytes())?;
    if with_body {
        stream.write_all(body)?;
    }
    stream.flush()
}

/// The run folder's printable debrief (`output::debrief`), served at `<base>/debrief.html`.
const DEBRIEF: &str = crate::output::debrief::DEBRIEF_FILE;
/// Its content type.
const DEBRIEF_TYPE: &str = "text/html; charset=utf-8";

/// Answers with an HTML page read from a run folder under a policy that runs no script and
/// fetches nothing (inline styles and `data:` images only): a page put into the folder by
/// someone else cannot act on this server's origin.
fn respond_sandboxed(stream: &mut TcpStream, with_body: bool, body: &[u8]) -> std::io::Result<()> {
    let head = format!(
        "HTTP/1.1 200 OK\r\nContent-Type: {DEBRIEF_TYPE}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nContent-Security-Policy: sandbox; default-src 'none'; style-src 'unsafe-inline'; img-src data:\r\nConnection: close\r\n\r\n",
        body.len()
    );
    stream.write_all(head.as_bytes())?;
    if with_body {
        stream.write_all(body)?;
    }
    stream.flush()
}

fn handle(mut stream: TcpStream, mode: &Mode, access: &Access) -> std::io::Result<()> {
    stream.set_nonblocking(false)?;
    stream.set_read_timeout(Some(Duration::from_secs(5)))?;
    stream.set_write_timeout(Some(Duration::from_secs(5)))?;
    let head = peek_head(&stream)?;
    let mut headers = [httparse::EMPTY_HEADER; 32];
    let mut req = httparse::Request::new(&mut headers);
    let parsed = req.parse(&head).ok().filter(|s| s.is_complete());
    let (Some(_), Some(method), Some(target)) = (parsed, req.method, req.path) else {
        return respond(
            &mut stream,
            "400 Bad Request",
            "text/plain",
            b"bad request\n",
        );
    };
    if let Err(why) = access.check(req.headers) {
        // Consume what was peeked, so that the answer is not lost to a reset connection.
        let mut sink = vec![0u8; head.len()];
        let _ = stream.read_exact(&mut sink);
        let body = format!("forbidden: {why}\n");
        return respond(&mut stream, "403 Forbidden", "text/plain", body.as_bytes());
    }
    let path = target.split(['?', '#']).next().unwrap_or("");
    let upgrade = req.headers.iter().any(|h| {
        h.name.eq_ignore_ascii_case("upgrade")
            && String::from_utf8_lossy(h.value).eq_ignore_ascii_case("websocket")
    });
    if upgrade
        && path == "/ws"
        && let Mode::Drive { hub, .. } = mode
    {
        let query = target.split_once('?').map_or("", |(_, q)| q);
        return super::hub::serve_socket(stream, hub, query);
    }
    // Consume the head: the body of a GET is empty.
    let mut sink = vec![0u8; head.len()];
    stream.read_exact(&mut sink)?;
    if method != "GET" && method != "HEAD" {
        return respond(
            &mut stream,
            "405 Method Not Allowed",
            "text/plain",
            b"only GET\n",
        );
    }
    if let Some(a) = asset(path) {
        let get = method == "GET";
        return respond_to(&mut stream, get, "200 OK", a.content_type, a.bytes);
    }
    if path == "/session.json" {
        let video = matches!(mode, Mode::View { video: Some(_), .. });
        // The session's token, for the page this server served (Host and Origin checked
        // above: another site's page cannot read it). A watch-only hub has nothing to drive.
        let (token, watch_only) = match mode {
            Mode::Drive { hub, .. } => (hub.session_token(), hub.is_watch_only()),
            Mode::View { .. } => (None, false),
        };
        // `watch_only`: a learning environment's page (live/watch.rs), where nobody drives.
        let body = serde_json::json!({
            "mode": mode.name(), "video": video, "token": token, "watch_only": watch_only
        })
        .to_string();
        return respond(&mut stream, "200 OK", "application/json", body.as_bytes());
    }
    match mode {
        Mode::Drive { scene_json, hub } if path == "/scene.json" => {
            let set = hub.scene();
            let query = target.split_once('?').map_or("", |(_, q)| q);
            let k = super::hub::query_robot(query, hub.robots()).unwrap_or(0);
            let body = set
                .as_deref()
                .or(scene_json.get(k))
                .map_or("{}", String::as_str);
            respond(&mut stream, "200 OK", "application/json", body.as_bytes())
        }
        Mode::View { video: Some(v), .. } if path == "/video.mp4" => match v.bytes() {
            Ok(b) => respond_to(&mut stream, method == "GET", "200 OK", "video/mp4", &b),
            Err(e) => respond(
                &mut stream,
                "503 Service Unavailable",
                "text/plain; charset=utf-8",
                format!("no video: {e}\n").as_bytes(),
            ),
        },
        Mode::View { files, .. } => match files.iter().find(|f| f.0 == path) {
            Some((_, ctype, bytes)) if *ctype == DEBRIEF_TYPE => {
                respond_sandboxed(&mut stream, method == "GET", bytes)
            }
            Some((_, ctype, bytes)) => respond(&mut stream, "200 OK", ctype, bytes),
            None => respond(&mut stream, "404 Not Found", "text/plain", b"not found\n"),
        },
        _ => respond(&mut stream, "404 Not Found", "text/plain", b"not found\n"),
    }
}

/// Largest sensor stream `tracksim view` serves, bytes (a larger one is left out: the page
/// draws no readings of it).
pub const MAX_SENSOR_FILE_BYTES: u64 = 64 << 20;
/// Most bytes of sensor streams `tracksim view` holds in all (later streams are left out).
pub const MAX_SENSOR_BYTES: u64 = 256 << 20;

/// Whether `file` (a sensor's stream as `summary.json` names it) is `sensors/NAME.npz` with a
/// plain name (letters, digits, `_`, `-`, `.`; no path separator, not `..`).
fn plain_sensor_npz(file: &str) -> bool {
    let Some(name) = file
        .strip_prefix("sensors/")
        .and_then(|f| f.strip_suffix(".npz"))
    else {
        return false;
    };
    !name.is_empty()
        && !name.starts_with('.')
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
}

/// The `.npz` sensor streams `summary.json` lists (its `sensors[].file`), read from `dir`,
/// served at `/run/sensors/NAME.npz`: only plain names, each at most
/// [`MAX_SENSOR_FILE_BYTES`], at most [`MAX_SENSOR_BYTES`] in all; a missing, too large or
/// oddly named one is left out.
fn sensor_files(dir: &std::path::Path, summary: &[u8]) -> Vec<ViewFile> {
    let Ok(summary) = serde_json::from_slice::<serde_json::Value>(summary) else {
        return Vec::new();
    };
    let listed = summary["sensors"].as_array().cloned().unwrap_or_default();
    let mut total = 0;
    let mut files = Vec::new();
    for file in listed.iter().filter_map(|s| s["file"].as_str()) {
        if !plain_sensor_npz(file) || files.iter().any(|(u, _, _)| *u == format!("/run/{file}")) {
            continue;
        }
        let p = dir.join(file);
        let Ok(meta) = std::fs::metadata(&p) else {
            continue;
        };
        if !meta.is_file()
            || meta.len() > MAX_SENSOR_FILE_BYTES
            || total + meta.len() > MAX_SENSOR_BYTES
        {
            continue;
        }
        if let Ok(bytes) = std::fs::read(&p) {
            total += bytes.len() as u64;
            files.push((format!("/run/{file}"), "application/octet-stream", bytes));
        }
    }
    files
}

/// Most method runs of a `compare` folder that `tracksim view` serves (later ones are left out).
pub const MAX_COMPARE_RUNS: usize = 16;

/// One file `tracksim view` serves: (URL path, content type, bytes).
pub type ViewFile = (String, &'static str, Vec<u8>);

/// The files of one run in `dir`, their URLs under `prefix` (`/run` or `/run/<index>`), with
/// its `scene.json` at `/scene.json` (`prefix` `/run`) or `<prefix>/scene.json`.
fn run_files(dir: &std::path::Path, prefix: &str, sensors: bool) -> Result<Vec<ViewFile>> {
    crate::output::incomplete::check_complete(dir)?;
    let required = ["scene.json", "trajectory.csv", "belts.csv"];
    let optional = ["summary.json", "controls.csv", "ruts.csv", DEBRIEF];
    let mut files = Vec::new();
    for name in required.iter().chain(optional.iter()) {
        let p = dir.join(name);
        match std::fs::read(&p) {
            Ok(bytes) => {
                let ctype = if name.ends_with(".json") {
                    "application/json"
                } else if *name == DEBRIEF {
                    DEBRIEF_TYPE
                } else {
                    "text/csv; charset=utf-8"
                };
                let url = if *name == "scene.json" && prefix == "/run" {
                    "/scene.json".to_string()
                } else {
                    format!("{prefix}/{name}")
                };
                files.push((url, ctype, bytes));
            }
            Err(_) if optional.contains(name) => {}
            Err(source) => {
                let mut hint = String::new();
                if let Ok(rd) = std::fs::read_dir(dir) {
                    let subs: Vec<String> = rd
                        .filter_map(|e| e.ok())
                        .filter(|e| e.path().join("scene.json").is_file())
                        .map(|e| e.path().display().to_string())
                        .collect();
                    if !subs.is_empty() {
                        hint = format!(" (runs found in: {})", subs.join(", "));
                    }
                }
                return Err(Error::Io {
                    path: format!(
                        "{}: the folder of a run of `tracksim run`, `drive` or `compare` (one \
                         subfolder per method) holds it; re-run with this version to write it{hint}",
                        p.display()
                    )
                    .into(),
                    source,
                });
            }
        }
    }
    if sensors {
        let summary = files
            .iter()
            .find(|f| f.0 == format!("{prefix}/summary.json"));
        let mut extra = summary.map(|f| sensor_files(dir, &f.2)).unwrap_or_default();
        for f in &mut extra {
            f.0 = f.0.replacen("/run/", &format!("{prefix}/"), 1);
        }
        files.extend(extra);
    }
    Ok(files)
}

/// The method runs of a `tracksim compare` folder: its subfolders holding a run, in the order
/// of `compare.csv` (else by name), at most [`MAX_COMPARE_RUNS`].
fn compare_runs(dir: &std::path::Path) -> Vec<(String, std::path::PathBuf)> {
    let is_run = |p: &std::path::Path| {
        ["scene.json", "trajectory.csv", "belts.csv"]
            .iter()
            .all(|f| p.join(f).is_file())
    };
    let mut subs: Vec<(String, std::path::PathBuf)> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .filter(|e| is_run(&e.path()))
                .filter_map(|e| Some((e.file_name().into_string().ok()?, e.path())))
                .collect()
        })
        .unwrap_or_default();
    subs.sort();
    let order: Vec<String> = std::fs::read_to_string(dir.join("compare.csv"))
        .map(|t| {
            t.lines()
                .skip(1)
                .filter_map(|l| l.split(',').next().map(str::to_string))
                .collect()
        })
        .unwrap_or_default();
    let rank = |n: &str| order.iter().position(|m| m == n).unwrap_or(usize::MAX);
    subs.sort_by_key(|(n, _)| rank(n));
    subs.truncate(MAX_COMPARE_RUNS);
    subs
}

/// The trainee of a run (`summary.json`'s `trainee`, at `url` among its files), if named.
fn trainee_of(files: &[ViewFile], url: &str) -> Option<String> {
    let summary = files.iter().find(|f| f.0 == url)?;
    let v: serde_json::Value = serde_json::from_slice(&summary.2).ok()?;
    v["trainee"]
        .as_str()
        .map(|t| t.trim().to_string())
        .filter(|t| !t.is_empty())
}

/// Each listed run's `label`, what the page names its ghost and legend entry by: the trainee
/// (a robot of a team: `robot (trainee)`); a trainee with several runs in the folder, or a run
/// without one, also by its folder name.
fn label_runs(listed: &mut [serde_json::Value], team: bool) {
    let trainees: Vec<Option<String>> = listed
        .iter()
        .map(|r| r["trainee"].as_str().map(str::to_string))
        .collect();
    for (r, t) in listed.iter_mut().zip(&trainees) {
        let name = r["name"].as_str().unwrap_or("").to_string();
        let label = match t {
            Some(t) if team => format!("{name} ({t})"),
            Some(t) if trainees.iter().filter(|o| o.as_ref() == Some(t)).count() > 1 => {
                format!("{t} ({name})")
            }
            Some(t) => t.clone(),
            None => name,
        };
        r["label"] = serde_json::Value::String(label);
    }
}

/// The files of a finished run that `tracksim view` serves, read from `dir` once: `scene.json`,
/// `trajectory.csv`, `belts.csv` (required) and `summary.json`, `controls.csv` (if present),
/// and the `.npz` sensor streams `summary.json` lists (see [`MAX_SENSOR_FILE_BYTES`]), under
/// `/run/`; and `/runs.json`, the list of runs. A `tracksim compare` folder (no `scene.json`,
/// a run per method in its subfolders) serves each method's run under `/run/<index>/` (the
/// sensor streams of the first only), the first's `scene.json` at `/scene.json`, and lists
/// them all in `/runs.json`. URLs are fixed when the folder is read: none names a file.
pub fn view_files(dir: &std::path::Path) -> Result<Vec<ViewFile>> {
    let runs = if dir.join("scene.json").is_file() {
        Vec::new()
    } else {
        compare_runs(dir)
    };
    if runs.is_empty() {
        let mut files = run_files(dir, "/run", true)?;
        let name = dir
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "run".into());
        let attempts = attempt_files(dir, &mut files);
        let mut list = serde_json::json!({
            "compare": false,
            "runs": [{ "index": 0, "name": name, "base": "/run" }],
        });
        if !attempts.is_empty() {
            list["attempts"] = serde_json::json!(attempts);
        }
        files.push((
            "/runs.json".into(),
            "application/json",
            list.to_string().into_bytes(),
        ));
        return Ok(files);
    }
    let mut files = Vec::new();
    let mut listed = Vec::new();
    // A team run's folder (`team.json`: several robots of one world), a folder of sessions
    // (runs with a trainee) or a compare folder.
    let team = dir.join("team.json").is_file();
    for (name, path) in &runs {
        let i = listed.len();
        let prefix = format!("/run/{i}");
        let Ok(mut these) = run_files(path, &prefix, i == 0) else {
            continue;
        };
        let attempts = if team {
            stitch_attempts(path, &prefix, &mut these)
        } else {
            0
        };
        if i == 0
            && let Some(scene) = these.iter().find(|f| f.0 == format!("{prefix}/scene.json"))
        {
            let scene = ("/scene.json".to_string(), scene.1, scene.2.clone());
            these.push(scene);
        }
        let trainee = trainee_of(&these, &format!("{prefix}/summary.json"));
        files.extend(these);
        let mut entry = serde_json::json!({
            "index": i, "name": name, "base": prefix, "trainee": trainee,
        });
        if attempts > 0 {
            entry["attempts"] = serde_json::json!(attempts);
            let parts = attempt_parts(path, &prefix, attempts, &mut files);
            if !parts.is_empty() {
                entry["parts"] = serde_json::json!(parts);
            }
        }
        listed.push(entry);
    }
    if listed.is_empty() {
        return run_files(dir, "/run", true);
    }
    label_runs(&mut listed, team);
    let sessions = !team && listed.iter().any(|r| r["trainee"].is_string());
    let list = serde_json::json!({
        "compare": true, "team": team, "sessions": sessions, "runs": listed,
    });
    files.push((
        "/runs.json".into(),
        "application/json",
        list.to_string().into_bytes(),
    ));
    Ok(files)
}

/// The time series a reset robot of a team run is replayed from over the whole session.
const STITCHED: [&str; 3] = ["trajectory.csv", "belts.csv", "controls.csv"];

/// A robot of a team run that was reset (its earlier attempts in `dir/attempts/N/`, issue 43)
/// replayed over the whole session: its served [`STITCHED`] files (under `prefix`, in `files`)
/// become its attempts' rows in order, then its last attempt's, under the one header. Their
/// times are the world's, so the replay puts the robot back at its start at each reset, as the
/// session did (a file not written for the earlier attempts is served as the last one's).
/// Returns the robot's attempts (its earlier ones and the last; 0: none, or a part with
/// another header, when the last attempt's files are served as written).
fn stitch_attempts(dir: &std::path::Path, prefix: &str, files: &mut [ViewFile]) -> usize {
    let mut stitched = Vec::new();
    for name in STITCHED {
        let url = format!("{prefix}/{name}");
        let Some(last) = files.iter().position(|f| f.0 == url) else {
            continue;
        };
        // An attempt whose writing did not finish is not replayed as if it had.
        let Some(kept) = kept_attempts(dir) else {
            return 0;
        };
        let mut parts = Vec::new();
        for sub in kept {
            match std::fs::read(sub.join(name)) {
                Ok(bytes) => parts.push(bytes),
                Err(_) => break,
            }
        }
        if parts.is_empty() {
            // Not written for the earlier attempts (a replay has no `controls.csv`): the last
            // attempt's alone.
            continue;
        }
        parts.push(files[last].2.clone());
        let header = |b: &[u8]| b.split(|&c| c == b'\n').next().map(<[u8]>::to_vec);
        let first = header(&parts[0]);
        if parts.iter().any(|p| header(p) != first) {
            return 0;
        }
        let mut out = parts[0].clone();
        for p in &parts[1..] {
            let body = p
                .iter()
                .position(|&c| c == b'\n')
                .map_or(&p[..0], |i| &p[i + 1..]);
            if !out.ends_with(b"\n") {
                out.push(b'\n');
            }
            out.extend_from_slice(body);
        }
        stitched.push((name, last, out, parts.len()));
    }
    // The trajectory decides; every stitched file has as many attempts.
    let Some(attempts) = stitched
        .iter()
        .find(|s| s.0 == "trajectory.csv")
        .map(|s| s.3)
    else {
        return 0;
    };
    if stitched.iter().any(|s| s.3 != attempts) {
        return 0;
    }
    for (_, i, bytes, _) in stitched {
        files[i].2 = bytes;
    }
    attempts
}

/// Most earlier attempts of a session that `tracksim view` serves.
pub const MAX_ATTEMPTS: usize = crate::output::kept_attempts::MAX_ATTEMPTS;

/// The attempts of a reset robot of a team run whose time series [`stitch_attempts`] joined
/// (`attempts` of them), as its review replays them: each earlier attempt's `summary.json`
/// served under `prefix/attempt/N/`, and the list the page reads (`attempt`, `from_s`: the
/// world time its first sample has, `summary`: its URL), the last attempt (the robot's folder
/// itself) last. The page takes the review panel's events, the course score and the outcome
/// at a replay time from the attempt under way then. Empty when the folders do not hold
/// `attempts` attempts with their samples.
fn attempt_parts(
    dir: &std::path::Path,
    prefix: &str,
    attempts: usize,
    files: &mut Vec<ViewFile>,
) -> Vec<serde_json::Value> {
    let Some(mut kept) = kept_attempts(dir) else {
        return Vec::new();
    };
    kept.push(dir.to_path_buf());
    if kept.len() != attempts {
        return Vec::new();
    }
    let mut parts = Vec::new();
    let mut served = Vec::new();
    for (k, sub) in kept.iter().enumerate() {
        let n = k + 1;
        let Some(from) = std::fs::read(sub.join("trajectory.csv"))
            .ok()
            .and_then(|b| first_time(&b))
        else {
            return Vec::new();
        };
        let url = if n == attempts {
            let url = format!("{prefix}/summary.json");
            files.iter().any(|f| f.0 == url).then_some(url)
        } else {
            std::fs::read(sub.join("summary.json")).ok().map(|bytes| {
                let url = format!("{prefix}/attempt/{n}/summary.json");
                served.push((url.clone(), "application/json", bytes));
                url
            })
        };
        parts.push(serde_json::json!({ "attempt": n, "from_s": from, "summary": url }));
    }
    files.extend(served);
    parts
}

/// The earlier attempts of a drive session in `dir` (`attempts/N/`, issue 43), each a run
/// served under `/attempt/N/` (its `scene.json` there too; no sensor streams), appended to
/// `files`; returns the list the page's selector shows (`attempt`, `base`, `outcome`), the
/// session's folder itself last (the last attempt, at `/run`). Empty without attempts.
fn attempt_files(dir: &std::path::Path, files: &mut Vec<ViewFile>) -> Vec<serde_json::Value> {
    let mut list = Vec::new();
    for n in 1..=MAX_ATTEMPTS {
        let sub = dir.join(crate::run::attempt_folder(n));
        if !sub.join("scene.json").is_file() {
            break;
        }
        let prefix = format!("/attempt/{n}");
        let Ok(these) = run_files(&sub, &prefix, false) else {
            break;
        };
        let outcome = outcome_of(&these, &prefix);
        files.extend(these);
        list.push(serde_json::json!({ "attempt": n, "base": prefix, "outcome": outcome }));
    }
    if !list.is_empty() {
        let outcome = outcome_of(files, "/run");
        let n = list.len() + 1;
        list.push(serde_json::json!({ "attempt": n, "base": "/run", "outcome": outcome }));
    }
    list
}

/// A run's outcome in words from its served `summary.json` (under `prefix`), if any.
fn outcome_of(files: &[ViewFile], prefix: &str) -> Option<String> {
    let f = files
        .iter()
        .find(|f| f.0 == format!("{prefix}/summary.json"))?;
    let v: serde_json::Value = serde_json::from_slice(&f.2).ok()?;
    let status = v["course"]["status"]
        .as_str()
        .map(|s| format!(", course {s}"));
    Some(format!(
        "{}{} after {:.1} s",
        v["outcome"].as_str()?,
        status.unwrap_or_default(),
        v["sim_time_s"].as_f64()?
    ))
}
