//! The figures burnt into a video's frames: lines of text (DejaVu Sans Mono, embedded by the
//! `dejavu` crate, rasterised by `ab_glyph`; no system font) in white on a darkened band at the
//! top left of the frame.

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};

/// Draws `lines` into the rgb8 image `rgb` of `width` x `height` pixels, text
/// `height / 24` pixels high (at least 10).
pub fn draw_lines(rgb: &mut [u8], width: usize, height: usize, lines: &[String]) {
    let Ok(font) = FontRef::try_from_slice(dejavu::sans_mono::regular()) else {
        return;
    };
    let px = (height as f32 / 24.0).max(10.0);
    let scaled = font.as_scaled(PxScale::from(px));
    let line_h = (scaled.height() + scaled.line_gap()).ceil();
    let margin = (px / 3.0).round();
    let text_w = lines
        .iter()
        .map(|l| {
            l.chars()
                .map(|c| scaled.h_advance(font.glyph_id(c)))
                .sum::<f32>()
        })
        .fold(0.0f32, f32::max);
    // The band: the pixels under the text, darkened to 35 %.
    let bw = ((text_w + 2.0 * margin).ceil() as usize).min(width);
    let bh = ((line_h * lines.len() as f32 + 2.0 * margin).ceil() as usize).min(height);
    for y in 0..bh {
        for x in 0..bw {
            let i = 3 * (y * width + x);
            for b in &mut rgb[i..i + 3] {
                *b = (*b as u32 * 35 / 100) as u8;
            }
        }
    }
    for (k, line) in lines.iter().enumerate() {
        let mut x = margin;
        let base = margin + scaled.ascent() + k as f32 * line_h;
        for c in line.chars() {
            let id = font.glyph_id(c);
            let g = id.with_scale_and_position(PxScale::from(px), point(x, base));
            x += scaled.h_advance(id);
            let Some(o) = font.outline_glyph(g) else {
                continue;
            };
            let b = o.px_bounds();
            o.draw(|gx, gy, cov| {
                let (px_x, px_y) = (b.min.x as i64 + gx as i64, b.min.y as i64 + gy as i64);
                if px_x < 0 || px_y < 0 || px_x >= width as i64 || px_y >= height as i64 {
                    return;
                }
                let i = 3 * (px_y as usize * width + px_x as usize);
                let a = cov.clamp(0.0, 1.0);
                for v in &mut rgb[i..i + 3] {
                    *v = (*v as f32 * (1.0 - a) + 255.0 * a).round() as u8;
                }
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_lightens_a_band_at_the_top_left_only() {
        let (w, h) = (160, 120);
        let mut rgb = vec![100u8; 3 * w * h];
        draw_lines(&mut rgb, w, h, &["t 1.00 s".into()]);
        let at = |x: usize, y: usize| rgb[3 * (y * w + x)];
        let top_left = (0..20).flat_map(|y| (0..60).map(move |x| (x, y)));
        assert!(top_left.clone().any(|(x, y)| at(x, y) > 200), "no text");
        assert!(top_left.clone().any(|(x, y)| at(x, y) < 50), "no band");
        assert_eq!(at(w - 1, h - 1), 100);
    }
}
