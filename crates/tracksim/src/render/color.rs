//! Colours: [`Rgb`] (8-bit sRGB values), read from and written as `"#rrggbb"`, and the
//! default palette: a colour per terrain kind and per vehicle part, and the sky's.

use std::fmt;

/// A colour, 8-bit sRGB values (red, green, blue).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct Rgb(pub [u8; 3]);

impl Rgb {
    /// Reads `"#rrggbb"` (six hexadecimal digits after a `#`, either case).
    pub fn parse(s: &str) -> Option<Rgb> {
        let h = s.strip_prefix('#')?;
        if h.len() != 6 || !h.bytes().all(|b| b.is_ascii_hexdigit()) {
            return None;
        }
        let byte = |i: usize| u8::from_str_radix(&h[i..i + 2], 16).ok();
        Some(Rgb([byte(0)?, byte(2)?, byte(4)?]))
    }

    /// From fractions 0..1 (URDF's `rgba`), rounded and clamped.
    pub fn from_unit(r: f64, g: f64, b: f64) -> Rgb {
        let c = |v: f64| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
        Rgb([c(r), c(g), c(b)])
    }

    /// The values as fractions 0..1.
    pub fn unit(self) -> [f32; 3] {
        self.0.map(|v| v as f32 / 255.0)
    }
}

impl fmt::Display for Rgb {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [r, g, b] = self.0;
        write!(f, "#{r:02x}{g:02x}{b:02x}")
    }
}

/// The default colours (each settable in the files: a terrain entry's `color`, the vehicle's
/// `[vehicle.colors]`, a URDF link's `<material><color>`).
pub mod palette {
    use super::Rgb;
    /// `[terrain.ground]`: grey concrete.
    pub const GROUND: Rgb = Rgb([0x8c, 0x88, 0x80]);
    /// Ground or boxes with deformable soil: sand brown.
    pub const SOIL: Rgb = Rgb([0xb0, 0x93, 0x66]);
    /// `[[terrain.boxes]]`: light stone.
    pub const BOX: Rgb = Rgb([0xb8, 0xb0, 0xa2]);
    /// `[[terrain.staircases]]`: concrete steps.
    pub const STAIRCASE: Rgb = Rgb([0xa9, 0xa4, 0x9a]);
    /// Stair nosings (cylinders): dark steel.
    pub const NOSING: Rgb = Rgb([0x5a, 0x5e, 0x63]);
    /// `[[terrain.inclines]]`: plywood.
    pub const INCLINE: Rgb = Rgb([0xc4, 0xa8, 0x7c]);
    /// `[[terrain.heightfields]]`: earth.
    pub const HEIGHTFIELD: Rgb = Rgb([0x86, 0x78, 0x5a]);
    /// `[[terrain.rough]]`: grassy earth.
    pub const ROUGH: Rgb = Rgb([0x6f, 0x7a, 0x4f]);
    /// `[[terrain.meshes]]`: grey.
    pub const MESH: Rgb = Rgb([0x9a, 0x9a, 0x96]);
    /// NIST test obstacles (stepfields, pitch/roll ramps, hurdles, gaps): pine.
    pub const TEST_OBSTACLE: Rgb = Rgb([0xd2, 0xb2, 0x80]);
    /// Loose boxes: cardboard orange.
    pub const LOOSE_BOX: Rgb = Rgb([0xcf, 0x8a, 0x3e]);
    /// Conveyors: black belts.
    pub const CONVEYOR: Rgb = Rgb([0x33, 0x33, 0x33]);
    /// A vehicle's body: olive drab.
    pub const BODY: Rgb = Rgb([0x5b, 0x63, 0x3a]);
    /// Tracks (belts and grousers): black rubber.
    pub const TRACK: Rgb = Rgb([0x26, 0x26, 0x26]);
    /// Flipper arms: dark olive.
    pub const FLIPPER: Rgb = Rgb([0x44, 0x4a, 0x2c]);
    /// A collider of no known part.
    pub const OTHER: Rgb = Rgb([0x80, 0x80, 0x80]);
    /// The sky straight up.
    pub const SKY_ZENITH: Rgb = Rgb([0x4a, 0x7f, 0xc1]);
    /// The sky at the horizon.
    pub const SKY_HORIZON: Rgb = Rgb([0xc8, 0xd8, 0xe8]);
    /// Below the horizon where nothing is hit (ground beyond the camera's range).
    pub const FAR_GROUND: Rgb = Rgb([0x77, 0x72, 0x68]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex_reads_and_writes() {
        assert_eq!(Rgb::parse("#ff8000"), Some(Rgb([255, 128, 0])));
        assert_eq!(Rgb::parse("#FF8000").unwrap().to_string(), "#ff8000");
        for bad in [
            "ff8000", "#ff800", "#ff80000", "#gg8000", "", "#", "#ff80 0",
        ] {
            assert_eq!(Rgb::parse(bad), None, "{bad}");
        }
        assert_eq!(Rgb::from_unit(1.0, 0.5, -1.0), Rgb([255, 128, 0]));
    }
}
