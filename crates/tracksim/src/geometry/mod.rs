//! Track paths: closed loops of straight and circular segments (paper Sec. III-A), planar or
//! spatial (Fig. 8), and the grouser pattern distributed along them by arc length (Sec. III-B).
//!
//! All quantities are SI (m, rad) in `f64`, in the frame of the link the track hangs on (the
//! *track frame*). Every length and pose is computed in closed form; nothing is sampled.
//!
//! - `segment.rs`: one piece of a path ([`Segment`]);
//! - `path_error.rs`: what can be wrong with a path ([`PathError`]);
//! - `track_path.rs`: a validated closed loop ([`TrackPath`]);
//! - `pulley_loop.rs`: a belt wrapped around pulleys ([`Pulley`], [`TrackPath::from_pulleys`]);
//! - `frame.rs`: an orthonormal frame on a path ([`Frame`]);
//! - `grouser_layout.rs`: grousers spaced evenly along a path ([`GrouserLayout`]);
//! - `collision_shape.rs`: a compiled collision shape ([`CollisionShape`]).

mod collision_shape;
mod frame;
mod grouser_layout;
mod path_error;
mod pulley_loop;
mod segment;
#[cfg(test)]
mod tests;
mod track_path;

pub use collision_shape::CollisionShape;
pub use frame::Frame;
pub use grouser_layout::GrouserLayout;
pub use path_error::PathError;
pub use pulley_loop::Pulley;
pub use segment::Segment;
pub use track_path::TrackPath;

/// Largest gap allowed between the end of one segment and the start of the next, m.
pub const JOIN_TOLERANCE_M: f64 = 1e-5;
/// Largest angle allowed between the end tangent of one segment and the start tangent of the
/// next, and between the loop's total turning and one full turn, rad.
pub const TANGENT_TOLERANCE_RAD: f64 = 1e-4;
