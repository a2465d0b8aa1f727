//! `signals.png` / `signals.svg` (issue 14.4): what a stall or a turn looks like over time: forward
//! position and speed, yaw, flipper angles, and per track the slip and the traction, one panel
//! each. With several runs (`compare`) every series is labelled `run/track`.

use super::plot::{DrawResult, FONT, PlotRun, draw_time_panel, points, write_png_svg};
use crate::error::Result;
use crate::world::Sample;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::{Path, PathBuf};

type Series = Vec<(String, Vec<(f64, f64)>)>;

/// One series per run of `value`.
fn per_run(runs: &[PlotRun], value: impl Fn(&Sample) -> f64) -> Series {
    runs.iter()
        .map(|r| {
            let label = if runs.len() > 1 {
                r.label.to_string()
            } else {
                String::new()
            };
            (label, points(r.result, |s| (s.t, value(s))))
        })
        .collect()
}

/// One series per run and per item `i` of `value(sample, i)` (tracks or flippers named `names`).
fn per_item(
    runs: &[PlotRun],
    names: impl Fn(&PlotRun) -> Vec<String>,
    value: impl Fn(&Sample, usize) -> Option<f64>,
) -> Series {
    let mut out = Vec::new();
    for r in runs {
        for (i, n) in names(r).iter().enumerate() {
            let label = if runs.len() > 1 {
                format!("{}/{n}", r.label)
            } else {
                n.clone()
            };
            let pts = points(r.result, |s| (s.t, value(s, i).unwrap_or(f64::NAN)));
            out.push((label, pts));
        }
    }
    out
}

/// Forward speed in the body frame, m/s.
fn forward_speed(s: &Sample) -> f64 {
    let (c, sn) = (s.pose.yaw.cos(), s.pose.yaw.sin());
    s.linvel[0] * c + s.linvel[1] * sn
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    runs: &[PlotRun],
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let body = root.titled(title, (FONT, 24).into_font().style(FontStyle::Bold))?;
    let first_drive = |r: &PlotRun| {
        r.result
            .samples
            .first()
            .and_then(|s| s.drive.iter().flatten().next().copied())
    };
    let drive = runs.iter().find_map(first_drive);
    let panels = body.split_evenly((if drive.is_some() { 4 } else { 3 }, 2));
    let tracks = |r: &PlotRun| r.result.track_names.clone();
    let flippers = |r: &PlotRun| r.result.flipper_names.clone();
    draw_time_panel(&panels[0], "x (m)", &per_run(runs, |s| s.pose.x))?;
    draw_time_panel(
        &panels[1],
        "forward speed (m/s)",
        &per_run(runs, forward_speed),
    )?;
    draw_time_panel(
        &panels[2],
        "yaw (°)",
        &per_run(runs, |s| s.pose.yaw.to_degrees()),
    )?;
    let fl = per_item(runs, flippers, |s, i| {
        s.flipper_angle.get(i).map(|a| a.to_degrees())
    });
    draw_time_panel(&panels[3], "flipper angle (°)", &fl)?;
    let slip = per_item(runs, tracks, |s, i| s.slip.get(i).copied());
    draw_time_panel(&panels[4], "slip ratio", &slip)?;
    let traction = per_item(runs, tracks, |s, i| s.loads.get(i).map(|l| l.traction_n));
    draw_time_panel(&panels[5], "traction (N)", &traction)?;
    if let Some(d) = drive {
        let torque = per_item(runs, tracks, |s, i| {
            s.drive
                .get(i)
                .copied()
                .flatten()
                .map(|d| d.sprocket_torque_nm)
        });
        draw_time_panel(&panels[6], "sprocket torque (N m)", &torque)?;
        if d.electrical.is_some() {
            let current = per_item(runs, tracks, |s, i| {
                s.drive
                    .get(i)
                    .copied()
                    .flatten()
                    .and_then(|d| d.electrical)
                    .map(|e| e.current)
            });
            draw_time_panel(&panels[7], "motor current (A)", &current)?;
        } else {
            let power = per_item(runs, tracks, |s, i| {
                s.drive.get(i).copied().flatten().map(|d| d.power_w)
            });
            draw_time_panel(&panels[7], "belt power (W)", &power)?;
        }
    }
    Ok(())
}

/// Writes `<stem>.png` and `<stem>.svg` for `runs` into `dir`.
pub fn write_signals(
    title: &str,
    runs: &[PlotRun],
    dir: &Path,
    stem: &str,
) -> Result<Vec<PathBuf>> {
    write_png_svg(
        dir,
        stem,
        |root| draw(root, title, runs),
        |root| draw(root, title, runs),
    )
}
