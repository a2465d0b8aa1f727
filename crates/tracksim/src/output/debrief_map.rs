//! The course map of a debrief (`debrief.html`, [`super::debrief`]): a top view as inline SVG,
//! drawn as the page's minimap draws it (x up the page, y to the left): the terrain's raised
//! boxes and cylinders, the course's gates (numbered in the order they are passed) and marked
//! obstacles, the path driven, its start and end, and the moments of the run on the path
//! (gates passed, faults, stalls). Read from `scene.json` (as [`super::replay::Scene`] writes
//! it) and the path of `trajectory.csv`; nothing is drawn from outside the file.

use quick_xml::escape::escape;
use serde_json::Value;
use std::fmt::Write;

/// Width and height of the map, px (the SVG scales to the page width in print).
pub const MAP_PX: f64 = 640.0;
/// Most points of the path drawn (a long session's path is thinned to this many).
pub const MAX_PATH_POINTS: usize = 4000;
/// Margin around what is drawn, m.
const MARGIN_M: f64 = 0.5;
/// Smallest side of the area drawn, m (a short run still shows its surroundings).
const MIN_SPAN_M: f64 = 3.0;

/// A moment of the run marked on the path: its position (world x, y, m), its kind (`gate`,
/// `fault`, `stall`, `outcome`, ...) and a label shown on hover.
#[derive(Clone, Debug, PartialEq)]
pub struct MapMark {
    /// World x, y, m.
    pub at: [f64; 2],
    /// The event's kind.
    pub kind: String,
    /// What it was (hover text).
    pub label: String,
}

/// World (x, y) to the map's px: x up, y to the left, about the centre `c` at `s` px/m.
struct Frame {
    c: [f64; 2],
    s: f64,
}

impl Frame {
    fn px(&self, x: f64, y: f64) -> (f64, f64) {
        (
            MAP_PX / 2.0 - (y - self.c[1]) * self.s,
            MAP_PX / 2.0 - (x - self.c[0]) * self.s,
        )
    }
}

fn nums(v: &Value) -> Vec<f64> {
    v.as_array()
        .map(|a| a.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default()
}

/// The footprint corners (world x, y) of a box of half extents `h` (m) at `c`, turned by `yaw`.
fn corners(c: [f64; 2], h: [f64; 2], yaw: f64) -> [[f64; 2]; 4] {
    let (cs, sn) = (yaw.cos(), yaw.sin());
    [[1.0, 1.0], [1.0, -1.0], [-1.0, -1.0], [-1.0, 1.0]].map(|[a, b]| {
        let (lx, ly) = (a * h[0], b * h[1]);
        [c[0] + lx * cs - ly * sn, c[1] + lx * sn + ly * cs]
    })
}

/// Yaw about z of a quaternion `[x, y, z, w]`, rad.
fn quat_yaw(q: &[f64]) -> f64 {
    match q {
        [x, y, z, w] => (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z)),
        _ => 0.0,
    }
}

/// A gate's two ends (world x, y): across its crossing direction, its width apart (a
/// waypoint: its diameter), and its centre.
fn gate_ends(g: &Value) -> ([f64; 2], [f64; 2], [f64; 2], Option<f64>) {
    let c = nums(&g["centre_m"]);
    let c = [
        c.first().copied().unwrap_or(0.0),
        c.get(1).copied().unwrap_or(0.0),
    ];
    let radius = g["radius_m"].as_f64();
    let half = g["width_m"]
        .as_f64()
        .map_or(radius.unwrap_or(0.5), |w| w / 2.0);
    let yaw = g["yaw_rad"].as_f64().unwrap_or(0.0);
    let (ax, ay) = (-yaw.sin() * half, yaw.cos() * half);
    (c, [c[0] + ax, c[1] + ay], [c[0] - ax, c[1] - ay], radius)
}

/// The world extent (x0, x1, y0, y1) of the path, the gates and the obstacles.
fn extent(scene: &Value, path: &[[f64; 2]]) -> [f64; 4] {
    let mut e = [f64::MAX, f64::MIN, f64::MAX, f64::MIN];
    let mut grow = |p: [f64; 2]| {
        if p[0].is_finite() && p[1].is_finite() {
            e = [
                e[0].min(p[0]),
                e[1].max(p[0]),
                e[2].min(p[1]),
                e[3].max(p[1]),
            ];
        }
    };
    path.iter().for_each(|p| grow(*p));
    for g in scene["course"]["gates"].as_array().into_iter().flatten() {
        let (_, a, b, _) = gate_ends(g);
        grow(a);
        grow(b);
    }
    for o in scene["course"]["obstacles"]
        .as_array()
        .into_iter()
        .flatten()
    {
        let c = nums(&o["centre_m"]);
        if c.len() >= 2 {
            grow([c[0], c[1]]);
        }
    }
    if e[0] > e[1] {
        return [-1.0, 1.0, -1.0, 1.0];
    }
    e
}

fn polygon(out: &mut String, f: &Frame, pts: &[[f64; 2]], style: &str, title: Option<&str>) {
    let points: Vec<String> = pts
        .iter()
        .map(|p| {
            let (u, v) = f.px(p[0], p[1]);
            format!("{u:.1},{v:.1}")
        })
        .collect();
    let _ = write!(out, r#"<polygon points="{}" {style}>"#, points.join(" "));
    if let Some(t) = title {
        let _ = write!(out, "<title>{}</title>", escape(t));
    }
    out.push_str("</polygon>\n");
}

/// The terrain's raised boxes (tops above the ground) and cylinders, as footprints.
fn terrain(out: &mut String, f: &Frame, scene: &Value) {
    let ground = scene["terrain"]["ground_z_m"].as_f64().unwrap_or(0.0);
    for b in scene["terrain"]["boxes"].as_array().into_iter().flatten() {
        let (c, h) = (nums(&b["centre_m"]), nums(&b["half_m"]));
        if c.len() < 3 || h.len() < 3 || c[2] + h[2] <= ground + 0.01 {
            continue;
        }
        let yaw = quat_yaw(&nums(&b["quat_xyzw"]));
        let pts = corners([c[0], c[1]], [h[0], h[1]], yaw);
        let top = format!("top {:.2} m", c[2] + h[2]);
        let style = r##"fill="#cdbf9f" fill-opacity="0.8" stroke="#9a8a66" stroke-width="0.5""##;
        polygon(out, f, &pts, style, Some(&top));
    }
    for cy in scene["terrain"]["cylinders"]
        .as_array()
        .into_iter()
        .flatten()
    {
        let c = nums(&cy["centre_m"]);
        let (Some(r), Some(hl)) = (cy["radius_m"].as_f64(), cy["half_length_m"].as_f64()) else {
            continue;
        };
        if c.len() < 2 {
            continue;
        }
        let yaw = cy["yaw_rad"].as_f64().unwrap_or(0.0);
        let pts = corners([c[0], c[1]], [r, hl], yaw);
        let style = r##"fill="#b8a488" fill-opacity="0.8""##;
        polygon(out, f, &pts, style, None);
    }
}

/// The course's marked obstacles (red) and gates (blue, numbered from 1).
fn course(out: &mut String, f: &Frame, scene: &Value) {
    for o in scene["course"]["obstacles"]
        .as_array()
        .into_iter()
        .flatten()
    {
        let (c, h) = (nums(&o["centre_m"]), nums(&o["half_m"]));
        if c.len() < 2 || h.len() < 2 {
            continue;
        }
        let yaw = o["yaw_rad"].as_f64().unwrap_or(0.0);
        let pts = corners([c[0], c[1]], [h[0], h[1]], yaw);
        let name = o["name"].as_str().unwrap_or("obstacle");
        let style = r##"fill="#dc5a3c" fill-opacity="0.85" class="obstacle""##;
        polygon(out, f, &pts, style, Some(name));
    }
    for (i, g) in scene["course"]["gates"]
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
    {
        let (c, a, b, radius) = gate_ends(g);
        let (cu, cv) = f.px(c[0], c[1]);
        if let (Some(r), true) = (radius, g["width_m"].is_null()) {
            let _ = writeln!(
                out,
                r##"<circle class="gate" cx="{cu:.1}" cy="{cv:.1}" r="{:.1}" fill="none" stroke="#1f8fd0" stroke-width="2"/>"##,
                r * f.s
            );
        } else {
            let ((au, av), (bu, bv)) = (f.px(a[0], a[1]), f.px(b[0], b[1]));
            let _ = writeln!(
                out,
                r##"<line class="gate" x1="{au:.1}" y1="{av:.1}" x2="{bu:.1}" y2="{bv:.1}" stroke="#1f8fd0" stroke-width="3"/>"##
            );
        }
        let _ = writeln!(
            out,
            r##"<text x="{:.1}" y="{:.1}" font-size="12" fill="#0b4f7a">{}</text>"##,
            cu + 4.0,
            cv - 4.0,
            i + 1
        );
    }
}

/// The path (thinned to [`MAX_PATH_POINTS`]), its start (green) and end (black).
fn path_svg(out: &mut String, f: &Frame, path: &[[f64; 2]]) {
    let stride = path.len().div_ceil(MAX_PATH_POINTS).max(1);
    let mut pts: Vec<String> = path
        .iter()
        .step_by(stride)
        .map(|p| {
            let (u, v) = f.px(p[0], p[1]);
            format!("{u:.1},{v:.1}")
        })
        .collect();
    if let Some(last) = path.last()
        && !(path.len() - 1).is_multiple_of(stride)
    {
        let (u, v) = f.px(last[0], last[1]);
        pts.push(format!("{u:.1},{v:.1}"));
    }
    let _ = writeln!(
        out,
        r##"<polyline class="path" points="{}" fill="none" stroke="#202020" stroke-width="1.8"/>"##,
        pts.join(" ")
    );
    if let (Some(s), Some(e)) = (path.first(), path.last()) {
        let (su, sv) = f.px(s[0], s[1]);
        let (eu, ev) = f.px(e[0], e[1]);
        let _ = writeln!(
            out,
            r##"<circle cx="{su:.1}" cy="{sv:.1}" r="6" fill="#2e9e3e"><title>start</title></circle>"##
        );
        let _ = writeln!(
            out,
            r##"<rect x="{:.1}" y="{:.1}" width="10" height="10" fill="#111"><title>end</title></rect>"##,
            eu - 5.0,
            ev - 5.0
        );
    }
}

/// The marks of the run's moments on the path.
fn marks_svg(out: &mut String, f: &Frame, marks: &[MapMark]) {
    for m in marks {
        let (u, v) = f.px(m.at[0], m.at[1]);
        let colour = match m.kind.as_str() {
            "gate" | "repetition" => "#1f8fd0",
            "fault" => "#d02020",
            "stall" => "#e09020",
            _ => "#606060",
        };
        let _ = writeln!(
            out,
            r##"<circle class="mark mark-{}" cx="{u:.1}" cy="{v:.1}" r="4" fill="{colour}" stroke="#fff" stroke-width="1"><title>{}</title></circle>"##,
            escape(m.kind.as_str()),
            escape(m.label.as_str())
        );
    }
}

/// A scale bar of a round length and the direction of +x.
fn scale(out: &mut String, f: &Frame) {
    let span = MAP_PX / f.s;
    let len = [0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0]
        .into_iter()
        .rev()
        .find(|l| *l <= span / 4.0)
        .unwrap_or(0.1);
    let w = len * f.s;
    let y = MAP_PX - 14.0;
    let _ = writeln!(
        out,
        r##"<line x1="12" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#000" stroke-width="2"/><text x="12" y="{:.1}" font-size="11">{len} m</text>"##,
        12.0 + w,
        y - 5.0
    );
    let _ = writeln!(
        out,
        r##"<text x="{:.1}" y="16" font-size="11">x ↑  y ←</text>"##,
        MAP_PX - 70.0
    );
}

/// The map as an `<svg>` element: the terrain and course of `scene` (`scene.json`), the path
/// (world x, y, m) and the run's moments.
pub fn course_map_svg(scene: &Value, path: &[[f64; 2]], marks: &[MapMark]) -> String {
    let [x0, x1, y0, y1] = extent(scene, path);
    let span = ((x1 - x0).max(y1 - y0) + 2.0 * MARGIN_M).max(MIN_SPAN_M);
    let f = Frame {
        c: [(x0 + x1) / 2.0, (y0 + y1) / 2.0],
        s: MAP_PX / span,
    };
    let mut out = format!(
        r##"<svg class="map" xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {MAP_PX} {MAP_PX}" width="{MAP_PX}" height="{MAP_PX}" role="img" aria-label="top view of the course and the path driven">
<rect width="{MAP_PX}" height="{MAP_PX}" fill="#f4f1ea"/>
"##
    );
    terrain(&mut out, &f, scene);
    course(&mut out, &f, scene);
    path_svg(&mut out, &f, path);
    marks_svg(&mut out, &f, marks);
    scale(&mut out, &f);
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_map_draws_gates_obstacles_the_path_and_marks_in_the_minimaps_frame() {
        let scene = serde_json::json!({
            "terrain": { "ground_z_m": 0.0, "boxes": [
                { "centre_m": [1.0, 0.0, 0.1], "half_m": [0.2, 0.5, 0.1], "quat_xyzw": [0, 0, 0, 1] },
                { "centre_m": [0.0, 0.0, -0.5], "half_m": [9.0, 9.0, 0.5], "quat_xyzw": [0, 0, 0, 1] }
            ] },
            "course": {
                "gates": [
                    { "kind": "line", "centre_m": [2.0, 0.0], "width_m": 1.0, "yaw_rad": 0.0, "radius_m": null },
                    { "kind": "waypoint", "centre_m": [0.0, 1.0], "radius_m": 0.3, "width_m": null, "yaw_rad": null }
                ],
                "obstacles": [ { "name": "pylon <A>", "centre_m": [1.0, 1.0, 0.2], "half_m": [0.1, 0.1, 0.2], "yaw_rad": 0.0 } ]
            }
        });
        let path = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
        let marks = [MapMark {
            at: [2.0, 0.0],
            kind: "gate".into(),
            label: "gate 0 passed & more".into(),
        }];
        let svg = course_map_svg(&scene, &path, &marks);
        assert_eq!(svg.matches(r#"class="gate""#).count(), 2, "{svg}");
        assert_eq!(
            svg.matches("<circle class=\"gate\"").count(),
            1,
            "the waypoint a ring"
        );
        assert_eq!(svg.matches(r#"class="obstacle""#).count(), 1);
        assert!(svg.contains("pylon &lt;A&gt;"), "names escaped");
        assert!(svg.contains("gate 0 passed &amp; more"));
        // The raised box drawn, the ground slab below the ground's top not.
        assert_eq!(svg.matches("top 0.20 m").count(), 1);
        assert_eq!(svg.matches("top 0.00 m").count(), 0);
        // x up the map: the path's end (x = 2) is above its start (x = 0), same column (y = 0).
        let pl = svg.split(r#"class="path" points=""#).nth(1).unwrap();
        let pts: Vec<(f64, f64)> = pl
            .split('"')
            .next()
            .unwrap()
            .split(' ')
            .map(|p| {
                let (u, v) = p.split_once(',').unwrap();
                (u.parse().unwrap(), v.parse().unwrap())
            })
            .collect();
        assert_eq!(pts.len(), 3);
        assert!(pts[2].1 < pts[0].1, "{pts:?}");
        assert!((pts[2].0 - pts[0].0).abs() < 1e-9, "{pts:?}");
    }
}
