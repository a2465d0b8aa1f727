//! The simulated vehicle weighs what its file says (issue 11.2). Track methods floor the mass of
//! their link and wheel bodies (`simulation.min_link_mass_kg`: light links on impulse joints
//! hop), which adds mass; this build stage takes the excess back from the body each track runs
//! on (chassis or flipper), so that the total mass and the centre of mass are the file's. The
//! parent's inertia is scaled with its mass (its shape is unchanged). Flippers keep their mass:
//! a light flipper arm carrying heavier links was measured unstable (the PackBot's 1 kg arm
//! paying for 1.6 kg of floored sub-track links, kept at 0.25 kg, was flung off at 0.07 s on the
//! stairs), so the chassis pays for its flippers' tracks too: total and centre of mass at the
//! start pose are the file's, and the flipper assemblies weigh that excess more than the file
//! says (reported in [`MassReport`]). A floor that would leave the chassis with less than
//! [`MIN_PARENT_MASS_FRACTION`] of its mass is refused with an error naming the key.

use serde::Serialize;

/// Smallest fraction of its file mass the chassis may keep after giving its tracks' floored
/// bodies their extra mass.
pub const MIN_PARENT_MASS_FRACTION: f64 = 0.25;

/// Simulated and file mass of one part of the vehicle, kg.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PartMass {
    /// "body", "flipper NAME" or "track NAME".
    pub part: String,
    /// What the file says, kg.
    pub file_kg: f64,
    /// What is simulated, kg (for a track: all its bodies).
    pub simulated_kg: f64,
}

/// Masses of a built vehicle: every part and the totals, kg.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MassReport {
    /// Every part.
    pub parts: Vec<PartMass>,
    /// Total of the file, kg.
    pub total_file_kg: f64,
    /// Total simulated, kg.
    pub total_simulated_kg: f64,
    /// Simulated centre of mass of the whole vehicle in the chassis frame (x forward, z up), m.
    pub centre_of_mass_body_m: [f64; 3],
}

impl MassReport {
    /// The totals and every part as lines of text.
    pub fn lines(&self) -> Vec<String> {
        let c = self.centre_of_mass_body_m;
        let mut out = vec![format!(
            "mass simulated {:.3} kg (file {:.3} kg), centre of mass [{:.4}, {:.4}, {:.4}] m (body frame)",
            self.total_simulated_kg, self.total_file_kg, c[0], c[1], c[2]
        )];
        for p in &self.parts {
            out.push(format!(
                "{:<22} {:8.3} kg simulated, {:8.3} kg in the file",
                p.part, p.simulated_kg, p.file_kg
            ));
        }
        out
    }
}
