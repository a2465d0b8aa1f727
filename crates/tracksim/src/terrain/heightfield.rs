//! `[[terrain.heightfields]]`: height maps read from greyscale PNG files, and
//! [`HeightFieldModel`], the compiled grid that rough fields produce too.

use super::checks::MAX_GRID_VERTICES;
use super::parse;
use crate::check::Checker;
use crate::render::Rgb;
use crate::spec::HeightFieldSpec;
use glam::{DQuat, DVec3};
use std::path::{Path, PathBuf};

/// A height field, compiled: a regular grid of heights in metres.
#[derive(Clone, Debug)]
pub struct HeightFieldModel {
    /// Centre of the grid (x, y; z is 0: heights are absolute), m.
    pub centre: DVec3,
    /// Rotation about z around the centre, rad.
    pub yaw: f64,
    /// Extent along the grid's x (columns), m.
    pub size_x: f64,
    /// Extent along the grid's y (rows), m.
    pub size_y: f64,
    /// Number of rows (vertices along y), at least 2.
    pub rows: usize,
    /// Number of columns (vertices along x), at least 2.
    pub cols: usize,
    /// Heights z, m, row-major (`heights[r * cols + c]`): row 0 at the +y edge, column 0 at
    /// the -x edge (before yaw).
    pub heights: Vec<f64>,
    /// Friction coefficient.
    pub friction: f64,
    /// Colour in camera images.
    pub color: crate::render::Rgb,
    /// The file it was read from (None for generated fields).
    pub source: Option<PathBuf>,
}

impl HeightFieldModel {
    /// World position of the grid vertex in row `r`, column `c`, m.
    pub fn vertex(&self, r: usize, c: usize) -> DVec3 {
        let lx = -0.5 * self.size_x + self.size_x * c as f64 / (self.cols - 1) as f64;
        let ly = 0.5 * self.size_y - self.size_y * r as f64 / (self.rows - 1) as f64;
        let p = DQuat::from_rotation_z(self.yaw) * DVec3::new(lx, ly, 0.0);
        DVec3::new(
            self.centre.x + p.x,
            self.centre.y + p.y,
            self.heights[r * self.cols + c],
        )
    }
}

/// Reads a PNG height map: (columns, rows, values in [0, 1] row-major, row 0 = top row).
fn load_png(path: &Path) -> Result<(usize, usize, Vec<f64>), String> {
    let bytes = crate::files::read_bounded(path, crate::files::MAX_PNG_BYTES).map_err(|e| {
        format!(
            "cannot read {e}; give the path of a greyscale PNG file relative to the scenario's \
             folder"
        )
    })?;
    parse::png::decode(&bytes, path, MAX_GRID_VERTICES)
}

/// Checks one PNG height map (key `k`, file relative to `base_dir`) and reads it.
pub(super) fn compile(
    c: &mut Checker,
    k: &str,
    s: &HeightFieldSpec,
    base_dir: &Path,
) -> Option<HeightFieldModel> {
    let n = c.issues.len();
    c.positive(&format!("{k}.size_x_m"), s.size_x_m, "m");
    c.positive(&format!("{k}.size_y_m"), s.size_y_m, "m");
    c.finite(&format!("{k}.min_z_m"), &[s.min_z_m]);
    c.finite(&format!("{k}.max_z_m"), &[s.max_z_m]);
    if s.min_z_m.is_finite() && s.max_z_m.is_finite() && s.max_z_m < s.min_z_m {
        c.push(
            format!("{k}.max_z_m"),
            format!("must be >= min_z_m ({} m), got {} m", s.min_z_m, s.max_z_m),
        );
    }
    c.finite(&format!("{k}.centre_m"), &s.centre_m);
    c.finite(&format!("{k}.yaw_deg"), &[s.yaw_deg]);
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    let path = base_dir.join(&s.file);
    let img = match load_png(&path) {
        Ok(img) => Some(img),
        Err(msg) => {
            c.push(format!("{k}.file"), msg);
            None
        }
    };
    let (w, h, vals) = img?;
    if c.issues.len() != n {
        return None;
    }
    let span = s.max_z_m - s.min_z_m;
    Some(HeightFieldModel {
        centre: DVec3::new(s.centre_m[0], s.centre_m[1], 0.0),
        yaw: s.yaw_deg.to_radians(),
        size_x: s.size_x_m,
        size_y: s.size_y_m,
        rows: h,
        cols: w,
        heights: vals.iter().map(|v| s.min_z_m + span * v).collect(),
        friction: s.friction,
        color: Rgb::default(),
        source: Some(path),
    })
}
