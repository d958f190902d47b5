//! Bearing characteristic (defect) frequencies from kinematics, eq. 37 and its companions.
//!
//! Outer ring fixed, inner ring turning at the shaft rate `f_r`, pure rolling, with
//! `g = (D / d_m) cos(alpha)`:
//!
//! | name | frequency |
//! | --- | --- |
//! | FTF (cage) | `f_r / 2 (1 - g)` |
//! | BPFO | `Z f_r / 2 (1 - g)` (eq. 37, `f_0`) |
//! | BPFI | `Z f_r / 2 (1 + g)` (eq. 37, `f_i`) |
//! | BSF | `d_m / (2 D) f_r (1 - g^2)` |
//! | 2xBSF | `2 BSF` (a ball defect strikes both races once per ball revolution) |

use serde::{Deserialize, Serialize};

/// The geometry the kinematic frequencies need.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct KinematicGeometry {
    /// Number of balls Z, -.
    pub ball_count: usize,
    /// Ball diameter D, m.
    pub ball_diameter: f64,
    /// Pitch diameter d_m, m.
    pub pitch_diameter: f64,
    /// Contact angle alpha, rad (nominal, or an actual running angle).
    pub contact_angle: f64,
}

impl KinematicGeometry {
    /// Geometry of a scene bearing, with the pitch diameter taken as the mean of bore and
    /// outside diameters, `d_m = (bore + OD) / 2`, as the paper does: for the H7005C
    /// (Z = 16, D = 5.556 mm, 25/47 mm -> d_m = 36.0 mm, 15 deg) at 10000 rpm this gives the
    /// paper's BPFO 1134.6 Hz and BPFI 1532.1 Hz. (The mean groove diameter, 35.9935 mm,
    /// would give 1134.53 / 1532.13 Hz.)
    pub fn from_bearing(b: &crate::scene::Bearing) -> Self {
        KinematicGeometry {
            ball_count: b.ball_count,
            ball_diameter: b.ball_diameter,
            pitch_diameter: 0.5 * (b.bore_diameter + b.outer_diameter),
            contact_angle: b.contact_angle,
        }
    }

    /// The same bearing at another (e.g. measured or simulated running) contact angle, rad.
    pub fn with_contact_angle(self, contact_angle: f64) -> Self {
        KinematicGeometry {
            contact_angle,
            ..self
        }
    }

    /// Check that the numbers describe a ball bearing; the error names the offending field.
    pub fn validate(&self) -> Result<(), (&'static str, String)> {
        if self.ball_count == 0 {
            return Err(("ball_count", "must be >= 1".into()));
        }
        if !(self.ball_diameter.is_finite() && self.ball_diameter > 0.0) {
            return Err((
                "ball_diameter",
                format!("must be a finite length > 0 m (got {})", self.ball_diameter),
            ));
        }
        if !(self.pitch_diameter.is_finite() && self.pitch_diameter > self.ball_diameter) {
            return Err((
                "pitch_diameter",
                format!(
                    "must be > ball_diameter = {} m (got {})",
                    self.ball_diameter, self.pitch_diameter
                ),
            ));
        }
        if !(self.contact_angle.is_finite()
            && (0.0..std::f64::consts::FRAC_PI_2).contains(&self.contact_angle))
        {
            return Err((
                "contact_angle",
                format!("must be in [0, pi/2) rad (got {})", self.contact_angle),
            ));
        }
        Ok(())
    }
}

/// Names accepted by [`kinematic_preset`].
pub fn kinematic_preset_names() -> &'static [&'static str] {
    &["h7005c", "cwru6205"]
}

/// A built-in bearing geometry (case-insensitive name):
///
/// - `h7005c`: the paper's spindle bearing (Table 1), via [`KinematicGeometry::from_bearing`];
/// - `cwru6205`: the CWRU drive-end 6205-2RS JEM SKF: 9 balls, D = 0.3126 in,
///   d_m = 1.537 in, 0 deg (CWRU data centre geometry).
pub fn kinematic_preset(name: &str) -> Option<KinematicGeometry> {
    const INCH: f64 = 0.0254;
    match name.to_ascii_lowercase().as_str() {
        "h7005c" => crate::scene::preset_scene("h7005c")
            .map(|s| KinematicGeometry::from_bearing(&s.bearing)),
        "cwru6205" => Some(KinematicGeometry {
            ball_count: 9,
            ball_diameter: 0.3126 * INCH,
            pitch_diameter: 1.537 * INCH,
            contact_angle: 0.0,
        }),
        _ => None,
    }
}

/// Characteristic frequencies, all Hz.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct CharacteristicFrequencies {
    /// Shaft (inner ring) rotation frequency, Hz.
    pub shaft_hz: f64,
    /// Ball pass frequency, outer race, Hz.
    pub bpfo: f64,
    /// Ball pass frequency, inner race, Hz.
    pub bpfi: f64,
    /// Fundamental train (cage) frequency, Hz.
    pub ftf: f64,
    /// Ball spin frequency, Hz.
    pub bsf: f64,
    /// Twice the ball spin frequency (ball defect hitting both races), Hz.
    pub bsf2: f64,
}

impl CharacteristicFrequencies {
    /// `(name, frequency in Hz)` in report order: BPFO, BPFI, FTF, BSF, 2xBSF.
    pub fn named(&self) -> [(&'static str, f64); 5] {
        [
            ("BPFO", self.bpfo),
            ("BPFI", self.bpfi),
            ("FTF", self.ftf),
            ("BSF", self.bsf),
            ("2xBSF", self.bsf2),
        ]
    }
}

/// Characteristic frequencies of `g` at shaft frequency `shaft_hz` (Hz), using `g.contact_angle`
/// (pass `g.with_contact_angle(actual)` for a running angle other than the nominal one).
pub fn characteristic_frequencies(
    g: &KinematicGeometry,
    shaft_hz: f64,
) -> CharacteristicFrequencies {
    let ratio = g.ball_diameter / g.pitch_diameter * g.contact_angle.cos();
    let z = g.ball_count as f64;
    let ftf = 0.5 * shaft_hz * (1.0 - ratio);
    let bsf = g.pitch_diameter / (2.0 * g.ball_diameter) * shaft_hz * (1.0 - ratio * ratio);
    CharacteristicFrequencies {
        shaft_hz,
        bpfo: z * ftf,
        bpfi: 0.5 * z * shaft_hz * (1.0 + ratio),
        ftf,
        bsf,
        bsf2: 2.0 * bsf,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn h7005c_matches_the_paper_at_10000_rpm() {
        let g = kinematic_preset("H7005C").unwrap();
        assert_eq!(g.ball_count, 16);
        assert!((g.pitch_diameter - 36.0e-3).abs() < 1e-12);
        let f = characteristic_frequencies(&g, 10_000.0 / 60.0);
        // The paper quotes one decimal: 1134.6 / 1532.1 Hz, so +/- 0.05 Hz.
        assert!((f.bpfo - 1134.6).abs() < 0.05, "BPFO {}", f.bpfo);
        assert!((f.bpfi - 1532.1).abs() < 0.05, "BPFI {}", f.bpfi);
        // identities: BPFO + BPFI = Z f_r, BPFO = Z FTF
        assert!((f.bpfo + f.bpfi - 16.0 * f.shaft_hz).abs() < 1e-9);
        assert!((f.bpfo - 16.0 * f.ftf).abs() < 1e-9);
    }

    #[test]
    fn cwru_multipliers_match_the_data_centre_table() {
        let g = kinematic_preset("cwru6205").unwrap();
        let f = characteristic_frequencies(&g, 1.0);
        // CWRU publishes 4-5 significant figures: BPFI 5.4152, BPFO 3.5848, FTF 0.39828,
        // BSF 2.357 (2xBSF 4.7135); 1e-4 relative covers the published rounding.
        for (got, want) in [
            (f.bpfi, 5.4152),
            (f.bpfo, 3.5848),
            (f.ftf, 0.39828),
            (f.bsf2, 4.7135),
        ] {
            assert!(((got - want) / want).abs() < 1e-4, "{got} vs {want}");
        }
    }

    #[test]
    fn actual_contact_angle_moves_the_frequencies() {
        let g = kinematic_preset("h7005c").unwrap();
        let nominal = characteristic_frequencies(&g, 100.0);
        let loaded = characteristic_frequencies(&g.with_contact_angle(25f64.to_radians()), 100.0);
        // a larger contact angle shortens the effective ball lever: BPFO up, BPFI down
        assert!(loaded.bpfo > nominal.bpfo && loaded.bpfi < nominal.bpfi);
        assert!(kinematic_preset("nope").is_none());
        assert!(kinematic_preset_names()
            .iter()
            .all(|n| kinematic_preset(n).is_some()));
    }
}
