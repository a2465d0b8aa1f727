//! `debrief.html`: a printable debrief of one run folder (issue 43), for a trainer and a
//! trainee after a session: who drove what and when, the course's score table, every event
//! with its time (gates, repetitions, faults, stalls, the largest tilt, the outcome), the path
//! on the course map (top view with gates and obstacles: [`super::debrief_map`]) and the key
//! plots (speed, slip, roll and pitch: [`super::debrief_plots`]).
//!
//! The page is self-contained: inline CSS and SVG, no script, no image or font fetched, no
//! link out of the file (the browser prints it to PDF as it is, `@media print` laying it out
//! on A4). It is built from the folder's own files (`summary.json`, `trajectory.csv`,
//! `scene.json`), so [`write_debrief`] rewrites it for any finished run folder
//! (`tracksim debrief DIR`) and [`super::write_outputs`] writes it for every run of a
//! scenario with a `[course]`.

use super::debrief_map::{MapMark, course_map_svg};
use super::debrief_plots::{Columns, key_plots};
use crate::error::{Error, Result};
use quick_xml::escape::escape;
use serde_json::Value;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// The file name of the debrief in a run folder.
pub const DEBRIEF_FILE: &str = "debrief.html";
/// Largest `summary.json` or `scene.json` read, bytes (a scene with meshes is a few MB).
pub const MAX_JSON_BYTES: u64 = 256 << 20;
/// Largest `trajectory.csv` read, bytes (an hour's session at 100 Hz is about 200 MB).
pub const MAX_TRAJECTORY_BYTES: u64 = 2 << 30;

const STYLE: &str = r"
body { font-family: 'DejaVu Sans', Arial, sans-serif; font-size: 11pt; color: #111; margin: 2em auto; max-width: 960px; padding: 0 1em; }
h1 { font-size: 18pt; margin: 0 0 0.2em 0; } h2 { font-size: 13pt; margin: 1.2em 0 0.4em 0; border-bottom: 1px solid #999; }
table { border-collapse: collapse; margin: 0.3em 0; } td, th { border: 1px solid #bbb; padding: 2px 8px; text-align: left; vertical-align: top; }
th { background: #eee; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
tr.fault td { color: #a00000; } tr.outcome td { font-weight: bold; }
.status-completed { color: #1a7a2a; font-weight: bold; } .status-failed { color: #a00000; font-weight: bold; }
svg { max-width: 100%; height: auto; display: block; } .plots svg { margin-bottom: 0.6em; }
.legend span { display: inline-block; margin-right: 1.2em; } .sw { display: inline-block; width: 10px; height: 10px; border-radius: 5px; margin-right: 4px; }
.muted { color: #666; font-size: 9pt; }
@page { size: A4; margin: 14mm; }
@media print { body { margin: 0; max-width: none; font-size: 9.5pt; } h2 { break-after: avoid; } table, svg { break-inside: avoid; } .map-section { break-before: page; } }
";

fn io(path: &Path, message: String) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(message),
    }
}

fn read_json(path: &Path) -> Result<Value> {
    let text = crate::files::read_text_bounded(path, MAX_JSON_BYTES)?;
    serde_json::from_str(&text).map_err(|e| Error::Parse {
        path: path.to_path_buf(),
        message: format!("{e}: not the JSON a run writes; re-run to write it again"),
    })
}

/// Text, HTML-escaped.
fn h(s: &str) -> String {
    escape(s).into_owned()
}

fn num(v: &Value, digits: usize) -> String {
    v.as_f64()
        .map_or_else(|| "-".to_string(), |x| format!("{x:.digits$}"))
}

/// A row of a two-column table: `key`, then `value` (already HTML) in a cell of id `id`.
fn row(out: &mut String, key: &str, id: &str, value: &str) {
    let _ = writeln!(out, r#"<tr><th>{key}</th><td id="{id}">{value}</td></tr>"#);
}

/// Who drove what, when, and how it ended.
fn run_table(out: &mut String, s: &Value) {
    out.push_str("<h2>Run</h2>\n<table class=\"run\">\n");
    let text = |k: &str| s[k].as_str().map_or_else(|| "-".to_string(), h);
    row(out, "trainee", "trainee", &text("trainee"));
    row(out, "scenario", "scenario", &text("scenario"));
    row(out, "vehicle", "vehicle", &text("vehicle"));
    row(out, "track method", "method", &text("method"));
    row(out, "started (UTC)", "started", &text("started_utc"));
    row(
        out,
        "simulated time",
        "sim-time",
        &format!("{} s", num(&s["sim_time_s"], 2)),
    );
    row(
        out,
        "distance driven",
        "distance",
        &format!("{} m", num(&s["distance_m"], 2)),
    );
    let outcome = s["outcome"].as_str().unwrap_or("-");
    let class = match outcome {
        "success" => "status-completed",
        "failure" => "status-failed",
        _ => "",
    };
    let value = format!(
        r#"<span class="{class}">{}</span> at {} s: {}"#,
        h(outcome),
        num(&s["outcome_time_s"], 2),
        text("outcome_reason")
    );
    row(out, "outcome", "outcome", &value);
    out.push_str("</table>\n");
}

/// The course's score table (`summary.json` `course`, run/course.rs `CourseScore`).
fn score_table(out: &mut String, c: &Value) {
    let name = c["name"].as_str().unwrap_or("course");
    let _ = writeln!(out, "<h2>Score: {}</h2>\n<table class=\"score\">", h(name));
    let status = c["status"].as_str().unwrap_or("-");
    let class = match status {
        "completed" => "status-completed",
        "time_limit" | "not_completed" => "status-failed",
        _ => "",
    };
    row(
        out,
        "status",
        "status",
        &format!(
            r#"<span class="{class}">{}</span>"#,
            h(&status.replace('_', " "))
        ),
    );
    let reps = format!(
        "{} of {}",
        c["repetitions_done"].as_u64().unwrap_or(0),
        c["repetitions_required"].as_u64().unwrap_or(0)
    );
    row(out, "repetitions", "repetitions", &reps);
    let gates = c["gates_passed"].as_u64().map_or_else(
        || {
            let n = c["events"]
                .as_array()
                .map_or(0, |e| e.iter().filter(|e| e["kind"] == "gate").count());
            n.to_string()
        },
        |n| n.to_string(),
    );
    let per_rep = c["gates_total"].as_u64().unwrap_or(0);
    row(out, "gates passed", "gates", &gates);
    row(
        out,
        "gates per repetition",
        "gates-total",
        &per_rep.to_string(),
    );
    let times: Vec<String> = c["rep_times_s"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|t| format!("{} s", num(t, 2)))
        .collect();
    let times = if times.is_empty() {
        "-".to_string()
    } else {
        times.join(", ")
    };
    row(out, "time per repetition", "rep-times", &times);
    let limit = c["time_limit_s"]
        .as_f64()
        .map_or_else(String::new, |l| format!(" (limit {l} s)"));
    let time = format!("{} s{limit}", num(&c["score"]["time_s"], 2));
    row(out, "time", "time", &time);
    let f = &c["faults"];
    let faults = format!(
        "{} (reset {}, tip-over {}, touch {})",
        c["score"]["faults"].as_u64().unwrap_or(0),
        f["reset"].as_u64().unwrap_or(0),
        f["tip_over"].as_u64().unwrap_or(0),
        f["touch"].as_u64().unwrap_or(0)
    );
    row(out, "faults", "faults", &faults);
    row(
        out,
        "penalty",
        "penalty",
        &format!("{} s", num(&c["penalty_s"], 2)),
    );
    let score = format!(
        "<b>{} s</b> (time + penalty)",
        num(&c["score"]["score_s"], 2)
    );
    row(out, "score", "score", &score);
    out.push_str("</table>\n");
}

/// One moment of the run: time, kind, words, and its end (a stall).
struct Moment {
    t: f64,
    t_end: Option<f64>,
    kind: String,
    detail: String,
}

/// The run's events (`events`: stalls, the largest tilt, the outcome) and the course's
/// (`course.events`: gates, repetitions, faults, the finish), in time order.
fn moments(s: &Value) -> Vec<Moment> {
    let mut all: Vec<Moment> = s["events"]
        .as_array()
        .into_iter()
        .flatten()
        .chain(s["course"]["events"].as_array().into_iter().flatten())
        .filter_map(|e| {
            Some(Moment {
                t: e["t_s"].as_f64()?,
                t_end: e["t_end_s"].as_f64(),
                kind: e["kind"].as_str().unwrap_or("event").to_string(),
                detail: e["detail"].as_str().unwrap_or("").to_string(),
            })
        })
        .collect();
    // Stable: at one time the course's events keep their order, the outcome comes last.
    all.sort_by(|a, b| {
        a.t.total_cmp(&b.t)
            .then((a.kind == "outcome").cmp(&(b.kind == "outcome")))
    });
    all
}

fn events_table(out: &mut String, all: &[Moment]) {
    let _ = writeln!(
        out,
        "<h2>Events ({})</h2>\n<table class=\"events\">\n<tr><th>t (s)</th><th>event</th><th>what</th></tr>",
        all.len()
    );
    for m in all {
        let class = match m.kind.as_str() {
            "fault" => "fault",
            "outcome" | "finished" => "outcome",
            _ => "",
        };
        let kind = if m.kind == "largest_tilt" {
            "largest tilt"
        } else {
            m.kind.as_str()
        };
        let until = m
            .t_end
            .map_or_else(String::new, |e| format!(" (to {e:.2} s)"));
        let _ = writeln!(
            out,
            r#"<tr class="{class}"><td class="num">{:.2}</td><td>{}</td><td>{}{until}</td></tr>"#,
            m.t,
            h(kind),
            h(&m.detail)
        );
    }
    out.push_str("</table>\n");
}

/// The body's (x, y) at each sample and its sample times.
fn path(c: &Columns) -> (Vec<f64>, Vec<[f64; 2]>) {
    let (Some(it), Some(ix), Some(iy)) = (c.col("t_s"), c.col("x_m"), c.col("y_m")) else {
        return (Vec::new(), Vec::new());
    };
    c.rows
        .iter()
        .filter_map(|r| Some((*r.get(it)?, [*r.get(ix)?, *r.get(iy)?])))
        .filter(|(t, p)| t.is_finite() && p[0].is_finite() && p[1].is_finite())
        .unzip()
}

/// The moments on the path: where the body was at each (the first sample at or after it).
fn marks(all: &[Moment], times: &[f64], pts: &[[f64; 2]]) -> Vec<MapMark> {
    all.iter()
        .filter(|m| matches!(m.kind.as_str(), "gate" | "fault" | "stall" | "outcome"))
        .filter_map(|m| {
            let k = times
                .partition_point(|t| *t < m.t - 1e-9)
                .min(pts.len().checked_sub(1)?);
            Some(MapMark {
                at: pts[k],
                kind: m.kind.clone(),
                label: format!("{:.2} s: {}", m.t, m.detail),
            })
        })
        .collect()
}

fn map_section(out: &mut String, scene: &Value, c: &Columns, all: &[Moment]) {
    let (times, pts) = path(c);
    out.push_str("<section class=\"map-section\">\n<h2>Path on the course (top view)</h2>\n");
    out.push_str(&course_map_svg(scene, &pts, &marks(all, &times, &pts)));
    out.push_str(
        "<p class=\"legend muted\"><span><i class=\"sw\" style=\"background:#2e9e3e\"></i>start</span>\
         <span><i class=\"sw\" style=\"background:#111\"></i>end</span>\
         <span><i class=\"sw\" style=\"background:#1f8fd0\"></i>gate (numbered in order) / passed</span>\
         <span><i class=\"sw\" style=\"background:#d02020\"></i>fault</span>\
         <span><i class=\"sw\" style=\"background:#e09020\"></i>stall</span>\
         <span><i class=\"sw\" style=\"background:#dc5a3c\"></i>marked obstacle</span>\
         <span><i class=\"sw\" style=\"background:#cdbf9f\"></i>raised terrain</span></p>\n</section>\n",
    );
}

/// The debrief page of the run folder `dir` (module docs).
pub fn debrief_html(dir: &Path) -> Result<String> {
    let summary = read_json(&dir.join("summary.json"))?;
    let tp = dir.join("trajectory.csv");
    let traj = Columns::parse(
        &crate::files::read_text_bounded(&tp, MAX_TRAJECTORY_BYTES)?,
        &tp,
    )?;
    let sp = dir.join("scene.json");
    let scene = if sp.is_file() {
        read_json(&sp)?
    } else {
        Value::Null
    };
    let course = &summary["course"];
    let title = match (course["name"].as_str(), summary["trainee"].as_str()) {
        (Some(c), Some(t)) => format!("Debrief: {t} on {c}"),
        (Some(c), None) => format!("Debrief: {c}"),
        (None, Some(t)) => format!("Debrief: {t}"),
        (None, None) => "Debrief".to_string(),
    };
    let mut out = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n<h1>{}</h1>\n<p class=\"muted\">{}</p>\n",
        h(&title),
        h(&title),
        h(summary["started_utc"].as_str().unwrap_or(""))
    );
    if course.is_object() {
        score_table(&mut out, course);
    }
    run_table(&mut out, &summary);
    let all = moments(&summary);
    events_table(&mut out, &all);
    map_section(&mut out, &scene, &traj, &all);
    out.push_str("<h2>Plots</h2>\n<div class=\"plots\">\n");
    for (title, svg) in key_plots(&traj)? {
        let _ = writeln!(out, "<h3>{title}</h3>\n{svg}");
    }
    let _ = write!(
        out,
        "</div>\n<p class=\"muted\">Written by tracksim {} from this folder's summary.json, \
         trajectory.csv and scene.json; <code>tracksim debrief FOLDER</code> writes it again. \
         Print it from the browser (to PDF) as it is.</p>\n</body>\n</html>\n",
        env!("CARGO_PKG_VERSION")
    );
    Ok(out)
}

/// Writes `debrief.html` ([`debrief_html`]) into the run folder `dir`; returns its path.
pub fn write_debrief(dir: &Path) -> Result<PathBuf> {
    if !dir.join("summary.json").is_file() {
        return Err(io(
            &dir.join("summary.json"),
            "not found: give the folder of a run (`tracksim run`, `drive` or `ros` write \
             summary.json and trajectory.csv into it)"
                .into(),
        ));
    }
    let html = debrief_html(dir)?;
    let p = dir.join(DEBRIEF_FILE);
    crate::files::write_atomic(&p, html.as_bytes())?;
    Ok(p)
}
