//! Colour images by ray tracing (issue 41): one ray per pixel against a scene that answers ray
//! queries ([`RenderScene`]: the running world through Rapier's broad phase, or a replayed
//! run), the hit's colour ([`Rgb`]) shaded by one sun with a shadow ray ([`Light`]), a sky
//! and a ground horizon where nothing is hit. No GPU, no rasteriser: the same rays the depth
//! camera casts, so colour and depth agree pixel for pixel.
//!
//! - `color.rs`: [`Rgb`], the `"#rrggbb"` form of the files and the default palette;
//! - `light.rs`: [`Light`], the light model (ambient plus Lambert from one sun, shadowed);
//! - `camera.rs`: [`Intrinsics`] (pinhole, square pixels) and [`CameraPose`], the chase pose;
//! - `shapes.rs`: closed-form ray tests of boxes and cylinders (faster than the generic ones);
//! - `encode.rs`: frames as PNG bytes (rgb8; depth as 16-bit millimetres);
//! - `trace.rs`: [`RenderScene`] and [`render`], which fills a [`Frame`] (rgb8 and depth) by
//!   tiles culled against the scene's bounding boxes, on one thread or on a rayon pool, with
//!   the same bytes either way.
//!
//! Layering: this module imports nothing of the crate (Rapier and glam only), so the terrain,
//! the model, the sensors and the outputs can all use it.

mod camera;
mod color;
pub mod encode;
mod light;
pub mod shapes;
mod trace;

pub use camera::{CameraPose, ChaseCamera, Intrinsics};
pub use color::{Rgb, palette};
pub use light::Light;
pub use trace::{Candidate, Frame, Hit, RenderScene, TILE, render};
