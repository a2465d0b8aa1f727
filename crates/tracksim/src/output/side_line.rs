//! The polyline of the side view ([`SideLine`]), shared by the vehicle outline, the plots and
//! the terrain drawn under runs (its own file so that they import it downward).

/// A polyline in the side view: (x, z) points, m.
pub type SideLine = Vec<(f64, f64)>;
