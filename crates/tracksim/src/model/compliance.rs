//! Contact compliance of a track's rubber (issue 11.6): the compiled `[tracks.compliance]`
//! (a spring and damper along the contact normal for the grousers and for the belt), its
//! checks, and the elastic formulas that turn a rubber's modulus and a part's dimensions into
//! a stiffness.
//!
//! The world applies a [`ContactSpring`] per contact manifold (one grouser or belt link against
//! one terrain piece): the solver lets the part sink by `F / k` into the terrain, where `F` is
//! the manifold's normal force low-pass filtered with the time constant `c / k`. That is a
//! Kelvin-Voigt element (`F = k d + c d'`) in series with the engine's own contact
//! regularisation (`world/compliance.rs`).

use crate::check::Checker;
use crate::spec::{ComplianceSpec, ContactSpringSpec};

/// A contact spring and damper in parallel along the contact normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactSpring {
    /// Stiffness, N/m.
    pub stiffness: f64,
    /// Damping, N s/m.
    pub damping: f64,
}

impl ContactSpring {
    /// The relaxation time `c / k`, s: how fast the deflection follows a change of load.
    pub fn relaxation_time(&self) -> f64 {
        self.damping / self.stiffness
    }

    /// The spring from a stiffness `k` (N/m) and the rubber's loss factor `eta` at frequency
    /// `hz`: a Kelvin-Voigt element dissipates `eta` of its stored energy per radian at
    /// `c = eta k / (2 pi hz)`.
    pub fn from_loss_factor(k: f64, eta: f64, hz: f64) -> Self {
        ContactSpring {
            stiffness: k,
            damping: eta * k / (std::f64::consts::TAU * hz),
        }
    }
}

/// A track's contact compliance; `None` parts keep the engine's own contact.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Compliance {
    /// Each grouser against the terrain.
    pub grousers: Option<ContactSpring>,
    /// Each belt link against the terrain.
    pub belt: Option<ContactSpring>,
}

impl Compliance {
    /// True if neither part is compliant (the default: rigid).
    pub fn is_rigid(&self) -> bool {
        self.grousers.is_none() && self.belt.is_none()
    }
}

/// Checks `[<key>]` (a [`ComplianceSpec`]) and compiles it.
pub(crate) fn compile_compliance(c: &mut Checker, key: &str, s: &ComplianceSpec) -> Compliance {
    let mut spring = |part: &str, sp: &Option<ContactSpringSpec>| {
        sp.as_ref().map(|sp| {
            let k = format!("{key}.{part}");
            if !(sp.stiffness_n_per_m.is_finite() && sp.stiffness_n_per_m > 0.0) {
                c.push(
                    format!("{k}.stiffness_n_per_m"),
                    format!(
                        "must be a finite number > 0 N/m, got {} (track rubber: about 1e4 N/m for a small grouser, see VALIDATION.md; remove the [{k}] table for a rigid contact)",
                        sp.stiffness_n_per_m
                    ),
                );
            }
            c.non_negative(&format!("{k}.damping_ns_per_m"), sp.damping_ns_per_m, "N s/m");
            ContactSpring {
                stiffness: sp.stiffness_n_per_m,
                damping: sp.damping_ns_per_m,
            }
        })
    };
    Compliance {
        grousers: spring("grousers", &s.grousers),
        belt: spring("belt", &s.belt),
    }
}

/// Shear correction factor of a rectangular cross-section (Timoshenko beam).
const SHEAR_FACTOR_RECTANGLE: f64 = 5.0 / 6.0;

/// Stiffness, N/m, of a rubber lug (grouser) standing on the belt under a load across it at its
/// tip: a cantilever of height `height` m and width `width` m (across the belt) whose thickness
/// along the belt tapers linearly from `root_thickness` m (on the belt) to `tip_thickness` m,
/// bending and shear deflections added (Timoshenko), modulus `youngs_modulus` Pa, shear
/// modulus `E / (2 (1 + poisson))`. The lug's softest mode: pressed along its height the same
/// lug is several times stiffer (see [`lug_compression_stiffness`]).
pub fn lug_tip_stiffness(
    youngs_modulus: f64,
    poisson: f64,
    width: f64,
    height: f64,
    root_thickness: f64,
    tip_thickness: f64,
) -> f64 {
    let g = youngs_modulus / (2.0 * (1.0 + poisson));
    let n = 400;
    let dx = height / n as f64;
    let (mut bend, mut shear) = (0.0, 0.0);
    for i in 0..n {
        let x = (i as f64 + 0.5) * dx;
        let t = root_thickness + (tip_thickness - root_thickness) * x / height;
        let inertia = width * t.powi(3) / 12.0;
        bend += (height - x).powi(2) / (youngs_modulus * inertia) * dx;
        shear += 1.0 / (SHEAR_FACTOR_RECTANGLE * g * width * t) * dx;
    }
    1.0 / (bend + shear)
}

/// Stiffness, N/m, of the same tapered lug as [`lug_tip_stiffness`] pressed along its height
/// (uniaxial compression, `E A(x)` integrated over the height).
pub fn lug_compression_stiffness(
    youngs_modulus: f64,
    width: f64,
    height: f64,
    root_thickness: f64,
    tip_thickness: f64,
) -> f64 {
    let n = 400;
    let dx = height / n as f64;
    let mut flex = 0.0;
    for i in 0..n {
        let x = (i as f64 + 0.5) * dx;
        let t = root_thickness + (tip_thickness - root_thickness) * x / height;
        flex += dx / (youngs_modulus * width * t);
    }
    1.0 / flex
}

/// Stiffness, N/m, of a belt of rubber `thickness` m compressed between a pulley (or the
/// rigid backing) and the terrain over a patch `width` m by `length` m: `E w l / t`.
pub fn belt_compression_stiffness(
    youngs_modulus: f64,
    width: f64,
    length: f64,
    thickness: f64,
) -> f64 {
    youngs_modulus * width * length / thickness
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_lug_matches_the_textbook() {
        // Uniform lug: bending 3 E I / h^3 and shear kappa G A / h in series.
        let (e, w, h, t): (f64, f64, f64, f64) = (5.0e6, 0.02, 0.016, 0.01);
        let bend = 3.0 * e * (w * t * t * t / 12.0) / h.powi(3);
        let shear = SHEAR_FACTOR_RECTANGLE * (e / 3.0) * w * t / h;
        let k = lug_tip_stiffness(e, 0.5, w, h, t, t);
        let expect = 1.0 / (1.0 / bend + 1.0 / shear);
        assert!((k / expect - 1.0).abs() < 1e-4, "{k} vs {expect}");
        let kc = lug_compression_stiffness(e, w, h, t, t);
        assert!((kc / (e * w * t / h) - 1.0).abs() < 1e-9);
    }
}
