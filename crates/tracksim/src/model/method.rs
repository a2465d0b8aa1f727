//! The track method of a scenario as data: [`Method`], parsed once where the scenario is
//! compiled (`simulation.method`), with what the method can model. The track layer turns it into
//! an implementation (`tracks::build_track`); nothing above the model names a method.

use crate::error::SpecIssue;

/// Track methods (how tracks are modelled), all built from the same vehicle description.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// The paper's segment links with grousers (Okada et al. 2020): `okada2020`.
    Okada2020,
    /// The paper's method without grousers, links restored every step: `okada2020_no_grousers`.
    Okada2020NoGrousers,
    /// The paper's method with a 2-point tip capsule per grouser on the flat ground and the
    /// exact grouser on all other terrain: `okada2020_line_tips` (issue 16.2).
    Okada2020LineTips,
    /// The paper's method with every 4 consecutive grousers of a link in one compound collider
    /// and Rapier's contact clustering: `okada2020_clustered` (issue 16.2).
    Okada2020Clustered,
    /// k wheels per track along the lower run on velocity-driven revolute joints: `wheelsK`
    /// (e.g. `wheels4`, `wheels13`).
    Wheels(usize),
    /// One rigid outline per track whose contacts get the belt's surface velocity (Pecka et al.
    /// 2017, Gazebo's TrackController): `constraint_to_ground`.
    ConstraintToGround,
    /// A closed chain of plates on hinges around sprocket and idler: `plates`.
    Plates,
}

impl Method {
    /// The methods `tracksim compare` runs, in table order.
    pub const COMPARED: &'static [Method] = &[
        Method::Okada2020,
        Method::Okada2020NoGrousers,
        Method::Okada2020LineTips,
        Method::Okada2020Clustered,
        Method::Wheels(4),
        Method::Wheels(13),
        Method::ConstraintToGround,
        Method::Plates,
    ];

    /// Names accepted by [`Self::from_name`], for messages.
    pub const NAMES: &'static str = "\"okada2020\", \"okada2020_no_grousers\", \"okada2020_line_tips\", \"okada2020_clustered\", \"wheelsK\" (K = 1..100, e.g. \"wheels4\"), \"constraint_to_ground\", \"plates\"";

    /// Parses a method name.
    pub fn from_name(name: &str) -> Option<Method> {
        Some(match name {
            "okada2020" => Method::Okada2020,
            "okada2020_no_grousers" => Method::Okada2020NoGrousers,
            "okada2020_line_tips" => Method::Okada2020LineTips,
            "okada2020_clustered" => Method::Okada2020Clustered,
            "constraint_to_ground" => Method::ConstraintToGround,
            "plates" => Method::Plates,
            _ => {
                let k: usize = name.strip_prefix("wheels")?.parse().ok()?;
                if !(1..=100).contains(&k) {
                    return None;
                }
                Method::Wheels(k)
            }
        })
    }

    /// Parses the method name a file gives under `key`, or says what is accepted.
    pub fn parse(key: &str, name: &str) -> std::result::Result<Method, SpecIssue> {
        Method::from_name(name).ok_or_else(|| {
            let names: Vec<String> = Method::COMPARED.iter().map(|m| m.name()).collect();
            let names: Vec<&str> = names.iter().map(String::as_str).collect();
            let hint = crate::check::did_you_mean(name, &names)
                .map(|m| format!(" (did you mean \"{m}\"?)"))
                .unwrap_or_default();
            SpecIssue::new(
                key,
                format!(
                    "unknown track method \"{}\"{hint}; use one of {}",
                    crate::check::echoed(name),
                    Method::NAMES
                ),
            )
        })
    }

    /// The method's name.
    pub fn name(&self) -> String {
        match self {
            Method::Okada2020 => "okada2020".into(),
            Method::Okada2020NoGrousers => "okada2020_no_grousers".into(),
            Method::Okada2020LineTips => "okada2020_line_tips".into(),
            Method::Okada2020Clustered => "okada2020_clustered".into(),
            Method::Wheels(k) => format!("wheels{k}"),
            Method::ConstraintToGround => "constraint_to_ground".into(),
            Method::Plates => "plates".into(),
        }
    }

    /// Whether the method models a drive motor (`[tracks.motor]`): only the segment links feel
    /// the load at their joints.
    pub fn models_motors(&self) -> bool {
        matches!(
            self,
            Method::Okada2020 | Method::Okada2020NoGrousers | Method::Okada2020LineTips
        )
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.name())
    }
}

impl From<Method> for String {
    fn from(m: Method) -> String {
        m.name()
    }
}
