//! Deformable soil at run time (issue 30; docs/SOIL.md, docs/DESIGN.md "Soil"). Rapier still
//! resolves every contact; the soil decides how the ground pushes back, in the contact hook,
//! per contact manifold of a vehicle part with a soil surface:
//!
//! - **Normal**: the part owns a patch of ground (a grouser: one pitch of the track's
//!   footprint, `pitch x width`, centred on it; any other part: its bounding box seen from
//!   above). The patch's pressure is the manifold's normal force (last step's impulses,
//!   low-pass filtered with the soil's damping, as the contact compliance does) over its area;
//!   Bekker's law with the cells' plastic memory gives the sinkage (`SoilModel::loaded_sinkage`)
//!   and the solver is told the part may sink that deep (`dist += sinkage`): it pushes back
//!   only what is deeper. A grouser's tip sinks its height further: grousers are fully
//!   embedded and the soil between them moves with the belt (Wong's track model), so the belt
//!   surface of a track with grousers does not touch the soil (its contacts are dropped).
//! - **Tangential**: the manifold's friction coefficient is the patch's shear limit over its
//!   normal force. A grouser patch shears at the tip plane, `A (c + p tan phi)`, unless the
//!   soil ploughs past the grouser first: the smooth belt's `A p tan delta` plus the Rankine
//!   passive resistance of the grouser's face with the track's pressure as surcharge (the
//!   smaller governs). Other parts shear at the interface, `A p tan delta`. Either is
//!   mobilised by Janosi-Hanamoto with the mean shear displacement of the patch's cells.
//! - **After the step**: each loaded cell keeps its largest sinkage (the rut) and accumulates
//!   the slip of the part over it (its shear displacement), which restarts once a cell has been
//!   unloaded for [`SHEAR_RESET_S`]. Every deepening of a cell costs Bekker's work
//!   (`integral p dz` over its area, from its old depth to the new): Bekker's compaction
//!   resistance, given back as an impulse on the chassis against its horizontal motion (none
//!   when that would take more than half its momentum: a robot settling, not driving).
//! - **Reported forces**: the normal load is the solver's normal impulses (exact); the thrust
//!   is the friction impulses, whose vehicle total is measured by momentum (Rapier's twist
//!   friction keeps only its last substep's impulse; see
//!   [`crate::world::Simulation::soil_contact_impulses`]).

mod hook;
mod patch;
mod report;
mod state;
mod step;

pub(crate) use hook::modify_soil_contacts;
pub use report::{RutCell, TrackSoil};
pub(crate) use state::{SoilState, build_soil};

/// A cell unloaded this long forgets its shear displacement, s.
pub const SHEAR_RESET_S: f64 = 0.1;
/// Largest friction coefficient a soil contact gets (a light load on cohesive soil), -.
const MU_CAP: f32 = 5.0;
/// Cells whose centre lies within this of a patch's edge are outside it, m: far above the f32
/// rounding of a position near the floating origin (0.1 um), far below a cell.
const EDGE_MARGIN_M: f64 = 1e-6;
/// Below this chassis speed no compaction impulse is applied, m/s.
const COMPACTION_MIN_SPEED_MPS: f64 = 1e-3;
/// Time constant of the pressure a rut keeps, s: the footprint's pressure (its force over its
/// patches' area) low-pass filtered this long sets how deep a cell is pressed for good. A
/// track's grouser patches in contact alternate between N and N + 1 as grousers pass the
/// pulleys (one pitch of area: 6 % on PackBot), and the solver's force fluctuates; a cell
/// keeps its largest sinkage, so a rut that followed each step's pressure kept its peaks
/// (issue 38.4: sinkage 14 % over Bekker at n = 0.5 = the pressure over N patches, not the
/// mean).
const RUT_PRESSURE_TIME_S: f64 = 0.5;
/// A track whose belt is held and whose parent moves slower than this (horizontally) is
/// parked: its soil contacts hold on to where it was parked (static friction's anchor), m/s.
const ANCHOR_SPEED_MPS: f64 = 0.01;
/// ... and turns slower than this, rad/s.
const ANCHOR_TURN_RADPS: f64 = 0.05;
/// Time constant of a parked track's return to its anchor, s.
const ANCHOR_TIME_S: f32 = 0.2;
/// Largest speed of that return, m/s (below [`ANCHOR_SPEED_MPS`]: the return never releases
/// the anchor).
const ANCHOR_MAX_MPS: f32 = 0.002;
