//! What the soil reports: per track (`TrackSoil`) and per rut cell (`RutCell`).

/// What one track does in the soil over the last step.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TrackSoil {
    /// Mean sinkage of the track's loaded patches weighted by their load (belt level below the
    /// undisturbed surface), m; 0 off soil.
    pub sinkage_m: f64,
    /// Largest sinkage of a loaded patch, m.
    pub max_sinkage_m: f64,
    /// The soil's normal load on the track, N.
    pub normal_n: f64,
    /// The soil's shear force on the track along the chassis's forward axis, N (its thrust).
    pub thrust_n: f64,
    /// Compaction resistance given back this step, N (work of compacting fresh soil over the
    /// distance driven).
    pub compaction_n: f64,
    /// Area of the loaded patches, m^2 (the contact area `A` of Wong's thrust).
    pub contact_area_m2: f64,
    /// Length of ground the loaded patches span along the chassis's x, m (Wong's `l`).
    pub contact_length_m: f64,
}

/// A loaded soil cell, in world coordinates.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct RutCell {
    /// Index of the soil.
    pub soil: usize,
    /// Cell centre x, m.
    pub x_m: f64,
    /// Cell centre y, m.
    pub y_m: f64,
    /// Height of the undisturbed surface there, m (the terrain's top).
    pub surface_z_m: f64,
    /// Cell side, m.
    pub cell_m: f64,
    /// Largest sinkage the cell was pressed to (the rut's depth; the elastic rebound,
    /// `p / K_e`, is below a tenth of a millimetre for the presets), m.
    pub depth_m: f64,
    /// Time the cell was first loaded, s.
    pub t_s: f64,
}
