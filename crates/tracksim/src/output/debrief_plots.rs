//! The key plots of a debrief (`debrief.html`, [`super::debrief`]) as inline SVG: the body's
//! forward speed and each belt's speed (m/s), each track's slip ratio, roll and pitch
//! (degrees) against time, from the columns of `trajectory.csv`, drawn by the run plots' own
//! time panel ([`super::plot`]) with the embedded font's metrics.

use super::plot::{DrawResult, draw_time_panel, ensure_font};
use crate::error::{Error, Result};
use plotters::prelude::*;
use std::path::Path;

/// Size of one plot, px.
pub const PLOT_PX: (u32, u32) = (900, 260);
/// Most points per series drawn (a long session's samples are thinned to this many).
pub const MAX_PLOT_POINTS: usize = 1500;

/// `trajectory.csv` as columns: the header's names and each row's numbers (an empty or
/// unreadable cell: NaN).
#[derive(Clone, Debug, Default)]
pub struct Columns {
    /// Column names.
    pub names: Vec<String>,
    /// Rows of numbers, one per sample.
    pub rows: Vec<Vec<f64>>,
}

impl Columns {
    /// Parses CSV text (`path` names the file in an error).
    pub fn parse(text: &str, path: &Path) -> Result<Columns> {
        let mut r = csv::ReaderBuilder::new().from_reader(text.as_bytes());
        let bad = |e: csv::Error| Error::Parse {
            path: path.to_path_buf(),
            message: format!("{e}: the trajectory.csv of a run is needed; re-run to write it"),
        };
        let names: Vec<String> = r
            .headers()
            .map_err(bad)?
            .iter()
            .map(str::to_string)
            .collect();
        let mut rows = Vec::new();
        for rec in r.records() {
            let rec = rec.map_err(bad)?;
            rows.push(
                rec.iter()
                    .map(|c| c.trim().parse().unwrap_or(f64::NAN))
                    .collect(),
            );
        }
        Ok(Columns { names, rows })
    }

    /// Index of the column `name`.
    pub fn col(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// The names `X` of the columns `prefix X suffix`, in order.
    pub fn items(&self, prefix: &str, suffix: &str) -> Vec<String> {
        self.names
            .iter()
            .filter_map(|n| n.strip_prefix(prefix)?.strip_suffix(suffix))
            .map(str::to_string)
            .collect()
    }

    /// (t, f(row)) of every `stride`-th row and the last, where `t_s` and `f` are finite.
    fn series(&self, f: impl Fn(&[f64]) -> Option<f64>) -> Vec<(f64, f64)> {
        let Some(it) = self.col("t_s") else {
            return Vec::new();
        };
        let stride = self.rows.len().div_ceil(MAX_PLOT_POINTS).max(1);
        let last = self.rows.len().saturating_sub(1);
        self.rows
            .iter()
            .enumerate()
            .filter(|(i, _)| i.is_multiple_of(stride) || *i == last)
            .filter_map(|(_, r)| Some((*r.get(it)?, f(r)?)))
            .filter(|(t, v)| t.is_finite() && v.is_finite())
            .collect()
    }

    /// The series of column `name` (empty without it).
    fn column(&self, name: &str) -> Vec<(f64, f64)> {
        match self.col(name) {
            Some(i) => self.series(|r| r.get(i).copied()),
            None => Vec::new(),
        }
    }
}

type Series = Vec<(String, Vec<(f64, f64)>)>;

/// The forward speed of the body (its velocity along its heading) and each belt's speed.
fn speeds(c: &Columns) -> Series {
    let mut out = Vec::new();
    if let (Some(vx), Some(vy), Some(yaw)) = (c.col("vx_mps"), c.col("vy_mps"), c.col("yaw_rad")) {
        let fwd =
            c.series(|r| Some(r.get(vx)? * r.get(yaw)?.cos() + r.get(vy)? * r.get(yaw)?.sin()));
        out.push(("body forward".to_string(), fwd));
    }
    for n in c.items("belt_speed_", "_mps") {
        out.push((
            format!("belt {n}"),
            c.column(&format!("belt_speed_{n}_mps")),
        ));
    }
    out
}

/// Each track's slip ratio.
fn slips(c: &Columns) -> Series {
    // `slip_N` columns (not the soil's `..._slip...`): the track names are the belt speeds'.
    c.items("belt_speed_", "_mps")
        .into_iter()
        .map(|n| {
            let s = c.column(&format!("slip_{n}"));
            (n, s)
        })
        .collect()
}

/// Roll and pitch, degrees.
fn attitude(c: &Columns) -> Series {
    ["roll", "pitch"]
        .into_iter()
        .map(|a| {
            let s = c
                .column(&format!("{a}_rad"))
                .into_iter()
                .map(|(t, v)| (t, v.to_degrees()))
                .collect();
            (a.to_string(), s)
        })
        .collect()
}

/// One panel as an `<svg>` element.
fn panel_svg(y_desc: &str, series: &Series) -> Result<String> {
    let fail = |e: String| Error::Io {
        path: "debrief.html".into(),
        source: std::io::Error::other(format!("drawing the plot {y_desc}: {e}")),
    };
    if !ensure_font() {
        return Err(fail(
            "the embedded DejaVu Sans font could not be loaded".into(),
        ));
    }
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, PLOT_PX).into_drawing_area();
        let draw = || -> DrawResult {
            root.fill(&WHITE)?;
            draw_time_panel(&root, y_desc, series)
        };
        draw().map_err(|e| fail(e.to_string()))?;
        root.present().map_err(|e| fail(e.to_string()))?;
    }
    Ok(text)
}

/// The key plots: (title, `<svg>` element) of the speeds, slips and attitude, each drawn when
/// its columns are there.
pub fn key_plots(c: &Columns) -> Result<Vec<(&'static str, String)>> {
    let panels: [(&'static str, &str, Series); 3] = [
        ("Speed", "speed (m/s)", speeds(c)),
        ("Slip", "slip ratio", slips(c)),
        ("Roll and pitch", "angle (°)", attitude(c)),
    ];
    let mut out = Vec::new();
    for (title, y_desc, series) in panels {
        if series.iter().any(|(_, p)| !p.is_empty()) {
            out.push((title, panel_svg(y_desc, &series)?));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plots_read_the_trajectorys_columns() {
        let text = "t_s,x_m,vx_mps,vy_mps,yaw_rad,roll_rad,pitch_rad,belt_speed_left_mps,belt_speed_right_mps,slip_left,slip_right,icr_x_m\n\
                    0.0,0,0.0,0,0,0,0,0.0,0.0,0,0,\n\
                    0.01,0,0.3,0,0,0.1,0,0.3,0.3,0.5,0.5,1.0\n";
        let c = Columns::parse(text, Path::new("trajectory.csv")).unwrap();
        assert_eq!(c.items("belt_speed_", "_mps"), ["left", "right"]);
        assert!(c.rows[0][11].is_nan(), "an empty cell is NaN");
        let s = speeds(&c);
        assert_eq!(s.len(), 3);
        assert_eq!(s[0].1, vec![(0.0, 0.0), (0.01, 0.3)]);
        assert_eq!(slips(&c)[1].1, vec![(0.0, 0.0), (0.01, 0.5)]);
        assert!((attitude(&c)[0].1[1].1 - 0.1f64.to_degrees()).abs() < 1e-12);
        let plots = key_plots(&c).unwrap();
        assert_eq!(plots.len(), 3);
        for (_, svg) in &plots {
            assert!(svg.starts_with("<svg"), "{svg}");
        }
        // Many rows are thinned to at most MAX_PLOT_POINTS (+ the last).
        let mut long = String::from("t_s,roll_rad\n");
        for i in 0..10_000 {
            long.push_str(&format!("{:.2},0.0\n", f64::from(i) * 0.01));
        }
        let c = Columns::parse(&long, Path::new("t.csv")).unwrap();
        let n = c.column("roll_rad").len();
        assert!(n <= MAX_PLOT_POINTS + 1 && n > MAX_PLOT_POINTS / 2, "{n}");
        assert_eq!(c.column("roll_rad").last().unwrap().0, 99.99);
    }
}
