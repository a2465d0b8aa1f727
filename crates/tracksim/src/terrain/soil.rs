//! Deformable soil (issue 30): the soil's parameters, checked, with the published presets, and
//! the closed-form laws of terramechanics the contact model and the validation share. Pure
//! functions of SI values; the run-time state (ruts, shear displacement) is `world::soil`.
//!
//! - Bekker's pressure-sinkage law `p = (k_c / b + k_phi) z^n` (b: the smaller side of the
//!   loaded patch);
//! - Mohr-Coulomb shear strength `tau_max = c + p tan(phi)`;
//! - Janosi and Hanamoto's shear build-up `tau = tau_max (1 - exp(-j / K))`, `j` the shear
//!   displacement;
//! - elastic unloading and reloading along `K_e` below the largest sinkage reached (Chrono's
//!   SCM), so a rut keeps its depth and a second pass at the same load sinks no further;
//! - Rankine's passive earth pressure with a surcharge on a grouser face (Terzaghi);
//! - Wong's closed forms: the thrust of a track with uniform pressure and Bekker's compaction
//!   resistance.

use crate::check::Checker;
use crate::spec::SoilSpec;

/// Collider user data of a soil surface: [`SOIL_TAG`] | soil index.
pub const SOIL_TAG: u128 = 0x534f_494c << 64; // "SOIL"
/// Cells per side of a rut-grid tile.
pub const TILE_CELLS: usize = 64;

/// The user data tagging a terrain collider as soil number `index`.
pub fn soil_tag(index: usize) -> u128 {
    SOIL_TAG | index as u128
}

/// The soil index of a collider's user data, if it is tagged as soil.
pub fn tagged_soil(user_data: u128) -> Option<usize> {
    (user_data & !0xffff_ffff == SOIL_TAG).then_some((user_data & 0xffff_ffff) as usize)
}

/// A soil, compiled: SI units, angles in radians.
#[derive(Clone, Debug, PartialEq)]
pub struct SoilModel {
    /// The preset it started from, if any.
    pub preset: Option<String>,
    /// Bekker's sinkage exponent.
    pub n: f64,
    /// Bekker's cohesive modulus, N/m^(n+1).
    pub k_c: f64,
    /// Bekker's frictional modulus, N/m^(n+2).
    pub k_phi: f64,
    /// Cohesion, Pa.
    pub cohesion: f64,
    /// Angle of internal friction, rad.
    pub phi: f64,
    /// Janosi-Hanamoto shear deformation modulus, m.
    pub shear_k: f64,
    /// Elastic unloading stiffness, Pa/m.
    pub elastic_stiffness: f64,
    /// Damping of the normal response, Pa s/m.
    pub damping: f64,
    /// Bulk density, kg/m^3.
    pub density: f64,
    /// Friction angle of a smooth surface on the soil, rad.
    pub interface_phi: f64,
    /// Rut-grid cell side, m (1 / cell is a whole number).
    pub cell: f64,
    /// Largest number of rut-grid tiles kept.
    pub max_tiles: usize,
}

/// A published soil: its name, values (n, k_c, k_phi, c Pa, phi deg, K m, density kg/m^3)
/// and where they come from.
pub struct Preset {
    /// The name a file gives as `preset`.
    pub name: &'static str,
    /// n, k_c, k_phi, c (Pa), phi (deg), K (m), density (kg/m^3).
    pub values: [f64; 7],
    /// The source.
    pub source: &'static str,
}

/// The presets. Bekker and Mohr-Coulomb values as quoted by Project Chrono's SCM tests
/// (`test_WVP_softsoil_traction`, `SynSCMTerrainAgent.h`) from Wong, Theory of Ground
/// Vehicles; densities are typical values (not in those tables), used only by the grouser
/// faces' passive pressure.
pub const PRESETS: [Preset; 5] = [
    Preset {
        name: "dry_sand",
        values: [1.1, 0.99e3, 1528.43e3, 1.04e3, 28.0, 0.025, 1600.0],
        source: "Wong, Theory of Ground Vehicles (dry sand; K quoted as 0.01-0.025 m, the upper end taken)",
    },
    Preset {
        name: "lete_sand",
        values: [0.793, 102e3, 5301e3, 1.3e3, 31.1, 0.012, 1600.0],
        source: "LETE sand (Wong, Theory of Ground Vehicles; Chrono SCM tests)",
    },
    Preset {
        name: "clayey_soil",
        values: [0.5, 13.19e3, 692.15e3, 4.14e3, 13.0, 0.006, 1800.0],
        source: "Wong, Theory of Ground Vehicles (clayey soil)",
    },
    Preset {
        name: "lunar_regolith",
        values: [1.0, 1.4e3, 820e3, 0.17e3, 35.0, 0.018, 1500.0],
        source: "lunar regolith as used in rover studies (Chrono SCM tests)",
    },
    Preset {
        name: "snow",
        values: [1.1, 0.0, 0.2e6, 0.0, 30.0, 0.01, 400.0],
        source: "Project Chrono SCM's \"soft\" soil (snow-like)",
    },
];

/// SCM's elastic unloading stiffness in Chrono's vehicle demos, Pa/m (every preset).
pub const DEFAULT_ELASTIC_STIFFNESS_PA_PER_M: f64 = 2e8;
/// SCM's damping in Chrono's vehicle demos, Pa s/m (every preset).
pub const DEFAULT_DAMPING_PA_S_PER_M: f64 = 3e4;
/// Default rut-grid cell, m.
pub const DEFAULT_CELL_M: f64 = 0.01;
/// Default largest number of rut-grid tiles.
pub const DEFAULT_MAX_TILES: u32 = 512;
/// Acceleration of gravity the passive pressure uses, m/s^2 (the world's).
pub const GRAVITY_MPS2: f64 = 9.81;

/// Checks a `soil` table (key `k`, e.g. `terrain.ground.soil`) and compiles it.
pub(super) fn compile(c: &mut Checker, k: &str, s: &SoilSpec) -> Option<SoilModel> {
    let n0 = c.issues.len();
    let preset = match &s.preset {
        Some(name) => match PRESETS.iter().find(|p| p.name == name) {
            Some(p) => Some(p),
            None => {
                let known: Vec<&str> = PRESETS.iter().map(|p| p.name).collect();
                c.push(
                    format!("{k}.preset"),
                    crate::check::unknown_name("soil preset", name, &known),
                );
                return None;
            }
        },
        None => None,
    };
    let pv = |i: usize| preset.map(|p| p.values[i]);
    let mut take = |key: &str, given: Option<f64>, i: Option<usize>| -> f64 {
        match given.or(i.and_then(pv)) {
            Some(v) => v,
            None => {
                c.push(
                    format!("{k}.{key}"),
                    format!("missing: give {key}, or a preset (e.g. preset = \"dry_sand\")"),
                );
                f64::NAN
            }
        }
    };
    let n = take("n", s.n, Some(0));
    let k_c = take("k_c", s.k_c, Some(1));
    let k_phi = take("k_phi", s.k_phi, Some(2));
    let cohesion = take("cohesion_pa", s.cohesion_pa, Some(3));
    let phi_deg = take("friction_angle_deg", s.friction_angle_deg, Some(4));
    let shear_k = take("shear_modulus_m", s.shear_modulus_m, Some(5));
    let density = take("density_kg_per_m3", s.density_kg_per_m3, Some(6));
    if c.issues.len() > n0 {
        return None;
    }
    let ke = s
        .elastic_stiffness_pa_per_m
        .unwrap_or(DEFAULT_ELASTIC_STIFFNESS_PA_PER_M);
    let damping = s.damping_pa_s_per_m.unwrap_or(DEFAULT_DAMPING_PA_S_PER_M);
    let delta_deg = s
        .interface_friction_angle_deg
        .unwrap_or(phi_deg * 2.0 / 3.0);
    let cell = s.cell_m.unwrap_or(DEFAULT_CELL_M);
    let max_tiles = s.max_tiles.unwrap_or(DEFAULT_MAX_TILES);
    let mut range = |key: &str, v: f64, lo: f64, hi: f64, unit: &str| {
        if !(v.is_finite() && v >= lo && v <= hi) {
            c.push(
                format!("{k}.{key}"),
                format!("must be between {lo} and {hi}{unit}, got {v}"),
            );
        }
    };
    range("n", n, 0.1, 3.0, "");
    range("k_c", k_c, 0.0, 1e9, " N/m^(n+1)");
    range("k_phi", k_phi, 0.0, 1e12, " N/m^(n+2)");
    range("cohesion_pa", cohesion, 0.0, 1e6, " Pa");
    range("friction_angle_deg", phi_deg, 0.0, 60.0, " deg");
    range("shear_modulus_m", shear_k, 1e-4, 1.0, " m");
    range("elastic_stiffness_pa_per_m", ke, 1e4, 1e12, " Pa/m");
    range("damping_pa_s_per_m", damping, 0.0, 1e9, " Pa s/m");
    range("density_kg_per_m3", density, 1.0, 5000.0, " kg/m^3");
    range(
        "interface_friction_angle_deg",
        delta_deg,
        0.0,
        phi_deg.max(0.0),
        " deg (at most friction_angle_deg)",
    );
    range("cell_m", cell, 0.002, 0.1, " m");
    range("max_tiles", max_tiles as f64, 4.0, 65536.0, "");
    if k_c + k_phi <= 0.0 {
        c.push(
            format!("{k}.k_phi"),
            "k_c and k_phi are both 0: the soil would carry no load; give k_phi > 0",
        );
    }
    let per_m = 1.0 / cell;
    if cell.is_finite() && (per_m - per_m.round()).abs() > 1e-9 * per_m {
        c.push(
            format!("{k}.cell_m"),
            format!(
                "must divide a metre into whole cells (0.005, 0.01, 0.02, 0.025, ...), got {cell}"
            ),
        );
    }
    if c.issues.len() > n0 {
        return None;
    }
    Some(SoilModel {
        preset: s.preset.clone(),
        n,
        k_c,
        k_phi,
        cohesion,
        phi: phi_deg.to_radians(),
        shear_k,
        elastic_stiffness: ke,
        damping,
        density,
        interface_phi: delta_deg.to_radians(),
        cell: 1.0 / per_m.round(),
        max_tiles: max_tiles as usize,
    })
}

/// The preset `name` with the default elastic stiffness, damping, interface angle and grid
/// (None for an unknown name).
pub fn preset(name: &str) -> Option<SoilModel> {
    let spec = SoilSpec {
        preset: Some(name.into()),
        ..Default::default()
    };
    compile(&mut Checker::default(), "soil", &spec)
}

impl SoilModel {
    /// Cells per metre of the rut grid.
    pub fn cells_per_m(&self) -> i64 {
        (1.0 / self.cell).round() as i64
    }

    /// Bekker's modulus `k_c / b + k_phi` for a patch of smaller side `b` m, N/m^(n+2).
    pub fn modulus(&self, b: f64) -> f64 {
        self.k_c / b.max(1e-3) + self.k_phi
    }

    /// Bekker pressure at sinkage `z` m under a patch of smaller side `b` m, Pa.
    pub fn pressure(&self, z: f64, b: f64) -> f64 {
        self.modulus(b) * z.max(0.0).powf(self.n)
    }

    /// Bekker sinkage under pressure `p` Pa on a patch of smaller side `b` m, m.
    pub fn sinkage(&self, p: f64, b: f64) -> f64 {
        (p.max(0.0) / self.modulus(b)).powf(1.0 / self.n)
    }

    /// Sinkage under pressure `p` Pa (patch side `b` m) on soil already pressed to `z_max` m:
    /// below the pressure that reached `z_max` the soil answers elastically along `K_e`
    /// (unloading and reloading), above it plastically along Bekker's curve.
    pub fn loaded_sinkage(&self, p: f64, b: f64, z_max: f64) -> f64 {
        let p_max = self.pressure(z_max, b);
        if p >= p_max {
            self.sinkage(p, b)
        } else {
            (z_max - (p_max - p) / self.elastic_stiffness).max(0.0)
        }
    }

    /// The depth a rut pressed to `z_max` m under a patch of side `b` m keeps once unloaded
    /// (the elastic part springs back), m.
    pub fn rut_depth(&self, z_max: f64, b: f64) -> f64 {
        (z_max - self.pressure(z_max, b) / self.elastic_stiffness).max(0.0)
    }

    /// Work of pressing a unit area from sinkage `z0` to `z1` along Bekker's curve, J/m^2
    /// (`integral p dz`; 0 unless `z1 > z0`).
    pub fn compaction_work(&self, z0: f64, z1: f64, b: f64) -> f64 {
        if z1 <= z0 {
            return 0.0;
        }
        let e = self.n + 1.0;
        self.modulus(b) * (z1.powf(e) - z0.max(0.0).powf(e)) / e
    }

    /// Mohr-Coulomb shear strength under pressure `p` Pa, Pa.
    pub fn shear_strength(&self, p: f64) -> f64 {
        self.cohesion + p.max(0.0) * self.phi.tan()
    }

    /// Janosi-Hanamoto: the fraction of the shear strength mobilised at shear displacement
    /// `j` m, in [0, 1).
    pub fn mobilised(&self, j: f64) -> f64 {
        1.0 - (-j.abs() / self.shear_k).exp()
    }

    /// Rankine's passive earth pressure coefficient `N_phi = tan^2(45 deg + phi / 2)`.
    pub fn passive_coefficient(&self) -> f64 {
        (std::f64::consts::FRAC_PI_4 + 0.5 * self.phi).tan().powi(2)
    }

    /// Passive resistance of a vertical grouser face `h` m deep and `b` m wide under a
    /// surcharge `q` Pa (the track's pressure on the soil beside it), N (Rankine, with
    /// Terzaghi's cohesion and surcharge terms):
    /// `b (gamma h^2 N_phi / 2 + 2 c h sqrt(N_phi) + q h N_phi)`.
    pub fn passive_force(&self, h: f64, b: f64, q: f64) -> f64 {
        let np = self.passive_coefficient();
        let gamma = self.density * GRAVITY_MPS2;
        b * (0.5 * gamma * h * h * np + 2.0 * self.cohesion * h * np.sqrt() + q.max(0.0) * h * np)
    }

    /// Wong's thrust of a track with uniform pressure, N: contact area `area` m^2, load `w` N,
    /// contact length `l` m, slip `s` (0..1):
    /// `(A c + W tan phi) (1 - K / (s l) (1 - exp(-s l / K)))`.
    pub fn wong_thrust(&self, area: f64, w: f64, l: f64, s: f64) -> f64 {
        let f_max = area * self.cohesion + w * self.phi.tan();
        if s <= 0.0 {
            return 0.0;
        }
        let x = s * l / self.shear_k;
        f_max * (1.0 - (1.0 - (-x).exp()) / x)
    }

    /// Bekker's compaction resistance of one track of width `b` m sinking `z` m, N:
    /// `b (k_c / b + k_phi) z^(n+1) / (n + 1)`.
    pub fn compaction_resistance(&self, b: f64, z: f64) -> f64 {
        b * self.compaction_work(0.0, z, b)
    }

    /// Bytes of one rut-grid tile ([`TILE_CELLS`]^2 cells).
    pub fn tile_bytes() -> usize {
        TILE_CELLS * TILE_CELLS * std::mem::size_of::<[f32; 4]>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dry_sand() -> SoilModel {
        let mut c = Checker::default();
        let s = SoilSpec {
            preset: Some("dry_sand".into()),
            ..Default::default()
        };
        compile(&mut c, "soil", &s).unwrap()
    }

    #[test]
    fn bekker_round_trips_and_unloads_elastically() {
        let s = dry_sand();
        let b = 0.075;
        let z = s.sinkage(1700.0, b);
        assert!((s.pressure(z, b) - 1700.0).abs() < 1e-6);
        // Reloading below the largest pressure stays on the elastic line: shallower.
        let z2 = s.loaded_sinkage(800.0, b, z);
        assert!(z2 < z && z2 > z - 1700.0 / s.elastic_stiffness);
        // Above it, the virgin curve.
        assert_eq!(s.loaded_sinkage(3000.0, b, z), s.sinkage(3000.0, b));
    }

    #[test]
    fn wong_thrust_tends_to_the_mohr_coulomb_limit() {
        let s = dry_sand();
        let (a, w, l) = (0.04, 60.0, 0.5);
        let f_max = a * s.cohesion + w * s.phi.tan();
        let f1 = s.wong_thrust(a, w, l, 0.999);
        assert!(f1 < f_max && f1 > 0.9 * f_max);
        assert!(s.wong_thrust(a, w, l, 0.1) < s.wong_thrust(a, w, l, 0.3));
    }

    #[test]
    fn bad_values_name_their_key() {
        let mut c = Checker::default();
        let s = SoilSpec {
            preset: Some("dry_snad".into()),
            ..Default::default()
        };
        assert!(compile(&mut c, "terrain.ground.soil", &s).is_none());
        assert_eq!(c.issues[0].key, "terrain.ground.soil.preset");
        let mut c = Checker::default();
        let s = SoilSpec {
            preset: Some("dry_sand".into()),
            cell_m: Some(0.03),
            friction_angle_deg: Some(70.0),
            ..Default::default()
        };
        assert!(compile(&mut c, "g", &s).is_none());
        let keys: Vec<_> = c.issues.iter().map(|i| i.key.as_str()).collect();
        assert!(
            keys.contains(&"g.cell_m") && keys.contains(&"g.friction_angle_deg"),
            "{keys:?}"
        );
        let mut c = Checker::default();
        assert!(compile(&mut c, "g", &SoilSpec::default()).is_none());
        assert!(c.issues.iter().any(|i| i.key == "g.n"));
    }
}
