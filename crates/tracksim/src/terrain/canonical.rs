//! The canonical order of a compiled terrain ([`TerrainModel::canonicalize`]).
//!
//! Rapier's results depend on the order colliders are inserted: it decides the collider
//! handles, the broad phase's tree, the order contact pairs are found and so the order in which
//! the solver visits their constraints (projected Gauss-Seidel is order dependent). Issue 38
//! measured a staircase that climbs when its boxes are listed bottom-up and stalls when the same
//! boxes are listed top-down. So the compiled terrain is put in one order that depends only on
//! the geometry: pieces of each kind sorted by their numbers (centre first, then size, pose,
//! friction, soil), soils numbered in the order the sorted pieces first use them. Any
//! permutation of a file's entries that describes the same pieces gives the same world.

use super::{BoxModel, CylinderModel, HeightFieldModel, MeshModel, TerrainModel};
use std::cmp::Ordering;

/// Lexicographic order of two lists of numbers by `f64::total_cmp` (a total order: -0 before
/// +0, NaN last; compiled terrain holds no NaN).
fn cmp_numbers(a: &[f64], b: &[f64]) -> Ordering {
    for (x, y) in a.iter().zip(b) {
        match x.total_cmp(y) {
            Ordering::Equal => {}
            o => return o,
        }
    }
    a.len().cmp(&b.len())
}

fn box_key(b: &BoxModel, soils: &[super::SoilModel]) -> (Vec<f64>, String) {
    let soil = b.soil.and_then(|i| soils.get(i));
    (
        vec![
            b.centre.x,
            b.centre.y,
            b.centre.z,
            b.half.x,
            b.half.y,
            b.half.z,
            b.yaw,
            b.pitch,
            b.friction,
            b.color.0[0] as f64,
            b.color.0[1] as f64,
            b.color.0[2] as f64,
        ],
        format!("{soil:?}"),
    )
}

fn cylinder_key(c: &CylinderModel) -> Vec<f64> {
    vec![
        c.centre.x,
        c.centre.y,
        c.centre.z,
        c.yaw,
        c.half_length,
        c.radius,
        c.friction,
        c.color.0[0] as f64,
        c.color.0[1] as f64,
        c.color.0[2] as f64,
    ]
}

fn heightfield_key(h: &HeightFieldModel) -> Vec<f64> {
    let mut k = vec![
        h.centre.x,
        h.centre.y,
        h.centre.z,
        h.yaw,
        h.size_x,
        h.size_y,
        h.rows as f64,
        h.cols as f64,
        h.friction,
        h.color.0[0] as f64,
        h.color.0[1] as f64,
        h.color.0[2] as f64,
    ];
    k.extend_from_slice(&h.heights);
    k
}

fn mesh_key(m: &MeshModel) -> Vec<f64> {
    let mut k = Vec::with_capacity(2 + m.vertices.len() * 3 + m.triangles.len() * 3);
    k.push(m.vertices.len() as f64);
    k.push(m.friction);
    k.extend(m.color.0.map(f64::from));
    for v in &m.vertices {
        k.extend_from_slice(&[v.x, v.y, v.z]);
    }
    for t in &m.triangles {
        k.extend(t.iter().map(|&i| i as f64));
    }
    k
}

impl TerrainModel {
    /// Puts the pieces of every kind in their canonical order and renumbers the soils in the
    /// order the ground and the sorted boxes first use them (see the module's text). The
    /// geometry is unchanged; only the order of the lists.
    pub fn canonicalize(&mut self) {
        let soils = std::mem::take(&mut self.soils);
        let mut keyed: Vec<((Vec<f64>, String), BoxModel)> = std::mem::take(&mut self.boxes)
            .into_iter()
            .map(|b| (box_key(&b, &soils), b))
            .collect();
        keyed.sort_by(|(a, _), (b, _)| cmp_numbers(&a.0, &b.0).then_with(|| a.1.cmp(&b.1)));
        self.boxes = keyed.into_iter().map(|(_, b)| b).collect();
        self.cylinders
            .sort_by(|a, b| cmp_numbers(&cylinder_key(a), &cylinder_key(b)));
        self.heightfields
            .sort_by_cached_key(|h| OrderedNumbers(heightfield_key(h)));
        self.meshes
            .sort_by_cached_key(|m| OrderedNumbers(mesh_key(m)));
        // Soils by first use: the ground's, then the boxes' in their new order.
        let mut renumber: Vec<Option<usize>> = vec![None; soils.len()];
        let mut kept = Vec::new();
        let mut take = |i: usize| -> usize {
            *renumber[i].get_or_insert_with(|| {
                kept.push(soils[i].clone());
                kept.len() - 1
            })
        };
        self.ground_soil = self.ground_soil.map(&mut take);
        for b in &mut self.boxes {
            b.soil = b.soil.map(&mut take);
        }
        self.soils = kept;
    }
}

/// A list of numbers ordered by [`cmp_numbers`] (for `sort_by_cached_key`).
#[derive(PartialEq)]
struct OrderedNumbers(Vec<f64>);

impl Eq for OrderedNumbers {}

impl PartialOrd for OrderedNumbers {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for OrderedNumbers {
    fn cmp(&self, other: &Self) -> Ordering {
        cmp_numbers(&self.0, &other.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn b(x: f64, z: f64) -> BoxModel {
        BoxModel {
            centre: DVec3::new(x, 0.0, z),
            half: DVec3::splat(0.1),
            yaw: 0.0,
            pitch: 0.0,
            friction: 0.6,
            color: crate::render::Rgb::default(),
            soil: None,
        }
    }

    #[test]
    fn any_order_of_boxes_gives_one_order() {
        let mut a = TerrainModel {
            boxes: vec![b(1.0, 0.0), b(0.0, 0.5), b(1.0, -0.2)],
            ..Default::default()
        };
        let mut c = a.clone();
        c.boxes.reverse();
        a.canonicalize();
        c.canonicalize();
        assert_eq!(format!("{:?}", a.boxes), format!("{:?}", c.boxes));
        let xs: Vec<f64> = a.boxes.iter().map(|b| b.centre.x).collect();
        assert_eq!(xs, vec![0.0, 1.0, 1.0]);
        assert_eq!(a.boxes[1].centre.z, -0.2);
    }
}
