//! Localized raceway defects (eqs. 33-36, Figure 8).
//!
//! A ball over a pit of width `w` (along the raceway) sinks until it rests on the pit's
//! edges or its bottom. Resting on an edge at horizontal distance `d` from the ball
//! centre, the drop is `R - sqrt(R^2 - d^2)` with `R` the relative radius of ball and
//! race in the rolling direction (ball curvature against race curvature: a convex inner
//! race lets the ball sink deeper than a concave outer race). The nearer edge governs,
//! so the drop rises from zero at an edge to its maximum at the centre: continuous, and
//! never more than the geometry allows nor than the depth. While the ball bears on an
//! edge, the contact load points from the edge to the ball centre: it is tilted in the
//! rolling plane by `psi`, `sin(psi) = d / r_ball` (eq. 36).

use super::frames::Azimuth;

/// A defect on one raceway, in that ring's body frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RaceDefect {
    /// Azimuth of the defect centre in the ring body frame, rad.
    pub angle: f64,
    /// Half the defect's angular extent on the contact path, rad (theta_e of eq. 33).
    pub half_angle: f64,
    /// Width along the raceway, m.
    pub width: f64,
    /// Depth, m.
    pub depth: f64,
    /// `angle` as sine and cosine, and the cosine of `half_angle`: a ball is over the
    /// defect when the cosine of its distance exceeds it, so the test needs no atan2.
    pub azimuth: Azimuth,
    pub cos_half: f64,
}

impl RaceDefect {
    /// A defect centred at `angle` (rad) of `width` and `depth` (m) on a contact path of
    /// radius `path_radius` (m).
    pub fn new(angle: f64, width: f64, depth: f64, path_radius: f64) -> RaceDefect {
        let half_angle = 0.5 * width / path_radius;
        RaceDefect {
            angle,
            half_angle,
            width,
            depth,
            azimuth: Azimuth::new(angle),
            cos_half: half_angle.cos(),
        }
    }
}

/// Effect of a defect on one contact.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DefectEffect {
    /// Reduction of the contact deformation, m (eq. 34).
    pub drop: f64,
    /// Tilt of the load direction in the rolling plane, rad (eq. 36); its sign is that of
    /// the tangential force on the ball along +e_t.
    pub psi: f64,
}

/// `a % TAU` to the bit, without the remainder's `fmod` loop (about 100 instructions; a
/// ball and defect at every step and a ball at every averaged step made it 1.4 % of the
/// Table-1 case's instructions). `fmod`'s result is exact, so with the right quotient `q`
/// the fused `a - q TAU` (one rounding of an exactly representable value) is that result;
/// the quotient from the rounded `a / TAU` is off by one at most, next to a multiple of
/// `TAU`, which the range check corrects. Zero keeps `a`'s sign, as `fmod`'s does.
#[inline]
pub fn rem_turn(a: f64) -> f64 {
    use std::f64::consts::TAU;
    if !a.is_finite() || a.abs() >= 1e15 {
        // where the quotient loses integers, and NaN or infinity: as `fmod`
        return a % TAU;
    }
    let mut q = (a / TAU).trunc();
    let mut r = (-q).mul_add(TAU, a);
    // the result lies in [0, TAU) for positive `a`, (-TAU, 0] for negative
    if a >= 0.0 {
        if r < 0.0 {
            q -= 1.0;
            r = (-q).mul_add(TAU, a);
        } else if r >= TAU {
            q += 1.0;
            r = (-q).mul_add(TAU, a);
        }
    } else if r > 0.0 {
        q += 1.0;
        r = (-q).mul_add(TAU, a);
    } else if r <= -TAU {
        q -= 1.0;
        r = (-q).mul_add(TAU, a);
    }
    if r == 0.0 {
        0.0_f64.copysign(a)
    } else {
        r
    }
}

/// Wrap an angle to (-pi, pi].
#[inline]
pub fn wrap_angle(a: f64) -> f64 {
    let two_pi = std::f64::consts::TAU;
    let mut x = rem_turn(a);
    if x > std::f64::consts::PI {
        x -= two_pi;
    } else if x <= -std::f64::consts::PI {
        x += two_pi;
    }
    x
}

/// Drop and load tilt for a ball whose contact sits `s` metres (arc length, signed along
/// +e_t) from the defect centre. `rx`: relative rolling radius, m; `ball_radius`, m.
#[inline]
pub fn defect_effect(s: f64, width: f64, depth: f64, rx: f64, ball_radius: f64) -> DefectEffect {
    let half = 0.5 * width;
    if s.abs() >= half {
        return DefectEffect::default();
    }
    let d = half - s.abs();
    let geometric = rx - (rx * rx - d * d).max(0.0).sqrt();
    if geometric >= depth {
        // rests on the bottom: load stays normal
        DefectEffect {
            drop: depth,
            psi: 0.0,
        }
    } else {
        // rests on the nearer edge; it pushes the ball away from itself
        let psi = (d / ball_radius).min(1.0).asin();
        DefectEffect {
            drop: geometric,
            psi: -s.signum() * psi,
        }
    }
}

/// Combined effect of every defect of a race on a ball at ring-frame azimuth `body`
/// (already relative to the ring's spin), contact-path radius `r_path`.
#[inline]
pub fn race_defects_effect(
    defects: &[RaceDefect],
    body: &Azimuth,
    r_path: f64,
    rx: f64,
    ball_radius: f64,
) -> DefectEffect {
    let mut out = DefectEffect::default();
    for d in defects {
        let rel = body.minus(&d.azimuth);
        // |distance| < half angle (< pi/2 for any defect a ball fits in)
        if rel.cos > d.cos_half {
            let dtheta = rel.angle();
            let e = defect_effect(dtheta * r_path, d.width, d.depth, rx, ball_radius);
            if e.drop > out.drop {
                out = e;
            }
        }
    }
    out
}

/// Maximum drop a ball can make into a defect of `width` (at its centre), m.
pub fn max_drop(width: f64, depth: f64, rx: f64) -> f64 {
    let h = 0.5 * width;
    (rx - (rx * rx - h * h).max(0.0).sqrt()).min(depth)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outer_defect_drop_is_geometry_limited() {
        // Engineering notes: 0.5 mm outer defect on the H7005C limits the drop to ~10 um.
        let d = 5.556e-3;
        let gamma = d * 15f64.to_radians().cos() / 35.9935e-3;
        let rx_o = 0.5 * d * (1.0 + gamma);
        let h = max_drop(0.5e-3, 0.1e-3, rx_o);
        assert!((h - 9.8e-6).abs() < 0.3e-6, "{h}");
        // inner race (convex) lets the ball sink deeper than the outer for the same width
        let rx_i = 0.5 * d * (1.0 - gamma);
        assert!(max_drop(0.2e-3, 0.1e-3, rx_i) > max_drop(0.2e-3, 0.1e-3, rx_o));
        // a shallow pit limits by depth
        assert_eq!(max_drop(0.5e-3, 1e-6, rx_o), 1e-6);
    }

    #[test]
    fn profile_is_continuous_and_load_turns_at_the_edges() {
        let (w, h, rx, rb) = (0.2e-3, 0.1e-3, 3.2e-3, 2.778e-3);
        assert_eq!(defect_effect(0.1e-3, w, h, rx, rb).drop, 0.0);
        let just_in = defect_effect(0.1e-3 - 1e-9, w, h, rx, rb);
        assert!(just_in.drop < 1e-12);
        // entering (s < 0): pushed forward (+e_t); leaving (s > 0): pushed back
        assert!(defect_effect(-0.05e-3, w, h, rx, rb).psi > 0.0);
        assert!(defect_effect(0.05e-3, w, h, rx, rb).psi < 0.0);
        let centre = defect_effect(0.0, w, h, rx, rb);
        assert!((centre.drop - max_drop(w, h, rx)).abs() < 1e-15);
        assert!((wrap_angle(3.0 * std::f64::consts::PI) - std::f64::consts::PI).abs() < 1e-12);
    }

    /// `rem_turn` is `%` by a turn to the bit: both zeros, the multiples of a turn and
    /// their neighbours (where the rounded quotient is off by one), a spread up to the
    /// angles long runs reach, and the range past the fused form.
    #[test]
    fn rem_turn_is_the_remainder_to_the_bit() {
        use std::f64::consts::TAU;
        let mut xs = vec![
            0.0,
            -0.0,
            f64::MIN_POSITIVE,
            1e15,
            3e16,
            f64::INFINITY,
            f64::NAN,
        ];
        for k in 1..5000 {
            let m = TAU * k as f64;
            for d in -3i64..=3 {
                xs.push(f64::from_bits((m.to_bits() as i64 + d) as u64));
            }
        }
        let mut x = 1e-12;
        while x < 1e9 {
            xs.extend([x, x * 1.000_000_7, x * 3.3]);
            x *= 1.001;
        }
        for x in xs.iter().flat_map(|&x| [x, -x]) {
            let (got, want) = (rem_turn(x), x % TAU);
            assert!(
                got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                "{x}: {got} {want}"
            );
        }
    }
}
