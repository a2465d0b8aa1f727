//! The light model: one sun at infinity and an ambient term. A surface of colour `c` with unit
//! normal `n` is drawn `c * (ambient + diffuse * max(0, n . s) * lit)`, where `s` is the unit
//! direction towards the sun and `lit` is 1 when a shadow ray from the surface towards the sun
//! reaches the sky within [`Light::shadow_range`], else 0 (Lambert's cosine law, hard shadows).
//! The values stay 8-bit sRGB, scaled linearly (no gamma step): a patch in shadow is exactly
//! `ambient / (ambient + diffuse * cos)` as bright as the same patch lit.
//!
//! Where nothing is hit, a ray looking up sees the sky (from [`palette::SKY_HORIZON`] to
//! [`palette::SKY_ZENITH`] with the sine of its elevation) and a ray looking down sees
//! [`palette::FAR_GROUND`] (ground beyond the camera's range).

use super::color::{Rgb, palette};
use glam::Vec3;

/// One sun and an ambient term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Unit direction towards the sun, world frame (REP 103: x forward, y left, z up).
    pub sun: Vec3,
    /// Fraction of a colour seen in shadow (0..1).
    pub ambient: f32,
    /// Fraction added by the sun on a surface facing it (ambient + diffuse <= 1).
    pub diffuse: f32,
    /// Length of a shadow ray, m: what is further towards the sun casts no shadow.
    pub shadow_range: f32,
}

/// The sun's elevation above the horizon, degrees.
pub const SUN_ELEVATION_DEG: f32 = 55.0;
/// The sun's azimuth, degrees about z from +x (225: behind and to the right of a robot
/// driving along +x, so a chase camera sees the lit side).
pub const SUN_AZIMUTH_DEG: f32 = 225.0;

impl Default for Light {
    fn default() -> Self {
        let (el, az) = (SUN_ELEVATION_DEG.to_radians(), SUN_AZIMUTH_DEG.to_radians());
        Light {
            sun: Vec3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin()),
            ambient: 0.4,
            diffuse: 0.6,
            shadow_range: 10.0,
        }
    }
}

impl Light {
    /// The brightness factor of a surface with unit normal `n` (facing the viewer), `lit` or
    /// in shadow.
    pub fn factor(&self, n: Vec3, lit: bool) -> f32 {
        let cos = n.dot(self.sun).max(0.0);
        self.ambient + if lit { self.diffuse * cos } else { 0.0 }
    }

    /// Colour `c` under brightness factor `f` (>= 0), rounded half up to 8 bits (the cast
    /// saturates at 255).
    pub fn apply(c: Rgb, f: f32) -> [u8; 3] {
        c.0.map(|v| (v as f32 * f + 0.5) as u8)
    }

    /// What a ray of unit direction `d` sees when it hits nothing.
    pub fn background(d: Vec3) -> [u8; 3] {
        if d.z < 0.0 {
            return palette::FAR_GROUND.0;
        }
        let t = d.z.clamp(0.0, 1.0);
        let (h, z) = (palette::SKY_HORIZON.0, palette::SKY_ZENITH.0);
        std::array::from_fn(|i| (h[i] as f32 + (z[i] as f32 - h[i] as f32) * t + 0.5) as u8)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shadow_is_ambient_over_lit() {
        let l = Light::default();
        let up = Vec3::Z;
        let cos = l.sun.z;
        assert!((cos - SUN_ELEVATION_DEG.to_radians().sin()).abs() < 1e-6);
        let ratio = l.factor(up, false) / l.factor(up, true);
        assert!((ratio - 0.4 / (0.4 + 0.6 * cos)).abs() < 1e-6);
        // A face turned away from the sun is ambient only, lit or not.
        assert_eq!(l.factor(-l.sun, true), l.ambient);
    }
}
