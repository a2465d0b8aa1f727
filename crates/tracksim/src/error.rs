//! Error types. User mistakes become [`Error`] values that name the file, the key and the fix;
//! nothing in the library panics on bad input.

use std::fmt;
use std::path::PathBuf;

/// Longest key or message of a [`SpecIssue`], characters.
pub const MAX_ISSUE_CHARS: usize = 1000;

fn cut(s: String) -> String {
    if s.len() <= MAX_ISSUE_CHARS {
        return s;
    }
    let kept: String = s.chars().take(MAX_ISSUE_CHARS).collect();
    format!(
        "{kept} ... ({} characters cut)",
        s.chars().count() - MAX_ISSUE_CHARS
    )
}

/// One problem found in an input file, with the key path that holds it
/// (for example `tracks[1].path.pulleys[0].radius_m`).
#[derive(Clone, Debug, PartialEq)]
pub struct SpecIssue {
    /// Key path inside the file.
    pub key: String,
    /// What is wrong and how to fix it.
    pub message: String,
}

impl SpecIssue {
    /// Creates an issue at `key`; a message (or key) longer than [`MAX_ISSUE_CHARS`]
    /// characters is cut (a value from the file is never echoed whole: it may be 50 MB).
    pub fn new(key: impl Into<String>, message: impl Into<String>) -> Self {
        SpecIssue {
            key: cut(key.into()),
            message: cut(message.into()),
        }
    }

    /// An issue whose message is built only of bounded parts (names from the input already
    /// cut, lists from the code): kept whole, so a list of accepted keys is never cut.
    pub(crate) fn whole(key: impl Into<String>, message: impl Into<String>) -> Self {
        SpecIssue {
            key: cut(key.into()),
            message: message.into(),
        }
    }
}

impl fmt::Display for SpecIssue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.key.is_empty() {
            write!(f, "{}", self.message)
        } else {
            write!(f, "{}: {}", self.key, self.message)
        }
    }
}

/// Everything that can go wrong in tracksim.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A file is not valid TOML, has a wrong type, or an unknown key.
    #[error("{}: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// The parser's message (with line, column and key).
        message: String,
    },
    /// A file parsed but its values are wrong; every problem is listed.
    #[error("{}: {} problem(s):\n{}", path.display(), issues.len(), issues.iter().map(|i| format!("  - {i}")).collect::<Vec<_>>().join("\n"))]
    Invalid {
        /// The file.
        path: PathBuf,
        /// Each problem with its key path.
        issues: Vec<SpecIssue>,
    },
    /// Settings given through the API rather than a file are wrong (an environment's
    /// configuration, a sweep plan, the length of an array passed to a call); every problem is
    /// listed with its key (`grid_shape`, `runs`, `belt_speeds`, ...).
    #[error("{what}: {} problem(s):\n{}", issues.len(), issues.iter().map(|i| format!("  - {i}")).collect::<Vec<_>>().join("\n"))]
    Settings {
        /// What was being set (`environment settings`, `sweep plan`, `set_belt_speeds`).
        what: String,
        /// Each problem with its key.
        issues: Vec<SpecIssue>,
    },
    /// The vehicle cannot be built with the chosen track method.
    #[error("cannot build the vehicle: {0}")]
    Build(String),
    /// A video could not be encoded or read (`crate::video`): the codec's or the muxer's
    /// message.
    #[error("video: {0}")]
    Video(String),
    /// A run went past what one world holds exactly (robots spread further apart than
    /// `model::MAX_ROBOT_SPREAD_M`): the run stops.
    #[error("run stopped at t = {time_s:.3} s: {what}")]
    Limit {
        /// Simulated time when detected, s.
        time_s: f64,
        /// What was seen and what to do.
        what: String,
    },
    /// The simulation became unstable (non-finite state or a body flying off).
    #[error(
        "simulation unstable at t = {time_s:.4} s: {body} {what}; try a smaller dt, more solver iterations, or check masses and friction"
    )]
    Unstable {
        /// Simulated time when detected, s.
        time_s: f64,
        /// Which body.
        body: String,
        /// What was seen.
        what: String,
    },
}

impl Error {
    /// Whether this error of a step stops the world but leaves what was simulated sound (a
    /// blow-up the stability check caught, robots spread further apart than one world holds):
    /// the front ends write every robot's run up to it and exit 3 (issue 59).
    pub fn stops_world(&self) -> bool {
        matches!(self, Error::Unstable { .. } | Error::Limit { .. })
    }

    /// An [`Error::Settings`] of one problem at `key`.
    pub fn setting(
        what: impl Into<String>,
        key: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Error::Settings {
            what: what.into(),
            issues: vec![SpecIssue::new(key, message)],
        }
    }

    /// The problems listed by an [`Error::Invalid`] or [`Error::Settings`] (empty for the
    /// other kinds).
    pub fn issues(&self) -> &[SpecIssue] {
        match self {
            Error::Invalid { issues, .. } | Error::Settings { issues, .. } => issues,
            _ => &[],
        }
    }
}

/// Shorthand result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;
