//! Coordinate frames of section 2.1.
//!
//! Inertial frame: X is the bearing axis, Y and Z radial. A ball's azimuth frame has
//! the right-handed basis `(e_x, e_r, e_t)`: axial, radial (outward) and tangential (the
//! direction of increasing azimuth), with the azimuth measured from +Z towards -Y (eq. 3).

use super::cpu::twice_compiled;
use super::lanes::{F64x4, LANES};
use nalgebra::{Matrix3, Vector3};

/// Cardan transformation matrix `A(eta, xi, lambda)` of eq. 1 (maps inertial to body
/// components for rotations eta about X, xi about Y, lambda about Z).
pub fn cardan(eta: f64, xi: f64, lambda: f64) -> Matrix3<f64> {
    cardan_of(&Azimuth::new(eta), &Azimuth::new(xi), &Azimuth::new(lambda))
}

/// [`cardan`] from the three angles' sines and cosines.
#[inline]
pub fn cardan_of(eta: &Azimuth, xi: &Azimuth, lambda: &Azimuth) -> Matrix3<f64> {
    let (se, ce) = (eta.sin, eta.cos);
    let (sx, cx) = (xi.sin, xi.cos);
    let (sl, cl) = (lambda.sin, lambda.cos);
    Matrix3::new(
        cx * cl,
        ce * sl + se * sx * cl,
        se * sl - ce * sx * cl,
        -cx * sl,
        ce * cl - se * sx * sl,
        se * cl + ce * sx * sl,
        sx,
        -se * cx,
        ce * cx,
    )
}

/// An azimuth by its sine and cosine: one `sin_cos` serves every frame operation at that
/// azimuth, and sums of azimuths need none (angle addition).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Azimuth {
    pub sin: f64,
    pub cos: f64,
}

twice_compiled! {
    /// The azimuths of `angles` (rad) into `out` (as long), four side by side: each within
    /// 2 ulp of [`Azimuth::new`]'s ([`F64x4::sin_cos`]), for the balls of a pass at every
    /// right-hand side.
    pub fn azimuths(angles: &[f64], out: &mut [Azimuth]) = azimuths_body, wide azimuths_avx2;
}

#[inline(always)]
fn azimuths_body(angles: &[f64], out: &mut [Azimuth]) {
    debug_assert_eq!(angles.len(), out.len());
    for (a, o) in angles.chunks(LANES).zip(out.chunks_mut(LANES)) {
        let mut lanes = [0.0; LANES];
        lanes[..a.len()].copy_from_slice(a);
        let (sin, cos) = F64x4(lanes).sin_cos();
        for (l, o) in o.iter_mut().enumerate() {
            *o = Azimuth {
                sin: sin.0[l],
                cos: cos.0[l],
            };
        }
    }
}

twice_compiled! {
    /// The angles of `azimuths` (rad, in (-pi, pi]) into `out` (as long), four side by side:
    /// each within 2 epsilon (relative) of [`Azimuth::angle`]'s ([`F64x4::atan2`]), for a
    /// step's averages of the contact angles.
    pub fn angles(azimuths: &[Azimuth], out: &mut [f64]) = angles_body, wide angles_avx2;
}

#[inline(always)]
fn angles_body(azimuths: &[Azimuth], out: &mut [f64]) {
    debug_assert_eq!(azimuths.len(), out.len());
    for (a, o) in azimuths.chunks(LANES).zip(out.chunks_mut(LANES)) {
        // a short chunk's spare lanes at angle zero, not read
        let mut sin = [0.0; LANES];
        let mut cos = [1.0; LANES];
        for (l, az) in a.iter().enumerate() {
            (sin[l], cos[l]) = (az.sin, az.cos);
        }
        let angle = F64x4(sin).atan2(F64x4(cos));
        o.copy_from_slice(&angle.0[..o.len()]);
    }
}

impl Default for Azimuth {
    /// Azimuth zero.
    fn default() -> Azimuth {
        Azimuth { sin: 0.0, cos: 1.0 }
    }
}

impl Azimuth {
    #[inline]
    pub fn new(theta: f64) -> Azimuth {
        let (sin, cos) = theta.sin_cos();
        Azimuth { sin, cos }
    }

    /// The azimuth `self + other`.
    #[inline]
    pub fn plus(&self, other: &Azimuth) -> Azimuth {
        Azimuth {
            sin: self.sin * other.cos + self.cos * other.sin,
            cos: self.cos * other.cos - self.sin * other.sin,
        }
    }

    /// The azimuth `self - other`.
    #[inline]
    pub fn minus(&self, other: &Azimuth) -> Azimuth {
        Azimuth {
            sin: self.sin * other.cos - self.cos * other.sin,
            cos: self.cos * other.cos + self.sin * other.sin,
        }
    }

    /// The angle in (-pi, pi], rad.
    #[inline]
    pub fn angle(&self) -> f64 {
        self.sin.atan2(self.cos)
    }

    /// Radial unit vector: `(0, -sin, cos)`.
    #[inline]
    pub fn e_r(&self) -> Vector3<f64> {
        Vector3::new(0.0, -self.sin, self.cos)
    }

    /// Tangential unit vector (direction of increasing azimuth): `(0, -cos, -sin)`.
    #[inline]
    pub fn e_t(&self) -> Vector3<f64> {
        Vector3::new(0.0, -self.cos, -self.sin)
    }

    /// Inertial vector in azimuth-frame components `[x, r, t]`.
    #[inline]
    pub fn to_frame(&self, v: &Vector3<f64>) -> Vector3<f64> {
        let (s, c) = (self.sin, self.cos);
        Vector3::new(v.x, -s * v.y + c * v.z, -c * v.y - s * v.z)
    }

    /// Inertial vector from azimuth-frame components `[x, r, t]`.
    #[inline]
    pub fn from_frame(&self, a: &Vector3<f64>) -> Vector3<f64> {
        let (s, c) = (self.sin, self.cos);
        Vector3::new(a.x, -s * a.y - c * a.z, c * a.y - s * a.z)
    }
}

/// Radial unit vector at azimuth `theta`: `(0, -sin, cos)`.
#[inline]
pub fn e_r(theta: f64) -> Vector3<f64> {
    Azimuth::new(theta).e_r()
}

/// Tangential unit vector at azimuth `theta` (direction of increasing theta): `(0, -cos, -sin)`.
#[inline]
pub fn e_t(theta: f64) -> Vector3<f64> {
    Azimuth::new(theta).e_t()
}

/// Azimuth of a point, eq. 3: `atan2(-y, z)`.
#[inline]
pub fn azimuth(p: &Vector3<f64>) -> f64 {
    (-p.y).atan2(p.z)
}

/// Components of an inertial vector in the azimuth frame `[x, r, t]`.
#[inline]
pub fn to_azimuth(v: &Vector3<f64>, theta: f64) -> Vector3<f64> {
    Azimuth::new(theta).to_frame(v)
}

/// Inertial vector from azimuth-frame components `[x, r, t]`.
#[inline]
pub fn from_azimuth(a: &Vector3<f64>, theta: f64) -> Vector3<f64> {
    Azimuth::new(theta).from_frame(a)
}

/// Small-angle rotation of a ring tilted by `beta_y` about Y and `beta_z` about Z
/// (body-to-inertial), from the Cardan matrix with eta = 0.
pub fn tilt_matrix(beta_y: f64, beta_z: f64) -> Matrix3<f64> {
    cardan(0.0, beta_y, beta_z).transpose()
}

/// [`tilt_matrix`] from the two tilts' sines and cosines.
#[inline]
pub fn tilt_matrix_of(beta_y: &Azimuth, beta_z: &Azimuth) -> Matrix3<f64> {
    cardan_of(&Azimuth::default(), beta_y, beta_z).transpose()
}

#[cfg(test)]
mod tests {
    /// The angles' two copies agree to the bit, and each is [`Azimuth::angle`] within 2
    /// epsilon (relative; the lanes' `atan2` is tested over its whole range in `lanes`), over
    /// every quadrant and a chunk's spare lanes.
    #[test]
    fn the_angles_copies_agree_and_are_the_library_ones() {
        let azimuths: Vec<Azimuth> = (0..4003)
            .map(|k| Azimuth::new((k as f64 - 2001.0) * 1.57e-3))
            .collect();
        let mut wide = vec![0.0; azimuths.len()];
        let mut base = wide.clone();
        angles(&azimuths, &mut wide);
        angles_body(&azimuths, &mut base);
        for ((w, b), az) in wide.iter().zip(&base).zip(&azimuths) {
            assert_eq!(w.to_bits(), b.to_bits(), "{az:?}");
            let want = az.angle();
            assert!(
                (w - want).abs() <= 2.0 * f64::EPSILON * want.abs(),
                "{az:?}"
            );
        }
    }

    /// The copy this processor runs is the baseline copy to the bit (both fuse only where
    /// the code asks), over angles a long run reaches, both signs, and past the reduced
    /// range.
    #[test]
    fn the_azimuths_copies_agree_to_the_bit() {
        let angles: Vec<f64> = (0..4001)
            .map(|k| (k as f64 - 2000.0) * 61.7 + 1e-3 * k as f64)
            .chain([0.0, -0.0, 2e5, -3e6])
            .collect();
        let mut wide = vec![Azimuth::default(); angles.len()];
        let mut base = wide.clone();
        azimuths(&angles, &mut wide);
        azimuths_body(&angles, &mut base);
        for ((w, b), x) in wide.iter().zip(&base).zip(&angles) {
            assert_eq!(
                (w.sin.to_bits(), w.cos.to_bits()),
                (b.sin.to_bits(), b.cos.to_bits()),
                "{x}"
            );
        }
    }

    use super::*;

    #[test]
    fn cardan_is_a_rotation() {
        let a = cardan(0.3, -0.2, 1.1);
        let i = a * a.transpose();
        assert!((i - Matrix3::identity()).norm() < 1e-14);
        assert!((a.determinant() - 1.0).abs() < 1e-14);
        // pure rotation about X by eta maps Y to (0, cos, -sin)
        let r = cardan(0.4, 0.0, 0.0) * Vector3::y();
        assert!((r - Vector3::new(0.0, 0.4f64.cos(), -(0.4f64.sin()))).norm() < 1e-15);
    }

    #[test]
    fn azimuth_frame_is_right_handed_and_round_trips() {
        let th = 0.7;
        let (x, r, t) = (Vector3::x(), e_r(th), e_t(th));
        assert!((x.cross(&r) - t).norm() < 1e-15);
        assert!((r.cross(&t) - x).norm() < 1e-15);
        let v = Vector3::new(0.3, -1.2, 2.5);
        assert!((from_azimuth(&to_azimuth(&v, th), th) - v).norm() < 1e-14);
        assert!((azimuth(&(e_r(th) * 3.0)) - th).abs() < 1e-14);
    }

    #[test]
    fn azimuth_sums_and_differences_match_the_angles() {
        let (a, b) = (Azimuth::new(2.9), Azimuth::new(-1.3));
        // angle addition is exact up to a few roundings
        assert!((a.plus(&b).angle() - (2.9 - 1.3)).abs() < 1e-15);
        let d = a.minus(&b).angle();
        assert!(
            (d - (2.9 + 1.3 - std::f64::consts::TAU)).abs() < 1e-14,
            "{d}"
        );
    }
}
