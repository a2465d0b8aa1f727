//! Every sensor's stream in the run folder, under `sensors/`: scalar sensors (IMU, encoders) as
//! CSV, `t_s` then one column per value (pandas: `pd.read_csv`); array sensors (lidar, depth
//! camera, elevation map) as `.npz` (numpy: `np.load`), `t_s` (N readings), each channel as
//! `KEY` of shape (N, ...) in float32 (`range_m`, `points_m`, `depth_m`, `height_m`, the
//! sensor's world `position_m` and `orientation` quaternion x, y, z, w) and the fixed axes
//! (`azimuth_rad`, `elevation_rad`, `x_m`, `y_m`, `focal_length_px`). `docs/SENSORS.md` says what
//! each holds. Colour cameras write a PNG per reading under `sensors/NAME/` (`NNNNNN.png`
//! rgb8, `NNNNNN_depth.png` 16-bit millimetres) and `sensors/NAME.csv` (`t_s`, both files,
//! the sensor's position and orientation).

use crate::error::{Error, Result};
use crate::sensors::{LogData, SensorStream, StreamFormat, Values};
use ndarray::{ArrayD, IxDyn};
use ndarray_npy::NpzWriter;
use std::io::Cursor;
use std::path::{Path, PathBuf};

/// Writes every stream of `streams` under `dir/sensors/`; returns the files written.
pub fn write_sensor_streams(streams: &[SensorStream], dir: &Path) -> Result<Vec<PathBuf>> {
    if streams.is_empty() {
        return Ok(Vec::new());
    }
    let folder = dir.join("sensors");
    std::fs::create_dir_all(&folder).map_err(|source| Error::Io {
        path: folder.clone(),
        source,
    })?;
    let mut written = Vec::new();
    for s in streams {
        let path = dir.join(s.file_name());
        if s.format == StreamFormat::Png {
            written.extend(write_frames(s, dir)?);
        }
        match s.format {
            // A row at a time (the readings may be on disk).
            StreamFormat::Csv | StreamFormat::Png => {
                crate::files::write_atomic_with(&path, |w| write_csv(s, w))?
            }
            StreamFormat::Npz => {
                let bytes = npz_bytes(s).map_err(|e| Error::Io {
                    path: path.clone(),
                    source: std::io::Error::other(e),
                })?;
                crate::files::write_atomic(&path, &bytes)?;
            }
        }
        written.push(path);
    }
    Ok(written)
}

/// `t_s` and one column per value, a row per reading, written to `out` a row at a time.
fn write_csv(s: &SensorStream, out: &mut dyn std::io::Write) -> std::io::Result<()> {
    let mut w = csv::Writer::from_writer(out);
    let mut header = vec!["t_s".to_string()];
    for (i, c) in s.channels.iter().enumerate() {
        if s.is_image(i) {
            header.push(format!("{}_file", c.name));
        } else if c.columns.is_empty() {
            let key = c.key();
            header.extend((0..c.data.len()).map(|i| format!("{key}_{i}")));
        } else {
            header.extend(c.columns.iter().cloned());
        }
    }
    w.write_record(&header)?;
    for (k, r) in s.readings.iter().enumerate() {
        let mut row = vec![format!("{:.6}", r.t)];
        for (c, v) in s.channels.iter().zip(&r.values) {
            match v {
                Values::F64(v) => row.extend(v.iter().map(|x| format!("{x}"))),
                Values::F32(v) => row.extend(v.iter().map(|x| format!("{x}"))),
                Values::Png(_) => row.push(frame_file(s, c, k)),
            }
        }
        w.write_record(&row)?;
    }
    w.flush()
}

/// The stream as numpy arrays in an (uncompressed) `.npz`.
fn npz_bytes(s: &SensorStream) -> std::result::Result<Vec<u8>, String> {
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let mut npz = NpzWriter::new(Cursor::new(Vec::new()));
    let n = s.len();
    let t = ArrayD::from_shape_vec(IxDyn(&[n]), s.times()).map_err(|e| err(&e))?;
    npz.add_array("t_s", &t).map_err(|e| err(&e))?;
    // A channel at a time: numpy's arrays are written whole (the one output assembled in
    // memory, channel by channel).
    for (i, c) in s.channels.iter().enumerate() {
        let mut shape = vec![n];
        shape.extend_from_slice(&c.shape);
        let key = c.key();
        match s.channel_log(i) {
            LogData::F32(v) => {
                let a = ArrayD::from_shape_vec(IxDyn(&shape), v).map_err(|e| err(&e))?;
                npz.add_array(key.as_str(), &a).map_err(|e| err(&e))?;
            }
            LogData::F64(v) => {
                let a = ArrayD::from_shape_vec(IxDyn(&shape), v).map_err(|e| err(&e))?;
                npz.add_array(key.as_str(), &a).map_err(|e| err(&e))?;
            }
            LogData::Png(_) => return Err(format!("{}: images are written as PNG", s.name)),
        }
    }
    for a in &s.axes {
        let arr = ArrayD::from_shape_vec(IxDyn(&a.shape), a.data.clone()).map_err(|e| err(&e))?;
        npz.add_array(a.key().as_str(), &arr).map_err(|e| err(&e))?;
    }
    Ok(npz.finish().map_err(|e| err(&e))?.into_inner())
}

/// The file of reading `k` of image channel `c`, relative to the run folder:
/// `sensors/NAME/NNNNNN.png` (colour) or `sensors/NAME/NNNNNN_depth.png`.
fn frame_file(s: &SensorStream, c: &crate::sensors::Channel, k: usize) -> String {
    let suffix = if c.name == "rgb" {
        String::new()
    } else {
        format!("_{}", c.name)
    };
    format!("sensors/{}/{k:06}{suffix}.png", s.name)
}

/// Writes every image of a colour camera's stream under `dir/sensors/NAME/`.
fn write_frames(s: &SensorStream, dir: &Path) -> Result<Vec<PathBuf>> {
    let folder = dir.join("sensors").join(&s.name);
    std::fs::create_dir_all(&folder).map_err(|source| Error::Io {
        path: folder.clone(),
        source,
    })?;
    let mut written = Vec::new();
    for (k, r) in s.readings.iter().enumerate() {
        for (c, v) in s.channels.iter().zip(&r.values) {
            if let Values::Png(bytes) = v {
                let path = dir.join(frame_file(s, c, k));
                crate::files::write_atomic(&path, bytes)?;
                written.push(path);
            }
        }
    }
    Ok(written)
}
