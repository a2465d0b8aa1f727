//! `[[terrain.rough]]`: repeatable random rough ground, a seeded height field (white noise
//! smoothed by box filters, tapered at the borders, scaled to the wanted height).

use super::HeightFieldModel;
use super::checks::MAX_GRID_VERTICES;
use super::rng::SplitMix64;
use crate::check::Checker;
use crate::render::Rgb;
use crate::spec::RoughSpec;
use glam::DVec3;

/// One pass of a centred moving average of width 2 * rad + 1 along rows (`along_rows`) or
/// columns of a `rows` x `cols` row-major grid, keeping only fully covered outputs: the
/// result is `rows` x (`cols` - 2 rad) (or (`rows` - 2 rad) x `cols`).
fn box_pass(
    g: &[f64],
    rows: usize,
    cols: usize,
    rad: usize,
    along_rows: bool,
) -> (Vec<f64>, usize, usize) {
    let w = 2 * rad + 1;
    let inv = 1.0 / w as f64;
    if along_rows {
        let oc = cols - 2 * rad;
        let mut out = vec![0.0; rows * oc];
        for r in 0..rows {
            let line = &g[r * cols..(r + 1) * cols];
            let mut sum: f64 = line[..w].iter().sum();
            out[r * oc] = sum * inv;
            for j in 1..oc {
                sum += line[j + w - 1] - line[j - 1];
                out[r * oc + j] = sum * inv;
            }
        }
        (out, rows, oc)
    } else {
        let or = rows - 2 * rad;
        let mut out = vec![0.0; or * cols];
        for col in 0..cols {
            let mut sum: f64 = (0..w).map(|r| g[r * cols + col]).sum();
            out[col] = sum * inv;
            for i in 1..or {
                sum += g[(i + w - 1) * cols + col] - g[(i - 1) * cols + col];
                out[i * cols + col] = sum * inv;
            }
        }
        (out, or, cols)
    }
}

/// Checks one rough field (key `k`) and generates its heights.
pub(super) fn compile(c: &mut Checker, k: &str, s: &RoughSpec) -> Option<HeightFieldModel> {
    let n = c.issues.len();
    c.finite(&format!("{k}.centre_m"), &s.centre_m);
    c.positive(&format!("{k}.size_m[0]"), s.size_m[0], "m");
    c.positive(&format!("{k}.size_m[1]"), s.size_m[1], "m");
    c.positive(&format!("{k}.cell_m"), s.cell_m, "m");
    c.non_negative(&format!("{k}.correlation_m"), s.correlation_m, "m");
    c.finite(&format!("{k}.mean_z_m"), &[s.mean_z_m]);
    c.non_negative(&format!("{k}.edge_taper_m"), s.edge_taper_m, "m");
    c.finite(&format!("{k}.yaw_deg"), &[s.yaw_deg]);
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    match (s.rms_height_m, s.peak_height_m) {
        (Some(a), None) => c.positive(&format!("{k}.rms_height_m"), a, "m"),
        (None, Some(a)) => c.positive(&format!("{k}.peak_height_m"), a, "m"),
        _ => c.push(
            k,
            "give exactly one of rms_height_m (root-mean-square height, m) or peak_height_m \
             (largest height deviation, m)",
        ),
    }
    if c.issues.len() != n {
        return None;
    }
    let cols = (s.size_m[0] / s.cell_m).round().max(1.0) + 1.0;
    let rows = (s.size_m[1] / s.cell_m).round().max(1.0) + 1.0;
    let sigma = s.correlation_m / s.cell_m; // in cells
    // Three box filters of width w have variance 3 (w^2 - 1) / 12 = sigma^2.
    let rad_f = (((4.0 * sigma * sigma + 1.0).sqrt() - 1.0) * 0.5).round();
    let margin = 3.0 * rad_f;
    let total = (cols + 2.0 * margin) * (rows + 2.0 * margin);
    if total > MAX_GRID_VERTICES as f64 {
        c.push(
            k,
            format!(
                "the grid would need {total:.0} vertices (with the smoothing margin), more than \
                 {MAX_GRID_VERTICES}: increase cell_m, or reduce size_m or correlation_m"
            ),
        );
        return None;
    }
    let (cols, rows, rad) = (cols as usize, rows as usize, rad_f as usize);
    let (mut gc, mut gr) = (cols + 6 * rad, rows + 6 * rad);
    let mut rng = SplitMix64(s.seed);
    // Approximately normal noise (Irwin-Hall: sum of four uniforms), arithmetic only.
    let mut g: Vec<f64> = (0..gc * gr)
        .map(|_| rng.unit() + rng.unit() + rng.unit() + rng.unit() - 2.0)
        .collect();
    if rad > 0 {
        for along_rows in [true, false] {
            for _ in 0..3 {
                (g, gr, gc) = box_pass(&g, gr, gc, rad, along_rows);
            }
        }
    }
    debug_assert_eq!((gr, gc), (rows, cols));
    let mean = g.iter().sum::<f64>() / g.len() as f64;
    let (size_x, size_y) = (s.size_m[0], s.size_m[1]);
    let (dx, dy) = (size_x / (cols - 1) as f64, size_y / (rows - 1) as f64);
    for r in 0..rows {
        for col in 0..cols {
            let v = &mut g[r * cols + col];
            *v -= mean;
            if s.edge_taper_m > 0.0 {
                let ex = (col as f64 * dx).min((cols - 1 - col) as f64 * dx);
                let ey = (r as f64 * dy).min((rows - 1 - r) as f64 * dy);
                let u = (ex.min(ey) / s.edge_taper_m).min(1.0);
                *v *= u * u * (3.0 - 2.0 * u); // smoothstep
            }
        }
    }
    let measured = match s.rms_height_m {
        Some(_) => (g.iter().map(|v| v * v).sum::<f64>() / g.len() as f64).sqrt(),
        None => g.iter().fold(0.0f64, |m, v| m.max(v.abs())),
    };
    let wanted = s.rms_height_m.or(s.peak_height_m).unwrap_or(0.0);
    let factor = if measured > 0.0 {
        wanted / measured
    } else {
        0.0
    };
    Some(HeightFieldModel {
        centre: DVec3::new(s.centre_m[0], s.centre_m[1], 0.0),
        yaw: s.yaw_deg.to_radians(),
        size_x,
        size_y,
        rows,
        cols,
        heights: g.iter().map(|v| s.mean_z_m + v * factor).collect(),
        friction: s.friction,
        color: Rgb::default(),
        source: None,
    })
}
