//! Frames to an MP4 file: H.264 by OpenH264 (crate `openh264`, its default `source` feature
//! compiles Cisco's C++ from the crate's bundled source with `cc`: nothing is downloaded at
//! build or run time), muxed by the `mp4` crate (pure Rust, the muxer openh264's own example
//! uses; chosen over `muxide` for its reader too, which the tests use to check the files).
//!
//! The encoder runs on one thread, rate control off (every frame at the fixed quantiser
//! [`QP`]: constant quality, the size follows the picture), frame skipping off (a sample per
//! frame) and an IDR frame every two seconds (a player can seek), so the same frames give the
//! same bytes (the MP4's creation times are 0). Width and height
//! must be even (4:2:0 chroma). [`decode_mp4`] reads such a file back to rgb8 frames with
//! OpenH264's decoder (for checks and tests).

use crate::error::{Error, Result};
use bytes::Bytes;
use openh264::OpenH264API;
use openh264::decoder::Decoder;
use openh264::encoder::{
    Encoder, EncoderConfig, FrameRate, FrameType, IntraFramePeriod, QpRange, RateControlMode,
};
use openh264::formats::{RgbSliceU8, YUVBuffer, YUVSource};
use std::io::Cursor;

/// Quantisation parameter of every frame (rate control off: constant quality; 0 best, 51
/// coarsest).
pub const QP: u8 = 24;

fn codec(what: &str, e: impl std::fmt::Display) -> Error {
    Error::Video(format!("{what}: {e}"))
}

/// Encodes rgb8 frames into an H.264 MP4 in memory.
pub struct Mp4Encoder {
    width: usize,
    height: usize,
    fps: u32,
    encoder: Encoder,
    sps: Option<Vec<u8>>,
    pps: Option<Vec<u8>>,
    /// (AVCC sample bytes, is a sync sample, duration in frames).
    samples: Vec<(Vec<u8>, bool, u32)>,
}

impl Mp4Encoder {
    /// An encoder of `width` x `height` (even, at most 3840 x 2160) frames at `fps`.
    pub fn new(width: usize, height: usize, fps: u32) -> Result<Mp4Encoder> {
        if !width.is_multiple_of(2) || !height.is_multiple_of(2) || width == 0 || height == 0 {
            return Err(codec(
                "size",
                format!("{width}x{height}: H.264 4:2:0 needs an even width and height"),
            ));
        }
        let config = EncoderConfig::new()
            .max_frame_rate(FrameRate::from_hz(fps as f32))
            .rate_control_mode(RateControlMode::Off)
            .qp(QpRange::new(QP, QP))
            .skip_frames(false)
            .num_threads(1)
            .intra_frame_period(IntraFramePeriod::from_num_frames(2 * fps));
        let encoder = Encoder::with_api_config(OpenH264API::from_source(), config)
            .map_err(|e| codec("encoder", e))?;
        Ok(Mp4Encoder {
            width,
            height,
            fps,
            encoder,
            sps: None,
            pps: None,
            samples: Vec::new(),
        })
    }

    /// Adds one rgb8 frame (`3 * width * height` bytes).
    pub fn push(&mut self, rgb: &[u8]) -> Result<()> {
        let yuv = YUVBuffer::from_rgb8_source(RgbSliceU8::new(rgb, (self.width, self.height)));
        let bs = self
            .encoder
            .encode(&yuv)
            .map_err(|e| codec("encoding", e))?;
        let mut sample = Vec::new();
        for l in 0..bs.num_layers() {
            let Some(layer) = bs.layer(l) else { continue };
            for n in 0..layer.nal_count() {
                let Some(nal) = layer.nal_unit(n) else {
                    continue;
                };
                let nal = strip_start_code(nal);
                match nal.first().map(|b| b & 0x1f) {
                    Some(7) => self.sps = Some(nal.to_vec()),
                    Some(8) => self.pps = Some(nal.to_vec()),
                    Some(_) => {
                        sample.extend_from_slice(&(nal.len() as u32).to_be_bytes());
                        sample.extend_from_slice(nal);
                    }
                    None => {}
                }
            }
        }
        let sync = matches!(bs.frame_type(), FrameType::IDR | FrameType::I);
        match (sample.is_empty(), self.samples.last_mut()) {
            // A skipped frame: the previous one lasts longer.
            (true, Some(last)) => last.2 += 1,
            (true, None) => {}
            (false, _) => self.samples.push((sample, sync, 1)),
        }
        Ok(())
    }

    /// The MP4 file's bytes.
    pub fn finish(self) -> Result<Vec<u8>> {
        let (Some(sps), Some(pps)) = (self.sps, self.pps) else {
            return Err(codec("encoding", "no frame was encoded"));
        };
        let config = mp4::Mp4Config {
            major_brand: "isom".parse().map_err(|e| codec("mp4", e))?,
            minor_version: 512,
            compatible_brands: ["isom", "iso2", "avc1", "mp41"]
                .iter()
                .map(|b| b.parse().map_err(|e| codec("mp4", e)))
                .collect::<Result<_>>()?,
            timescale: 1000,
        };
        let mut w = mp4::Mp4Writer::write_start(Cursor::new(Vec::new()), &config)
            .map_err(|e| codec("mp4", e))?;
        // One frame lasts 1000 units of the track's time scale.
        let tick = 1000u32;
        w.add_track(&mp4::TrackConfig {
            track_type: mp4::TrackType::Video,
            timescale: self.fps * tick,
            language: "und".into(),
            media_conf: mp4::MediaConfig::AvcConfig(mp4::AvcConfig {
                width: self.width as u16,
                height: self.height as u16,
                seq_param_set: sps,
                pic_param_set: pps,
            }),
        })
        .map_err(|e| codec("mp4", e))?;
        let mut start = 0u64;
        for (bytes, sync, frames) in self.samples {
            let duration = frames * tick;
            w.write_sample(
                1,
                &mp4::Mp4Sample {
                    start_time: start,
                    duration,
                    rendering_offset: 0,
                    is_sync: sync,
                    bytes: Bytes::from(bytes),
                },
            )
            .map_err(|e| codec("mp4", e))?;
            start += duration as u64;
        }
        w.write_end().map_err(|e| codec("mp4", e))?;
        Ok(w.into_writer().into_inner())
    }
}

/// A NAL unit without its Annex B start code (`00 00 01` or `00 00 00 01`).
fn strip_start_code(nal: &[u8]) -> &[u8] {
    if nal.starts_with(&[0, 0, 0, 1]) {
        &nal[4..]
    } else if nal.starts_with(&[0, 0, 1]) {
        &nal[3..]
    } else {
        nal
    }
}

/// An MP4 read back: its one H.264 track's size, frame rate and frames.
#[derive(Clone, Debug)]
pub struct DecodedVideo {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Samples in the track.
    pub samples: u32,
    /// Frames per second (samples over the track's duration).
    pub fps: f64,
    /// Each decoded frame, rgb8.
    pub frames: Vec<Vec<u8>>,
}

/// Decodes the H.264 track of an MP4 file (`bytes`) to rgb8 frames with OpenH264.
pub fn decode_mp4(bytes: &[u8]) -> Result<DecodedVideo> {
    let mut r = mp4::Mp4Reader::read_header(Cursor::new(bytes), bytes.len() as u64)
        .map_err(|e| codec("mp4", e))?;
    let (id, width, height, samples, fps, sps, pps) = {
        let t = r
            .tracks()
            .values()
            .find(|t| matches!(t.media_type(), Ok(mp4::MediaType::H264)))
            .ok_or_else(|| codec("mp4", "no H.264 track"))?;
        (
            t.track_id(),
            t.width() as usize,
            t.height() as usize,
            t.sample_count(),
            t.frame_rate(),
            t.sequence_parameter_set()
                .map_err(|e| codec("mp4", e))?
                .to_vec(),
            t.picture_parameter_set()
                .map_err(|e| codec("mp4", e))?
                .to_vec(),
        )
    };
    let mut dec = Decoder::new().map_err(|e| codec("decoder", e))?;
    let mut frames = Vec::new();
    for i in 1..=samples {
        let Some(s) = r.read_sample(id, i).map_err(|e| codec("mp4", e))? else {
            continue;
        };
        let mut annex_b = Vec::new();
        if i == 1 {
            for ps in [&sps, &pps] {
                annex_b.extend_from_slice(&[0, 0, 0, 1]);
                annex_b.extend_from_slice(ps);
            }
        }
        let mut rest: &[u8] = &s.bytes;
        while rest.len() >= 4 {
            let n = u32::from_be_bytes([rest[0], rest[1], rest[2], rest[3]]) as usize;
            let end = (4 + n).min(rest.len());
            annex_b.extend_from_slice(&[0, 0, 0, 1]);
            annex_b.extend_from_slice(&rest[4..end]);
            rest = &rest[end..];
        }
        if let Some(img) = dec.decode(&annex_b).map_err(|e| codec("decoding", e))? {
            let (w, h) = img.dimensions();
            let mut rgb = vec![0; 3 * w * h];
            img.write_rgb8(&mut rgb);
            frames.push(rgb);
        }
    }
    Ok(DecodedVideo {
        width,
        height,
        samples,
        fps,
        frames,
    })
}

/// Peak signal-to-noise ratio of two 8-bit images of the same size, dB (`inf` when equal).
pub fn psnr(a: &[u8], b: &[u8]) -> f64 {
    let n = a.len().min(b.len()).max(1);
    let mse = a
        .iter()
        .zip(b)
        .map(|(&x, &y)| (x as f64 - y as f64).powi(2))
        .sum::<f64>()
        / n as f64;
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0f64 * 255.0 / mse).log10()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A gradient with a moving square, encoded and decoded: every frame back, close to the
    /// original (PSNR above 30 dB), and the same bytes twice.
    #[test]
    fn frames_round_trip_through_mp4() {
        let (w, h, fps) = (64, 48, 10);
        let frame = |k: usize| -> Vec<u8> {
            let mut rgb = vec![0u8; 3 * w * h];
            for y in 0..h {
                for x in 0..w {
                    let i = 3 * (y * w + x);
                    let inside = (x + 4 * w - 4 * k) % w < 12 && (10..30).contains(&y);
                    rgb[i] = (x * 4) as u8;
                    rgb[i + 1] = (y * 5) as u8;
                    rgb[i + 2] = if inside { 230 } else { 40 };
                }
            }
            rgb
        };
        let encode = || {
            let mut e = Mp4Encoder::new(w, h, fps).unwrap();
            for k in 0..12 {
                e.push(&frame(k)).unwrap();
            }
            e.finish().unwrap()
        };
        let bytes = encode();
        assert_eq!(bytes, encode(), "not deterministic");
        let d = decode_mp4(&bytes).unwrap();
        assert_eq!((d.width, d.height, d.samples), (w, h, 12));
        assert!((d.fps - fps as f64).abs() < 1e-6, "{}", d.fps);
        assert_eq!(d.frames.len(), 12);
        for k in [0, 6, 11] {
            let p = psnr(&frame(k), &d.frames[k]);
            assert!(p > 30.0, "frame {k}: {p} dB");
        }
        assert!(Mp4Encoder::new(63, 48, 10).is_err());
    }
}
