//! The paper's own Gazebo plugin (`libContinuousTrack.so`, `libContinuousTrackSimple.so`) read
//! from a URDF file's `<gazebo>` blocks with roxmltree: its trajectory segments (raw SDF
//! prismatic joints = straights, revolute joints = arcs, each driving a segment link that is
//! part of the belt, not of the robot), the sprocket's pitch diameter and the grouser pattern.
//!
//! Frames: an SDF `<link><pose>` inside a URDF's `<gazebo>` is in the model frame (the root
//! link's); a `<joint><pose>` is in its child link's frame. Everything returned here is in the
//! model (chassis) frame.

use glam::{DAffine3, DQuat, DVec3, EulerRot};
use roxmltree::Node;

/// One trajectory segment of the plugin.
#[derive(Clone, Debug, PartialEq)]
pub enum PluginSegment {
    /// A prismatic joint: a straight run.
    Straight {
        /// The segment's joint name.
        joint: String,
        /// Start point in the chassis frame, m.
        start: DVec3,
        /// Unit direction of belt travel in the chassis frame.
        direction: DVec3,
        /// `<end_position>` (ContinuousTrack) or the segment link's collision box length
        /// (ContinuousTrackSimple), m.
        length: f64,
    },
    /// A revolute joint: an arc about the joint's axis.
    Arc {
        /// The segment's joint name.
        joint: String,
        /// Centre (the joint's origin) in the chassis frame, m.
        centre: DVec3,
        /// Radius: the distance from the segment link's origin (on the belt) to the joint, m.
        radius: f64,
        /// `<end_position>`, rad (`None` with ContinuousTrackSimple, which gives none).
        angle: Option<f64>,
        /// `<pitch_diameter>` of the segment (ContinuousTrackSimple), m.
        pitch_diameter: Option<f64>,
    },
}

/// One `<pattern><element>`: the cross-section of a shoe or grouser.
#[derive(Clone, Debug, PartialEq)]
pub enum PatternElement {
    /// A `<box><size>` (x along the belt, y across, z outwards), m.
    Box([f64; 3]),
    /// A `<polyline>` extruded by `<height>`: its points after the element's `<pose>`, in the
    /// element frame (x along the belt, y across, z outwards), m.
    Prism(Vec<DVec3>),
}

/// A `libContinuousTrack.so` or `libContinuousTrackSimple.so` plugin block.
#[derive(Clone, Debug, PartialEq)]
pub struct ContinuousTrackPlugin {
    /// `<plugin name>`.
    pub name: String,
    /// True for `libContinuousTrackSimple.so` (no pattern, no `<end_position>`).
    pub simple: bool,
    /// Line of the `<plugin>` element in the file.
    pub line: u32,
    /// `<sprocket><joint>`.
    pub sprocket_joint: Option<String>,
    /// `<sprocket><pitch_diameter>`, m.
    pub sprocket_pitch_diameter: Option<f64>,
    /// The link the segment joints hang on (their `<parent>`), the track's link.
    pub parent_link: String,
    /// The trajectory, in order of belt travel.
    pub segments: Vec<PluginSegment>,
    /// Sum of the segment links' `<mass>`, kg.
    pub belt_mass: f64,
    /// Belt width: the segment links' collision box y size or cylinder length, m.
    pub width: Option<f64>,
    /// The segment collisions' `<mu>`.
    pub friction: Option<f64>,
    /// `<pattern><elements_per_round>`.
    pub elements_per_round: Option<usize>,
    /// `<pattern><element>`s, used in turn around the belt.
    pub elements: Vec<PatternElement>,
}

fn child<'a>(n: Node<'a, 'a>, tag: &str) -> Option<Node<'a, 'a>> {
    n.children().find(|c| c.has_tag_name(tag))
}

fn text<'a>(n: Node<'a, 'a>, tag: &str) -> Option<&'a str> {
    child(n, tag).and_then(|c| c.text()).map(str::trim)
}

fn numbers(s: &str) -> Option<Vec<f64>> {
    s.split_whitespace()
        .map(|v| v.parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect()
}

fn number(n: Node, tag: &str) -> Option<f64> {
    numbers(text(n, tag)?)?.first().copied()
}

/// An SDF `<pose>x y z roll pitch yaw</pose>` child of `n` (identity when absent).
fn pose(n: Node) -> Result<DAffine3, String> {
    let Some(t) = text(n, "pose") else {
        return Ok(DAffine3::IDENTITY);
    };
    match numbers(t).as_deref() {
        Some([x, y, z, r, p, w]) => Ok(DAffine3::from_rotation_translation(
            DQuat::from_euler(EulerRot::ZYX, *w, *p, *r),
            DVec3::new(*x, *y, *z),
        )),
        _ => Err(format!("<pose>{t}</pose> is not six finite numbers")),
    }
}

/// The `<plugin>` elements of the paper's plugin in `doc`'s `<gazebo>` blocks.
fn plugins<'a>(doc: &'a roxmltree::Document<'a>) -> Vec<Node<'a, 'a>> {
    doc.root_element()
        .children()
        .filter(|g| g.has_tag_name("gazebo"))
        .flat_map(|g| g.children().filter(|p| p.has_tag_name("plugin")))
        .filter(|p| {
            p.attribute("filename")
                .unwrap_or_default()
                .to_ascii_lowercase()
                .contains("continuoustrack")
        })
        .collect()
}

/// The raw SDF element `<TAG name="NAME">` in a `<gazebo>` block without `reference`.
fn sdf<'a>(doc: &'a roxmltree::Document<'a>, tag: &str, name: &str) -> Option<Node<'a, 'a>> {
    doc.root_element()
        .children()
        .filter(|g| g.has_tag_name("gazebo") && g.attribute("reference").is_none())
        .flat_map(|g| g.children())
        .find(|n| n.has_tag_name(tag) && n.attribute("name") == Some(name))
}

/// Reads every paper-plugin block of the URDF text `xml`; `Err` names what is wrong.
pub fn read(xml: &str) -> Result<Vec<ContinuousTrackPlugin>, String> {
    let doc = roxmltree::Document::parse_with_options(
        xml,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        },
    )
    .map_err(|e| format!("not well-formed XML: {e}"))?;
    plugins(&doc)
        .into_iter()
        .map(|p| read_plugin(&doc, p))
        .collect()
}

/// One plugin block.
fn read_plugin<'a>(
    doc: &'a roxmltree::Document<'a>,
    p: Node<'a, 'a>,
) -> Result<ContinuousTrackPlugin, String> {
    let line = doc.text_pos_at(p.range().start).row;
    let at = |m: String| format!("<plugin> (line {line}): {m}");
    let simple = p
        .attribute("filename")
        .unwrap_or_default()
        .to_ascii_lowercase()
        .contains("simple");
    let sprocket = child(p, "sprocket");
    let list = child(p, "trajectory")
        .or_else(|| child(p, "track"))
        .ok_or_else(|| at("has no <trajectory> (or <track>) of segments".into()))?;
    let mut out = ContinuousTrackPlugin {
        name: p.attribute("name").unwrap_or("track").to_string(),
        simple,
        line,
        sprocket_joint: sprocket.and_then(|s| text(s, "joint")).map(String::from),
        sprocket_pitch_diameter: sprocket.and_then(|s| number(s, "pitch_diameter")),
        parent_link: String::new(),
        segments: Vec::new(),
        belt_mass: 0.0,
        width: None,
        friction: None,
        elements_per_round: None,
        elements: Vec::new(),
    };
    for s in list.children().filter(|c| c.has_tag_name("segment")) {
        let joint = text(s, "joint").ok_or_else(|| at("a <segment> has no <joint>".into()))?;
        segment(doc, s, joint, &mut out).map_err(|m| at(format!("segment {joint}: {m}")))?;
    }
    if out.segments.is_empty() {
        return Err(at("its trajectory has no <segment>".into()));
    }
    if let Some(pat) = child(p, "pattern") {
        out.elements_per_round = number(pat, "elements_per_round")
            .filter(|n| *n >= 1.0 && *n <= 10_000.0)
            .map(|n| n as usize);
        for e in pat.children().filter(|c| c.has_tag_name("element")) {
            if let Some(el) = element(e).map_err(|m| at(format!("<pattern><element>: {m}")))? {
                out.elements.push(el);
            }
        }
    }
    Ok(out)
}

/// One trajectory segment: its SDF joint and child link.
fn segment<'a>(
    doc: &'a roxmltree::Document<'a>,
    s: Node<'a, 'a>,
    joint: &str,
    out: &mut ContinuousTrackPlugin,
) -> Result<(), String> {
    let j = sdf(doc, "joint", joint).ok_or("no SDF <joint> of that name in a <gazebo> block")?;
    let link_name = text(j, "child").ok_or("its <joint> has no <child>")?;
    let parent = text(j, "parent").ok_or("its <joint> has no <parent>")?;
    if out.parent_link.is_empty() {
        out.parent_link = parent.to_string();
    } else if out.parent_link != parent {
        return Err(format!(
            "its parent is {parent}, the others' {}: one track hangs on one link",
            out.parent_link
        ));
    }
    let link = sdf(doc, "link", link_name)
        .ok_or_else(|| format!("its child link {link_name} is not an SDF <link>"))?;
    let link_pose = pose(link)?;
    out.belt_mass += child(link, "inertial")
        .and_then(|i| number(i, "mass"))
        .unwrap_or(0.0);
    let collision = child(link, "collision");
    let geometry = collision.and_then(|c| child(c, "geometry"));
    let size = geometry
        .and_then(|g| child(g, "box"))
        .and_then(|b| text(b, "size"))
        .and_then(numbers);
    let cylinder_length = geometry
        .and_then(|g| child(g, "cylinder"))
        .and_then(|c| number(c, "length"));
    if out.width.is_none() {
        out.width = size
            .as_ref()
            .and_then(|v| v.get(1).copied())
            .or(cylinder_length);
    }
    if out.friction.is_none() {
        out.friction = collision
            .and_then(|c| c.descendants().find(|d| d.has_tag_name("mu")))
            .and_then(|m| m.text())
            .and_then(|t| t.trim().parse().ok());
    }
    let end = number(s, "end_position");
    match j.attribute("type") {
        Some("prismatic") => {
            let axis = child(j, "axis")
                .and_then(|a| text(a, "xyz"))
                .and_then(numbers)
                .and_then(|v| (v.len() == 3).then(|| DVec3::new(v[0], v[1], v[2])))
                .unwrap_or(DVec3::X);
            let length = end
                .or_else(|| size.and_then(|v| v.first().copied()))
                .ok_or("a straight needs <end_position> or a collision <box>")?;
            out.segments.push(PluginSegment::Straight {
                joint: joint.into(),
                start: link_pose.translation,
                direction: (link_pose.matrix3 * axis).normalize_or_zero(),
                length,
            });
        }
        Some("revolute") => {
            let centre = (link_pose * pose(j)?).translation;
            out.segments.push(PluginSegment::Arc {
                joint: joint.into(),
                centre,
                radius: (link_pose.translation - centre).length(),
                angle: end,
                pitch_diameter: number(s, "pitch_diameter"),
            });
        }
        t => {
            return Err(format!(
                "its joint type is {t:?}: a segment is prismatic or revolute"
            ));
        }
    }
    Ok(())
}

/// One `<element>`: its first collision's geometry, in the element frame.
fn element(e: Node) -> Result<Option<PatternElement>, String> {
    let Some(c) = child(e, "collision") else {
        return Ok(None);
    };
    let frame = pose(c)?;
    let Some(g) = child(c, "geometry") else {
        return Ok(None);
    };
    if let Some(b) = child(g, "box") {
        let v = text(b, "size").and_then(numbers).unwrap_or_default();
        return match v.as_slice() {
            [x, y, z]
                if frame.matrix3.abs_diff_eq(glam::DMat3::IDENTITY, 1e-9)
                    && frame.translation.length() < 1e-12 =>
            {
                Ok(Some(PatternElement::Box([*x, *y, *z])))
            }
            [x, y, z] => {
                let h = DVec3::new(*x, *y, *z) * 0.5;
                let corners = (0..8)
                    .map(|k| {
                        let s = DVec3::new(
                            if k & 1 == 0 { -1.0 } else { 1.0 },
                            if k & 2 == 0 { -1.0 } else { 1.0 },
                            if k & 4 == 0 { -1.0 } else { 1.0 },
                        );
                        frame.transform_point3(h * s)
                    })
                    .collect();
                Ok(Some(PatternElement::Prism(corners)))
            }
            _ => Err("<box><size> is not three numbers".into()),
        };
    }
    if let Some(p) = child(g, "polyline") {
        let height = number(p, "height").ok_or("<polyline> has no <height>")?;
        let mut pts = Vec::new();
        for q in p.children().filter(|c| c.has_tag_name("point")) {
            let v = q.text().and_then(numbers).unwrap_or_default();
            let [x, y] = v.as_slice() else {
                return Err("a <polyline><point> is not two numbers".into());
            };
            for z in [0.0, height] {
                pts.push(frame.transform_point3(DVec3::new(*x, *y, z)));
            }
        }
        if pts.len() < 6 {
            return Err("<polyline> needs at least three points".into());
        }
        return Ok(Some(PatternElement::Prism(pts)));
    }
    Ok(None)
}

impl ContinuousTrackPlugin {
    /// The trajectory's length: straights plus radius times angle (the arcs' `<end_position>`;
    /// `None` when an arc has none, as with ContinuousTrackSimple), m.
    pub fn trajectory_length(&self) -> Option<f64> {
        self.segments
            .iter()
            .map(|s| match s {
                PluginSegment::Straight { length, .. } => Some(*length),
                PluginSegment::Arc { radius, angle, .. } => angle.map(|a| a * radius),
            })
            .sum()
    }
}
