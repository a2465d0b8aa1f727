//! How close a run came to its limits (issue 62), from its samples: the peak pitch and roll
//! against the tip-over limit, the smallest normal load each track carried (a track that
//! leaves the ground steers and drives nothing), the largest slip, and each motor's peak belt
//! force against what it could deliver at that speed. `summary.json` `margins`; an ensemble
//! gives their spread. Samples are the output interval's, so a peak between two samples is
//! not seen (the interval is the run's resolution, `output_interval_s`).

use super::SampleLog;
use serde::{Deserialize, Serialize};

/// The largest value of a quantity over a run and when it was reached.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Peak {
    /// The value (its unit in the field's name).
    pub value: f64,
    /// When it was reached, s.
    pub t_s: f64,
}

/// The largest of the values offered so far (non-finite ones and `None` are passed over).
fn keep_max(best: &mut Option<Peak>, v: Option<f64>, t: f64) {
    if let Some(v) = v.filter(|v| v.is_finite())
        && best.is_none_or(|b| v > b.value)
    {
        *best = Some(Peak { value: v, t_s: t });
    }
}

/// A track's margins over a run.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TrackMargin {
    /// The track's name.
    pub name: String,
    /// The smallest normal load it carried after the first second (the robot settling on its
    /// tracks at the start is not a margin), N, and when: 0 N means it left the ground.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_normal_load_n: Option<Peak>,
    /// The largest |slip| after the first second (the belts spin up against a robot at rest
    /// at the start: slip near 1 there says nothing), as `slip` in `trajectory.csv`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_abs_slip: Option<Peak>,
    /// Its motor's largest share of the belt force it could deliver at the belt's speed
    /// (`[tracks.motor]` only): 1 is saturated (stalled or at full torque).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_motor_load_fraction: Option<Peak>,
}

/// How close a run came to its limits (`summary.json` `margins`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Margins {
    /// The tip-over limit on |pitch| and |roll| (`outcome.max_tilt_deg`), deg.
    pub tip_limit_deg: f64,
    /// The largest |pitch|, deg, and when.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_abs_pitch_deg: Option<Peak>,
    /// The largest |roll|, deg, and when.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_abs_roll_deg: Option<Peak>,
    /// The tip limit less the larger of the two peaks, deg: how much more the robot could
    /// have tilted (negative: it passed the limit).
    pub tilt_margin_deg: f64,
    /// Each track's.
    pub tracks: Vec<TrackMargin>,
}

/// Time after the start before the normal loads and the slip count, s: the robot is placed
/// 1 mm above the ground and settles, and its belts spin up.
pub const SETTLE_S: f64 = 1.0;

impl Margins {
    /// The margins of `samples` of a robot with tracks `track_names` and tip-over limit
    /// `max_tilt` rad.
    pub fn of(samples: &SampleLog, track_names: &[String], max_tilt: f64) -> Margins {
        // One pass: a long session's samples are read back from disk (`SampleLog`).
        let (mut pitch, mut roll) = (None, None);
        let n = track_names.len();
        // Per track: the peak of the negative load (its smallest load), of |slip|, of the
        // motor's load share.
        let mut per_track = vec![[None; 3]; n];
        for s in samples.iter() {
            keep_max(&mut pitch, Some(s.pose.pitch.abs().to_degrees()), s.t);
            keep_max(&mut roll, Some(s.pose.roll.abs().to_degrees()), s.t);
            for (i, [load, slip, motor]) in per_track.iter_mut().enumerate() {
                if s.t >= SETTLE_S {
                    keep_max(load, s.loads.get(i).map(|l| -l.normal_n), s.t);
                    keep_max(slip, s.slip.get(i).map(|x| x.abs()), s.t);
                }
                let share = s.drive.get(i).copied().flatten().and_then(|d| {
                    (d.max_belt_force_n > 0.0).then(|| d.belt_force_n.abs() / d.max_belt_force_n)
                });
                keep_max(motor, share, s.t);
            }
        }
        let tip = max_tilt.to_degrees();
        let worst = pitch
            .map_or(0.0, |p: Peak| p.value)
            .max(roll.map_or(0.0, |p: Peak| p.value));
        let tracks = track_names
            .iter()
            .zip(per_track)
            .map(|(name, [load, slip, motor])| TrackMargin {
                name: name.clone(),
                min_normal_load_n: load.map(|p: Peak| Peak {
                    value: -p.value,
                    t_s: p.t_s,
                }),
                peak_abs_slip: slip,
                peak_motor_load_fraction: motor,
            })
            .collect();
        Margins {
            tip_limit_deg: tip,
            peak_abs_pitch_deg: pitch,
            peak_abs_roll_deg: roll,
            tilt_margin_deg: tip - worst,
            tracks,
        }
    }
}
