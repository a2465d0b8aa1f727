//! The world of an SDF file as a tracksim scenario (`world.toml` beside the imported vehicle):
//! its static models as terrain (`urdf::sdf::world_terrain_lenient`: what tracksim's terrain
//! cannot hold is left out and listed; cylinders and spheres written as OBJ meshes,
//! `solid_N.obj`, in world coordinates), the robot model's pose in the world as the start
//! (x, y, yaw; placement sets the height), and the flat scenario's command.

use super::write::{FLAT_BELT_SPEED_MPS, drive_for, prune, relative};
use crate::spec::{MeshSpec, TerrainSpec, UpAxis};
use crate::urdf::sdf::WorldSolid;
use glam::DVec3;
use std::path::Path;

/// Facets round a cylinder or a sphere's equator when it is written as a mesh: the chord of a
/// 0.1 m radius is then 0.5 mm inside the circle.
pub const SOLID_SEGMENTS: usize = 32;

/// A cylinder (along its z) or sphere as a closed triangle mesh in its frame `pose`: OBJ text
/// (vertices in the world, m; faces counter-clockwise seen from outside).
pub fn solid_obj(s: &WorldSolid) -> String {
    let n = SOLID_SEGMENTS;
    let ring = |z: f64, r: f64| -> Vec<DVec3> {
        (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                DVec3::new(r * a.cos(), r * a.sin(), z)
            })
            .collect()
    };
    // Rings from the bottom up, then the two poles (a cylinder's cap centres).
    let rings: Vec<Vec<DVec3>> = match s.length {
        Some(l) => vec![ring(-l / 2.0, s.radius), ring(l / 2.0, s.radius)],
        None => (1..n / 2)
            .map(|i| {
                let phi = std::f64::consts::PI * i as f64 / (n / 2) as f64;
                ring(-s.radius * phi.cos(), s.radius * phi.sin())
            })
            .collect(),
    };
    let half = s.length.map_or(s.radius, |l| l / 2.0);
    let mut v: Vec<DVec3> = rings.iter().flatten().copied().collect();
    let (bottom, top) = (v.len() + 1, v.len() + 2);
    v.push(DVec3::new(0.0, 0.0, -half));
    v.push(DVec3::new(0.0, 0.0, half));
    let id = |ring: usize, k: usize| ring * n + k % n + 1;
    let mut f: Vec<[usize; 3]> = Vec::new();
    for r in 0..rings.len() - 1 {
        for k in 0..n {
            f.push([id(r, k), id(r, k + 1), id(r + 1, k + 1)]);
            f.push([id(r, k), id(r + 1, k + 1), id(r + 1, k)]);
        }
    }
    let last = rings.len() - 1;
    for k in 0..n {
        f.push([bottom, id(0, k + 1), id(0, k)]);
        f.push([top, id(last, k), id(last, k + 1)]);
    }
    let mut out = String::from("# written by tracksim import: a solid of an SDF world, m\n");
    for p in v {
        let w = s.pose.transform_point3(p);
        out.push_str(&format!("v {} {} {}\n", w.x, w.y, w.z));
    }
    for [a, b, c] in f {
        out.push_str(&format!("f {a} {b} {c}\n"));
    }
    out
}

/// Simulated time of the world scenario, s.
pub const WORLD_DURATION_S: f64 = 20.0;

/// The file name of the world scenario.
pub const WORLD_FILE: &str = "world.toml";

/// Whether the XML text `xml` is an SDF file holding a `<world>`.
pub fn has_world(xml: &str) -> bool {
    roxmltree::Document::parse(xml).is_ok_and(|d| {
        d.root_element().has_tag_name("sdf")
            && d.root_element().children().any(|c| c.has_tag_name("world"))
    })
}

/// Mesh and height-map files made relative to the folder `out` the scenario is written in.
fn files_relative_to(t: &mut TerrainSpec, model: &Path, out: &Path) {
    let dir = model.parent().unwrap_or(Path::new("."));
    let rel = |f: &str| -> String {
        let p = Path::new(f);
        let p = if p.is_absolute() {
            p.to_path_buf()
        } else {
            dir.join(p)
        };
        relative(out, &p).to_string_lossy().replace('\\', "/")
    };
    for m in &mut t.meshes {
        m.file = rel(&m.file.to_string_lossy()).into();
    }
    for h in &mut t.heightfields {
        h.file = rel(&h.file.to_string_lossy()).into();
    }
}

/// The world scenario's text for the SDF file `model` (robot model `sdf_model`, vehicle file
/// `vehicle` beside it) written into `out`, and the lines of what was left out of the world.
pub fn world_text(
    model: &Path,
    sdf_model: Option<&str>,
    vehicle: &str,
    out: &Path,
) -> Result<(String, Vec<String>), String> {
    let flat = |issues: Vec<crate::error::SpecIssue>| {
        issues
            .iter()
            .map(|i| format!("{}: {}", i.key, i.message))
            .collect::<Vec<_>>()
            .join("; ")
    };
    let world = crate::urdf::sdf::world_terrain_lenient(model).map_err(flat)?;
    let start = crate::urdf::sdf::model_start_pose(model, sdf_model).map_err(flat)?;
    let mut terrain = world.terrain;
    files_relative_to(&mut terrain, model, out);
    let mut left: Vec<String> = world
        .left_out
        .iter()
        .map(|i| format!("left out of the world: {}: {}", i.key, i.message))
        .collect();
    for (k, solid) in world.solids.iter().enumerate() {
        let file = format!("solid_{k}.obj");
        std::fs::write(out.join(&file), solid_obj(solid))
            .map_err(|e| format!("{}: {e}", out.join(&file).display()))?;
        left.push(format!(
            "{} ({}) written as the mesh {file} ({SOLID_SEGMENTS} facets round)",
            solid.issue.key,
            if solid.length.is_some() {
                "a cylinder"
            } else {
                "a sphere"
            }
        ));
        terrain.meshes.push(MeshSpec {
            file: file.into(),
            scale: 1.0,
            translation_m: [0.0; 3],
            yaw_deg: 0.0,
            up_axis: UpAxis::Z,
            friction: solid.friction,
            color: None,
        });
    }
    let mut t = toml::Table::new();
    t.insert(
        "description".into(),
        format!(
            "{} (imported) in the world of {} at {FLAT_BELT_SPEED_MPS} m/s",
            vehicle.trim_end_matches(".toml"),
            model
                .file_name()
                .map_or(String::new(), |f| f.to_string_lossy().into_owned())
        )
        .into(),
    );
    let mut veh = toml::Table::new();
    veh.insert("file".into(), vehicle.into());
    if let Some(p) = start {
        let x = p.matrix3.x_axis;
        veh.insert("x_m".into(), p.translation.x.into());
        veh.insert("y_m".into(), p.translation.y.into());
        veh.insert("yaw_deg".into(), x.y.atan2(x.x).to_degrees().into());
    }
    t.insert("vehicle".into(), veh.into());
    let mut tv = toml::Value::try_from(&terrain).map_err(|e| e.to_string())?;
    prune(&mut tv);
    t.insert("terrain".into(), tv);
    drive_for(&mut t, WORLD_DURATION_S);
    let body = toml::to_string(&t).map_err(|e| e.to_string())?;
    let mut head = vec![
        "Written by `tracksim import`: the SDF world's static models as terrain, the robot at its \
         pose in the world, all tracks at 0.3 m/s."
            .to_string(),
    ];
    head.extend(left.iter().cloned());
    let left = left
        .into_iter()
        .filter(|l| l.starts_with("left out"))
        .collect();
    let comments: String = head.iter().map(|l| format!("# {l}\n")).collect();
    Ok((format!("{comments}{body}"), left))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::SpecIssue;
    use glam::DAffine3;

    /// Vertices and faces of OBJ text.
    fn parse(obj: &str) -> (Vec<DVec3>, Vec<[usize; 3]>) {
        let (mut v, mut f) = (Vec::new(), Vec::new());
        for l in obj.lines() {
            let w: Vec<&str> = l.split_whitespace().collect();
            match w.first() {
                Some(&"v") => v.push(DVec3::new(
                    w[1].parse().unwrap(),
                    w[2].parse().unwrap(),
                    w[3].parse().unwrap(),
                )),
                Some(&"f") => f.push([1, 2, 3].map(|i| w[i].parse::<usize>().unwrap() - 1)),
                _ => {}
            }
        }
        (v, f)
    }

    /// Enclosed volume (divergence theorem; positive when the faces turn outwards), m^3.
    fn volume(v: &[DVec3], f: &[[usize; 3]]) -> f64 {
        f.iter()
            .map(|[a, b, c]| v[*a].dot(v[*b].cross(v[*c])) / 6.0)
            .sum()
    }

    /// Every edge in exactly two faces, once each way: a closed, consistently turned surface.
    fn closed(f: &[[usize; 3]]) -> bool {
        let mut edges = std::collections::HashMap::new();
        for t in f {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        edges
            .iter()
            .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1))
    }

    #[test]
    fn a_cylinder_and_a_sphere_are_closed_meshes_of_their_volume_where_the_world_puts_them() {
        let pose = DAffine3::from_rotation_translation(
            glam::DQuat::from_rotation_x(0.7),
            DVec3::new(2.0, -1.0, 0.5),
        );
        let solid = |length| WorldSolid {
            radius: 0.2,
            length,
            pose,
            friction: 0.6,
            issue: SpecIssue::new("k", "m"),
        };
        // A 32-gon prism holds n/(2 pi) sin(2 pi/n) of the cylinder: 0.64 % less.
        let n = SOLID_SEGMENTS as f64;
        let polygon = n / std::f64::consts::TAU * (std::f64::consts::TAU / n).sin();
        let (v, f) = parse(&solid_obj(&solid(Some(1.0))));
        assert!(closed(&f));
        let want = std::f64::consts::PI * 0.04 * 1.0 * polygon;
        assert!(
            (volume(&v, &f) - want).abs() < 1e-9,
            "{} vs {want}",
            volume(&v, &f)
        );
        let axis = pose.matrix3 * DVec3::Z;
        for p in &v {
            let d = *p - pose.translation;
            let along = d.dot(axis);
            let off = (d - axis * along).length();
            assert!(along.abs() <= 0.5 + 1e-12 && off <= 0.2 + 1e-12);
        }
        // A sphere: within 3 % of 4/3 pi r^3 (a 32 x 16 facet UV sphere holds less), closed,
        // every vertex on it.
        let (v, f) = parse(&solid_obj(&solid(None)));
        assert!(closed(&f));
        let ball = 4.0 / 3.0 * std::f64::consts::PI * 0.008;
        let got = volume(&v, &f);
        assert!(got < ball && got > 0.97 * ball, "{got} vs {ball}");
        assert!(
            v.iter()
                .all(|p| ((*p - pose.translation).length() - 0.2).abs() < 1e-12)
        );
    }
}
