//! Greyscale PNG height maps: decoding the image into grey values (pure: bytes in, numbers
//! out; no file access).

use std::path::Path;

/// Decodes a PNG height map (8 or 16 bit greyscale, optionally with alpha, which is ignored):
/// (columns, rows, values in [0, 1] row-major, row 0 = top row). `path` only names the file in
/// error messages. An image of more than `max_pixels` pixels is refused from its header,
/// before anything is decoded.
pub(in crate::terrain) fn decode(
    bytes: &[u8],
    path: &Path,
    max_pixels: usize,
) -> Result<(usize, usize, Vec<f64>), String> {
    let bad = |e: &dyn std::fmt::Display| {
        format!(
            "{} is not a readable PNG image ({e}); save the height map as an 8- or 16-bit \
             greyscale PNG",
            path.display()
        )
    };
    let mut dec = png::Decoder::new(std::io::Cursor::new(bytes));
    dec.set_transformations(png::Transformations::EXPAND);
    let mut reader = dec.read_info().map_err(|e| bad(&e))?;
    let (w, h) = (reader.info().width as u64, reader.info().height as u64);
    if w * h > max_pixels as u64 {
        return Err(format!(
            "{} has {w} x {h} pixels, more than {max_pixels}: downsample it",
            path.display()
        ));
    }
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| bad(&"image too large"))?;
    let mut buf = vec![0u8; size];
    let info = reader.next_frame(&mut buf).map_err(|e| bad(&e))?;
    let channels = match info.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        other => {
            return Err(format!(
                "{} is a {other:?} PNG, but height maps must be greyscale: convert it to an 8- \
                 or 16-bit greyscale PNG (e.g. `convert in.png -colorspace Gray -depth 16 \
                 out.png`)",
                path.display()
            ));
        }
    };
    let (w, h) = (info.width as usize, info.height as usize);
    if w < 2 || h < 2 {
        return Err(format!(
            "{} is {w} x {h} pixels: a height map needs at least 2 x 2",
            path.display()
        ));
    }
    let mut out = Vec::with_capacity(w * h);
    for r in 0..h {
        let line = &buf[r * info.line_size..(r + 1) * info.line_size];
        for col in 0..w {
            let v = match info.bit_depth {
                png::BitDepth::Sixteen => {
                    let o = 2 * channels * col;
                    u16::from_be_bytes([line[o], line[o + 1]]) as f64 / 65535.0
                }
                png::BitDepth::Eight => line[channels * col] as f64 / 255.0,
                other => {
                    return Err(format!(
                        "{} has an unsupported bit depth {other:?}: save it as an 8- or 16-bit \
                         greyscale PNG",
                        path.display()
                    ));
                }
            };
            out.push(v);
        }
    }
    Ok((w, h, out))
}
