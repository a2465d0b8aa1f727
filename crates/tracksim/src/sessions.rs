//! `tracksim sessions DIR`: the runs in a folder tabulated (trainee, scenario, course, score,
//! date), sortable, as aligned text or CSV. A run folder is a folder holding `summary.json`
//! (any front end's: `run`, `drive`, `ros`); folders are searched to [`MAX_DEPTH`] levels
//! below DIR. A `summary.json` that cannot be read or parsed gives a warning naming it, never
//! an error.

use crate::error::{Error, Result, SpecIssue};
use serde_json::Value;
use std::cmp::Ordering;
use std::path::{Path, PathBuf};

/// Levels of subfolders below DIR searched for run folders (DIR itself is level 0).
pub const MAX_DEPTH: usize = 3;
/// Largest `summary.json` read, bytes (a run's is a few kB; more is not a summary).
pub const MAX_SUMMARY_BYTES: u64 = 16 << 20;
/// Most run folders tabulated (a bound on a folder of millions of runs); more give a warning.
pub const MAX_SESSIONS: usize = 100_000;

/// One session (run folder).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SessionRow {
    /// Trainee (empty: not given).
    pub trainee: String,
    /// Scenario file (empty: not known).
    pub scenario: String,
    /// Course name (empty: no course).
    pub course: String,
    /// Repetitions completed.
    pub repetitions: Option<u32>,
    /// Repetitions required.
    pub repetitions_required: Option<u32>,
    /// Time of the trial, s.
    pub time_s: Option<f64>,
    /// Faults.
    pub faults: Option<u32>,
    /// Penalty time, s.
    pub penalty_s: Option<f64>,
    /// Score time (time plus penalties), s.
    pub score_s: Option<f64>,
    /// The run's outcome.
    pub outcome: String,
    /// Start date, ISO 8601 UTC (empty: not recorded).
    pub date: String,
    /// The run folder.
    pub folder: PathBuf,
}

/// The sessions found under a folder, and a warning per unreadable `summary.json`.
#[derive(Clone, Debug, Default)]
pub struct SessionTable {
    /// The rows, in folder order until sorted.
    pub rows: Vec<SessionRow>,
    /// One line per summary that could not be read (naming the file) or limit reached.
    pub warnings: Vec<String>,
}

/// A column to sort by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SortKey {
    /// Trainee name.
    Trainee,
    /// Scenario file.
    Scenario,
    /// Course name.
    Course,
    /// Repetitions completed (most first).
    Repetitions,
    /// Trial time (shortest first).
    Time,
    /// Faults (fewest first).
    Faults,
    /// Penalty time (least first).
    Penalty,
    /// Score time: time plus penalties (best first: most repetitions, then lowest score).
    Score,
    /// Outcome name.
    Outcome,
    /// Start date (oldest first).
    Date,
    /// Folder path.
    Folder,
}

impl SortKey {
    /// Every key's name, as `--sort` takes it.
    pub const NAMES: &'static [&'static str] = &[
        "trainee",
        "scenario",
        "course",
        "repetitions",
        "time",
        "faults",
        "penalty",
        "score",
        "outcome",
        "date",
        "folder",
    ];

    /// The key of `name` (one of [`SortKey::NAMES`]).
    pub fn parse(name: &str) -> Option<SortKey> {
        use SortKey::*;
        let all = [
            Trainee,
            Scenario,
            Course,
            Repetitions,
            Time,
            Faults,
            Penalty,
            Score,
            Outcome,
            Date,
            Folder,
        ];
        Self::NAMES.iter().position(|n| *n == name).map(|i| all[i])
    }
}

/// A row from the text of a `summary.json` (in `folder`); `Err`: not a summary.
pub fn parse_summary(text: &str, folder: &Path) -> std::result::Result<SessionRow, String> {
    let v: Value = serde_json::from_str(text).map_err(|e| e.to_string())?;
    if !v.is_object() || v.get("outcome").is_none() {
        return Err("not a tracksim summary (no outcome)".into());
    }
    let s = |v: &Value, k: &str| v.get(k).and_then(Value::as_str).unwrap_or("").to_string();
    let score = v.pointer("/course/score");
    let num = |k: &str| score.and_then(|s| s.get(k)).and_then(Value::as_f64);
    let int = |k: &str| num(k).map(|n| n as u32);
    let course = v.get("course").filter(|c| c.is_object());
    Ok(SessionRow {
        trainee: s(&v, "trainee"),
        scenario: s(&v, "scenario"),
        course: course.map(|c| s(c, "name")).unwrap_or_default(),
        repetitions: int("repetitions"),
        repetitions_required: course
            .and_then(|c| c.get("repetitions_required"))
            .and_then(Value::as_u64)
            .map(|n| n as u32),
        time_s: num("time_s"),
        faults: int("faults"),
        penalty_s: num("penalty_s"),
        score_s: num("score_s"),
        outcome: s(&v, "outcome"),
        date: s(&v, "started_utc"),
        folder: folder.to_path_buf(),
    })
}

fn walk(dir: &Path, depth: usize, found: &mut Vec<PathBuf>, t: &mut SessionTable) {
    if found.len() >= MAX_SESSIONS {
        return;
    }
    let summary = dir.join("summary.json");
    if summary.is_file() {
        found.push(summary);
    }
    if depth >= MAX_DEPTH {
        return;
    }
    let Ok(entries) = std::fs::read_dir(dir) else {
        t.warnings
            .push(format!("warning: cannot list {}: skipped", dir.display()));
        return;
    };
    let mut dirs: Vec<PathBuf> = entries
        .flatten()
        .filter(|e| e.file_type().is_ok_and(|f| f.is_dir()))
        .map(|e| e.path())
        .collect();
    dirs.sort();
    for d in dirs {
        walk(&d, depth + 1, found, t);
    }
}

/// Scans `dir` and its subfolders (to [`MAX_DEPTH`]) for run folders; a `dir` that is not a
/// readable folder is an error, a bad `summary.json` a warning.
pub fn scan_sessions(dir: &Path) -> Result<SessionTable> {
    let meta = std::fs::metadata(dir).map_err(|source| Error::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    if !meta.is_dir() {
        return Err(Error::Invalid {
            path: dir.to_path_buf(),
            issues: vec![SpecIssue::new(
                "",
                "is not a folder: give the folder that holds the run folders",
            )],
        });
    }
    std::fs::read_dir(dir).map_err(|source| Error::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut t = SessionTable::default();
    let mut found = Vec::new();
    walk(dir, 0, &mut found, &mut t);
    if found.len() >= MAX_SESSIONS {
        t.warnings.push(format!(
            "warning: more than {MAX_SESSIONS} run folders: only the first are listed"
        ));
    }
    for f in found {
        let folder = f.parent().unwrap_or(dir).to_path_buf();
        let text = crate::files::read_text_bounded(&f, MAX_SUMMARY_BYTES);
        match text
            .map_err(|e| e.to_string())
            .and_then(|s| parse_summary(&s, &folder))
        {
            Ok(row) => t.rows.push(row),
            Err(e) => t
                .warnings
                .push(format!("warning: {}: skipped: {e}", f.display())),
        }
    }
    Ok(t)
}

fn opt_cmp<T: PartialOrd>(a: Option<T>, b: Option<T>) -> Ordering {
    match (a, b) {
        (Some(a), Some(b)) => a.partial_cmp(&b).unwrap_or(Ordering::Equal),
        (Some(_), None) => Ordering::Less,
        (None, Some(_)) => Ordering::Greater,
        (None, None) => Ordering::Equal,
    }
}

/// [`opt_cmp`] with the values in descending order (the most repetitions first); `None`
/// still last.
fn opt_cmp_desc<T: PartialOrd>(a: Option<T>, b: Option<T>) -> Ordering {
    match (a, b) {
        (Some(a), Some(b)) => b.partial_cmp(&a).unwrap_or(Ordering::Equal),
        (a, b) => opt_cmp(a, b),
    }
}

/// Sorts `rows` by `key` (ties by date, then folder); `reverse` turns the order round. Rows
/// without the figure (no course) come last.
pub fn sort_rows(rows: &mut [SessionRow], key: SortKey, reverse: bool) {
    rows.sort_by(|a, b| {
        let o = match key {
            SortKey::Trainee => a.trainee.cmp(&b.trainee),
            SortKey::Scenario => a.scenario.cmp(&b.scenario),
            SortKey::Course => a.course.cmp(&b.course),
            SortKey::Repetitions => opt_cmp_desc(a.repetitions, b.repetitions),
            SortKey::Time => opt_cmp(a.time_s, b.time_s),
            SortKey::Faults => opt_cmp(a.faults, b.faults),
            SortKey::Penalty => opt_cmp(a.penalty_s, b.penalty_s),
            SortKey::Score => opt_cmp_desc(a.repetitions, b.repetitions)
                .then_with(|| opt_cmp(a.score_s, b.score_s)),
            SortKey::Outcome => a.outcome.cmp(&b.outcome),
            SortKey::Date => a.date.cmp(&b.date),
            SortKey::Folder => a.folder.cmp(&b.folder),
        };
        let o = o
            .then_with(|| a.date.cmp(&b.date))
            .then_with(|| a.folder.cmp(&b.folder));
        if reverse { o.reverse() } else { o }
    });
}

/// The columns of the table and the CSV.
pub const COLUMNS: [&str; 11] = [
    "trainee",
    "scenario",
    "course",
    "repetitions",
    "time_s",
    "faults",
    "penalty_s",
    "score_s",
    "outcome",
    "date",
    "folder",
];

fn cells(r: &SessionRow) -> [String; 11] {
    let f = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.2}"));
    let reps = match (r.repetitions, r.repetitions_required) {
        (Some(d), Some(n)) => format!("{d}/{n}"),
        (Some(d), None) => d.to_string(),
        _ => String::new(),
    };
    [
        r.trainee.clone(),
        r.scenario.clone(),
        r.course.clone(),
        reps,
        f(r.time_s),
        r.faults.map_or(String::new(), |n| n.to_string()),
        f(r.penalty_s),
        f(r.score_s),
        r.outcome.clone(),
        r.date.clone(),
        r.folder.display().to_string(),
    ]
}

/// The rows as CSV text (header [`COLUMNS`]; repetitions as `done/required`).
pub fn table_csv(rows: &[SessionRow]) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(COLUMNS).expect("writes to memory");
    for r in rows {
        w.write_record(cells(r)).expect("writes to memory");
    }
    String::from_utf8(w.into_inner().expect("writes to memory")).expect("CSV of strings is UTF-8")
}

/// The rows as a text table, columns aligned (a `-` for an empty cell).
pub fn table_text(rows: &[SessionRow]) -> String {
    let mut all: Vec<Vec<String>> = vec![COLUMNS.iter().map(|c| c.to_string()).collect()];
    for r in rows {
        all.push(
            cells(r)
                .into_iter()
                .map(|c| {
                    let c: String = c.chars().filter(|ch| !ch.is_control()).collect();
                    if c.is_empty() { "-".into() } else { c }
                })
                .collect(),
        );
    }
    let widths: Vec<usize> = (0..COLUMNS.len())
        .map(|i| all.iter().map(|r| r[i].chars().count()).max().unwrap_or(0))
        .collect();
    all.iter()
        .map(|r| {
            r.iter()
                .zip(&widths)
                .map(|(c, w)| format!("{c:<w$}"))
                .collect::<Vec<_>>()
                .join("  ")
                .trim_end()
                .to_string()
        })
        .collect::<Vec<_>>()
        .join("\n")
}
