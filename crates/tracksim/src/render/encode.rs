//! Frames as PNG bytes: colour as 8-bit RGB, depth as 16-bit grey in millimetres (the
//! `16UC1` convention of ROS depth images: 0 is no reading, nearer than the minimum range or
//! not a number; 65535 is beyond the maximum range or farther than 65.534 m).

/// Depth in millimetres as written to a 16-bit PNG (see the module's text).
pub fn depth_mm(d: f32) -> u16 {
    if d.is_nan() || d == f32::NEG_INFINITY || d < 0.0 {
        0
    } else if d == f32::INFINITY {
        u16::MAX
    } else {
        (d * 1000.0).round().clamp(1.0, 65534.0) as u16
    }
}

/// An rgb8 image of `width` x `height` pixels as PNG bytes (fast compression).
pub fn rgb8_png(width: usize, height: usize, rgb: &[u8]) -> Vec<u8> {
    encode(
        width,
        height,
        png::ColorType::Rgb,
        png::BitDepth::Eight,
        rgb,
    )
}

/// A depth image (m, [`super::Frame::depth`]) as a 16-bit grey PNG in millimetres.
pub fn depth16_png(width: usize, height: usize, depth: &[f32]) -> Vec<u8> {
    let bytes: Vec<u8> = depth
        .iter()
        .flat_map(|&d| depth_mm(d).to_be_bytes())
        .collect();
    encode(
        width,
        height,
        png::ColorType::Grayscale,
        png::BitDepth::Sixteen,
        &bytes,
    )
}

fn encode(w: usize, h: usize, color: png::ColorType, depth: png::BitDepth, data: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut e = png::Encoder::new(&mut out, w as u32, h as u32);
        e.set_color(color);
        e.set_depth(depth);
        e.set_compression(png::Compression::Fast);
        // Writing to a Vec cannot fail, and the sizes match the data by construction.
        let mut wr = e.write_header().expect("PNG header into memory");
        wr.write_image_data(data).expect("PNG data into memory");
    }
    out
}

/// The values of a PNG written here: 8-bit levels of an rgb8 image, or depths in metres of a
/// 16-bit one (`+inf` for 65535, `-inf` for 0). `None` for bytes that are not such a PNG.
pub fn decode_values(bytes: &[u8]) -> Option<Vec<f64>> {
    let mut d = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .ok()?;
    let mut buf = vec![0; d.output_buffer_size()?];
    let info = d.next_frame(&mut buf).ok()?;
    let buf = &buf[..info.buffer_size()];
    Some(match info.bit_depth {
        png::BitDepth::Sixteen => buf
            .chunks_exact(2)
            .map(|b| match u16::from_be_bytes([b[0], b[1]]) {
                0 => f64::NEG_INFINITY,
                u16::MAX => f64::INFINITY,
                mm => mm as f64 / 1000.0,
            })
            .collect(),
        _ => buf.iter().map(|&b| b as f64).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depth_codes() {
        assert_eq!(depth_mm(f32::NEG_INFINITY), 0);
        assert_eq!(depth_mm(f32::NAN), 0);
        assert_eq!(depth_mm(f32::INFINITY), 65535);
        assert_eq!(depth_mm(1.2344), 1234);
        assert_eq!(depth_mm(100.0), 65534);
    }

    #[test]
    fn rgb_png_decodes_to_the_same_bytes() {
        let rgb: Vec<u8> = (0..2 * 3 * 3).map(|i| (i * 13) as u8).collect();
        let bytes = rgb8_png(3, 2, &rgb);
        let mut d = png::Decoder::new(std::io::Cursor::new(bytes))
            .read_info()
            .unwrap();
        let mut buf = vec![0; d.output_buffer_size().unwrap()];
        let info = d.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (3, 2));
        assert_eq!(&buf[..info.buffer_size()], &rgb[..]);
    }
}
