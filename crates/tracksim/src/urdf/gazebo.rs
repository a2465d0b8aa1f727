//! The Gazebo extensions of a URDF file that tracksim reads: the `TrackedVehicle` plugin
//! block (which links are tracks and flippers, `tracks_separation`) and each link's friction
//! (`<gazebo reference="LINK"><mu1>`). Everything else under `<gazebo>` is Gazebo's own and
//! ignored. The plugin block is read the same way inside an SDF `<model>` (`sdf/`): gz-sim's
//! form (`<left_track><link>NAME</link></left_track>`) and Gazebo classic's
//! `SimpleTrackedVehiclePlugin` form (`<left_track>NAME</left_track>`). `TrackController`
//! plugins (the belt's speed in gz-sim) are not read: tracksim simulates the belt itself.

use std::collections::HashMap;

/// A `gz::sim::systems::TrackedVehicle` (or Gazebo classic tracked-vehicle) plugin block.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TrackedVehiclePlugin {
    /// `<left_track><link>`: links of the left tracks.
    pub left_tracks: Vec<String>,
    /// `<right_track><link>`: links of the right tracks.
    pub right_tracks: Vec<String>,
    /// `<left_flipper><link>`: links of the left flipper tracks.
    pub left_flippers: Vec<String>,
    /// `<right_flipper><link>`: links of the right flipper tracks.
    pub right_flippers: Vec<String>,
    /// `<tracks_separation>`, m.
    pub tracks_separation: Option<f64>,
    /// `<tracks_height>`, m (gz-sim's height of the tracks, for its steering; read, not used
    /// by the simulation).
    pub tracks_height: Option<f64>,
    /// Line of the `<plugin>` element.
    pub line: u32,
    /// The URDF (or SDF) file's name, for messages.
    pub file: String,
}

impl TrackedVehiclePlugin {
    /// Every link the plugin names as a track, with its element's tag.
    pub fn track_links(&self) -> Vec<(&'static str, &str)> {
        self.left_tracks
            .iter()
            .map(|l| ("left_track", l.as_str()))
            .chain(
                self.right_tracks
                    .iter()
                    .map(|l| ("right_track", l.as_str())),
            )
            .chain(
                self.left_flippers
                    .iter()
                    .map(|l| ("left_flipper", l.as_str())),
            )
            .chain(
                self.right_flippers
                    .iter()
                    .map(|l| ("right_flipper", l.as_str())),
            )
            .collect()
    }

    /// `<plugin><TAG> (FILE line N)`, the key of a message about one of its elements.
    pub fn at(&self, tag: &str) -> String {
        format!("<plugin><{tag}> ({} line {})", self.file, self.line)
    }
}

/// What tracksim reads of a URDF file's `<gazebo>` elements.
#[derive(Clone, Debug, Default)]
pub struct GazeboExtensions {
    /// The tracked-vehicle plugin, if the file has one.
    pub plugin: Option<TrackedVehiclePlugin>,
    /// `<mu1>` by link name (`<gazebo reference="LINK">`).
    pub friction: HashMap<String, f64>,
    /// Values that could not be read: (element, text).
    pub unreadable: Vec<(String, String)>,
}

/// True when `plugin` is a tracked-vehicle plugin (gz-sim's `TrackedVehicle`, classic
/// Gazebo's `TrackedVehiclePlugin` or `SimpleTrackedVehiclePlugin`).
pub(super) fn is_tracked_vehicle(plugin: roxmltree::Node) -> bool {
    let name = plugin
        .attribute("name")
        .unwrap_or_default()
        .to_ascii_lowercase();
    let file = plugin
        .attribute("filename")
        .unwrap_or_default()
        .to_ascii_lowercase();
    name.contains("trackedvehicle")
        || file.contains("tracked-vehicle")
        || file.contains("trackedvehicle")
        || file.contains("tracked_vehicle")
}

fn text_of<'a>(n: roxmltree::Node<'a, 'a>, tag: &str) -> Option<&'a str> {
    n.children()
        .find(|c| c.has_tag_name(tag))
        .and_then(|c| c.text())
        .map(str::trim)
}

impl GazeboExtensions {
    /// Reads the `<gazebo>` children of `robot`; `line` gives an element's line.
    pub fn read(robot: roxmltree::Node, line: &dyn Fn(roxmltree::Node) -> u32) -> Self {
        let mut out = GazeboExtensions::default();
        for g in robot.children().filter(|n| n.has_tag_name("gazebo")) {
            // An empty `<mu1>` is a number left out, not "no friction given".
            if let Some(link) = g.attribute("reference")
                && let Some(mu) = g
                    .children()
                    .find(|c| c.has_tag_name("mu1"))
                    .map(|c| c.text().map_or("", str::trim))
            {
                match mu.parse::<f64>() {
                    Ok(v) => {
                        out.friction.insert(link.to_string(), v);
                    }
                    Err(_) => out
                        .unreadable
                        .push((format!("<gazebo reference=\"{link}\"><mu1>"), mu.into())),
                }
            }
            for p in g.children().filter(|n| n.has_tag_name("plugin")) {
                if is_tracked_vehicle(p) {
                    out.plugin = Some(read_plugin(p, line, &mut out.unreadable));
                }
            }
        }
        out
    }
}

/// The link names of the plugin's `<TAG>` elements: gz-sim's `<TAG><link>NAME</link></TAG>`
/// or classic Gazebo's `<TAG>NAME</TAG>`.
fn plugin_links(p: roxmltree::Node, tag: &str) -> Vec<String> {
    p.children()
        .filter(|c| c.has_tag_name(tag))
        .filter_map(|c| text_of(c, "link").or_else(|| c.text().map(str::trim)))
        .filter(|l| !l.is_empty())
        .map(String::from)
        .collect()
}

/// Reads a tracked-vehicle `<plugin>` element (a URDF's `<gazebo>` child or an SDF `<model>`
/// child); numbers that cannot be read go to `unreadable` as (element, text).
pub(super) fn read_plugin(
    p: roxmltree::Node,
    line: &dyn Fn(roxmltree::Node) -> u32,
    unreadable: &mut Vec<(String, String)>,
) -> TrackedVehiclePlugin {
    let mut plugin = TrackedVehiclePlugin {
        left_tracks: plugin_links(p, "left_track"),
        right_tracks: plugin_links(p, "right_track"),
        left_flippers: plugin_links(p, "left_flipper"),
        right_flippers: plugin_links(p, "right_flipper"),
        tracks_separation: None,
        tracks_height: None,
        line: line(p),
        file: String::new(),
    };
    for (tag, slot) in [
        ("tracks_separation", &mut plugin.tracks_separation),
        ("tracks_height", &mut plugin.tracks_height),
    ] {
        if let Some(t) = text_of(p, tag) {
            match t.parse::<f64>() {
                Ok(v) => *slot = Some(v),
                Err(_) => unreadable.push((format!("<plugin><{tag}>"), t.into())),
            }
        }
    }
    plugin
}
