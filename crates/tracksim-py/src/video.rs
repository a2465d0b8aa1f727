//! `tracksim.write_video`: a run folder rendered to an MP4, as `tracksim video` does.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::PathBuf;
use tracksim::video::{self, Camera, VideoOptions};

/// Renders the run folder `dir` (a `tracksim run`, or an episode the environments recorded
/// with `record_dir`) to the H.264 MP4 `out` (default `dir/video.mp4`), from the chase camera
/// or the vehicle's sensor `camera`, at `fps` frames per second (default 30) and `size`
/// (width, height) pixels, both even (default 640 x 480); returns the file's path. The bytes do
/// not depend on the threads rendering them (docs/VIDEO.md).
#[pyfunction]
#[pyo3(signature = (dir, out=None, camera="chase", fps=None, size=None))]
pub(crate) fn write_video(
    py: Python<'_>,
    dir: PathBuf,
    out: Option<PathBuf>,
    camera: &str,
    fps: Option<u32>,
    size: Option<(usize, usize)>,
) -> PyResult<PathBuf> {
    let d = VideoOptions::default();
    let (width, height) = size.unwrap_or((d.width, d.height));
    let opts = VideoOptions {
        camera: if camera == "chase" {
            Camera::Chase
        } else {
            Camera::Sensor(camera.to_string())
        },
        fps: fps.unwrap_or(d.fps),
        width,
        height,
        ..d
    };
    if let Some(i) = opts.issues().into_iter().next() {
        let key = i.key.trim_start_matches("--");
        return Err(PyValueError::new_err(format!("{key}: {}", i.message)));
    }
    let out = out.unwrap_or_else(|| dir.join("video.mp4"));
    py.detach(|| video::write_video(&dir, &out, &opts))
        .map_err(crate::common::py_err)?;
    Ok(out)
}
