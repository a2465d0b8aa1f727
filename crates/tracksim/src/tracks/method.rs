//! The one place where a [`Method`] (data, parsed in the model layer) becomes an
//! implementation: the track of a vehicle or a conveyor, and the world settings a method needs.

use super::constraint_to_ground::ConstraintToGround;
use super::okada2020::{GrouserColliders, SegmentLinks};
use super::plates::Plates;
use super::track::{BuildContext, Track};
use super::wheels::Wheels;
use crate::error::Result;
use crate::model::{Method, TrackModel};
use rapier3d::prelude::IntegrationParameters;

/// Builds one track of the vehicle with `method` on `ctx.parent`. Only the paper's method and
/// the plate chain (as cleats) keep the grousers; the multiple wheels reach the grouser tips.
pub fn build_track(
    method: Method,
    ctx: &mut BuildContext,
    track: &TrackModel,
) -> Result<Box<dyn Track>> {
    Ok(match method {
        Method::Okada2020 => Box::new(SegmentLinks::build(ctx, track)?),
        Method::Okada2020NoGrousers => {
            let smooth = TrackModel {
                grousers: None,
                ..track.clone()
            };
            Box::new(SegmentLinks::build(ctx, &smooth)?)
        }
        Method::Okada2020LineTips => Box::new(SegmentLinks::build_with(
            ctx,
            track,
            GrouserColliders::LineTips,
        )?),
        Method::Okada2020Clustered => Box::new(SegmentLinks::build_with(
            ctx,
            track,
            GrouserColliders::Compound,
        )?),
        Method::Wheels(k) => Box::new(Wheels::build(ctx, track, k)?),
        Method::ConstraintToGround => Box::new(ConstraintToGround::build(ctx, track)?),
        Method::Plates => Box::new(Plates::build(ctx, track)?),
    })
}

/// The belt of a conveyor (a track whose parent is a fixed frame of the world): the paper's
/// segment links with grousers, whatever the vehicle's method.
pub fn build_conveyor_belt(ctx: &mut BuildContext, track: &TrackModel) -> Result<Box<dyn Track>> {
    Ok(Box::new(SegmentLinks::build(ctx, track)?))
}

/// The settings of the world's integration parameters that `method` needs (the contact
/// clustering of `okada2020_clustered`); the others change nothing.
pub fn configure_world(method: Method, params: &mut IntegrationParameters) {
    if method == Method::Okada2020Clustered {
        super::clustered::world_settings(params);
    }
}
