//! Terrains: what a scenario's `[terrain]` says, its compiled form, and its insertion into a
//! Rapier world. Every surface carries its own friction coefficient (default 0.6). Heights are
//! z-up, x forward, y left (REP 103).
//!
//! A `[terrain]` table may combine, in any number:
//! - `[terrain.ground]`: an infinite flat plane (simulated as a tile kept under the vehicle,
//!   [`GROUND_TILE_HALF_M`]);
//! - `[[terrain.boxes]]`: boxes (steps, walls, bumps);
//! - `[[terrain.staircases]]`, `[[terrain.inclines]]`: stairs and ramps built from boxes;
//! - `[[terrain.heightfields]]`: height maps read from greyscale PNG files (8 or 16 bit);
//! - `[[terrain.rough]]`: repeatable random rough ground (a seeded height field);
//! - `[[terrain.meshes]]`: triangle meshes read from STL (binary or ASCII) or OBJ files;
//! - the standard response-robot test obstacles (NIST / ASTM E54.09), built from boxes:
//!   `[[terrain.stepfields]]`, `[[terrain.pitch_roll_ramps]]`, `[[terrain.hurdles]]`,
//!   `[[terrain.gaps]]`.
//!
//! Obstacles placed by a start point and a yaw (`x_m`, `y_m`, `z_m`, `yaw_deg`) are described
//! in their own frame: local x is the direction of travel (rotated by `yaw_deg` about z from
//! the world x axis), local y to its left, and `z_m` the floor height they stand on.
//!
//! Grid convention (PNG height maps, rough fields, stepfield patterns): a grid is seen from
//! above as an image with north up, i.e. row 0 is the +y edge (rows run towards -y) and
//! column 0 the -x edge (columns run towards +x), before any yaw.

use crate::check::{Checker, v3};
use crate::error::SpecIssue;
use glam::{DQuat, DVec3};
use rapier3d::parry::shape::TriMeshFlags;
use rapier3d::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

fn default_friction() -> f64 {
    0.6
}
fn default_one() -> f64 {
    1.0
}

/// The terrain.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TerrainSpec {
    /// A flat ground plane.
    #[serde(default)]
    pub ground: Option<GroundSpec>,
    /// Boxes: steps, walls, bumps.
    #[serde(default)]
    pub boxes: Vec<BoxSpec>,
    /// Staircases built from boxes.
    #[serde(default)]
    pub staircases: Vec<StaircaseSpec>,
    /// Inclined planes (thin tilted boxes).
    #[serde(default)]
    pub inclines: Vec<InclineSpec>,
    /// Height maps from greyscale PNG files.
    #[serde(default)]
    pub heightfields: Vec<HeightFieldSpec>,
    /// Procedurally generated rough ground.
    #[serde(default)]
    pub rough: Vec<RoughSpec>,
    /// Triangle meshes from STL or OBJ files.
    #[serde(default)]
    pub meshes: Vec<MeshSpec>,
    /// ASTM E2828-style stepfields.
    #[serde(default)]
    pub stepfields: Vec<StepfieldSpec>,
    /// ASTM E2826/E2827-style pitch/roll ramp fields.
    #[serde(default)]
    pub pitch_roll_ramps: Vec<PitchRollRampSpec>,
    /// ASTM E2802-style hurdles.
    #[serde(default)]
    pub hurdles: Vec<HurdleSpec>,
    /// ASTM E2801-style gaps.
    #[serde(default)]
    pub gaps: Vec<GapSpec>,
}

/// Flat ground.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GroundSpec {
    /// Friction coefficient.
    #[serde(default = "default_friction")]
    pub friction: f64,
    /// Height of the surface, m.
    #[serde(default)]
    pub z_m: f64,
}

/// A box obstacle.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSpec {
    /// Centre, m.
    pub centre_m: [f64; 3],
    /// Full sizes, m.
    pub size_m: [f64; 3],
    /// Rotation about z, degrees.
    #[serde(default)]
    pub yaw_deg: f64,
    /// Rotation about y, degrees (for ramps).
    #[serde(default)]
    pub pitch_deg: f64,
    /// Friction coefficient.
    #[serde(default = "default_friction")]
    pub friction: f64,
}

/// A straight staircase of `count` equal steps, built from boxes (exact edges). In its own
/// frame the first riser's foot is at the origin, the steps climb towards +x and are
/// `width_m` wide, centred on y = 0. Step k (1..=count) has its tread at height k * rise_m and
/// its riser at x = (k - 1) * run_m; the top tread is run_m + landing_m deep.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct StaircaseSpec {
    /// x of the foot of the first riser (centre of the width), m.
    pub x_m: f64,
    /// y of the foot of the first riser (centre of the width), m (default 0).
    #[serde(default)]
    pub y_m: f64,
    /// Floor height the staircase stands on, m (default 0).
    #[serde(default)]
    pub z_m: f64,
    /// Direction of ascent, degrees about z from +x (default 0: climbing towards +x).
    #[serde(default)]
    pub yaw_deg: f64,
    /// Height of each step, m.
    pub rise_m: f64,
    /// Depth of each tread (horizontal), m.
    pub run_m: f64,
    /// Number of steps (risers), at least 1.
    pub count: u32,
    /// Width of the stairs (across the direction of ascent), m.
    pub width_m: f64,
    /// Radius of a rounded front edge (nosing) on every tread, m; absent: sharp edges. Must
    /// not exceed rise_m or run_m. The rounding is a cylinder along the edge.
    #[serde(default)]
    pub nosing_radius_m: Option<f64>,
    /// Extra depth of the top tread (a landing), m (default 0: the top tread is run_m deep).
    #[serde(default)]
    pub landing_m: Option<f64>,
    /// Friction coefficient.
    #[serde(default = "default_friction")]
    pub friction: f64,
}

/// An inclined plane: a thin tilted box whose top surface starts on the floor along its lower
/// edge at (x_m, y_m, z_m) and rises at `angle_deg` towards +x (rotated by `yaw_deg`). The
/// surface height at a distance d past the lower edge is z_m + d * tan(angle).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct InclineSpec {
    /// x of the middle of the lower edge, m.
    pub x_m: f64,
    /// y of the middle of the lower edge, m (default 0).
    #[serde(default)]
    pub y_m: f64,
    /// Height of the lower edge (the floor), m (default 0).
    #[serde(default)]
    pub z_m: f64,
    /// Direction of ascent, degrees about z from +x (default 0).
    #[serde(default)]
    pub yaw_deg: f64,
    /// Slope, degrees (0 < angle < 90).
    pub angle_deg: f64,
    /// Length of the inclined surface measured along the slope, m.
    pub length_m: f64,
    /// Width across the slope, m.
    pub width_m: f64,
    /// Thickness of the plate (below the surface), m (default 0.05).
    #[serde(default = "default_incline_thickness")]
    pub thickness_m: f64,
    /// Friction coefficient.
    #[serde(default = "default_friction")]
    pub friction: f64,
}
fn default_incline_thickness() -> f64 {
    0.05
}

/// A height map read from a greyscale PNG file (8 or 16 bit; grey + alpha is accepted and the
/// alpha ignored). A pixel value v of the maximum V (255 or 65535) becomes the height
/// min_z_m + (max_z_m - min_z_m) * v / V. Pixels are the grid's vertices: the image spans
/// exactly size_x_m by size_y_m, so a w-pixel-wide image has cells size_x_m / (w - 1) wide.
/// Orientation (before yaw): image row 0 is the +y edge (north up when viewed as an image),
/// column 0 is the -x edge.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct HeightFieldSpec {
    /// The PNG file, relative to the scenario's folder.
    pub file: PathBuf,
    /// Extent along x (image width), m.
    pub size_x_m: f64,
    /// Extent along y (image height), m.
    pub size_y_m: f64,
    /// Height of a black pixel (value 0), m.
    pub min_z_m: f64,
    /// Height of a white pixel (value 255 or 65535), m.
    pub max_z_m: f64,
    /// Centre of the map, `[x, y]` m (default [0, 0]).
    #[serde(default)]
    pub centre_m: [f64; 2],
    /// Rotation about z around the centre, degrees (default 0).
    #[serde(default)]
    pub yaw_deg: f64,
    /// Friction coefficient.
    #[serde(default = "default_friction")]
    pub friction: f64,
}

/// Procedurally generated rough ground, built as a height field. White noise from a
/// splitmix64 generator seeded by `seed` (the same seed gives bit-identical heights on every
/// run) is smoothed by three box filters (approximately a Gaussian of standard deviation
/// `correlation_m`), faded to `mean_z_m` over `edge_taper_m` at the borders, and scaled so
/// that exactly one of `rms_height_m` (root mean square of z - mean_z_m over all vertices) or
/// `peak_height_m` (largest |z - mean_z_m|) holds.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RoughSpec {
    /// Seed of the random generator (default 0).
    #[serde(default)]
    pub seed: u64,
    /// Centre of the field, `[x, y]` m (default [0, 0]).
    #[serde(default)]
    pub centre_m: [f64; 2],
    /// Extent `[x, y]`, m.
    pub size_m: [f64; 2],
    /// Grid spacing, m (default 0.05; rounded so that a whole number of cells fits the size).
    #[serde(default = "default_cell")]
    pub cell_m: f64,
    /// Root-mean-square height about mean_z_m, m (give this or peak_height_m).
    #[serde(default)]
    pub rms_height_m: Option<f64>,
    /// Largest deviation from mean_z_m, m (give this or rms_height_m).
    #[serde(default)]
    pub peak_height_m: Option<f64>,
    /// Correlation length: standard deviation of the smoothing kernel, m (default 0.2;
    /// 0 gives uncorrelated heights at every vertex).
    #[serde(default = "default_correlation")]
    pub correlation_m: f64,
    /// Reference height the roughness varies about, m (default 0).
    #[serde(default)]
    pub mean_z_m: f64,
    /// Width of the border over which the heights fade to mean_z_m, m (default 0: none).
    #[serde(default)]
    pub edge_taper_m: f64,
    /// Rotation about z around the centre, degrees (default 0).
    #[serde(default)]
    pub yaw_deg: f64,
    /// Friction coefficient.
    #[serde(default = "default_friction")]
    pub friction: f64,
}
fn default_cell() -> f64 {
    0.05
}
fn default_correlation() -> f64 {
    0.2
}

/// The up axis of a mesh file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum UpAxis {
    /// The file is z-up (as the simulator).
    #[default]
    Z,
    /// The file is y-up (common for OBJ exports): its +y becomes +z, its +z becomes -y.
    Y,
}

/// A triangle mesh read from an STL (binary or ASCII) or OBJ file. File coordinates are in
/// metres before `scale`; they are turned z-up (`up_axis`), scaled, rotated by `yaw_deg` about
/// z, then translated by `translation_m`.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// The `.stl` or `.obj` file, relative to the scenario's folder.
    pub file: PathBuf,
    /// Uniform scale factor applied to the file's coordinates (default 1; e.g. 0.001 for mm).
    #[serde(default = "default_one")]
    pub scale: f64,
    /// Translation, m (default [0, 0, 0]).
    #[serde(default)]
    pub translation_m: [f64; 3],
    /// Rotation about z, degrees (default 0).
    #[serde(default)]
    pub yaw_deg: f64,
    /// Up axis of the file: "z" (default) or "y".
    #[serde(default)]
    pub up_axis: UpAxis,
    /// Friction coefficient.
    #[serde(default = "default_friction")]
    pub friction: f64,
}

/// A stepfield after ASTM E2828 (Standard Test Method for Evaluating Emergency Response Robot
/// Capabilities: Mobility: Confined Area Terrains: Symmetric Stepfields): a grid of square
/// posts `post_m` wide whose heights are whole multiples of `step_m`. The standard could not
/// be consulted here: the post width (0.1 m, about a 4x4-inch post), the step (0.1 m) and the
/// default pattern (a 12 x 12 diamond-shaped hill of 1 to 4 steps, symmetric about both centre
/// lines) are approximations. The field starts at x_m (its -x edge) and is centred on y_m.
/// `pattern[r][c]` is the height in steps of the post in row r (row 0 at the +y edge) and
/// column c (column 0 at the -x edge, the entry side); 0 leaves the floor bare. Instead of a
/// pattern, a `seed` gives a repeatable random pattern of `rows` x `columns` posts of 1 to
/// `max_steps` steps.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct StepfieldSpec {
    /// x of the field's entry (-x) edge, m.
    pub x_m: f64,
    /// y of the field's centre line, m (default 0).
    #[serde(default)]
    pub y_m: f64,
    /// Floor height, m (default 0).
    #[serde(default)]
    pub z_m: f64,
    /// Direction of travel through the field, degrees about z from +x (default 0).
    #[serde(default)]
    pub yaw_deg: f64,
    /// Side of the square posts, m (default 0.1).
    #[serde(default = "default_post")]
    pub post_m: f64,
    /// Height of one step, m (default 0.1).
    #[serde(default = "default_post")]
    pub step_m: f64,
    /// Post heights in steps, a list of equally long rows (see the type's docs).
    #[serde(default)]
    pub pattern: Option<Vec<Vec<u32>>>,
    /// Seed of a random pattern (instead of `pattern`).
    #[serde(default)]
    pub seed: Option<u64>,
    /// Rows of a random pattern (default 12).
    #[serde(default)]
    pub rows: Option<u32>,
    /// Columns of a random pattern (default 12).
    #[serde(default)]
    pub columns: Option<u32>,
    /// Tallest post of a random pattern, in steps (default 4).
    #[serde(default)]
    pub max_steps: Option<u32>,
    /// Friction coefficient.
    #[serde(default = "default_friction")]
    pub friction: f64,
}
fn default_post() -> f64 {
    0.1
}

/// Which way the ramps of a [`PitchRollRampSpec`] slope.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RampOrientation {
    /// Slopes along the direction of travel: hills and valleys crossed one after the other.
    #[default]
    Pitch,
    /// Slopes across the direction of travel: ridges and valleys running along it.
    Roll,
}

/// A field of pitch or roll ramps after ASTM E2826 (Continuous Pitch/Roll Ramps) and E2827
/// (Crossing Pitch/Roll Ramps). Each panel is a thin plate covering `panel_m` x `panel_m` of
/// floor (horizontally) at `angle_deg`, neighbours sloping in opposite directions so that the
/// surface is a continuous zigzag. "pitch": `count` panels along x, alternately rising and
/// falling (peaks panel_m * tan(angle) high, about 0.32 m), each `lanes` panels wide; "roll":
/// `lanes` panels across, alternately rising towards +y and -y, each `count` panels long. The
/// standards could not be consulted here: the 15 degree angle and the 1.2 m (4 ft plywood)
/// panels are the commonly quoted values; the layout, counts and plate thickness are
/// approximations. The field starts at x_m (its -x edge) and is centred on y_m.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PitchRollRampSpec {
    /// x of the field's entry (-x) edge, m.
    pub x_m: f64,
    /// y of the field's centre line, m (default 0).
    #[serde(default)]
    pub y_m: f64,
    /// Floor height, m (default 0).
    #[serde(default)]
    pub z_m: f64,
    /// Direction of travel, degrees about z from +x (default 0).
    #[serde(default)]
    pub yaw_deg: f64,
    /// "pitch" (default) or "roll".
    #[serde(default)]
    pub orientation: RampOrientation,
    /// Slope of every panel, degrees (default 15).
    #[serde(default = "default_ramp_angle")]
    pub angle_deg: f64,
    /// Horizontal side of a panel, m (default 1.2).
    #[serde(default = "default_panel")]
    pub panel_m: f64,
    /// Panels along x (default 4).
    #[serde(default = "default_ramp_count")]
    pub count: u32,
    /// Panels across (default 2).
    #[serde(default = "default_lanes")]
    pub lanes: u32,
    /// Thickness of the plates, m (default 0.02).
    #[serde(default = "default_plate")]
    pub thickness_m: f64,
    /// Friction coefficient.
    #[serde(default = "default_friction")]
    pub friction: f64,
}
fn default_ramp_angle() -> f64 {
    15.0
}
fn default_panel() -> f64 {
    1.2
}
fn default_ramp_count() -> u32 {
    4
}
fn default_lanes() -> u32 {
    2
}
fn default_plate() -> f64 {
    0.02
}

/// A hurdle after ASTM E2802 (Mobility: Confined Area Obstacles: Hurdles): a bar of
/// rectangular section `height_m` high and `thickness_m` deep lying across the lane, its near
/// face at x_m. The standard could not be consulted here: the default thickness (0.1 m, about
/// a 4x4-inch timber) and width (1.2 m) are approximations.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct HurdleSpec {
    /// x of the near (-x) face, m.
    pub x_m: f64,
    /// y of the middle of the hurdle, m (default 0).
    #[serde(default)]
    pub y_m: f64,
    /// Floor height, m (default 0).
    #[serde(default)]
    pub z_m: f64,
    /// Direction of travel, degrees about z from +x (default 0).
    #[serde(default)]
    pub yaw_deg: f64,
    /// Height above the floor, m.
    pub height_m: f64,
    /// Depth along the direction of travel, m (default 0.1).
    #[serde(default = "default_post")]
    pub thickness_m: f64,
    /// Length across the lane, m (default 1.2).
    #[serde(default = "default_panel")]
    pub width_m: f64,
    /// Friction coefficient.
    #[serde(default = "default_friction")]
    pub friction: f64,
}

/// A gap after ASTM E2801 (Mobility: Confined Area Obstacles: Gaps): two platforms
/// `height_m` high separated by a gap `gap_width_m` wide (along the direction of travel); the
/// first platform ends at x_m, the second starts at x_m + gap_width_m. The standard could not
/// be consulted here: the platform length and width (1.2 m each) are approximations.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GapSpec {
    /// x of the gap's near edge (the end of the first platform), m.
    pub x_m: f64,
    /// y of the lane's centre line, m (default 0).
    #[serde(default)]
    pub y_m: f64,
    /// Floor height, m (default 0).
    #[serde(default)]
    pub z_m: f64,
    /// Direction of travel, degrees about z from +x (default 0).
    #[serde(default)]
    pub yaw_deg: f64,
    /// Width of the gap along the direction of travel, m.
    pub gap_width_m: f64,
    /// Height of both platforms above the floor, m.
    pub height_m: f64,
    /// Length of each platform along the direction of travel, m (default 1.2).
    #[serde(default = "default_panel")]
    pub platform_length_m: f64,
    /// Width of the platforms across the lane, m (default 1.2).
    #[serde(default = "default_panel")]
    pub width_m: f64,
    /// Friction coefficient.
    #[serde(default = "default_friction")]
    pub friction: f64,
}

/// A box obstacle, compiled.
#[derive(Clone, Debug)]
pub struct BoxModel {
    /// Centre, m.
    pub centre: DVec3,
    /// Half extents, m.
    pub half: DVec3,
    /// Yaw, rad.
    pub yaw: f64,
    /// Pitch, rad.
    pub pitch: f64,
    /// Friction coefficient.
    pub friction: f64,
}

impl BoxModel {
    /// Orientation.
    pub fn rotation(&self) -> DQuat {
        DQuat::from_rotation_z(self.yaw) * DQuat::from_rotation_y(self.pitch)
    }
}

/// A horizontal cylinder (e.g. a stair nosing), compiled.
#[derive(Clone, Debug)]
pub struct CylinderModel {
    /// Centre, m.
    pub centre: DVec3,
    /// Yaw, rad: the axis is the y axis rotated by this about z.
    pub yaw: f64,
    /// Half length along the axis, m.
    pub half_length: f64,
    /// Radius, m.
    pub radius: f64,
    /// Friction coefficient.
    pub friction: f64,
}

/// A height field, compiled: a regular grid of heights in metres.
#[derive(Clone, Debug)]
pub struct HeightFieldModel {
    /// Centre of the grid (x, y; z is 0: heights are absolute), m.
    pub centre: DVec3,
    /// Rotation about z around the centre, rad.
    pub yaw: f64,
    /// Extent along the grid's x (columns), m.
    pub size_x: f64,
    /// Extent along the grid's y (rows), m.
    pub size_y: f64,
    /// Number of rows (vertices along y), at least 2.
    pub rows: usize,
    /// Number of columns (vertices along x), at least 2.
    pub cols: usize,
    /// Heights z, m, row-major (`heights[r * cols + c]`): row 0 at the +y edge, column 0 at
    /// the -x edge (before yaw).
    pub heights: Vec<f64>,
    /// Friction coefficient.
    pub friction: f64,
    /// The file it was read from (None for generated fields).
    pub source: Option<PathBuf>,
}

impl HeightFieldModel {
    /// World position of the grid vertex in row `r`, column `c`, m.
    pub fn vertex(&self, r: usize, c: usize) -> DVec3 {
        let lx = -0.5 * self.size_x + self.size_x * c as f64 / (self.cols - 1) as f64;
        let ly = 0.5 * self.size_y - self.size_y * r as f64 / (self.rows - 1) as f64;
        let p = DQuat::from_rotation_z(self.yaw) * DVec3::new(lx, ly, 0.0);
        DVec3::new(
            self.centre.x + p.x,
            self.centre.y + p.y,
            self.heights[r * self.cols + c],
        )
    }

    /// Rapier's pose for this field: Rapier height fields are y-up with rows along their z,
    /// so a +90 degree rotation about x takes their (x, height, z) to our (x, -z, height).
    fn pose(&self) -> DQuat {
        DQuat::from_rotation_z(self.yaw) * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2)
    }
}

/// A triangle mesh, compiled: vertices already transformed into the world, m.
#[derive(Clone, Debug)]
pub struct MeshModel {
    /// Vertices in world coordinates, m.
    pub vertices: Vec<DVec3>,
    /// Triangles (indices into `vertices`), degenerate ones removed.
    pub triangles: Vec<[u32; 3]>,
    /// Friction coefficient.
    pub friction: f64,
    /// The file it was read from.
    pub source: PathBuf,
}

/// The terrain, compiled: everything in SI units, files already read.
#[derive(Clone, Debug, Default)]
pub struct TerrainModel {
    /// Flat ground: (surface height m, friction).
    pub ground: Option<(f64, f64)>,
    /// Boxes (including those generated by staircases, inclines and test-method obstacles).
    pub boxes: Vec<BoxModel>,
    /// Cylinders (stair nosings).
    pub cylinders: Vec<CylinderModel>,
    /// Height fields (from PNG files and rough fields).
    pub heightfields: Vec<HeightFieldModel>,
    /// Triangle meshes (from STL / OBJ files).
    pub meshes: Vec<MeshModel>,
}

/// A local frame on the floor: origin and yaw.
struct Frame {
    origin: DVec3,
    yaw: f64,
}

impl Frame {
    fn new(x: f64, y: f64, z: f64, yaw_deg: f64) -> Self {
        Frame {
            origin: DVec3::new(x, y, z),
            yaw: yaw_deg.to_radians(),
        }
    }
    fn point(&self, p: DVec3) -> DVec3 {
        self.origin + DQuat::from_rotation_z(self.yaw) * p
    }
    /// An axis-aligned box (in this frame) from its min and max corners.
    fn aabb(&self, lo: DVec3, hi: DVec3, friction: f64) -> BoxModel {
        BoxModel {
            centre: self.point((lo + hi) * 0.5),
            half: (hi - lo) * 0.5,
            yaw: self.yaw,
            pitch: 0.0,
            friction,
        }
    }
    /// A sloped plate whose top surface starts at `low` (middle of its lower edge, local) and
    /// rises at `angle` rad along the local horizontal direction `dir_yaw` rad, over the
    /// slope length `ls`; `w` wide, `t` thick.
    #[allow(clippy::too_many_arguments)]
    fn plate(
        &self,
        low: DVec3,
        dir_yaw: f64,
        angle: f64,
        ls: f64,
        w: f64,
        t: f64,
        friction: f64,
    ) -> BoxModel {
        let d = DVec3::new(dir_yaw.cos(), dir_yaw.sin(), 0.0);
        let u = d * angle.cos() + DVec3::Z * angle.sin();
        let n = -d * angle.sin() + DVec3::Z * angle.cos();
        BoxModel {
            centre: self.point(low + u * (ls * 0.5) - n * (t * 0.5)),
            half: DVec3::new(ls * 0.5, w * 0.5, t * 0.5),
            yaw: self.yaw + dir_yaw,
            pitch: -angle,
            friction,
        }
    }
}

/// splitmix64 (Steele, Lea, Flood 2014): small, fast, and fixed here so that a seed always
/// gives the same numbers.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// Checks a place-and-yaw quadruple.
fn check_place(c: &mut Checker, k: &str, x: f64, y: f64, z: f64, yaw: f64) {
    c.finite(&format!("{k}.x_m"), &[x]);
    c.finite(&format!("{k}.y_m"), &[y]);
    c.finite(&format!("{k}.z_m"), &[z]);
    c.finite(&format!("{k}.yaw_deg"), &[yaw]);
}

fn check_angle(c: &mut Checker, key: &str, a: f64) {
    if !(a.is_finite() && a > 0.0 && a < 90.0) {
        c.push(
            key,
            format!("must be a finite angle with 0 < angle < 90 degrees, got {a}"),
        );
    }
}

fn check_count(c: &mut Checker, key: &str, n: u32, max: u32) {
    if n == 0 || n > max {
        c.push(
            key,
            format!("must be a whole number from 1 to {max}, got {n}"),
        );
    }
}

/// Largest number of grid vertices a height field may have (a 2000 x 2000 grid).
const MAX_GRID_VERTICES: usize = 4_000_000;
/// Largest number of boxes one generator may make.
const MAX_GENERATED_BOXES: usize = 100_000;

/// Compiles `[terrain]`; problems are appended to `issues` with their key paths. Files named
/// in the terrain are relative to `base_dir` (the scenario file's folder).
pub fn compile_terrain(
    spec: &TerrainSpec,
    base_dir: &Path,
    issues: &mut Vec<SpecIssue>,
) -> TerrainModel {
    let mut c = Checker::default();
    let mut terrain = TerrainModel::default();
    if let Some(g) = &spec.ground {
        c.non_negative("terrain.ground.friction", g.friction, "");
        c.finite("terrain.ground.z_m", &[g.z_m]);
        terrain.ground = Some((g.z_m, g.friction));
    }
    for (i, b) in spec.boxes.iter().enumerate() {
        let k = format!("terrain.boxes[{i}]");
        c.finite(&format!("{k}.centre_m"), &b.centre_m);
        for (j, s) in b.size_m.iter().enumerate() {
            c.positive(&format!("{k}.size_m[{j}]"), *s, "m");
        }
        c.finite(&format!("{k}.yaw_deg"), &[b.yaw_deg, b.pitch_deg]);
        c.non_negative(&format!("{k}.friction"), b.friction, "");
        terrain.boxes.push(BoxModel {
            centre: v3(b.centre_m),
            half: v3(b.size_m) * 0.5,
            yaw: b.yaw_deg.to_radians(),
            pitch: b.pitch_deg.to_radians(),
            friction: b.friction,
        });
    }
    for (i, s) in spec.staircases.iter().enumerate() {
        compile_staircase(&mut c, &format!("terrain.staircases[{i}]"), s, &mut terrain);
    }
    for (i, s) in spec.inclines.iter().enumerate() {
        let k = format!("terrain.inclines[{i}]");
        let n = c.issues.len();
        check_place(&mut c, &k, s.x_m, s.y_m, s.z_m, s.yaw_deg);
        check_angle(&mut c, &format!("{k}.angle_deg"), s.angle_deg);
        c.positive(&format!("{k}.length_m"), s.length_m, "m");
        c.positive(&format!("{k}.width_m"), s.width_m, "m");
        c.positive(&format!("{k}.thickness_m"), s.thickness_m, "m");
        c.non_negative(&format!("{k}.friction"), s.friction, "");
        if c.issues.len() == n {
            let fr = Frame::new(s.x_m, s.y_m, s.z_m, s.yaw_deg);
            terrain.boxes.push(fr.plate(
                DVec3::ZERO,
                0.0,
                s.angle_deg.to_radians(),
                s.length_m,
                s.width_m,
                s.thickness_m,
                s.friction,
            ));
        }
    }
    for (i, s) in spec.heightfields.iter().enumerate() {
        let k = format!("terrain.heightfields[{i}]");
        if let Some(h) = compile_png_field(&mut c, &k, s, base_dir) {
            terrain.heightfields.push(h);
        }
    }
    for (i, s) in spec.rough.iter().enumerate() {
        if let Some(h) = compile_rough(&mut c, &format!("terrain.rough[{i}]"), s) {
            terrain.heightfields.push(h);
        }
    }
    for (i, s) in spec.meshes.iter().enumerate() {
        if let Some(m) = compile_mesh(&mut c, &format!("terrain.meshes[{i}]"), s, base_dir) {
            terrain.meshes.push(m);
        }
    }
    for (i, s) in spec.stepfields.iter().enumerate() {
        compile_stepfield(&mut c, &format!("terrain.stepfields[{i}]"), s, &mut terrain);
    }
    for (i, s) in spec.pitch_roll_ramps.iter().enumerate() {
        compile_ramps(
            &mut c,
            &format!("terrain.pitch_roll_ramps[{i}]"),
            s,
            &mut terrain,
        );
    }
    for (i, s) in spec.hurdles.iter().enumerate() {
        let k = format!("terrain.hurdles[{i}]");
        let n = c.issues.len();
        check_place(&mut c, &k, s.x_m, s.y_m, s.z_m, s.yaw_deg);
        c.positive(&format!("{k}.height_m"), s.height_m, "m");
        c.positive(&format!("{k}.thickness_m"), s.thickness_m, "m");
        c.positive(&format!("{k}.width_m"), s.width_m, "m");
        c.non_negative(&format!("{k}.friction"), s.friction, "");
        if c.issues.len() == n {
            let fr = Frame::new(s.x_m, s.y_m, s.z_m, s.yaw_deg);
            terrain.boxes.push(fr.aabb(
                DVec3::new(0.0, -0.5 * s.width_m, 0.0),
                DVec3::new(s.thickness_m, 0.5 * s.width_m, s.height_m),
                s.friction,
            ));
        }
    }
    for (i, s) in spec.gaps.iter().enumerate() {
        let k = format!("terrain.gaps[{i}]");
        let n = c.issues.len();
        check_place(&mut c, &k, s.x_m, s.y_m, s.z_m, s.yaw_deg);
        c.positive(&format!("{k}.gap_width_m"), s.gap_width_m, "m");
        c.positive(&format!("{k}.height_m"), s.height_m, "m");
        c.positive(&format!("{k}.platform_length_m"), s.platform_length_m, "m");
        c.positive(&format!("{k}.width_m"), s.width_m, "m");
        c.non_negative(&format!("{k}.friction"), s.friction, "");
        if c.issues.len() == n {
            let fr = Frame::new(s.x_m, s.y_m, s.z_m, s.yaw_deg);
            let (l, g, hw) = (s.platform_length_m, s.gap_width_m, 0.5 * s.width_m);
            terrain.boxes.push(fr.aabb(
                DVec3::new(-l, -hw, 0.0),
                DVec3::new(0.0, hw, s.height_m),
                s.friction,
            ));
            terrain.boxes.push(fr.aabb(
                DVec3::new(g, -hw, 0.0),
                DVec3::new(g + l, hw, s.height_m),
                s.friction,
            ));
        }
    }
    let empty = terrain.ground.is_none()
        && terrain.boxes.is_empty()
        && terrain.cylinders.is_empty()
        && terrain.heightfields.is_empty()
        && terrain.meshes.is_empty();
    if empty && c.issues.is_empty() {
        c.push(
            "terrain",
            "nothing to drive on: add [terrain.ground] (flat ground), [[terrain.boxes]], \
             [[terrain.staircases]], [[terrain.inclines]], [[terrain.heightfields]], \
             [[terrain.rough]], [[terrain.meshes]] or a test obstacle ([[terrain.stepfields]], \
             [[terrain.pitch_roll_ramps]], [[terrain.hurdles]], [[terrain.gaps]])",
        );
    }
    issues.extend(c.issues);
    terrain
}

fn compile_staircase(c: &mut Checker, k: &str, s: &StaircaseSpec, t: &mut TerrainModel) {
    let n = c.issues.len();
    check_place(c, k, s.x_m, s.y_m, s.z_m, s.yaw_deg);
    c.positive(&format!("{k}.rise_m"), s.rise_m, "m");
    c.positive(&format!("{k}.run_m"), s.run_m, "m");
    c.positive(&format!("{k}.width_m"), s.width_m, "m");
    check_count(c, &format!("{k}.count"), s.count, 10_000);
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    let landing = s.landing_m.unwrap_or(0.0);
    c.non_negative(&format!("{k}.landing_m"), landing, "m");
    let r = s.nosing_radius_m.unwrap_or(0.0);
    if let Some(r) = s.nosing_radius_m {
        c.positive(&format!("{k}.nosing_radius_m"), r, "m");
        if r > s.rise_m.min(s.run_m) {
            c.push(
                format!("{k}.nosing_radius_m"),
                format!(
                    "must not exceed rise_m ({}) or run_m ({}), got {r}: make it smaller or \
                     leave it out for sharp edges",
                    s.rise_m, s.run_m
                ),
            );
        }
    }
    if c.issues.len() != n {
        return;
    }
    let fr = Frame::new(s.x_m, s.y_m, s.z_m, s.yaw_deg);
    let hw = 0.5 * s.width_m;
    for step in 1..=s.count {
        let front = (step - 1) as f64 * s.run_m;
        let depth = if step == s.count {
            s.run_m + landing
        } else {
            s.run_m
        };
        let top = step as f64 * s.rise_m;
        let back = front + depth;
        if r > 0.0 {
            t.boxes.push(fr.aabb(
                DVec3::new(front + r, -hw, 0.0),
                DVec3::new(back, hw, top),
                s.friction,
            ));
            if top - r > 1e-9 {
                t.boxes.push(fr.aabb(
                    DVec3::new(front, -hw, 0.0),
                    DVec3::new(front + r, hw, top - r),
                    s.friction,
                ));
            }
            t.cylinders.push(CylinderModel {
                centre: fr.point(DVec3::new(front + r, 0.0, top - r)),
                yaw: fr.yaw,
                half_length: hw,
                radius: r,
                friction: s.friction,
            });
        } else {
            t.boxes.push(fr.aabb(
                DVec3::new(front, -hw, 0.0),
                DVec3::new(back, hw, top),
                s.friction,
            ));
        }
    }
}

/// Reads a PNG height map: (columns, rows, values in [0, 1] row-major, row 0 = top row).
fn load_png(path: &Path) -> Result<(usize, usize, Vec<f64>), String> {
    let bytes = std::fs::read(path).map_err(|e| {
        format!(
            "cannot read {}: {e}; give the path of a greyscale PNG file relative to the \
             scenario's folder",
            path.display()
        )
    })?;
    let bad = |e: &dyn std::fmt::Display| {
        format!(
            "{} is not a readable PNG image ({e}); save the height map as an 8- or 16-bit \
             greyscale PNG",
            path.display()
        )
    };
    let mut dec = png::Decoder::new(std::io::Cursor::new(&bytes[..]));
    dec.set_transformations(png::Transformations::EXPAND);
    let mut reader = dec.read_info().map_err(|e| bad(&e))?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| bad(&"image too large"))?;
    let mut buf = vec![0u8; size];
    let info = reader.next_frame(&mut buf).map_err(|e| bad(&e))?;
    let channels = match info.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        other => {
            return Err(format!(
                "{} is a {other:?} PNG, but height maps must be greyscale: convert it to an 8- \
                 or 16-bit greyscale PNG (e.g. `convert in.png -colorspace Gray -depth 16 \
                 out.png`)",
                path.display()
            ));
        }
    };
    let (w, h) = (info.width as usize, info.height as usize);
    if w < 2 || h < 2 {
        return Err(format!(
            "{} is {w} x {h} pixels: a height map needs at least 2 x 2",
            path.display()
        ));
    }
    let mut out = Vec::with_capacity(w * h);
    for r in 0..h {
        let line = &buf[r * info.line_size..(r + 1) * info.line_size];
        for col in 0..w {
            let v = match info.bit_depth {
                png::BitDepth::Sixteen => {
                    let o = 2 * channels * col;
                    u16::from_be_bytes([line[o], line[o + 1]]) as f64 / 65535.0
                }
                png::BitDepth::Eight => line[channels * col] as f64 / 255.0,
                other => {
                    return Err(format!(
                        "{} has an unsupported bit depth {other:?}: save it as an 8- or 16-bit \
                         greyscale PNG",
                        path.display()
                    ));
                }
            };
            out.push(v);
        }
    }
    Ok((w, h, out))
}

fn compile_png_field(
    c: &mut Checker,
    k: &str,
    s: &HeightFieldSpec,
    base_dir: &Path,
) -> Option<HeightFieldModel> {
    let n = c.issues.len();
    c.positive(&format!("{k}.size_x_m"), s.size_x_m, "m");
    c.positive(&format!("{k}.size_y_m"), s.size_y_m, "m");
    c.finite(&format!("{k}.min_z_m"), &[s.min_z_m]);
    c.finite(&format!("{k}.max_z_m"), &[s.max_z_m]);
    if s.min_z_m.is_finite() && s.max_z_m.is_finite() && s.max_z_m < s.min_z_m {
        c.push(
            format!("{k}.max_z_m"),
            format!("must be >= min_z_m ({} m), got {} m", s.min_z_m, s.max_z_m),
        );
    }
    c.finite(&format!("{k}.centre_m"), &s.centre_m);
    c.finite(&format!("{k}.yaw_deg"), &[s.yaw_deg]);
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    let path = base_dir.join(&s.file);
    let img = match load_png(&path) {
        Ok(img) => Some(img),
        Err(msg) => {
            c.push(format!("{k}.file"), msg);
            None
        }
    };
    let (w, h, vals) = img?;
    if w * h > MAX_GRID_VERTICES {
        c.push(
            format!("{k}.file"),
            format!(
                "{} has {w} x {h} pixels, more than {MAX_GRID_VERTICES}: downsample it",
                path.display()
            ),
        );
    }
    if c.issues.len() != n {
        return None;
    }
    let span = s.max_z_m - s.min_z_m;
    Some(HeightFieldModel {
        centre: DVec3::new(s.centre_m[0], s.centre_m[1], 0.0),
        yaw: s.yaw_deg.to_radians(),
        size_x: s.size_x_m,
        size_y: s.size_y_m,
        rows: h,
        cols: w,
        heights: vals.iter().map(|v| s.min_z_m + span * v).collect(),
        friction: s.friction,
        source: Some(path),
    })
}

/// One pass of a centred moving average of width 2 * rad + 1 along rows (`along_rows`) or
/// columns of a `rows` x `cols` row-major grid, keeping only fully covered outputs: the
/// result is `rows` x (`cols` - 2 rad) (or (`rows` - 2 rad) x `cols`).
fn box_pass(
    g: &[f64],
    rows: usize,
    cols: usize,
    rad: usize,
    along_rows: bool,
) -> (Vec<f64>, usize, usize) {
    let w = 2 * rad + 1;
    let inv = 1.0 / w as f64;
    if along_rows {
        let oc = cols - 2 * rad;
        let mut out = vec![0.0; rows * oc];
        for r in 0..rows {
            let line = &g[r * cols..(r + 1) * cols];
            let mut sum: f64 = line[..w].iter().sum();
            out[r * oc] = sum * inv;
            for j in 1..oc {
                sum += line[j + w - 1] - line[j - 1];
                out[r * oc + j] = sum * inv;
            }
        }
        (out, rows, oc)
    } else {
        let or = rows - 2 * rad;
        let mut out = vec![0.0; or * cols];
        for col in 0..cols {
            let mut sum: f64 = (0..w).map(|r| g[r * cols + col]).sum();
            out[col] = sum * inv;
            for i in 1..or {
                sum += g[(i + w - 1) * cols + col] - g[(i - 1) * cols + col];
                out[i * cols + col] = sum * inv;
            }
        }
        (out, or, cols)
    }
}

fn compile_rough(c: &mut Checker, k: &str, s: &RoughSpec) -> Option<HeightFieldModel> {
    let n = c.issues.len();
    c.finite(&format!("{k}.centre_m"), &s.centre_m);
    c.positive(&format!("{k}.size_m[0]"), s.size_m[0], "m");
    c.positive(&format!("{k}.size_m[1]"), s.size_m[1], "m");
    c.positive(&format!("{k}.cell_m"), s.cell_m, "m");
    c.non_negative(&format!("{k}.correlation_m"), s.correlation_m, "m");
    c.finite(&format!("{k}.mean_z_m"), &[s.mean_z_m]);
    c.non_negative(&format!("{k}.edge_taper_m"), s.edge_taper_m, "m");
    c.finite(&format!("{k}.yaw_deg"), &[s.yaw_deg]);
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    match (s.rms_height_m, s.peak_height_m) {
        (Some(a), None) => c.positive(&format!("{k}.rms_height_m"), a, "m"),
        (None, Some(a)) => c.positive(&format!("{k}.peak_height_m"), a, "m"),
        _ => c.push(
            k,
            "give exactly one of rms_height_m (root-mean-square height, m) or peak_height_m \
             (largest height deviation, m)",
        ),
    }
    if c.issues.len() != n {
        return None;
    }
    let cols = (s.size_m[0] / s.cell_m).round().max(1.0) + 1.0;
    let rows = (s.size_m[1] / s.cell_m).round().max(1.0) + 1.0;
    let sigma = s.correlation_m / s.cell_m; // in cells
    // Three box filters of width w have variance 3 (w^2 - 1) / 12 = sigma^2.
    let rad_f = (((4.0 * sigma * sigma + 1.0).sqrt() - 1.0) * 0.5).round();
    let margin = 3.0 * rad_f;
    let total = (cols + 2.0 * margin) * (rows + 2.0 * margin);
    if total > MAX_GRID_VERTICES as f64 {
        c.push(
            k,
            format!(
                "the grid would need {total:.0} vertices (with the smoothing margin), more than \
                 {MAX_GRID_VERTICES}: increase cell_m, or reduce size_m or correlation_m"
            ),
        );
        return None;
    }
    let (cols, rows, rad) = (cols as usize, rows as usize, rad_f as usize);
    let (mut gc, mut gr) = (cols + 6 * rad, rows + 6 * rad);
    let mut rng = SplitMix64(s.seed);
    // Approximately normal noise (Irwin-Hall: sum of four uniforms), arithmetic only.
    let mut g: Vec<f64> = (0..gc * gr)
        .map(|_| rng.unit() + rng.unit() + rng.unit() + rng.unit() - 2.0)
        .collect();
    if rad > 0 {
        for along_rows in [true, false] {
            for _ in 0..3 {
                (g, gr, gc) = box_pass(&g, gr, gc, rad, along_rows);
            }
        }
    }
    debug_assert_eq!((gr, gc), (rows, cols));
    let mean = g.iter().sum::<f64>() / g.len() as f64;
    let (size_x, size_y) = (s.size_m[0], s.size_m[1]);
    let (dx, dy) = (size_x / (cols - 1) as f64, size_y / (rows - 1) as f64);
    for r in 0..rows {
        for col in 0..cols {
            let v = &mut g[r * cols + col];
            *v -= mean;
            if s.edge_taper_m > 0.0 {
                let ex = (col as f64 * dx).min((cols - 1 - col) as f64 * dx);
                let ey = (r as f64 * dy).min((rows - 1 - r) as f64 * dy);
                let u = (ex.min(ey) / s.edge_taper_m).min(1.0);
                *v *= u * u * (3.0 - 2.0 * u); // smoothstep
            }
        }
    }
    let measured = match s.rms_height_m {
        Some(_) => (g.iter().map(|v| v * v).sum::<f64>() / g.len() as f64).sqrt(),
        None => g.iter().fold(0.0f64, |m, v| m.max(v.abs())),
    };
    let wanted = s.rms_height_m.or(s.peak_height_m).unwrap_or(0.0);
    let factor = if measured > 0.0 {
        wanted / measured
    } else {
        0.0
    };
    Some(HeightFieldModel {
        centre: DVec3::new(s.centre_m[0], s.centre_m[1], 0.0),
        yaw: s.yaw_deg.to_radians(),
        size_x,
        size_y,
        rows,
        cols,
        heights: g.iter().map(|v| s.mean_z_m + v * factor).collect(),
        friction: s.friction,
        source: None,
    })
}

/// Triangles as read from a mesh file: vertices and index triples.
type RawMesh = (Vec<DVec3>, Vec<[u32; 3]>);

fn parse_f64(tok: Option<&str>, what: &str) -> Result<f64, String> {
    let t = tok.ok_or_else(|| format!("missing {what}"))?;
    t.parse::<f64>()
        .map_err(|_| format!("{what} {t:?} is not a number"))
}

/// Reads an STL file, binary or ASCII.
fn parse_stl(bytes: &[u8]) -> Result<RawMesh, String> {
    let binary_len = |b: &[u8]| {
        (b.len() >= 84).then(|| 84 + 50 * u32::from_le_bytes([b[80], b[81], b[82], b[83]]) as u64)
    };
    let is_binary = binary_len(bytes) == Some(bytes.len() as u64);
    let mut verts = Vec::new();
    if is_binary {
        let n = (bytes.len() - 84) / 50;
        for t in 0..n {
            let rec = &bytes[84 + 50 * t..84 + 50 * (t + 1)];
            for v in 0..3 {
                let o = 12 + 12 * v;
                let c = |i: usize| {
                    f32::from_le_bytes([
                        rec[o + 4 * i],
                        rec[o + 4 * i + 1],
                        rec[o + 4 * i + 2],
                        rec[o + 4 * i + 3],
                    ]) as f64
                };
                verts.push(DVec3::new(c(0), c(1), c(2)));
            }
        }
    } else {
        let text = std::str::from_utf8(bytes).map_err(|_| {
            "is neither a binary STL (its size does not match its triangle count) nor an ASCII \
             STL (not text)"
                .to_string()
        })?;
        if !text.trim_start().starts_with("solid") {
            return Err(
                "is neither a binary STL (its size does not match its triangle count) nor an \
                 ASCII STL (it does not start with `solid`)"
                    .into(),
            );
        }
        let mut toks = text.split_whitespace();
        while let Some(t) = toks.next() {
            if t == "vertex" {
                let x = parse_f64(toks.next(), "vertex x")?;
                let y = parse_f64(toks.next(), "vertex y")?;
                let z = parse_f64(toks.next(), "vertex z")?;
                verts.push(DVec3::new(x, y, z));
            }
        }
        if verts.len() % 3 != 0 {
            return Err(format!(
                "has {} vertices, not a multiple of 3: every facet needs 3 vertices",
                verts.len()
            ));
        }
    }
    let tris = (0..verts.len() as u32 / 3)
        .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
        .collect();
    Ok((verts, tris))
}

/// Reads the vertices (`v`) and faces (`f`, polygons fanned into triangles) of an OBJ file.
fn parse_obj(bytes: &[u8]) -> Result<RawMesh, String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "is not a text (OBJ) file".to_string())?;
    let mut verts = Vec::new();
    let mut tris = Vec::new();
    for (ln, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("");
        let mut toks = line.split_whitespace();
        let at = |e: String| format!("line {}: {e}", ln + 1);
        match toks.next() {
            Some("v") => {
                let x = parse_f64(toks.next(), "vertex x").map_err(at)?;
                let y = parse_f64(toks.next(), "vertex y").map_err(at)?;
                let z = parse_f64(toks.next(), "vertex z").map_err(at)?;
                verts.push(DVec3::new(x, y, z));
            }
            Some("f") => {
                let mut idx = Vec::new();
                for t in toks {
                    let first = t.split('/').next().unwrap_or("");
                    let i: i64 = first
                        .parse()
                        .map_err(|_| at(format!("face index {t:?} is not a number")))?;
                    let n = verts.len() as i64;
                    let j = if i > 0 { i - 1 } else { n + i };
                    if i == 0 || j < 0 || j >= n {
                        return Err(at(format!(
                            "face index {i} refers to no vertex ({n} defined so far)"
                        )));
                    }
                    idx.push(j as u32);
                }
                if idx.len() < 3 {
                    return Err(at("a face needs at least 3 vertices".into()));
                }
                for w in 1..idx.len() - 1 {
                    tris.push([idx[0], idx[w], idx[w + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok((verts, tris))
}

fn compile_mesh(c: &mut Checker, k: &str, s: &MeshSpec, base_dir: &Path) -> Option<MeshModel> {
    let n = c.issues.len();
    c.positive(&format!("{k}.scale"), s.scale, "");
    c.finite(&format!("{k}.translation_m"), &s.translation_m);
    c.finite(&format!("{k}.yaw_deg"), &[s.yaw_deg]);
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    let path = base_dir.join(&s.file);
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    let parser: fn(&[u8]) -> Result<RawMesh, String> = match ext.as_deref() {
        Some("stl") => parse_stl,
        Some("obj") => parse_obj,
        _ => {
            c.push(
                format!("{k}.file"),
                format!(
                    "{}: unsupported mesh format; give an .stl (binary or ASCII) or .obj file",
                    path.display()
                ),
            );
            return None;
        }
    };
    let bytes = match std::fs::read(&path) {
        Ok(b) => b,
        Err(e) => {
            c.push(
                format!("{k}.file"),
                format!(
                    "cannot read {}: {e}; give the path of an .stl or .obj file relative to the \
                     scenario's folder",
                    path.display()
                ),
            );
            return None;
        }
    };
    let (verts, tris) = match parser(&bytes) {
        Ok(m) => m,
        Err(e) => {
            c.push(
                format!("{k}.file"),
                format!("{} {e}; fix or re-export the mesh", path.display()),
            );
            return None;
        }
    };
    if let Some(i) = verts.iter().position(|v| !v.is_finite()) {
        c.push(
            format!("{k}.file"),
            format!(
                "{}: vertex {i} is not finite ({:?}); fix or re-export the mesh",
                path.display(),
                verts[i]
            ),
        );
    }
    if c.issues.len() != n {
        return None;
    }
    let rot = DQuat::from_rotation_z(s.yaw_deg.to_radians())
        * match s.up_axis {
            UpAxis::Z => DQuat::IDENTITY,
            UpAxis::Y => DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2),
        };
    let vertices: Vec<DVec3> = verts
        .iter()
        .map(|v| rot * (*v * s.scale) + v3(s.translation_m))
        .collect();
    let triangles: Vec<[u32; 3]> = tris
        .into_iter()
        .filter(|t| {
            let [a, b, cc] = t.map(|i| vertices[i as usize]);
            (b - a).cross(cc - a).length() > 1e-12
        })
        .collect();
    if triangles.is_empty() {
        c.push(
            format!("{k}.file"),
            format!(
                "{} has no triangles (or only degenerate ones): export the surface as a \
                 triangle mesh",
                path.display()
            ),
        );
        return None;
    }
    Some(MeshModel {
        vertices,
        triangles,
        friction: s.friction,
        source: path,
    })
}

/// The default symmetric stepfield pattern: a 12 x 12 diamond-shaped hill of 1 to 4 steps.
fn default_stepfield_pattern() -> Vec<Vec<u32>> {
    (0..12u32)
        .map(|r| {
            (0..12u32)
                .map(|col| 1 + (r.min(11 - r) + col.min(11 - col)) / 3)
                .collect()
        })
        .collect()
}

fn compile_stepfield(c: &mut Checker, k: &str, s: &StepfieldSpec, t: &mut TerrainModel) {
    let n = c.issues.len();
    check_place(c, k, s.x_m, s.y_m, s.z_m, s.yaw_deg);
    c.positive(&format!("{k}.post_m"), s.post_m, "m");
    c.positive(&format!("{k}.step_m"), s.step_m, "m");
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    let random = s.rows.is_some() || s.columns.is_some() || s.max_steps.is_some();
    let pattern = match (&s.pattern, s.seed) {
        (Some(_), Some(_)) => {
            c.push(
                format!("{k}.seed"),
                "give either pattern or seed (a random pattern), not both",
            );
            return;
        }
        (Some(_), None) if random => {
            c.push(
                format!("{k}.pattern"),
                "rows, columns and max_steps are for a random pattern (with seed): leave them \
                 out when giving a pattern",
            );
            return;
        }
        (Some(p), None) => {
            if p.is_empty() || p[0].is_empty() {
                c.push(
                    format!("{k}.pattern"),
                    "must be a non-empty list of non-empty rows, e.g. [[1, 2], [2, 1]]",
                );
                return;
            }
            for (r, row) in p.iter().enumerate() {
                if row.len() != p[0].len() {
                    c.push(
                        format!("{k}.pattern[{r}]"),
                        format!(
                            "has {} entries but row 0 has {}: all rows must be equally long",
                            row.len(),
                            p[0].len()
                        ),
                    );
                }
                for (col, v) in row.iter().enumerate() {
                    if *v > 1000 {
                        c.push(
                            format!("{k}.pattern[{r}][{col}]"),
                            format!("must be a number of steps from 0 to 1000, got {v}"),
                        );
                    }
                }
            }
            p.clone()
        }
        (None, Some(seed)) => {
            let rows = s.rows.unwrap_or(12);
            let cols = s.columns.unwrap_or(12);
            let max = s.max_steps.unwrap_or(4);
            check_count(c, &format!("{k}.rows"), rows, 1000);
            check_count(c, &format!("{k}.columns"), cols, 1000);
            check_count(c, &format!("{k}.max_steps"), max, 1000);
            if c.issues.len() != n {
                return;
            }
            let mut rng = SplitMix64(seed);
            (0..rows)
                .map(|_| {
                    (0..cols)
                        .map(|_| 1 + (rng.next_u64() % max as u64) as u32)
                        .collect()
                })
                .collect()
        }
        (None, None) if random => {
            c.push(
                format!("{k}.seed"),
                "rows, columns and max_steps describe a random pattern: give a seed too",
            );
            return;
        }
        (None, None) => default_stepfield_pattern(),
    };
    if pattern.len() * pattern[0].len() > MAX_GENERATED_BOXES {
        c.push(
            format!("{k}.pattern"),
            format!("more than {MAX_GENERATED_BOXES} posts: make the field smaller"),
        );
    }
    if c.issues.len() != n {
        return;
    }
    let fr = Frame::new(s.x_m, s.y_m, s.z_m, s.yaw_deg);
    let p = s.post_m;
    let y0 = 0.5 * p * pattern.len() as f64;
    for (r, row) in pattern.iter().enumerate() {
        for (col, &v) in row.iter().enumerate() {
            if v == 0 {
                continue;
            }
            let y_hi = y0 - r as f64 * p;
            t.boxes.push(fr.aabb(
                DVec3::new(col as f64 * p, y_hi - p, 0.0),
                DVec3::new((col + 1) as f64 * p, y_hi, v as f64 * s.step_m),
                s.friction,
            ));
        }
    }
}

fn compile_ramps(c: &mut Checker, k: &str, s: &PitchRollRampSpec, t: &mut TerrainModel) {
    let n = c.issues.len();
    check_place(c, k, s.x_m, s.y_m, s.z_m, s.yaw_deg);
    check_angle(c, &format!("{k}.angle_deg"), s.angle_deg);
    c.positive(&format!("{k}.panel_m"), s.panel_m, "m");
    check_count(c, &format!("{k}.count"), s.count, 1000);
    check_count(c, &format!("{k}.lanes"), s.lanes, 1000);
    c.positive(&format!("{k}.thickness_m"), s.thickness_m, "m");
    c.non_negative(&format!("{k}.friction"), s.friction, "");
    if c.issues.len() != n {
        return;
    }
    let fr = Frame::new(s.x_m, s.y_m, s.z_m, s.yaw_deg);
    let a = s.angle_deg.to_radians();
    let p = s.panel_m;
    let ls = p / a.cos();
    let half_w = 0.5 * p * s.lanes as f64;
    let len = p * s.count as f64;
    use std::f64::consts::{FRAC_PI_2, PI};
    match s.orientation {
        RampOrientation::Pitch => {
            for i in 0..s.count {
                let (low_x, dir) = if i % 2 == 0 {
                    (i as f64 * p, 0.0)
                } else {
                    ((i + 1) as f64 * p, PI)
                };
                let low = DVec3::new(low_x, 0.0, 0.0);
                t.boxes
                    .push(fr.plate(low, dir, a, ls, 2.0 * half_w, s.thickness_m, s.friction));
            }
        }
        RampOrientation::Roll => {
            for j in 0..s.lanes {
                // Lane j spans y in [half_w - (j + 1) p, half_w - j p].
                let (low_y, dir) = if j % 2 == 0 {
                    (half_w - (j + 1) as f64 * p, FRAC_PI_2)
                } else {
                    (half_w - j as f64 * p, -FRAC_PI_2)
                };
                let low = DVec3::new(0.5 * len, low_y, 0.0);
                t.boxes
                    .push(fr.plate(low, dir, a, ls, len, s.thickness_m, s.friction));
            }
        }
    }
}

use crate::check::{f, q};

/// Half-extent (x and y) of the flat-ground tile a simulation uses for `[terrain.ground]`, m.
///
/// An infinite plane (Rapier's half-space) has an infinite bounding box, so every collider of
/// the vehicle, the top runs' grousers included, is paired with it and goes through the narrow
/// phase every step. A finite box under the vehicle, re-centred as it drives (see
/// [`GROUND_RECENTRE_M`]), is the same flat surface for the vehicle and pairs only with what
/// is near it: measured +25 % real-time factor on the Table II case (BENCHMARKS.md). The tile
/// is kept small because the box-box contact loses f32 precision with large boxes (a 1 km
/// tile gave metre-deep spurious penetrations).
pub const GROUND_TILE_HALF_M: f64 = 10.0;
/// The ground tile is moved under the vehicle when the vehicle is this far (in x or y) from
/// the tile's centre, m: the vehicle always stays at least 6 m inside the tile.
pub const GROUND_RECENTRE_M: f64 = 4.0;
/// Thickness of the ground tile, m.
const GROUND_TILE_THICKNESS_M: f64 = 1.0;

impl TerrainModel {
    /// Inserts the terrain as colliders on one fixed body of `world`, in collision `groups`.
    /// `[terrain.ground]` becomes an infinite half-space, or, with `ground_tile`, a
    /// [`GROUND_TILE_HALF_M`] box on its own fixed body centred at (x, y) = `ground_tile`,
    /// whose handle is returned (move it with [`Self::recentre_ground_tile`]).
    pub fn insert_into(
        &self,
        world: &mut PhysicsWorld,
        groups: InteractionGroups,
        ground_tile: Option<(f64, f64)>,
    ) -> Option<RigidBodyHandle> {
        let fixed = world.bodies.insert(RigidBodyBuilder::fixed());
        let mut tile = None;
        if let Some((z, mu)) = self.ground {
            let c = match ground_tile {
                None => ColliderBuilder::new(SharedShape::halfspace(Vector::Z))
                    .translation(Vector::new(0.0, 0.0, z as f32)),
                Some(_) => ColliderBuilder::cuboid(
                    GROUND_TILE_HALF_M as f32,
                    GROUND_TILE_HALF_M as f32,
                    (GROUND_TILE_THICKNESS_M / 2.0) as f32,
                )
                .translation(Vector::new(
                    0.0,
                    0.0,
                    (z - GROUND_TILE_THICKNESS_M / 2.0) as f32,
                )),
            }
            .friction(mu as f32)
            .collision_groups(groups);
            let parent = match ground_tile {
                None => fixed,
                Some((x, y)) => {
                    let h = world.bodies.insert(
                        RigidBodyBuilder::fixed().translation(Vector::new(x as f32, y as f32, 0.0)),
                    );
                    tile = Some(h);
                    h
                }
            };
            world
                .colliders
                .insert_with_parent(c, parent, &mut world.bodies);
        }
        let mut add = |c: ColliderBuilder, friction: f64| {
            let c = c.friction(friction as f32).collision_groups(groups);
            world
                .colliders
                .insert_with_parent(c, fixed, &mut world.bodies);
        };
        for b in &self.boxes {
            add(
                ColliderBuilder::cuboid(b.half.x as f32, b.half.y as f32, b.half.z as f32)
                    .position(Pose::from_parts(f(b.centre), q(b.rotation()))),
                b.friction,
            );
        }
        for cy in &self.cylinders {
            // Rapier's cylinder axis is its local y.
            add(
                ColliderBuilder::cylinder(cy.half_length as f32, cy.radius as f32).position(
                    Pose::from_parts(f(cy.centre), q(DQuat::from_rotation_z(cy.yaw))),
                ),
                cy.friction,
            );
        }
        for h in &self.heightfields {
            // Rapier's grid is column-major, indexed [row (its z)][column (its x)].
            let mut data = vec![0.0f32; h.rows * h.cols];
            for r in 0..h.rows {
                for col in 0..h.cols {
                    data[r + col * h.rows] = h.heights[r * h.cols + col] as f32;
                }
            }
            add(
                ColliderBuilder::heightfield_with_flags(
                    Array2::new(h.rows, h.cols, data),
                    Vector::new(h.size_x as f32, 1.0, h.size_y as f32),
                    HeightFieldFlags::FIX_INTERNAL_EDGES,
                )
                .position(Pose::from_parts(f(h.centre), q(h.pose()))),
                h.friction,
            );
        }
        for m in &self.meshes {
            let verts = m.vertices.iter().map(|v| f(*v)).collect();
            // Cannot fail: compile_terrain keeps only meshes with triangles.
            if let Ok(b) = ColliderBuilder::trimesh_with_flags(
                verts,
                m.triangles.clone(),
                TriMeshFlags::FIX_INTERNAL_EDGES | TriMeshFlags::MERGE_DUPLICATE_VERTICES,
            ) {
                add(b, m.friction);
            }
        }
        tile
    }

    /// Moves the ground tile of [`Self::insert_into`] under (x, y) when that point is more than
    /// [`GROUND_RECENTRE_M`] from the tile's centre. The surface the vehicle touches does not
    /// change: same plane, same friction.
    pub fn recentre_ground_tile(world: &mut PhysicsWorld, tile: RigidBodyHandle, x: f64, y: f64) {
        let b = &world.bodies[tile];
        let c = b.translation();
        if (x - c.x as f64).abs() > GROUND_RECENTRE_M || (y - c.y as f64).abs() > GROUND_RECENTRE_M
        {
            let to = Vector::new(x.round() as f32, y.round() as f32, c.z);
            world.bodies[tile].set_translation(to, false);
        }
    }

    /// The extent of all finite surfaces: (min corner, max corner), m. x and y bound every
    /// box, cylinder, height field and mesh; z spans their lowest to highest points. `None`
    /// when there is an infinite ground plane (the terrain has no edge) or nothing at all.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        if self.ground.is_some() {
            return None;
        }
        self.finite_extent()
    }

    /// The extent of the finite surfaces (everything but the ground plane), m.
    fn finite_extent(&self) -> Option<(DVec3, DVec3)> {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        let mut grow = |p: DVec3| {
            lo = lo.min(p);
            hi = hi.max(p);
        };
        for b in &self.boxes {
            let rot = b.rotation();
            for i in 0..8 {
                let s = DVec3::new(
                    if i & 1 == 0 { -1.0 } else { 1.0 },
                    if i & 2 == 0 { -1.0 } else { 1.0 },
                    if i & 4 == 0 { -1.0 } else { 1.0 },
                );
                grow(b.centre + rot * (b.half * s));
            }
        }
        for cy in &self.cylinders {
            let axis = DQuat::from_rotation_z(cy.yaw) * DVec3::Y * cy.half_length;
            for e in [cy.centre + axis, cy.centre - axis] {
                grow(e - DVec3::splat(cy.radius));
                grow(e + DVec3::splat(cy.radius));
            }
        }
        for h in &self.heightfields {
            let (zmin, zmax) = h
                .heights
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| {
                    (a.min(*z), b.max(*z))
                });
            for (r, col) in [
                (0, 0),
                (0, h.cols - 1),
                (h.rows - 1, 0),
                (h.rows - 1, h.cols - 1),
            ] {
                let v = h.vertex(r, col);
                grow(DVec3::new(v.x, v.y, zmin));
                grow(DVec3::new(v.x, v.y, zmax));
            }
        }
        for m in &self.meshes {
            for t in &m.triangles {
                for i in t {
                    grow(m.vertices[*i as usize]);
                }
            }
        }
        lo.is_finite().then_some((lo, hi))
    }

    /// Height of the highest terrain surface at (x, y), m, found by a downward ray from just
    /// above the highest surface; `None` where there is nothing (off the terrain).
    pub fn height_at(&self, x: f64, y: f64) -> Option<f64> {
        self.heights_at(&[(x, y)])[0]
    }

    /// [`Self::height_at`] for many points at once (builds the terrain once), m.
    pub fn heights_at(&self, points: &[(f64, f64)]) -> Vec<Option<f64>> {
        let mut world = PhysicsWorld::new();
        self.insert_into(&mut world, InteractionGroups::all(), None);
        world.step_with_events(&(), &()); // no dynamic bodies: only updates the query structures
        // Rays start just above the highest surface: from far above, f32 rounding of the
        // shapes' rotations would be magnified by the distance.
        let (mut lo, mut hi) = self
            .finite_extent()
            .map_or((f64::INFINITY, f64::NEG_INFINITY), |(l, h)| (l.z, h.z));
        if let Some((z, _)) = self.ground {
            (lo, hi) = (lo.min(z), hi.max(z));
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return vec![None; points.len()];
        }
        let top = hi + 1.0;
        let reach = (top - lo + 1.0) as f32;
        points
            .iter()
            .map(|&(x, y)| {
                let ray = Ray::new(f(DVec3::new(x, y, top)), Vector::NEG_Z);
                world
                    .cast_ray(&ray, reach, true, QueryFilter::default())
                    .map(|(_, toi)| top - toi as f64)
            })
            .collect()
    }
}
