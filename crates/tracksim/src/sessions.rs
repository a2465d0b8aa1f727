//! `tracksim sessions DIR`: the runs in a folder tabulated (trainee, scenario, course, status,
//! score, date), sortable, as aligned text grouped by course or as CSV, and a leaderboard per
//! course ([`leaderboard`]). A run folder is a folder holding `summary.json` (any front end's:
//! `run`, `drive`, `ros`); folders are searched to [`MAX_DEPTH`] levels below DIR and named
//! relative to it, so that a class folder of team sessions (`CLASS/SESSION/ROBOT/attempts/N`)
//! counts every attempt whichever level it is pointed at (issue 59). A folder still marked
//! `INCOMPLETE` (its run killed, or being written) is listed as such (status `incomplete`),
//! never skipped without a word. A `summary.json` that cannot be read or parsed gives a
//! warning naming it, never an error.

use crate::error::{Error, Result, SpecIssue};
use serde_json::Value;
use std::cmp::Ordering;
use std::path::{Path, PathBuf};

/// Levels of subfolders below DIR searched for run folders (DIR itself is level 0): a class
/// folder of team sessions holds attempts 4 levels down (`SESSION/ROBOT/attempts/N`); 12
/// leaves room for folders of classes. Symbolic links are not followed (no loops).
pub const MAX_DEPTH: usize = 12;
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
    /// What became of the attempt, for a school ([`status_of`]): `completed`, `time limit`,
    /// `tipped over`, `failed`, `ended`, `interrupted` or `ran to the end`.
    pub status: String,
    /// Start date, ISO 8601 UTC (empty: not recorded).
    pub date: String,
    /// The run folder, relative to the folder scanned (`.`: that folder itself).
    pub folder: PathBuf,
}

/// The status of an attempt from its summary's outcome name, outcome reason and course status
/// (`completed`, `time_limit`, `not_completed`, `running`; `None` without a course):
/// - `tipped over`: the tilt limit ended it (whatever else was decided);
/// - `completed`: the course was completed, or a scenario without a course succeeded;
/// - `time limit`: the course's time limit passed, or the scenario's success condition was
///   not met in its time;
/// - `failed`: another failure;
/// - `ended`: the operator ended the session first; `interrupted`: Ctrl-C or a signal;
/// - `ran to the end`: a scenario without success conditions ran its duration;
/// - `incomplete`: the folder is marked `INCOMPLETE` (set by the scan, not from a summary).
pub fn status_of(outcome: &str, reason: &str, course_status: Option<&str>) -> &'static str {
    if reason.contains("tipped over") {
        return "tipped over";
    }
    match course_status {
        Some("completed") => return "completed",
        Some("time_limit") => return "time limit",
        _ => {}
    }
    match outcome {
        "success" if course_status.is_none() => "completed",
        "failure" if reason.contains("timeout") => "time limit",
        "failure" => "failed",
        "ended_by_operator" => "ended",
        "interrupted" => "interrupted",
        "completed" if course_status.is_some() => "ended",
        "completed" => "ran to the end",
        _ => "ended",
    }
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
    /// Status ([`status_of`]).
    Status,
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
        "status",
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
            Status,
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
    let course_status = course.and_then(|c| c.get("status")).and_then(Value::as_str);
    let status = status_of(&s(&v, "outcome"), &s(&v, "outcome_reason"), course_status);
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
        status: status.to_string(),
        date: s(&v, "started_utc"),
        folder: folder.to_path_buf(),
    })
}

fn walk(dir: &Path, depth: usize, found: &mut Vec<PathBuf>, t: &mut SessionTable) {
    if found.len() >= MAX_SESSIONS {
        return;
    }
    let summary = dir.join("summary.json");
    if summary.is_file() || crate::output::incomplete::is_incomplete(dir) {
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
        let folder = f.parent().unwrap_or(dir);
        let incomplete = crate::output::incomplete::is_incomplete(folder);
        let shown = match folder.strip_prefix(dir) {
            Ok(p) if p.as_os_str().is_empty() => PathBuf::from("."),
            Ok(p) => p.to_path_buf(),
            Err(_) => folder.to_path_buf(),
        };
        if incomplete {
            t.warnings.push(format!(
                "warning: {}: marked {}: its run was killed or lost before its outputs were \
                 written (or is still being written); listed as incomplete",
                folder.display(),
                crate::output::incomplete::INCOMPLETE_MARKER
            ));
            t.rows.push(SessionRow {
                outcome: "incomplete".into(),
                status: "incomplete".into(),
                folder: shown,
                ..SessionRow::default()
            });
            continue;
        }
        let folder = shown;
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
            SortKey::Status => a.status.cmp(&b.status),
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
pub const COLUMNS: [&str; 12] = [
    "trainee",
    "scenario",
    "course",
    "status",
    "repetitions",
    "time_s",
    "faults",
    "penalty_s",
    "score_s",
    "outcome",
    "date",
    "folder",
];

fn cells(r: &SessionRow) -> [String; 12] {
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
        r.status.clone(),
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

/// `rows` as aligned text (a `-` for an empty cell), headed by `columns`.
fn aligned(columns: &[&str], rows: impl Iterator<Item = Vec<String>>) -> String {
    let mut all: Vec<Vec<String>> = vec![columns.iter().map(|c| c.to_string()).collect()];
    for r in rows {
        all.push(
            r.into_iter()
                .map(|c| {
                    let c: String = c.chars().filter(|ch| !ch.is_control()).collect();
                    if c.is_empty() { "-".into() } else { c }
                })
                .collect(),
        );
    }
    let widths: Vec<usize> = (0..columns.len())
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

/// The rows as a text table, columns aligned (a `-` for an empty cell).
pub fn table_text(rows: &[SessionRow]) -> String {
    aligned(&COLUMNS, rows.iter().map(|r| cells(r).to_vec()))
}

/// The rows grouped by course (courses by name, runs without a course last), each group
/// headed by a line `course NAME: N sessions` and aligned as [`table_text`]; within a group
/// the rows keep their order.
pub fn table_text_by_course(rows: &[SessionRow]) -> String {
    let mut courses: Vec<&str> = rows.iter().map(|r| r.course.as_str()).collect();
    courses.sort_by(|a, b| (a.is_empty(), a).cmp(&(b.is_empty(), b)));
    courses.dedup();
    courses
        .iter()
        .map(|c| {
            let group: Vec<SessionRow> = rows.iter().filter(|r| r.course == *c).cloned().collect();
            let head = if c.is_empty() {
                format!("no course: {} sessions", group.len())
            } else {
                format!("course {c}: {} sessions", group.len())
            };
            format!("{}\n{}", head, table_text(&group))
        })
        .collect::<Vec<_>>()
        .join("\n\n")
}

/// One trainee's standing on one course ([`leaderboard`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Standing {
    /// The course.
    pub course: String,
    /// The trainee (empty: not given).
    pub trainee: String,
    /// Attempts (run folders) on the course.
    pub attempts: usize,
    /// Attempts whose status is `completed`.
    pub completed: usize,
    /// Best score (time plus penalties) of the completed attempts, s.
    pub best_s: Option<f64>,
    /// Mean score of the completed attempts, s.
    pub mean_s: Option<f64>,
    /// Standard deviation of the completed attempts' scores (n - 1), s: the spread of
    /// repeated trials, as ASTM's test methods for response robots report it.
    pub sd_s: Option<f64>,
}

/// The leaderboard of every course: per trainee the attempts, the completed attempts and their
/// best, mean and spread of score; within a course the best score first (trainees without a
/// completed attempt last, by name). Runs without a course are left out.
pub fn leaderboard(rows: &[SessionRow]) -> Vec<Standing> {
    let mut keys: Vec<(&str, &str)> = rows
        .iter()
        .filter(|r| !r.course.is_empty())
        .map(|r| (r.course.as_str(), r.trainee.as_str()))
        .collect();
    keys.sort();
    keys.dedup();
    let mut out: Vec<Standing> = keys
        .into_iter()
        .map(|(course, trainee)| {
            let mine: Vec<&SessionRow> = rows
                .iter()
                .filter(|r| r.course == course && r.trainee == trainee)
                .collect();
            let scores: Vec<f64> = mine
                .iter()
                .filter(|r| r.status == "completed")
                .filter_map(|r| r.score_s)
                .collect();
            let n = scores.len() as f64;
            let mean = (!scores.is_empty()).then(|| scores.iter().sum::<f64>() / n);
            let sd = mean
                .filter(|_| scores.len() > 1)
                .map(|m| (scores.iter().map(|s| (s - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt());
            Standing {
                course: course.to_string(),
                trainee: trainee.to_string(),
                attempts: mine.len(),
                completed: mine.iter().filter(|r| r.status == "completed").count(),
                best_s: scores.iter().copied().reduce(f64::min),
                mean_s: mean,
                sd_s: sd,
            }
        })
        .collect();
    out.sort_by(|a, b| {
        a.course
            .cmp(&b.course)
            .then_with(|| opt_cmp(a.best_s, b.best_s))
            .then_with(|| opt_cmp(a.mean_s, b.mean_s))
            .then_with(|| a.trainee.cmp(&b.trainee))
    });
    out
}

/// The columns of the leaderboard.
pub const LEADERBOARD_COLUMNS: [&str; 8] = [
    "course",
    "rank",
    "trainee",
    "completed",
    "attempts",
    "best_s",
    "mean_s",
    "sd_s",
];

fn standing_cells(board: &[Standing]) -> Vec<Vec<String>> {
    let f = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.2}"));
    let mut rank = 0;
    let mut course = "";
    board
        .iter()
        .map(|s| {
            if s.course != course {
                (course, rank) = (&s.course, 0);
            }
            rank += 1;
            vec![
                s.course.clone(),
                if s.best_s.is_some() {
                    rank.to_string()
                } else {
                    String::new()
                },
                s.trainee.clone(),
                s.completed.to_string(),
                s.attempts.to_string(),
                f(s.best_s),
                f(s.mean_s),
                f(s.sd_s),
            ]
        })
        .collect()
}

/// The leaderboard as aligned text (rank only for trainees with a completed attempt).
pub fn leaderboard_text(board: &[Standing]) -> String {
    aligned(&LEADERBOARD_COLUMNS, standing_cells(board).into_iter())
}

/// The leaderboard as CSV (header [`LEADERBOARD_COLUMNS`]).
pub fn leaderboard_csv(board: &[Standing]) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(LEADERBOARD_COLUMNS)
        .expect("writes to memory");
    for r in standing_cells(board) {
        w.write_record(r).expect("writes to memory");
    }
    String::from_utf8(w.into_inner().expect("writes to memory")).expect("CSV of strings is UTF-8")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(course: &str, trainee: &str, status: &str, score: Option<f64>) -> SessionRow {
        SessionRow {
            course: course.into(),
            trainee: trainee.into(),
            status: status.into(),
            score_s: score,
            ..Default::default()
        }
    }

    /// A class folder of two team sessions: in the first, blue was reset once (two attempts,
    /// `s1/blue/attempts/1` and `s1/blue`), red drove once; the second was lost (killed:
    /// only `INCOMPLETE`). Pointed at the class or at the session, blue has two attempts, and
    /// the lost session is a row of its own.
    #[test]
    fn attempts_are_found_at_any_depth_and_a_lost_session_is_listed() {
        let tmp = tempfile::tempdir().unwrap();
        let class = tmp.path();
        let summary = |dir: &Path, trainee: &str, score: f64| {
            std::fs::create_dir_all(dir).unwrap();
            let v = serde_json::json!({
                "outcome": "success", "outcome_reason": "", "trainee": trainee,
                "course": {"name": "race", "status": "completed",
                           "score": {"score_s": score, "time_s": score}},
            });
            std::fs::write(dir.join("summary.json"), v.to_string()).unwrap();
        };
        summary(&class.join("s1/blue/attempts/1"), "Ada", 30.0);
        summary(&class.join("s1/blue"), "Ada", 25.0);
        summary(&class.join("s1/red"), "Bob", 28.0);
        std::fs::create_dir_all(class.join("s2")).unwrap();
        std::fs::write(class.join("s2/INCOMPLETE"), "").unwrap();
        for (at, rows) in [(class.to_path_buf(), 4), (class.join("s1"), 3)] {
            let t = scan_sessions(&at).unwrap();
            assert_eq!(t.rows.len(), rows, "{}: {:?}", at.display(), t.rows);
            let board = leaderboard(&t.rows);
            let ada = board.iter().find(|s| s.trainee == "Ada").unwrap();
            assert_eq!((ada.attempts, ada.completed), (2, 2), "{}", at.display());
            assert_eq!(ada.best_s, Some(25.0));
        }
        let t = scan_sessions(class).unwrap();
        let lost: Vec<_> = t.rows.iter().filter(|r| r.status == "incomplete").collect();
        assert_eq!(lost.len(), 1);
        assert_eq!(lost[0].folder, PathBuf::from("s2"));
        assert!(
            t.warnings
                .iter()
                .any(|w| w.contains("s2") && w.contains("incomplete"))
        );
    }

    #[test]
    fn the_status_says_what_became_of_the_attempt() {
        let tipped = "tipped over (roll 80.0 deg, pitch 1.0 deg, limit 70.0 deg)";
        assert_eq!(
            status_of("failure", tipped, Some("not_completed")),
            "tipped over"
        );
        assert_eq!(
            status_of("ended_by_operator", "", Some("completed")),
            "completed"
        );
        assert_eq!(status_of("ended_by_operator", "", Some("running")), "ended");
        assert_eq!(status_of("completed", "", Some("time_limit")), "time limit");
        assert_eq!(
            status_of("success", "body passed x = 2 m", None),
            "completed"
        );
        let timeout = "timeout: no success condition met in 10.000 s";
        assert_eq!(status_of("failure", timeout, None), "time limit");
        assert_eq!(
            status_of("interrupted", "Ctrl-C at 3 s", None),
            "interrupted"
        );
        assert_eq!(
            status_of("completed", "ran to the end", None),
            "ran to the end"
        );
    }

    #[test]
    fn the_leaderboard_ranks_completed_attempts_by_best_score() {
        let rows = [
            row("loop", "Ada", "completed", Some(30.0)),
            row("loop", "Ada", "completed", Some(34.0)),
            row("loop", "Ada", "tipped over", Some(12.0)),
            row("loop", "Bob", "completed", Some(28.0)),
            row("loop", "Cy", "time limit", Some(90.0)),
            row("stairs", "Ada", "completed", Some(50.0)),
            row("", "Ada", "completed", Some(1.0)),
        ];
        let b = leaderboard(&rows);
        let names: Vec<_> = b
            .iter()
            .map(|s| (s.course.as_str(), s.trainee.as_str()))
            .collect();
        assert_eq!(
            names,
            [
                ("loop", "Bob"),
                ("loop", "Ada"),
                ("loop", "Cy"),
                ("stairs", "Ada")
            ]
        );
        let ada = &b[1];
        assert_eq!((ada.attempts, ada.completed), (3, 2));
        assert_eq!((ada.best_s, ada.mean_s), (Some(30.0), Some(32.0)));
        assert!((ada.sd_s.unwrap() - 8f64.sqrt()).abs() < 1e-12);
        assert_eq!((b[2].best_s, b[2].completed), (None, 0));
        let text = leaderboard_text(&b);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[1].starts_with("loop    1     Bob"), "{text}");
        assert!(lines[3].starts_with("loop    -     Cy"), "{text}");
        assert!(lines[4].starts_with("stairs  1     Ada"), "{text}");
        let csv = leaderboard_csv(&b);
        assert_eq!(csv.lines().nth(2), Some("loop,2,Ada,2,3,30.00,32.00,2.83"));
    }

    #[test]
    fn the_text_table_groups_by_course_with_runs_without_one_last() {
        let rows = [
            row("", "Ada", "ran to the end", None),
            row("stairs", "Bob", "completed", Some(50.0)),
            row("loop", "Ada", "completed", Some(30.0)),
            row("stairs", "Ada", "ended", None),
        ];
        let t = table_text_by_course(&rows);
        let heads: Vec<&str> = t
            .lines()
            .filter(|l| l.starts_with("course ") || l.starts_with("no course"))
            .collect();
        assert_eq!(
            heads,
            [
                "course loop: 1 sessions",
                "course stairs: 2 sessions",
                "no course: 1 sessions"
            ]
        );
    }
}
