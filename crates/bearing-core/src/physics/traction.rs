//! EHL traction coefficient (eqs. 14-15) and its slip-direction decomposition (eq. 16), and
//! an elastic-plastic film law from the lubricant's properties (docs/reference/model.md, "Traction
//! laws").

use super::exp::exp;
use super::hertz::HertzContact;
use super::rheology_traction::{ContactRheology, RheologyTraction};
use std::f64::consts::PI;

/// Traction curve `mu(s) = (a + b s) exp(-c s) + d`, s the slip speed in m/s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TractionCurve {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub d: f64,
}

/// Below this slip speed (m/s) the coefficient is scaled linearly to zero, so a curve
/// with mu(0) != 0 has no discontinuity at zero slip (fully flooded EHL: q_bd = 0).
pub const SLIP_REGULARIZATION: f64 = 1e-3;

impl TractionCurve {
    /// Coefficient at slip speed `s` >= 0, -.
    #[inline]
    pub fn mu(&self, s: f64) -> f64 {
        self.mu_over_s(s) * s
    }

    /// `mu(s) / s`, finite at s = 0: multiplies the slip vector to give the traction direction
    /// and magnitude without dividing by a vanishing speed, 1/(m/s). Branch-free, with the
    /// inlined exponential: it runs once per strip, the engine's innermost loop.
    #[inline]
    pub fn mu_over_s(&self, s: f64) -> f64 {
        let mu = (self.a + self.b * s) * exp(-self.c * s) + self.d;
        // below the regularisation speed mu is scaled by s / SLIP_REGULARIZATION
        mu / s.max(SLIP_REGULARIZATION)
    }
}

pub use super::rheology_traction::FILM_SPEED_FLOOR;

/// Barus exponents above this are capped (the viscous compliance is then negligible).
const MAX_BARUS_EXPONENT: f64 = 50.0;

/// The earlier film law of one ball-race pair (docs/reference/model.md, "Traction laws",
/// "The earlier `film` law"), kept to reproduce its studies; superseded by
/// [`super::rheology_traction`]. One slope per contact:
/// - at small slip an elastic film term over the contact's transit, `G b s / (u h)`, in
///   series with Barus-viscous flow at the mean Hertz pressure (the project's own closed
///   form; no read source gives it);
/// - above the Eyring stress `tau0`, `mu_E = (tau0 / p) asinh(k s p / tau0)` (the form of
///   Arana et al. 2019, eq. 13);
/// - at most `Lambda p`, blended by `mu = Lambda tanh(mu_E / Lambda)` (a smoothing of the
///   project's own).
///
/// Film thickness: Hamrock & Dowson's central formula (as given by Arana et al. 2019,
/// eq. 19); `p` the mean Hertz pressure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmTraction {
    /// Limiting shear stress over pressure, -.
    pub limiting: f64,
    /// Eyring stress, Pa.
    pub eyring_stress: f64,
    /// Film shear modulus, Pa.
    pub shear_modulus: f64,
    /// Inlet viscosity, Pa s.
    pub eta0: f64,
    /// Pressure-viscosity coefficient, 1/Pa.
    pub alpha: f64,
    /// `h_c = h_coef u^0.67 Q^-0.067` (Hamrock-Dowson), m (m/s)^-0.67 N^0.067.
    h_coef: f64,
    /// Semi-axes per cube-root load across (`a`) and along (`b`) the rolling direction,
    /// m/N^(1/3).
    a_coef: f64,
    b_coef: f64,
}

/// The lubricant's rheology for [`FilmTraction`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmRheology {
    /// Inlet viscosity, Pa s.
    pub eta0: f64,
    /// Pressure-viscosity coefficient, 1/Pa.
    pub alpha: f64,
    /// Elastic shear modulus of the film, Pa.
    pub shear_modulus: f64,
    /// Eyring stress, Pa.
    pub eyring_stress: f64,
    /// Limiting shear stress over pressure, -.
    pub limiting: f64,
}

impl FilmTraction {
    /// Constants for effective modulus `e_prime` (Pa), relative radius `rx` in the rolling
    /// direction (m), the pair's Hertz contact and the lubricant's rheology.
    pub fn new(e_prime: f64, rx: f64, hertz: &HertzContact, r: &FilmRheology) -> Self {
        let ellipticity = hertz.a_coef / hertz.b_coef;
        // H = 2.69 U^0.67 G^0.53 W^-0.067 (1 - 0.61 exp(-0.73 k)), h = Rx H
        let h_coef = rx
            * 2.69
            * (r.eta0 / (e_prime * rx)).powf(0.67)
            * (r.alpha * e_prime).powf(0.53)
            * (e_prime * rx * rx).powf(0.067)
            * (1.0 - 0.61 * (-0.73 * ellipticity).exp());
        FilmTraction {
            limiting: r.limiting,
            eyring_stress: r.eyring_stress,
            shear_modulus: r.shear_modulus,
            eta0: r.eta0,
            alpha: r.alpha,
            h_coef,
            a_coef: hertz.a_coef,
            b_coef: hertz.b_coef,
        }
    }

    /// Central film thickness at load `q` (N) and entrainment speed `um` (m/s), m.
    #[inline]
    pub fn film_thickness(&self, q: f64, um: f64) -> f64 {
        self.h_coef * um.max(FILM_SPEED_FLOOR).powf(0.67) * q.powf(-0.067)
    }

    /// The law at load `q` (N, > 0) and entrainment speed `um` (m/s).
    #[inline]
    pub fn at(&self, q: f64, um: f64) -> ContactTraction {
        let um = um.max(FILM_SPEED_FLOOR);
        let q13 = q.cbrt();
        let b = self.b_coef * q13;
        let p_mean = q / (PI * self.a_coef * q13 * b);
        let h = self.film_thickness(q, um);
        // compliances in series (Maxwell): elastic shear over the transit 2b, viscous flow
        let elastic = self.shear_modulus * b / (um * h * p_mean);
        let eta = self.eta0 * (self.alpha * p_mean).min(MAX_BARUS_EXPONENT).exp();
        let viscous = eta / (h * p_mean);
        ContactTraction::Film {
            slope: 1.0 / (1.0 / elastic + 1.0 / viscous),
            pressure_over_eyring: p_mean / self.eyring_stress,
            limiting: self.limiting,
        }
    }
}

/// The traction law of one ball-race pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TractionLaw {
    /// A curve of the slip speed alone (eq. 15), the same at every load and speed.
    Curve(TractionCurve),
    /// The earlier film law, which depends on the contact's load and entrainment speed.
    Film(FilmTraction),
    /// Traction from the lubricant's rheology, strip by strip (`rheology_traction`).
    Rheology(RheologyTraction),
}

impl TractionLaw {
    /// Whether evaluating the law needs the contact's entrainment speed.
    #[inline]
    pub fn needs_entrainment(&self) -> bool {
        matches!(self, TractionLaw::Film(_) | TractionLaw::Rheology(_))
    }

    /// The law at load `q` (N, > 0) and entrainment speed `um` (m/s; read by the film law
    /// only).
    #[inline]
    pub fn at(&self, q: f64, um: f64) -> ContactTraction {
        match self {
            TractionLaw::Curve(c) => ContactTraction::Curve(*c),
            TractionLaw::Film(f) => f.at(q, um),
            TractionLaw::Rheology(r) => ContactTraction::Rheology(r.at(q, um)),
        }
    }
}

/// A traction law evaluated for one contact: the coefficient's `mu(s) / s` per strip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactTraction {
    /// The scene's `mu(s)` curve (eq. 15).
    Curve(TractionCurve),
    /// [`FilmTraction`] at one load and speed: low-slip slope (s/m), mean pressure over the
    /// Eyring stress (-), limiting coefficient (-).
    Film {
        slope: f64,
        pressure_over_eyring: f64,
        limiting: f64,
    },
    /// [`RheologyTraction`] at one load and speed: each strip at its own pressure.
    Rheology(ContactRheology),
}

impl ContactTraction {
    /// `mu(s) / s` of the strip at `xi` of the semi-major axis (read by the rheology law
    /// only), finite at s = 0, 1/(m/s).
    #[inline]
    pub fn mu_over_s(&self, xi: f64, s: f64) -> f64 {
        match *self {
            ContactTraction::Rheology(r) => r.mu_over_s(xi, s),
            ContactTraction::Curve(c) => c.mu_over_s(s),
            ContactTraction::Film {
                slope,
                pressure_over_eyring,
                limiting,
            } => film_mu_over_s(slope, pressure_over_eyring, limiting, s),
        }
    }
}

/// The film law's `mu(s) / s` (see [`FilmTraction`]) for low-slip slope `slope` (s/m), mean
/// pressure over the Eyring stress `r` (-) and limiting coefficient `limiting` (-); finite at
/// s = 0, 1/(m/s).
#[inline]
pub fn film_mu_over_s(slope: f64, r: f64, limiting: f64, s: f64) -> f64 {
    // Eyring: mu_E / s = asinh(z) / (r s), z = k s r (series: asinh z / z ~ 1 - z^2/6)
    let z = slope * s * r;
    let mu_e_over_s = if z < 1e-4 {
        slope * (1.0 - z * z / 6.0)
    } else {
        z.asinh() / (r * s)
    };
    // limiting shear: tanh x / x ~ 1 - x^2/3
    let x = mu_e_over_s * s / limiting;
    let t = if x < 1e-4 {
        1.0 - x * x / 3.0
    } else {
        x.tanh() / x
    };
    mu_e_over_s * t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curve_is_continuous_and_peaks_where_designed() {
        // ADORE sample deck: peak 0.05 at 1 m/s, tends to 0.036.
        let t = TractionCurve {
            a: -0.036,
            b: 0.1018,
            c: 1.547,
            d: 0.036,
        };
        assert!(t.mu(0.0).abs() < 1e-12);
        assert!((t.mu(1.0) - 0.05).abs() < 2e-4, "{}", t.mu(1.0));
        assert!((t.mu(50.0) - 0.036).abs() < 1e-6);
        // continuity across the regularization threshold
        let s = SLIP_REGULARIZATION;
        assert!((t.mu(s * (1.0 - 1e-9)) - t.mu(s * (1.0 + 1e-9))).abs() < 1e-9);
        // eq. 15 in closed form with libm's exp: the inlined exp is within 2 ulp of it
        // (4.4e-16 relative), times mu ~ 0.05, plus two roundings: below 1e-16
        let s = 0.3;
        let closed = (t.a + t.b * s) * (-t.c * s).exp() + t.d;
        assert!((t.mu(s) - closed).abs() < 1e-16, "{} {closed}", t.mu(s));
    }

    #[test]
    fn film_law_matches_hand_figures() {
        use crate::physics::hertz::exact;
        // A steel ball-race pair of the H7005C's size in round numbers: Rx 2.5 mm, Ry 20 mm,
        // E' 228 GPa; eta0 0.03 Pa s, alpha 1.5e-8 1/Pa, G 1 GPa, tau0 5 MPa, Lambda 0.07.
        let (rx, ry, ep) = (2.5e-3, 20e-3, 2.28e11);
        let hz = exact(rx, ry, ep);
        let rheology = FilmRheology {
            eta0: 0.03,
            alpha: 1.5e-8,
            shear_modulus: 1e9,
            eyring_stress: 5e6,
            limiting: 0.07,
        };
        let f = FilmTraction::new(ep, rx, &hz, &rheology);
        let (q, um) = (100.0, 10.0);
        // Hamrock-Dowson by hand: U = eta0 um/(E' Rx), G = alpha E', W = Q/(E' Rx^2)
        let u = 0.03 * um / (ep * rx);
        let g = 1.5e-8 * ep;
        let w = q / (ep * rx * rx);
        let k = hz.a_coef / hz.b_coef;
        let h = rx
            * 2.69
            * u.powf(0.67)
            * g.powf(0.53)
            * w.powf(-0.067)
            * (1.0 - 0.61 * (-0.73 * k).exp());
        assert!((f.film_thickness(q, um) / h - 1.0).abs() < 1e-12);
        // a film of a few tenths of a micrometre, as EHL ball contacts run
        assert!((0.1e-6..1.0e-6).contains(&h), "{h}");
        let (a, b) = (hz.a_coef * q.cbrt(), hz.b_coef * q.cbrt());
        let p = q / (PI * a * b);
        let el = 1e9 * b / (um * h * p);
        let vi = 0.03 * (1.5e-8 * p).exp() / (h * p);
        let slope = el * vi / (el + vi);
        let law = f.at(q, um);
        let mu = |s: f64| law.mu_over_s(0.0, s) * s;
        // linear at small slip with the series slope
        assert!((law.mu_over_s(0.0, 0.0) / slope - 1.0).abs() < 1e-12);
        assert!((mu(1e-9) / (slope * 1e-9) - 1.0).abs() < 1e-6);
        // Eyring region by hand, and the limiting shear stress at large slip
        let s = 0.01;
        let mu_e = 5e6 / p * (slope * s * p / 5e6).asinh();
        assert!((mu(s) / (0.07 * (mu_e / 0.07).tanh()) - 1.0).abs() < 1e-12);
        assert!(mu(s) < 0.07 && mu(s) > 0.01, "{}", mu(s));
        // above the Eyring stress mu grows only logarithmically, and never past Lambda
        assert!(
            mu(1.0) < mu(1e3) && mu(1e3) < 0.07,
            "{} {}",
            mu(1.0),
            mu(1e3)
        );
        // mu / s continuous where the Eyring and the tanh series switch in
        for z_switch in [1e-4 / (slope * p / 5e6), 1e-4 * 0.07 / slope] {
            let below = law.mu_over_s(0.0, z_switch * (1.0 - 1e-9));
            let above = law.mu_over_s(0.0, z_switch * (1.0 + 1e-9));
            assert!((below / above - 1.0).abs() < 1e-9);
        }
    }
}
