//! Terrain descriptions (a scenario's `[terrain]` table): the serde structs of every terrain
//! kind, with their serde defaults. Unknown keys are rejected. Heights are z-up, x forward,
//! y left (REP 103); units are SI unless the key name says otherwise (`yaw_deg`).
//!
//! Obstacles placed by a start point and a yaw (`x_m`, `y_m`, `z_m`, `yaw_deg`) are described
//! in their own frame: local x is the direction of travel (rotated by `yaw_deg` about z from
//! the world x axis), local y to its left, and `z_m` the floor height they stand on.
//!
//! Grid convention (PNG height maps, rough fields, stepfield patterns): a grid is seen from
//! above as an image with north up, i.e. row 0 is the +y edge (rows run towards -y) and
//! column 0 the -x edge (columns run towards +x), before any yaw.
//!
//! These structs are only a description; `crate::terrain` checks and compiles them.

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

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
    /// Conveyors: tracks fixed in the world (compiled by the model layer).
    #[serde(default)]
    pub conveyors: Vec<super::ConveyorSpec>,
    /// Loose boxes: free bodies (compiled by the model layer).
    #[serde(default)]
    pub loose_boxes: Vec<super::LooseBoxSpec>,
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
    /// Deformable soil (`[terrain.ground.soil]`): the ground sinks, shears and keeps ruts
    /// (docs/SOIL.md). Absent: rigid.
    #[serde(default)]
    pub soil: Option<SoilSpec>,
    /// Colour in camera images, `"#rrggbb"` (default: the kind's colour, `render::palette`).
    #[serde(default)]
    pub color: Option<String>,
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
    /// Deformable soil on this surface (docs/SOIL.md). Absent: rigid.
    #[serde(default)]
    pub soil: Option<SoilSpec>,
    /// Colour in camera images, `"#rrggbb"` (default: the kind's colour, `render::palette`).
    #[serde(default)]
    pub color: Option<String>,
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
    /// Colour in camera images, `"#rrggbb"` (default: the kind's colour, `render::palette`).
    #[serde(default)]
    pub color: Option<String>,
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
    /// Deformable soil on this surface (docs/SOIL.md). Absent: rigid.
    #[serde(default)]
    pub soil: Option<SoilSpec>,
    /// Colour in camera images, `"#rrggbb"` (default: the kind's colour, `render::palette`).
    #[serde(default)]
    pub color: Option<String>,
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
    /// Colour in camera images, `"#rrggbb"` (default: the kind's colour, `render::palette`).
    #[serde(default)]
    pub color: Option<String>,
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
    /// Colour in camera images, `"#rrggbb"` (default: the kind's colour, `render::palette`).
    #[serde(default)]
    pub color: Option<String>,
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
    /// Colour in camera images, `"#rrggbb"` (default: the kind's colour, `render::palette`).
    #[serde(default)]
    pub color: Option<String>,
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
    /// Colour in camera images, `"#rrggbb"` (default: the kind's colour, `render::palette`).
    #[serde(default)]
    pub color: Option<String>,
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
    /// Colour in camera images, `"#rrggbb"` (default: the kind's colour, `render::palette`).
    #[serde(default)]
    pub color: Option<String>,
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
    /// Colour in camera images, `"#rrggbb"` (default: the kind's colour, `render::palette`).
    #[serde(default)]
    pub color: Option<String>,
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
    /// Colour in camera images, `"#rrggbb"` (default: the kind's colour, `render::palette`).
    #[serde(default)]
    pub color: Option<String>,
}

/// Deformable soil (issue 30): Bekker's pressure-sinkage law, the Mohr-Coulomb shear strength
/// built up by Janosi and Hanamoto's shear-displacement law, elastic unloading, and ruts kept
/// in a bounded grid. `preset` names a published parameter set (docs/SOIL.md lists them with
/// their sources); every other key overrides one value of it. Without a preset every Bekker
/// and Mohr-Coulomb key must be given.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SoilSpec {
    /// A published parameter set: "dry_sand", "lete_sand", "clayey_soil", "lunar_regolith",
    /// "snow".
    #[serde(default)]
    pub preset: Option<String>,
    /// Bekker's sinkage exponent `n` (dimensionless).
    #[serde(default)]
    pub n: Option<f64>,
    /// Bekker's cohesive modulus `k_c`, N/m^(n+1).
    #[serde(default)]
    pub k_c: Option<f64>,
    /// Bekker's frictional modulus `k_phi`, N/m^(n+2).
    #[serde(default)]
    pub k_phi: Option<f64>,
    /// Cohesion `c`, Pa.
    #[serde(default)]
    pub cohesion_pa: Option<f64>,
    /// Angle of internal friction `phi`, degrees.
    #[serde(default)]
    pub friction_angle_deg: Option<f64>,
    /// Janosi-Hanamoto shear deformation modulus `K`, m.
    #[serde(default)]
    pub shear_modulus_m: Option<f64>,
    /// Elastic unloading and reloading stiffness `K_e`, Pa/m (SCM's elastic stiffness).
    #[serde(default)]
    pub elastic_stiffness_pa_per_m: Option<f64>,
    /// Damping of the soil's normal response `R`, Pa s/m (SCM's damping).
    #[serde(default)]
    pub damping_pa_s_per_m: Option<f64>,
    /// Bulk density, kg/m^3 (the passive earth pressure on grouser faces).
    #[serde(default)]
    pub density_kg_per_m3: Option<f64>,
    /// Friction angle between a smooth surface (a belt without grousers, a hull) and the soil,
    /// degrees (default two thirds of `friction_angle_deg`).
    #[serde(default)]
    pub interface_friction_angle_deg: Option<f64>,
    /// Side of a cell of the rut grid, m (default 0.01; a whole number of cells per metre).
    #[serde(default)]
    pub cell_m: Option<f64>,
    /// Most tiles of 64 x 64 cells the rut grid keeps; the least recently touched is forgotten
    /// first (default 512).
    #[serde(default)]
    pub max_tiles: Option<u32>,
}
