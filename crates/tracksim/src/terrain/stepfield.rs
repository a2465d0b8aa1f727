//! `[[terrain.stepfields]]`: ASTM E2828-style stepfields, a grid of square box posts whose
//! heights come from a given pattern, a seeded random pattern or the default symmetric hill.

use super::TerrainModel;
use super::checks::{MAX_GENERATED_BOXES, check_count, check_place};
use super::frame::Frame;
use super::rng::SplitMix64;
use crate::check::Checker;
use crate::spec::StepfieldSpec;
use glam::DVec3;

/// The default symmetric stepfield pattern: a 12 x 12 diamond-shaped hill of 1 to 4 steps.
fn default_stepfield_pattern() -> Vec<Vec<u32>> {
    (0..12u32)
        .map(|r| {
            (0..12u32)
                .map(|col| 1 + (r.min(11 - r) + col.min(11 - col)) / 3)
                .collect()
        })
        .collect()
}

/// Checks one stepfield (key `k`) and adds its posts to `t`.
pub(super) fn compile(c: &mut Checker, k: &str, s: &StepfieldSpec, t: &mut TerrainModel) {
    let n = c.issues.len();
    check_place(c, k, s.x_m, s.y_m, s.z_m, s.yaw_deg);
    c.positive(&format!("{k}.post_m"), s.post_m, "m");
    c.positive(&format!("{k}.step_m"), s.step_m, "m");
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    let Some(pattern) = resolve_pattern(c, k, s, n) else {
        return;
    };
    if pattern.len() * pattern[0].len() > MAX_GENERATED_BOXES {
        c.push(
            format!("{k}.pattern"),
            format!("more than {MAX_GENERATED_BOXES} posts: make the field smaller"),
        );
    }
    if c.issues.len() != n {
        return;
    }
    let fr = Frame::new(s.x_m, s.y_m, s.z_m, s.yaw_deg);
    let p = s.post_m;
    let y0 = 0.5 * p * pattern.len() as f64;
    for (r, row) in pattern.iter().enumerate() {
        for (col, &v) in row.iter().enumerate() {
            if v == 0 {
                continue;
            }
            let y_hi = y0 - r as f64 * p;
            t.boxes.push(fr.aabb(
                DVec3::new(col as f64 * p, y_hi - p, 0.0),
                DVec3::new((col + 1) as f64 * p, y_hi, v as f64 * s.step_m),
                s.friction,
            ));
        }
    }
}

/// The pattern of post heights in steps: the given one (checked), a seeded random one, or the
/// default. `None` when the keys contradict each other or the random pattern's sizes are bad
/// (`n`: the number of issues before this stepfield's checks).
fn resolve_pattern(c: &mut Checker, k: &str, s: &StepfieldSpec, n: usize) -> Option<Vec<Vec<u32>>> {
    let random = s.rows.is_some() || s.columns.is_some() || s.max_steps.is_some();
    match (&s.pattern, s.seed) {
        (Some(_), Some(_)) => {
            c.push(
                format!("{k}.seed"),
                "give either pattern or seed (a random pattern), not both",
            );
            None
        }
        (Some(_), None) if random => {
            c.push(
                format!("{k}.pattern"),
                "rows, columns and max_steps are for a random pattern (with seed): leave them \
                 out when giving a pattern",
            );
            None
        }
        (Some(p), None) => given_pattern(c, k, p),
        (None, Some(seed)) => random_pattern(c, k, s, seed, n),
        (None, None) if random => {
            c.push(
                format!("{k}.seed"),
                "rows, columns and max_steps describe a random pattern: give a seed too",
            );
            None
        }
        (None, None) => Some(default_stepfield_pattern()),
    }
}

/// Checks a given pattern; `None` if it is empty (other problems are reported but the pattern
/// is still returned).
fn given_pattern(c: &mut Checker, k: &str, p: &[Vec<u32>]) -> Option<Vec<Vec<u32>>> {
    if p.is_empty() || p[0].is_empty() {
        c.push(
            format!("{k}.pattern"),
            "must be a non-empty list of non-empty rows, e.g. [[1, 2], [2, 1]]",
        );
        return None;
    }
    for (r, row) in p.iter().enumerate() {
        if row.len() != p[0].len() {
            c.push(
                format!("{k}.pattern[{r}]"),
                format!(
                    "has {} entries but row 0 has {}: all rows must be equally long",
                    row.len(),
                    p[0].len()
                ),
            );
        }
        for (col, v) in row.iter().enumerate() {
            if *v > 1000 {
                c.push(
                    format!("{k}.pattern[{r}][{col}]"),
                    format!("must be a number of steps from 0 to 1000, got {v}"),
                );
            }
        }
    }
    Some(p.to_vec())
}

/// A random pattern of `rows` x `columns` posts of 1 to `max_steps` steps from `seed`; `None`
/// if any issue has been reported since `n`.
fn random_pattern(
    c: &mut Checker,
    k: &str,
    s: &StepfieldSpec,
    seed: u64,
    n: usize,
) -> Option<Vec<Vec<u32>>> {
    let rows = s.rows.unwrap_or(12);
    let cols = s.columns.unwrap_or(12);
    let max = s.max_steps.unwrap_or(4);
    check_count(c, &format!("{k}.rows"), rows, 1000);
    check_count(c, &format!("{k}.columns"), cols, 1000);
    check_count(c, &format!("{k}.max_steps"), max, 1000);
    if c.issues.len() != n {
        return None;
    }
    let mut rng = SplitMix64(seed);
    Some(
        (0..rows)
            .map(|_| {
                (0..cols)
                    .map(|_| 1 + (rng.next_u64() % max as u64) as u32)
                    .collect()
            })
            .collect(),
    )
}
