//! What `tracksim import` guessed, every guess on its own line: which links are tracks and
//! why, each path's source shapes or segments, grousers, belt masses, the separation and height
//! found against the Gazebo plugin's. Printed, and written as comments at the top of the
//! vehicle file.

use super::propose::{ProposedPath, ProposedTrack};

/// Where the tracks were found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrackSource {
    /// The paper's `libContinuousTrack.so` / `libContinuousTrackSimple.so` plugin.
    ContinuousTrack,
    /// Gazebo's `TrackedVehicle` plugin's named links.
    TrackedVehicle,
    /// Links whose name contains "track".
    LinkNames,
}

/// A plugin value further than this fraction from the geometry's is warned about.
pub const PLUGIN_MISMATCH_FRACTION: f64 = 0.1;

/// Track separation and height: found in the geometry and said by the `TrackedVehicle` plugin.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Geometry {
    /// Distance between the left and right chassis tracks' mid-planes, m.
    pub separation: Option<f64>,
    /// The plugin's `<tracks_separation>`, m.
    pub plugin_separation: Option<f64>,
    /// The main track's path height (its z extent), m.
    pub height: Option<f64>,
    /// The plugin's `<tracks_height>`, m.
    pub plugin_height: Option<f64>,
}

impl Geometry {
    /// Warnings where the plugin disagrees with the geometry by more than
    /// [`PLUGIN_MISMATCH_FRACTION`].
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let pairs = [
            (
                "tracks_separation",
                self.plugin_separation,
                self.separation,
                "the left and right tracks' mid-planes are",
            ),
            (
                "tracks_height",
                self.plugin_height,
                self.height,
                "the track path is",
            ),
        ];
        for (tag, said, found, what) in pairs {
            if let (Some(s), Some(f)) = (said, found)
                && f > 0.0
                && ((s - f) / f).abs() > PLUGIN_MISMATCH_FRACTION
            {
                out.push(format!(
                    "the TrackedVehicle plugin's <{tag}> is {s} m but {what} {f:.4} m apart \
                     ({:+.0} %): Gazebo's odometry and steering with it would be off",
                    (s - f) / f * 100.0
                ));
            }
        }
        out
    }
}

/// Everything `tracksim import` decided.
#[derive(Clone, Debug)]
pub struct ImportReport {
    /// The model file.
    pub model: std::path::PathBuf,
    /// `<robot name>`.
    pub robot: String,
    /// Where the tracks were found.
    pub source: TrackSource,
    /// The tracks proposed.
    pub tracks: Vec<ProposedTrack>,
    /// Revolute joints written as `[joints.NAME]` (the flippers).
    pub flippers: Vec<String>,
    /// Revolute joints kept rigid (`rigid_joints`) with why: they carry no track and turn
    /// about an axis other than y (a sensor's gimbal, a steering joint; issue 60).
    pub rigid: Vec<(String, String)>,
    /// What the model reader assumed or dropped (merged links, arms found, ...), one line
    /// each: shown with the warnings.
    pub model_warnings: Vec<String>,
    /// Links that looked like tracks but gave none, with why.
    pub skipped: Vec<String>,
    /// Separation and height found against the plugin's.
    pub geometry: Geometry,
    /// The SDF `<model>` read (`--sdf-model`), written as the vehicle's `sdf_model`.
    pub sdf_model: Option<String>,
}

fn path_line(t: &ProposedTrack) -> String {
    let p = t
        .perimeter()
        .map_or("refused".into(), |p| format!("perimeter {p:.4} m"));
    match &t.path {
        ProposedPath::Pulleys(v) => format!(
            "path: {} pulleys {}, plane y {:.4} m in the link's frame (chassis y {:.4} m), {p}",
            v.len(),
            v.iter()
                .map(|q| format!("(x {:.4}, z {:.4}, r {:.4})", q.x, q.z, q.radius))
                .collect::<Vec<_>>()
                .join(" "),
            t.plane_y,
            t.chassis_y
        ),
        ProposedPath::Wheel(w) => format!(
            "path: a wheel at x {:.4}, z {:.4} m of radius {:.4} m, {p}",
            w.x, w.z, w.radius
        ),
    }
}

impl ImportReport {
    /// Warnings: the plugin's separation or height against the geometry, joints kept rigid,
    /// and what the model reader assumed.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = self.geometry.warnings();
        w.extend(
            self.rigid
                .iter()
                .map(|(j, why)| format!("joint \"{j}\": {why}")),
        );
        w.extend(self.model_warnings.iter().cloned());
        w
    }

    /// The report as lines of text.
    pub fn lines(&self) -> Vec<String> {
        let mut out = vec![format!(
            "imported {} (robot \"{}\"): {} track(s), found by {}",
            self.model.display(),
            self.robot,
            self.tracks.len(),
            match self.source {
                TrackSource::ContinuousTrack => "the paper's ContinuousTrack plugin",
                TrackSource::TrackedVehicle => "the Gazebo TrackedVehicle plugin's links",
                TrackSource::LinkNames => "link names (no track plugin)",
            }
        )];
        for t in &self.tracks {
            out.push(format!("track {} on link {}: {}", t.name, t.link, t.why));
            out.extend(t.sources.iter().map(|s| format!("  from {s}")));
            out.push(format!("  {}", path_line(t)));
            out.extend(t.guesses.iter().map(|g| format!("  {g}")));
        }
        out.extend(self.skipped.iter().map(|s| format!("not a track: {s}")));
        out.push(if self.flippers.is_empty() {
            "flippers: none (no revolute joint on the chassis)".into()
        } else {
            format!(
                "flippers: revolute joints {} with the default gains 2000 N m/rad, 50 N m s/rad \
                 ([joints.NAME])",
                self.flippers.join(", ")
            )
        });
        let g = &self.geometry;
        let fmt = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:.4} m"));
        out.push(format!(
            "separation found {} (plugin: {}); track height found {} (plugin: {})",
            fmt(g.separation),
            fmt(g.plugin_separation),
            fmt(g.height),
            fmt(g.plugin_height)
        ));
        out.extend(self.warnings().into_iter().map(|w| format!("warning: {w}")));
        out
    }
}
