//! Traction from the lubricant's rheology, strip by strip (docs/reference/model.md,
//! "Traction laws"; the sources and what was read of them:
//! docs/lab/research/issue-33-traction-sources.md).
//!
//! Each strip of eq. 13 is a film at its own pressure, the strip's mean Hertz pressure along
//! the rolling direction `p = (pi/4) p0 sqrt(1 - xi^2)`. On it:
//! - viscosity from Roelands' pressure-viscosity relation (as given by Stachowiak &
//!   Batchelor, Engineering Tribology, ch. 2, p. 21, and Nguyen-Schäfer 2019 sec. 1.8.1): `ln eta = ln eta0 + (ln eta0 + 9.67)((1 + p/p_R)^Z - 1)`;
//! - the Eyring stress from the local pressure-viscosity coefficient,
//!   `tau_E = 2 Lambda / alpha(p)` (Arana et al. 2019, the paragraph before eq. 8, which gives
//!   it as Bair & Winer's);
//! - the mean shear stress of Arana, Larrañaga & Ulacia (Proc IMechE J 233, 2019), eq. 13,
//!   isothermal (`Phi_T = 1`): `mu = min((tau_E/p) asinh(eta s / (tau_E h_c)), Lambda)`,
//!   the limiting shear stress `Lambda p` of Höglund (1999, as given by Arana, Table 2);
//! - `h_c` the Hamrock-Dowson central film (Arana eq. 19) with the reciprocal asymptotic
//!   isoviscous coefficient `alpha*` of Arana eq. 35.
//!
//! Left out, with the measured or computed reason in model.md: the film's elastic
//! (Maxwell) compliance (Deborah number 0.1-0.3 at the loaded balls' centre strips at 10000
//! rpm, lowering their low-slip slope by 10-30 %; negligible on the lightly loaded balls)
//! and shear heating (below 0.2 K at the slips of a rolling ball).

use super::exp::exp;
use super::hertz::{cube_root, HertzContact};
use super::lanes::{F64x4, Mask4, Vec3x4};
use nalgebra::Vector3;
use std::f64::consts::PI;

/// Below this entrainment speed (m/s) the film laws take this speed: the film thickness and
/// the elastic slope diverge as the speed vanishes. A numerical floor far below running
/// speeds: on the H7005C it binds below about 10 rpm (1 rpm entrains at about 1 mm/s).
pub const FILM_SPEED_FLOOR: f64 = 0.01;

/// Roelands' reference pressure `p_R`, Pa (5.1e-9 1/Pa in Stachowiak's form).
pub const ROELANDS_PRESSURE: f64 = 1.96e8;
/// `-ln(eta_R)` with Roelands' reference viscosity `eta_R = 6.31e-5` Pa s, -.
pub const ROELANDS_LN_ETA_R: f64 = 9.67;

/// Roelands' pressure-viscosity index Z of an oil of inlet viscosity `eta0` (Pa s) and
/// initial pressure-viscosity coefficient `alpha0` (1/Pa), from
/// `alpha0 = Z (ln eta0 + 9.67) / p_R` (Nguyen-Schäfer 2019 sec. 1.8.1), -. Needs
/// `eta0 > eta_R`; the preset's spindle oil gives 0.69.
pub fn roelands_z(eta0: f64, alpha0: f64) -> f64 {
    alpha0 * ROELANDS_PRESSURE / (eta0.ln() + ROELANDS_LN_ETA_R)
}

/// The lubricant's rheology for [`RheologyTraction`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rheology {
    /// Inlet (ambient-pressure) viscosity, Pa s.
    pub eta0: f64,
    /// Initial pressure-viscosity coefficient, 1/Pa.
    pub alpha0: f64,
    /// Roelands' pressure-viscosity index, -.
    pub z: f64,
    /// Limiting shear stress over pressure, -.
    pub limiting: f64,
}

/// The law's constants for one ball-race pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RheologyTraction {
    /// Limiting shear stress over pressure, -.
    pub limiting: f64,
    /// `ln eta0`, with eta0 in Pa s.
    ln_eta0: f64,
    /// `ln eta0 + 9.67`, -.
    roelands_c: f64,
    /// Roelands' index, -.
    z: f64,
    /// `h_c = h_coef u^0.67 Q^-0.067` (Hamrock-Dowson), m (m/s)^-0.67 N^0.067.
    h_coef: f64,
    /// `(pi/4) p0 / Q^(1/3)`: the centre strip's mean pressure per cube-root load,
    /// Pa/N^(1/3).
    p_strip_coef: f64,
    /// `ln` [`FILM_SPEED_FLOOR`] (m/s).
    ln_speed_floor: f64,
}

impl RheologyTraction {
    /// Constants for effective modulus `e_prime` (Pa), relative radius `rx` in the rolling
    /// direction (m), the pair's Hertz contact and the lubricant's rheology.
    pub fn new(e_prime: f64, rx: f64, hertz: &HertzContact, r: &Rheology) -> Self {
        let ellipticity = hertz.a_coef / hertz.b_coef;
        // Arana eq. 35: the film's coefficient from Roelands' parameters
        let alpha_star = r.alpha0 / (1.0 + (1.0 - r.z) / (r.alpha0 * ROELANDS_PRESSURE));
        // Arana eq. 19: h_c/Rx = 2.69 U^0.67 G^0.53 W^-0.067 (1 - 0.61 exp(-0.73 k))
        let h_coef = rx
            * 2.69
            * (r.eta0 / (e_prime * rx)).powf(0.67)
            * (alpha_star * e_prime).powf(0.53)
            * (e_prime * rx * rx).powf(0.067)
            * (1.0 - 0.61 * (-0.73 * ellipticity).exp());
        // p0 = 3 Q / (2 pi a b), a and b growing as Q^(1/3)
        let p0_coef = 3.0 / (2.0 * PI * hertz.a_coef * hertz.b_coef);
        RheologyTraction {
            limiting: r.limiting,
            ln_eta0: r.eta0.ln(),
            roelands_c: r.eta0.ln() + ROELANDS_LN_ETA_R,
            z: r.z,
            h_coef,
            p_strip_coef: 0.25 * PI * p0_coef,
            ln_speed_floor: FILM_SPEED_FLOOR.ln(),
        }
    }

    /// Central film thickness at load `q` (N) and entrainment speed `um` (m/s), m.
    ///
    /// `u^0.67 Q^-0.067` as one exponential of the two logarithms: libm's `powf` twice cost
    /// about 250 instructions per contact, this form about half (callgrind,
    /// docs/lab/benchmarks.md).
    #[inline]
    pub fn film_thickness(&self, q: f64, um: f64) -> f64 {
        self.film_thickness_ln(q, um.max(FILM_SPEED_FLOOR).ln())
    }

    /// [`RheologyTraction::film_thickness`] given `ln_um`, the logarithm of the entrainment
    /// speed (m/s) floored anywhere up to [`FILM_SPEED_FLOOR`]; the law floors it there.
    #[inline]
    fn film_thickness_ln(&self, q: f64, ln_um: f64) -> f64 {
        self.h_coef * exp(0.67 * ln_um.max(self.ln_speed_floor) - 0.067 * q.ln())
    }

    /// The law at load `q` (N, > 0) and entrainment speed `um` (m/s).
    #[inline]
    pub fn at(&self, q: f64, um: f64) -> ContactRheology {
        self.at_load(q, cube_root(q), um.max(FILM_SPEED_FLOOR).ln())
    }

    /// [`RheologyTraction::at`] given the load's cube root `q13 = cube_root(q)` and the
    /// entrainment speed's logarithm `ln_um` (floored anywhere up to [`FILM_SPEED_FLOOR`]),
    /// which the contact computes once for the ellipse's size and the rolling resistance.
    #[inline]
    pub fn at_load(&self, q: f64, q13: f64, ln_um: f64) -> ContactRheology {
        let h = self.film_thickness_ln(q, ln_um);
        ContactRheology {
            // the strip pressures scale with p0 ~ Q / (a b) ~ Q^(1/3)
            p_centre: self.p_strip_coef * q13,
            h,
            inv_2lambda_h: 1.0 / (2.0 * self.limiting * h),
            ln_eta0: self.ln_eta0,
            roelands_c: self.roelands_c,
            z: self.z,
            limiting: self.limiting,
        }
    }
}

/// [`RheologyTraction`] at one load and entrainment speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactRheology {
    /// Mean pressure along the rolling direction of a strip through the centre, Pa.
    pub p_centre: f64,
    /// Central film thickness, m.
    pub h: f64,
    /// `1 / (2 Lambda h)`, 1/m.
    inv_2lambda_h: f64,
    ln_eta0: f64,
    roelands_c: f64,
    z: f64,
    limiting: f64,
}

/// The film of one strip: its pressure and what its traction follows from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StripFilm {
    /// Mean pressure along the rolling direction, Pa.
    pub pressure: f64,
    /// Viscosity at that pressure (Roelands), Pa s.
    pub viscosity: f64,
    /// Local pressure-viscosity coefficient `d ln eta / dp`, 1/Pa.
    pub alpha: f64,
    /// Eyring stress `2 Lambda / alpha`, Pa.
    pub eyring_stress: f64,
}

impl ContactRheology {
    /// Pressure (Pa), viscosity (Pa s) and local pressure-viscosity coefficient (1/Pa) of
    /// the strip whose half-chord along the rolling direction is `chord` times the centre
    /// strip's (`sqrt(1 - xi^2)` at `xi` of the semi-major axis).
    #[inline(always)]
    fn film(&self, chord: f64) -> (f64, f64, f64) {
        let pressure = self.p_centre * chord;
        let x = 1.0 + pressure * (1.0 / ROELANDS_PRESSURE);
        // (1 + p/p_R)^Z
        let xz = exp(self.z * x.ln());
        let viscosity = exp(self.ln_eta0 + self.roelands_c * (xz - 1.0));
        let alpha = self.roelands_c * self.z * xz / (x * ROELANDS_PRESSURE);
        (pressure, viscosity, alpha)
    }

    /// The film of the strip at `xi` (fraction of the semi-major axis, |xi| <= 1).
    pub fn strip(&self, xi: f64) -> StripFilm {
        let (pressure, viscosity, alpha) = self.film((1.0 - xi * xi).max(0.0).sqrt());
        StripFilm {
            pressure,
            viscosity,
            alpha,
            eyring_stress: 2.0 * self.limiting / alpha,
        }
    }

    /// The law of the strip with half-chord ratio `chord` (see [`ContactRheology::film`]):
    /// what its `mu(s) / s` needs besides the slip. A pair of strips mirrored about the
    /// ellipse's centre shares it, so the strip loop computes it once per pair.
    #[inline(always)]
    pub fn strip_law(&self, chord: f64) -> StripLaw {
        let (pressure, viscosity, alpha) = self.film(chord);
        // a strip at the ellipse's edge carries no load and no traction: k = 0 gives mu = 0
        if pressure <= 0.0 {
            return StripLaw {
                c: 1.0,
                k: 0.0,
                limiting: self.limiting,
            };
        }
        StripLaw {
            c: 0.5 * alpha * pressure,
            // z / s = eta alpha / (2 Lambda h)
            k: viscosity * alpha * self.inv_2lambda_h,
            limiting: self.limiting,
        }
    }

    /// [`ContactRheology::strip_law`] for [`StripCellLaw::cell_mean`].
    #[inline(always)]
    pub fn strip_cell_law(&self, chord: f64) -> StripCellLaw {
        StripCellLaw {
            law: self.strip_law(chord),
        }
    }

    /// `mu(s) / s` of the strip with half-chord ratio `chord`, finite at s = 0, 1/(m/s).
    #[inline(always)]
    pub fn mu_over_s_chord(&self, chord: f64, s: f64) -> f64 {
        self.strip_law(chord).mu_over_s(s)
    }

    /// `mu(s) / s` of the strip at `xi` (fraction of the semi-major axis), 1/(m/s): the strip
    /// loop's form (the square root costs little beside the law's logarithms and
    /// exponentials, and keeps the curve's loop free of a column it does not read).
    #[inline(always)]
    pub fn mu_over_s(&self, xi: f64, s: f64) -> f64 {
        self.mu_over_s_chord((1.0 - xi * xi).max(0.0).sqrt(), s)
    }

    /// `mu(s)` of the strip at `xi`, -.
    pub fn mu(&self, xi: f64, s: f64) -> f64 {
        self.mu_over_s(xi, s) * s
    }
}

/// [`ContactRheology`] on one strip: Arana's eq. 13, `mu = min((tau_E/p) asinh(z), Lambda)`
/// with `z = eta s / (tau_E h)` and `tau_E = 2 Lambda / alpha`, written with
/// `c = alpha p / 2` as `mu = Lambda min(asinh(z), c) / c`: one division per strip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StripLaw {
    /// `alpha p / 2`, -.
    c: f64,
    /// `z / s = eta alpha / (2 Lambda h)`, 1/(m/s).
    k: f64,
    /// Limiting shear stress over pressure, -.
    limiting: f64,
}

impl StripLaw {
    /// `mu(s) / s`, finite at s = 0, 1/(m/s).
    #[inline(always)]
    pub fn mu_over_s(&self, s: f64) -> f64 {
        let z = self.k * s;
        if z < 1e-4 {
            // asinh z / z = 1 - z^2/6 + O(z^4): slope eta / (h p) = Lambda k / c
            return self.limiting * self.k * (1.0 - z * z / 6.0) / self.c;
        }
        let a = asinh_positive(z);
        if a >= self.c {
            // the film carries at most Lambda p
            self.limiting / s
        } else {
            self.limiting * a / (self.c * s)
        }
    }
}

impl StripLaw {
    /// The slip at which the film saturates, `sinh(c) / k` (m/s; infinite for a strip that
    /// carries nothing).
    #[inline(always)]
    fn saturation_slip(&self) -> f64 {
        if self.k <= 0.0 {
            return f64::INFINITY;
        }
        let e = exp(self.c.min(700.0));
        0.5 * (e - 1.0 / e) / self.k
    }

    /// `Lambda (cosh c - 1) / (c k)`, m/s: where the antiderivative of the saturated law
    /// `Lambda` meets that of the Eyring law (zero for a strip that carries nothing).
    #[inline(always)]
    fn saturation_offset(&self) -> f64 {
        if self.k <= 0.0 {
            return 0.0;
        }
        // c = alpha p / 2 stays below 50 at any pressure a steel contact survives; the
        // bound only keeps cosh finite
        let c = self.c.min(700.0);
        let e = exp(c);
        let cosh_minus_1 = 0.5 * (e + 1.0 / e) - 1.0;
        self.limiting * cosh_minus_1 / (c * self.k)
    }

    /// `M(r) = integral of mu(s) ds over 0..r` (m/s):
    /// `(Lambda/c) (r asinh(k r) - (sqrt(1 + k^2 r^2) - 1)/k)` below saturation,
    /// `Lambda r -` [`StripLaw::saturation_offset`] above.
    /// Returned with `mu(r)`, which it computes on the way.
    #[inline(always)]
    fn antiderivative_and_law(&self, r: f64) -> (f64, f64) {
        let x = self.k * r;
        if x <= 0.0 {
            return (0.0, 0.0);
        }
        let root = (1.0 + x * x).sqrt();
        // (sqrt(1 + x^2) - 1)/k = x r / (1 + sqrt(1 + x^2)), free of cancellation
        let tail = x / (1.0 + root);
        let a = if x < 1e-4 {
            x * (1.0 - x * x / 6.0)
        } else {
            (x + x * tail).ln_1p()
        };
        if a >= self.c {
            (self.limiting * r - self.saturation_offset(), self.limiting)
        } else {
            let scale = self.limiting / self.c;
            (scale * r * (a - tail), scale * a)
        }
    }
}

/// Span-to-slip ratio below which [`StripCellLaw::cell_mean`] takes the point value: there
/// the two differ by ~0.3 % of the law's relative curvature, except where `|v|` is near
/// the saturation kink, where they differ to first order, by up to `Lambda tanh(c)/(32 c)`
/// (1 % of `Lambda` at `c = 3`; review of 2026-11-28).
pub const CELL_POINT_RATIO: f64 = 0.25;

/// Steepness of the law on a cell's scale (zero-slip slope times the cell's slip span, in
/// `Lambda`s) below which [`StripCellLaw::cell_mean`] takes the point value: below 1 the
/// law's linear part alone would not reach `Lambda` within the cell, so the law bends
/// little there and the Gauss nodes integrate it as a smooth function. Measured on the
/// H7005C (docs/lab/benchmarks.md, "Cell means for the rheology law"): against 10, the
/// balls' traction moments at 10 nodes are about 4 times closer to 80 nodes' (9.3 %
/// against 41 % with a linear blend) for 12 % more run time on the Table-1 case.
pub const CELL_STEEPNESS: f64 = 1.0;

/// A [`StripLaw`] averaged over cells ([`StripCellLaw::cell_mean`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StripCellLaw {
    law: StripLaw,
}

impl StripCellLaw {
    /// The mean of the traction coefficient vector `mu(|v|) v / |v|` over a strip's cell,
    /// along which the slip runs linearly from `v - span/2` to `v + span/2` (m/s; `v` the
    /// slip at the strip, `span` the slip's change across its cell).
    ///
    /// Why: a loaded strip's law rises to `Lambda` within micrometres to millimetres per
    /// second of slip, while the ball's spin spreads the slip over tenths of a metre per
    /// second across the ellipse. Sampled at points, the contact's traction is then a
    /// staircase in the ball's slip, flat between the samples and nearly vertical where one
    /// changes sign: a ball balanced on a riser is stiff to ~1e-8 s, and the sum is far from
    /// the integral (docs/reference/model.md, "Traction quadrature"). Averaged over cells the
    /// steps join into the integral's slope.
    ///
    /// With `e` the span's direction, `v = t e + p` (`p` across it, `|p| = d`): along `e`
    /// the mean is exact, `(M(r+) - M(r-)) / |span|` with `r-+ = |v -+ span/2|` (since
    /// `r dr = t dt`); across it, `p` times the mean of `mu(r)/r`, by Simpson's rule in
    /// `u = asinh(t/d)` on the piece of the line where the law is below saturation, exact
    /// on the saturated rest ([`StripCellLaw::exact_cell_mean`]): within 0.01 `Lambda` of
    /// quadrature on the tested segments, those centred on zero slip and a gentle law's
    /// included (one panel over the whole line, the law's kink inside it, erred by up to
    /// 0.06), and smooth where the line passes near zero slip.
    ///
    /// The mean costs four of the law's logarithms to the point value's one, so it is
    /// taken only where the point value would be wrong or stiff, and the point value
    /// elsewhere, blended smoothly between the two (no jump in the force or its slope):
    /// - where the law is steep on the cell's scale: its zero-slip slope times the span,
    ///   `k |span| / c` in `Lambda`s, above [`CELL_STEEPNESS`] (the staircase's risers are
    ///   that many times the integral's slope);
    /// - and where the span is not short beside the slip, `|span| / |v|` above
    ///   [`CELL_POINT_RATIO`] (far from zero slip they differ by ~`(|span|/|v|)^2 / 24` of
    ///   the law's relative curvature).
    ///
    /// Both up to twice their threshold.
    #[inline(always)]
    pub fn cell_mean(&self, v: Vector3<f64>, span: Vector3<f64>) -> Vector3<f64> {
        let l2 = span.norm_squared();
        let s2 = v.norm_squared();
        let ratio2 = l2 / (CELL_POINT_RATIO * CELL_POINT_RATIO);
        // `(k/c)^2 l2 / CELL_STEEPNESS^2 <= 1` without the division (c > 0): most strips
        // stop here, and a division per strip was the loop's longest wait (perf annotate)
        let (k, c) = (self.law.k, self.law.c);
        let steep_num = k * k * l2;
        let steep_den = c * c * (CELL_STEEPNESS * CELL_STEEPNESS);
        if ratio2 <= s2 || steep_num <= steep_den {
            return self.law.mu_over_s(s2.sqrt()) * v;
        }
        let steep2 = steep_num / steep_den;
        let mean = self.exact_cell_mean(v, span, l2);
        let w_ratio = if ratio2 >= 4.0 * s2 {
            1.0
        } else {
            (ratio2 / s2).sqrt() - 1.0
        };
        let w_steep = if steep2 >= 4.0 {
            1.0
        } else {
            steep2.sqrt() - 1.0
        };
        // each by smoothstep: no jump in the force's slope either (measured: with linear
        // ramps `auto_slip` at 1e-7 came 1.05e-5 from `rk4_fsal` in the 2000 rpm cage test)
        let smooth = |x: f64| x * x * (3.0 - 2.0 * x);
        let w = smooth(w_ratio) * smooth(w_steep);
        if w >= 1.0 {
            return mean;
        }
        w * mean + (1.0 - w) * self.law.mu_over_s(s2.sqrt()) * v
    }

    /// [`StripCellLaw::cell_mean`] by the antiderivative, given `|span|^2`.
    #[inline(always)]
    fn exact_cell_mean(&self, v: Vector3<f64>, span: Vector3<f64>, l2: f64) -> Vector3<f64> {
        let l = l2.sqrt();
        let e = span / l;
        let t = v.dot(&e);
        let p = v - t * e;
        let d2 = p.norm_squared();
        let (t_minus, t_plus) = (t - 0.5 * l, t + 0.5 * l);
        let r_minus = (d2 + t_minus * t_minus).sqrt();
        let r_plus = (d2 + t_plus * t_plus).sqrt();
        let (m_minus, mu_minus) = self.law.antiderivative_and_law(r_minus);
        let (m_plus, mu_plus) = self.law.antiderivative_and_law(r_plus);
        let along = (m_plus - m_minus) / l;
        // Across: the mean of mu(r)/r times d. With tau = d sinh(u), d tau / r = du, so it
        // is (d/l) times the integral of mu(d cosh u) du over u- .. u+, by Simpson's rule
        // (the ends' mu come with the antiderivatives): exact where the law is saturated,
        // and mu is bounded where 1/r is not. `X = t + r = d e^u` (as d^2/(r - t) for
        // t < 0, free of cancellation), so `u+ - u- = ln(X+/X-)` and the midpoint's
        // `d cosh(u_m) = (sqrt(X+ X-) + d^2/sqrt(X+ X-))/2`.
        if d2 <= 1e-30 * l2 {
            // (an across share below 1e-13 of the traction)
            return along * e;
        }
        let x = |t: f64, r: f64| if t >= 0.0 { t + r } else { d2 / (r - t) };
        let (x_minus, x_plus) = (x(t_minus, r_minus), x(t_plus, r_plus));
        // The law saturates at `r_s = sinh(c) / k`, where its slope jumps: at `u = -+u_s`,
        // `X = d^2/X_s` and `X_s = r_s + sqrt(r_s^2 - d^2)`. Beyond them `mu = Lambda` is
        // integrated exactly, and Simpson's rule takes only the smooth piece between them
        // (a kink inside one Simpson panel cost up to 0.06 Lambda; review of 2026-11-28).
        let (mut a, mut b, mut mu_a, mut mu_b) = (x_minus, x_plus, mu_minus, mu_plus);
        let r_s = self.law.saturation_slip();
        if r_s * r_s > d2 {
            let x_s = r_s + (r_s * r_s - d2).sqrt();
            let x_s_low = d2 / x_s;
            if a < x_s_low {
                (a, mu_a) = (x_s_low, self.law.limiting);
            }
            if b > x_s {
                (b, mu_b) = (x_s, self.law.limiting);
            }
        } else {
            // the whole line is saturated
            b = a;
        }
        let whole = (x_plus / x_minus).ln();
        let mut integral = self.law.limiting * whole;
        if b > a {
            let g = (a * b).sqrt();
            let r_mid = 0.5 * (g + d2 / g);
            let mu_mid = self.law.mu_over_s(r_mid) * r_mid;
            let piece = (b / a).ln();
            integral += piece * ((mu_a + 4.0 * mu_mid + mu_b) / 6.0 - self.law.limiting);
        }
        (integral / l) * p + along * e
    }
}

/// [`ContactRheology`] of four contacts side by side ([`super::race_contact_lanes`]).
#[derive(Debug, Clone, Copy)]
pub struct ContactRheologyX4 {
    /// Mean pressure along the rolling direction of a strip through the centre, Pa.
    p_centre: F64x4,
    /// `1 / (2 Lambda h)`, 1/m.
    inv_2lambda_h: F64x4,
    ln_eta0: f64,
    roelands_c: f64,
    z: f64,
    limiting: f64,
}

impl RheologyTraction {
    /// [`RheologyTraction::at_load`] of four contacts, given also `ln_q`, the logarithm of
    /// each load (of N).
    #[inline(always)]
    pub fn at_load_lanes(&self, q13: F64x4, ln_um: F64x4, ln_q: F64x4) -> ContactRheologyX4 {
        let ln_um = ln_um.max(F64x4::splat(self.ln_speed_floor));
        let h = F64x4::splat(self.h_coef) * (0.67 * ln_um - 0.067 * ln_q).exp();
        ContactRheologyX4 {
            p_centre: self.p_strip_coef * q13,
            inv_2lambda_h: F64x4::splat(1.0) / ((2.0 * self.limiting) * h),
            ln_eta0: self.ln_eta0,
            roelands_c: self.roelands_c,
            z: self.z,
            limiting: self.limiting,
        }
    }
}

impl ContactRheologyX4 {
    /// [`ContactRheology::strip_law`] of the four contacts.
    #[inline(always)]
    pub fn strip_law(&self, chord: f64) -> StripLawX4 {
        let pressure = chord * self.p_centre;
        let x = F64x4::splat(1.0) + (1.0 / ROELANDS_PRESSURE) * pressure;
        let xz = (self.z * x.ln()).exp();
        let viscosity =
            (F64x4::splat(self.ln_eta0) + self.roelands_c * (xz - F64x4::splat(1.0))).exp();
        let alpha = (self.roelands_c * self.z) * xz / (ROELANDS_PRESSURE * x);
        // a strip at the ellipse's edge carries no load and no traction: k = 0 gives mu = 0
        let unloaded = pressure.le(F64x4::splat(0.0));
        StripLawX4 {
            c: F64x4::select(unloaded, F64x4::splat(1.0), 0.5 * alpha * pressure),
            k: F64x4::select(
                unloaded,
                F64x4::splat(0.0),
                viscosity * alpha * self.inv_2lambda_h,
            ),
            limiting: self.limiting,
        }
    }
}

/// [`StripLaw`] of four contacts.
#[derive(Debug, Clone, Copy)]
pub struct StripLawX4 {
    c: F64x4,
    k: F64x4,
    limiting: f64,
}

impl StripLawX4 {
    /// Lane `l`'s law as the scalar cell mean takes it: for a strip whose Eyring argument
    /// passes 1e150, which the lanes leave to it.
    #[inline(always)]
    pub fn lane(&self, l: usize) -> StripCellLaw {
        StripCellLaw {
            law: StripLaw {
                c: self.c.0[l],
                k: self.k.0[l],
                limiting: self.limiting,
            },
        }
    }

    /// Lanes where [`StripCellLaw::cell_mean`] is the point value: its own test, given the
    /// slip's squared size `s2` and its change's across the cell `l2` ((m/s)^2).
    #[inline(always)]
    pub fn takes_point_value(&self, s2: F64x4, l2: F64x4) -> Mask4 {
        let ratio2 = l2 / F64x4::splat(CELL_POINT_RATIO * CELL_POINT_RATIO);
        let steep_num = self.k * self.k * l2;
        let steep_den = self.c * self.c * F64x4::splat(CELL_STEEPNESS * CELL_STEEPNESS);
        let (a, b) = (ratio2.le(s2), steep_num.le(steep_den));
        [a[0] || b[0], a[1] || b[1], a[2] || b[2], a[3] || b[3]]
    }

    /// Lane `l`'s `alpha p / 2`, -.
    #[inline(always)]
    pub fn c_of(&self, l: usize) -> f64 {
        self.c.0[l]
    }

    /// Lane `l`'s `eta alpha / (2 Lambda h)`, 1/(m/s).
    #[inline(always)]
    pub fn k_of(&self, l: usize) -> f64 {
        self.k.0[l]
    }

    /// Four lanes' laws, each lane its own `c` and `k` (of different strips or contacts of
    /// one race, whose `limiting` they share).
    #[inline(always)]
    pub fn of_lanes(c: F64x4, k: F64x4, limiting: f64) -> StripLawX4 {
        StripLawX4 { c, k, limiting }
    }

    /// [`StripCellLaw::cell_mean`] of the four lanes, for lanes that do not take the point
    /// value (`takes_point_value` false): the same formulas, every branch taken in every
    /// lane and the lane's own chosen. Lanes whose law's `k s` passes 1e150 at `|v|` or at the midpoint are
    /// flagged in the mask returned (their value is not this one).
    #[inline(always)]
    pub fn cell_mean(&self, v: Vec3x4, span: Vec3x4) -> (Vec3x4, Mask4) {
        let one = F64x4::splat(1.0);
        let l2 = span.norm_squared();
        let s2 = v.norm_squared();
        let ratio2 = l2 / F64x4::splat(CELL_POINT_RATIO * CELL_POINT_RATIO);
        let steep2 = (self.k * self.k * l2)
            / (self.c * self.c * F64x4::splat(CELL_STEEPNESS * CELL_STEEPNESS));
        let (mean, huge_mean) = self.exact_cell_mean(v, span, l2);
        let w_ratio = F64x4::select((4.0 * s2).le(ratio2), one, (ratio2 / s2).sqrt() - one);
        let w_steep = F64x4::select(F64x4::splat(4.0).le(steep2), one, steep2.sqrt() - one);
        let smooth = |x: F64x4| x * x * (F64x4::splat(3.0) - 2.0 * x);
        let w = smooth(w_ratio) * smooth(w_steep);
        let (point, huge_point) = self.mu_over_s(s2.sqrt());
        let blend = mean.scale(w) + v.scale((one - w) * point);
        let whole = one.le(w);
        let out = Vec3x4::select(whole, mean, blend);
        let huge = std::array::from_fn(|l| huge_mean[l] || (!whole[l] && huge_point[l]));
        (out, huge)
    }

    /// [`StripCellLaw`]'s exact mean of the four lanes, given `|span|^2`.
    #[inline(always)]
    fn exact_cell_mean(&self, v: Vec3x4, span: Vec3x4, l2: F64x4) -> (Vec3x4, Mask4) {
        let zero = F64x4::splat(0.0);
        let lim = F64x4::splat(self.limiting);
        let l = l2.sqrt();
        let e = span.divided(l);
        let t = v.dot(e);
        let p = v - e.scale(t);
        let d2 = p.norm_squared();
        let half = 0.5 * l;
        let (t_minus, t_plus) = (t - half, t + half);
        let r_minus = (d2 + t_minus * t_minus).sqrt();
        let r_plus = (d2 + t_plus * t_plus).sqrt();
        let (m_minus, mu_minus) = self.antiderivative_and_law(r_minus);
        let (m_plus, mu_plus) = self.antiderivative_and_law(r_plus);
        let along = (m_plus - m_minus) / l;
        let only_along = d2.le(F64x4::splat(1e-30) * l2);
        let x = |t: F64x4, r: F64x4| F64x4::select(zero.le(t), t + r, d2 / (r - t));
        let (x_minus, x_plus) = (x(t_minus, r_minus), x(t_plus, r_plus));
        let (mut a, mut b, mut mu_a, mut mu_b) = (x_minus, x_plus, mu_minus, mu_plus);
        let r_s = self.saturation_slip();
        let r_s2 = r_s * r_s;
        let partly = d2.lt(r_s2);
        let x_s = r_s + (r_s2 - d2).sqrt();
        let x_s_low = d2 / x_s;
        let below = a.lt(x_s_low);
        let beyond = x_s.lt(b);
        let cut_a: Mask4 = std::array::from_fn(|k| partly[k] && below[k]);
        let cut_b: Mask4 = std::array::from_fn(|k| partly[k] && beyond[k]);
        a = F64x4::select(cut_a, x_s_low, a);
        mu_a = F64x4::select(cut_a, lim, mu_a);
        b = F64x4::select(cut_b, x_s, b);
        mu_b = F64x4::select(cut_b, lim, mu_b);
        // the whole line saturated
        b = F64x4::select(partly, b, a);
        let whole = (x_plus / x_minus).ln();
        let g = (a * b).sqrt();
        let r_mid = 0.5 * (g + d2 / g);
        let (mu_mid_over_r, huge) = self.mu_over_s(r_mid);
        let mu_mid = mu_mid_over_r * r_mid;
        let piece = (b / a).ln();
        let smooth_part = a.lt(b);
        let simpson = piece * ((mu_a + 4.0 * mu_mid + mu_b) / F64x4::splat(6.0) - lim);
        let integral = lim * whole + F64x4::select(smooth_part, simpson, zero);
        let across = p.scale(integral / l) + e.scale(along);
        let mean = Vec3x4::select(only_along, e.scale(along), across);
        let huge = std::array::from_fn(|k| !only_along[k] && smooth_part[k] && huge[k]);
        (mean, huge)
    }

    /// [`StripLaw::saturation_slip`] of the four lanes, m/s.
    #[inline(always)]
    fn saturation_slip(&self) -> F64x4 {
        let e = self.c.min(F64x4::splat(700.0)).exp();
        let r = 0.5 * (e - F64x4::splat(1.0) / e) / self.k;
        F64x4::select(self.k.le(F64x4::splat(0.0)), F64x4::splat(f64::INFINITY), r)
    }

    /// [`StripLaw::saturation_offset`] of the four lanes, m/s.
    #[inline(always)]
    fn saturation_offset(&self) -> F64x4 {
        let c = self.c.min(F64x4::splat(700.0));
        let e = c.exp();
        let cosh_minus_1 = 0.5 * (e + F64x4::splat(1.0) / e) - F64x4::splat(1.0);
        let offset = self.limiting * cosh_minus_1 / (c * self.k);
        F64x4::select(self.k.le(F64x4::splat(0.0)), F64x4::splat(0.0), offset)
    }

    /// [`StripLaw::antiderivative_and_law`] of the four lanes.
    #[inline(always)]
    fn antiderivative_and_law(&self, r: F64x4) -> (F64x4, F64x4) {
        let zero = F64x4::splat(0.0);
        let one = F64x4::splat(1.0);
        let lim = F64x4::splat(self.limiting);
        let x = self.k * r;
        let root = (one + x * x).sqrt();
        let tail = x / (one + root);
        let small = x.lt(F64x4::splat(1e-4));
        // the logarithm's argument kept positive where its branch is not taken
        let arg = (x + x * tail).max(F64x4::splat(1e-4));
        let a = F64x4::select(small, x * (one - x * x / F64x4::splat(6.0)), arg.ln_1p());
        let saturated = self.c.le(a);
        let scale = lim / self.c;
        let m = F64x4::select(
            saturated,
            lim * r - self.saturation_offset(),
            scale * r * (a - tail),
        );
        let mu = F64x4::select(saturated, lim, scale * a);
        let none = x.le(zero);
        (F64x4::select(none, zero, m), F64x4::select(none, zero, mu))
    }

    /// [`StripLaw::mu_over_s`] of the four lanes, 1/(m/s); lanes whose `k s` exceeds
    /// `1e150` are flagged in the mask returned (their value is not this one).
    #[inline(always)]
    pub fn mu_over_s(&self, s: F64x4) -> (F64x4, Mask4) {
        let z = self.k * s;
        let small = z.lt(F64x4::splat(1e-4));
        let huge = F64x4::splat(1e150).lt(z);
        // the Eyring branch's asinh for every lane, its argument kept where it is finite
        let zc = z.max(F64x4::splat(1e-4)).min(F64x4::splat(1e150));
        let z2 = zc * zc;
        let a = (zc + z2 / (F64x4::splat(1.0) + (F64x4::splat(1.0) + z2).sqrt())).ln_1p();
        let lim = F64x4::splat(self.limiting);
        let saturated = self.c.le(a);
        let eyring = F64x4::select(saturated, lim / s, lim * a / (self.c * s));
        let linear = lim * self.k * (F64x4::splat(1.0) - z * z / F64x4::splat(6.0)) / self.c;
        (F64x4::select(small, linear, eyring), huge)
    }
}

/// `asinh z` for `z >= 1e-4`: below [`ASINH_LN_FROM`] as `log1p(z + z^2 / (1 + sqrt(1 +
/// z^2)))`, from it on as `ln(z + sqrt(1 + z^2))`; one square root and one logarithm (the
/// standard library's `asinh` adds a `hypot`, which cost as much as the rest of the strip
/// law); within a few ulp of `f64::asinh` (tested), `ln(2 z)` where `z^2` would overflow.
#[inline(always)]
fn asinh_positive(z: f64) -> f64 {
    if z > 1e150 {
        return z.ln() + std::f64::consts::LN_2;
    }
    let z2 = z * z;
    let root = (1.0 + z2).sqrt();
    if z >= ASINH_LN_FROM {
        // `z + root >= 1.6`: no cancellation in `ln`, and no division
        return (z + root).ln();
    }
    (z + z2 / (1.0 + root)).ln_1p()
}

/// From this argument on [`asinh_positive`] takes `ln(z + sqrt(1 + z^2))`, libm's `log`
/// costing less than its `log1p` (and the form needing no division); the result is at least
/// 0.48 there, so `ln`'s absolute error of half an ulp of its argument's logarithm stays a
/// few ulp of it.
const ASINH_LN_FROM: f64 = 0.5;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::hertz::exact;

    /// Both forms of `asinh_positive` against the standard library's `asinh`, on 1000 points a
    /// decade from 1e-4 to 1e200. Within 4 machine epsilons relative (about 8 ulp of a
    /// result near 0.48): a few roundings in the argument of the logarithm and the
    /// logarithm's own half ulp (measured by the review: 1.9 epsilon at worst).
    #[test]
    fn asinh_positive_is_the_library_asinh_to_a_few_ulp() {
        let mut worst: f64 = 0.0;
        for e in -4..200 {
            for k in 0..1000 {
                let z = (1.0 + 9.0 * k as f64 / 1000.0) * 10f64.powi(e);
                let (a, b) = (asinh_positive(z), z.asinh());
                worst = worst.max(((a - b) / b).abs());
            }
        }
        assert!(
            worst <= 4.0 * f64::EPSILON,
            "worst relative difference {worst:e}"
        );
    }

    /// Z of the preset's oil (4.44 mPa s, 1.5e-8 1/Pa) and of Stachowiak's Table 2.3 spindle
    /// oil at 60 deg C (6.3 mPa s, 16e-9 1/Pa), as the research note computed them by hand
    /// (0.692 and 0.682) with the printed 5.1e-9 1/Pa for 1/p_R: within 0.2 % (the two
    /// constants differ by 0.04 %, the hand figures are rounded to three digits).
    #[test]
    fn roelands_index_of_the_spindle_oils() {
        assert!((roelands_z(4.44e-3, 1.5e-8) / 0.692 - 1.0).abs() < 2e-3);
        assert!((roelands_z(6.3e-3, 16e-9) / 0.682 - 1.0).abs() < 2e-3);
    }

    fn law(q: f64, um: f64) -> ContactRheology {
        let (rx, ry, ep) = (2.364e-3, 20e-3, 2.286e11);
        let hz = exact(rx, ry, ep);
        let r = Rheology {
            eta0: 4.44e-3,
            alpha0: 1.5e-8,
            z: roelands_z(4.44e-3, 1.5e-8),
            limiting: 0.047,
        };
        RheologyTraction::new(ep, rx, &hz, &r).at(q, um)
    }

    /// The local coefficient is the derivative of ln eta (central difference, relative step
    /// 1e-5: truncation ~1e-10, rounding ~1e-11 of alpha), and equals alpha0 at zero pressure.
    #[test]
    fn local_alpha_is_the_slope_of_ln_eta() {
        let c = law(100.0, 9.21);
        for xi in [0.0, 0.5, 0.9] {
            let f = c.strip(xi);
            let p = f.pressure;
            let d = 1e-5 * p;
            let at = |p: f64| {
                let x: f64 = 1.0 + p / ROELANDS_PRESSURE;
                c.ln_eta0 + c.roelands_c * (x.powf(c.z) - 1.0)
            };
            let slope = (at(p + d) - at(p - d)) / (2.0 * d);
            assert!(
                (f.alpha / slope - 1.0).abs() < 1e-8,
                "{xi}: {} {slope}",
                f.alpha
            );
            assert!((f.viscosity.ln() - at(p)).abs() < 1e-12);
        }
        let x0 = law(100.0, 9.21).strip(1.0);
        assert_eq!(x0.pressure, 0.0);
        assert!((x0.alpha / 1.5e-8 - 1.0).abs() < 1e-12);
    }

    /// Linear in slip with slope eta/(h p) at small slip, logarithmic above the Eyring
    /// stress, never above Lambda; mu/s continuous where the series switches in.
    #[test]
    fn shape_of_the_strip_law() {
        let c = law(100.0, 9.21);
        let f = c.strip(0.3);
        let slope = f.viscosity / (c.h * f.pressure);
        assert!((c.mu_over_s(0.3, 0.0) / slope - 1.0).abs() < 1e-15);
        assert!((c.mu(0.3, 1e-9) / (slope * 1e-9) - 1.0).abs() < 1e-6);
        assert!(c.mu(0.3, 10.0) == 0.047 && c.mu(0.3, 1e-3) < 0.047);
        let k = f.viscosity / (f.eyring_stress * c.h);
        let s_switch = 1e-4 / k;
        let below = c.mu_over_s(0.3, s_switch * (1.0 - 1e-9));
        let above = c.mu_over_s(0.3, s_switch * (1.0 + 1e-9));
        assert!((below / above - 1.0).abs() < 1e-9);
    }

    /// Composite Simpson's rule of `f` over `a..b` with `n` (even) intervals.
    fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
        let h = (b - a) / n as f64;
        let inner: f64 = (1..n)
            .map(|i| f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 })
            .sum();
        (f(a) + inner + f(b)) * h / 3.0
    }

    /// The strips of a loaded (100 N, 1000 N) and a nearly unloaded (1 N) contact, and the
    /// edge strip that carries nothing.
    fn strip_laws() -> Vec<StripLaw> {
        let mut laws = vec![];
        for q in [1.0, 100.0, 1000.0] {
            for chord in [1.0, 0.6, 0.0] {
                laws.push(law(q, 9.21).strip_law(chord));
            }
        }
        laws
    }

    /// The four lanes' law is the contact's, law by law and lane by lane: `mu(s)/s` over
    /// slips from 1e-15 to 1e4 m/s (its linear, Eyring and saturated ranges), the strip at
    /// the ellipse's edge (`c` = 1, `k` = 0) included, and the film of four loads at once.
    /// The lanes take `asinh` as `ln_1p` of the lanes (within about 2.4 ulp, lanes.rs),
    /// where the scalar law takes libm's, and `mu/s` two roundings more: 1e-14 (45 ulp)
    /// holds that and no difference of formula.
    #[test]
    fn the_lanes_law_is_the_contacts() {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-14 * b.abs();
        for law in strip_laws() {
            let lanes = StripLawX4 {
                c: F64x4::splat(law.c),
                k: F64x4::splat(law.k),
                limiting: law.limiting,
            };
            for e in -150..40 {
                let s = 10f64.powf(e as f64 / 10.0);
                let slips = F64x4([s, 1.5 * s, 2.5 * s, 7.0 * s]);
                let (got, huge) = lanes.mu_over_s(slips);
                for l in 0..4 {
                    assert!(!huge[l]);
                    let want = law.mu_over_s(slips.0[l]);
                    assert!(
                        close(got.0[l], want),
                        "{:?} at {}: {} {want}",
                        law,
                        slips.0[l],
                        got.0[l]
                    );
                }
            }
        }
        let (rx, ry, ep) = (2.364e-3, 20e-3, 2.286e11);
        let rheology = Rheology {
            eta0: 4.44e-3,
            alpha0: 1.5e-8,
            z: roelands_z(4.44e-3, 1.5e-8),
            limiting: 0.047,
        };
        let r = RheologyTraction::new(ep, rx, &exact(rx, ry, ep), &rheology);
        let loads = [1.0, 30.0, 100.0, 1000.0];
        let speeds = [0.001, 0.5, 9.21, 30.0];
        let q = F64x4(loads);
        let ln_um = F64x4(speeds).max(F64x4::splat(FILM_SPEED_FLOOR)).ln();
        let film = r.at_load_lanes(q.cube_root(), ln_um, q.ln());
        for chord in [1.0, 0.6, 0.0] {
            let lanes = film.strip_law(chord);
            for l in 0..4 {
                let want = r.at(loads[l], speeds[l]).strip_law(chord);
                let got = lanes.lane(l).law;
                assert!(
                    close(got.c, want.c) && close(got.k, want.k),
                    "{got:?} {want:?}"
                );
            }
        }
    }

    /// Slips from far inside the linear range to far beyond saturation, m/s.
    const SLIPS: [f64; 9] = [1e-9, 1e-7, 1e-5, 1e-4, 1e-3, 1e-2, 0.1, 0.5, 2.0];

    /// `M(b) - M(a)` is the integral of the law over `a..b`: against Simpson's rule with
    /// 20000 intervals on each decade, whose error on these smooth pieces is below 1e-12
    /// of the integral, except across the saturation kink, where the law's slope jumps and
    /// the interval holding it errs by `O(h^2)` times the jump, far below 1e-6 here; so
    /// 1e-6. The law is continuous, so `M` is continuous to rounding where the form changes
    /// at saturation.
    #[test]
    fn antiderivative_is_the_integral_of_the_law() {
        for law in strip_laws() {
            for pair in SLIPS.windows(2) {
                let (a, b) = (pair[0], pair[1]);
                let want = simpson(|s| law.mu_over_s(s) * s, a, b, 20_000);
                let got = law.antiderivative_and_law(b).0 - law.antiderivative_and_law(a).0;
                assert!(
                    (got - want).abs() <= 1e-6 * want.abs() + 1e-300,
                    "{law:?} {a}..{b}: {got} against {want}"
                );
            }
            if law.k > 0.0 {
                let r_s = law.c.sinh() / law.k;
                let (below, above) = (
                    law.antiderivative_and_law(r_s * (1.0 - 1e-12)).0,
                    law.antiderivative_and_law(r_s * (1.0 + 1e-12)).0,
                );
                assert!((above - below).abs() <= 1e-10 * below.abs(), "{law:?}");
            }
        }
    }

    /// The mean of `mu(|v|) v/|v|` along the segment `v + tau span`, `tau` in -1/2..1/2, by
    /// Simpson's rule with 200000 intervals (error below 1e-8 of Lambda where the segment
    /// passes a kink), -.
    fn segment_mean(law: &StripLaw, v: Vector3<f64>, span: Vector3<f64>) -> Vector3<f64> {
        let comp = |i: usize| {
            simpson(
                |tau| {
                    let w = v + tau * span;
                    law.mu_over_s(w.norm()) * w[i]
                },
                -0.5,
                0.5,
                200_000,
            )
        };
        Vector3::new(comp(0), comp(1), comp(2))
    }

    /// The cell mean against the segment's mean by quadrature:
    /// - along the span it is exact (to the reference's 1e-8 of Lambda and the
    ///   antiderivative's rounding);
    /// - across it Simpson's rule in `u` (`tau = d sinh u`) on the piece where the law is
    ///   below saturation, the rest exact: measured at most 0.0091 `Lambda` on these
    ///   segments (the 100 N contact's strip at 0.8 of the semi-axis, c = 4.0, on a
    ///   0.3 m/s cell centred on zero slip that passes it at a tenth of its length), so
    ///   0.012. With one Simpson panel over
    ///   the whole line (the rule before 2026-11-28) the segments centred on zero slip
    ///   erred by up to 0.014 `Lambda` on the preset's strips and 0.063 on the gentle
    ///   `c = 0.5` law; the midpoint rule in `u` by 0.043 and the law at the cell's RMS
    ///   slip by 0.12 on the first five segments. A segment through zero slip has no
    ///   across component.
    #[test]
    fn cell_mean_is_the_mean_over_the_cell() {
        let along_dir = Vector3::new(1.0, 0.0, 0.0);
        let mut laws = strip_laws();
        // a gentle law (a light load or a thin oil), whose Eyring bend is wide beside its
        // saturation: where a kink inside one Simpson panel erred most
        for k in [30.0, 300.0, 3000.0] {
            laws.push(StripLaw {
                c: 0.5,
                k,
                limiting: 0.047,
            });
        }
        for law in laws {
            let cell = StripCellLaw { law };
            for span_len in [1e-4, 1e-2, 0.3] {
                for (t, d) in [
                    (0.0, 0.0),
                    (0.3, 0.0),
                    (0.05, 0.003),
                    (-0.2, 0.03),
                    (2.0, 0.2),
                    (0.0, 0.01),
                    (0.0, 0.1),
                    (0.0, 0.3),
                    (0.2, 0.1),
                ] {
                    let v = Vector3::new(t * span_len, d * span_len, 0.0);
                    let span = span_len * along_dir;
                    let got = cell.exact_cell_mean(v, span, span.norm_squared());
                    let want = segment_mean(&law, v, span);
                    let scale = law.limiting;
                    assert!(
                        (got.x - want.x).abs() < 1e-7 * scale,
                        "{law:?} span {span_len} at ({t}, {d}): along {} against {}",
                        got.x,
                        want.x
                    );
                    assert!(got.z == 0.0);
                    if d == 0.0 {
                        assert_eq!(got.y, 0.0);
                    } else {
                        assert!(
                            (got.y - want.y).abs() <= 0.012 * scale,
                            "{law:?} span {span_len} at ({t}, {d}): across {} against {}",
                            got.y,
                            want.y
                        );
                    }
                }
            }
        }
    }

    /// Where the law is smooth on the cell's scale the point value is taken; the blend to
    /// the mean is continuous at both ends of each criterion (to 1e-9 of Lambda across a
    /// relative change of 1e-9 in the span); and where the law is linear in slip (slips of
    /// 1e-9 m/s) the mean's component along the span is the point value's (the across
    /// component is Simpson's, which a linear law does not make exact; the point value is
    /// taken there anyway).
    #[test]
    fn cell_mean_blends_continuously_into_the_point_value() {
        let law = law(1000.0, 9.21).strip_law(1.0);
        let cell = StripCellLaw { law };
        let v = Vector3::new(0.02, 0.001, 0.0);
        let dir = Vector3::new(1.0, 0.3, 0.0).normalize();
        let point = law.mu_over_s(v.norm()) * v;
        // steep everywhere below: the ratio criterion's two ends
        for edge in [CELL_POINT_RATIO, 2.0 * CELL_POINT_RATIO] {
            let l = edge * v.norm();
            let below = cell.cell_mean(v, l * (1.0 - 1e-9) * dir);
            let above = cell.cell_mean(v, l * (1.0 + 1e-9) * dir);
            assert!((below - above).norm() < 1e-9 * law.limiting, "ratio {edge}");
        }
        assert_eq!(cell.cell_mean(v, 0.2 * v.norm() * dir), point);
        // the steepness criterion's two ends, near zero slip (the ratio criterion is met)
        let v0 = Vector3::new(1e-9, 0.0, 0.0);
        for edge in [CELL_STEEPNESS, 2.0 * CELL_STEEPNESS] {
            let l = edge * law.c / law.k;
            let below = cell.cell_mean(v0, l * (1.0 - 1e-9) * dir);
            let above = cell.cell_mean(v0, l * (1.0 + 1e-9) * dir);
            assert!(
                (below - above).norm() < 1e-9 * law.limiting,
                "steepness {edge}"
            );
        }
        // a 1 N strip is linear on 1e-9 m/s
        let light = law_1n();
        let c = StripCellLaw { law: light };
        let tiny = Vector3::new(1e-9, 2e-10, 0.0);
        let mean = c.exact_cell_mean(tiny, 4.0 * tiny.norm() * dir, 16.0 * tiny.norm_squared());
        let pt = light.mu_over_s(tiny.norm()) * tiny;
        let along = (mean - pt).dot(&dir).abs();
        assert!(along <= 1e-12 * pt.norm(), "{mean} {pt}");
    }

    /// The lanes' cell mean is the scalar one, lane by lane, on the tests' strip laws, four
    /// different ones side by side (as the queue gathers them), on slips and cells that
    /// reach each of its branches, each counted: a line partly saturated (cut at its
    /// saturated end), one below saturation, one saturated throughout, one saturated at
    /// both ends but not between, and lines along the slip (through zero, from zero),
    /// where the mean has no across part; with the blends and the mean alone. The lanes' `mu(s)/s` is within 1e-14 of the scalar one (above) and their
    /// logarithms within 2 ulp of libm's (lanes.rs); the mean divides differences of the
    /// antiderivative by the cell, which multiplies those by at most `|v| / |span|`, 4
    /// where the mean is taken (`CELL_POINT_RATIO`). 1e-12 `Lambda` holds that with room,
    /// far below any difference of formula (the quadrature's own error is 1e-2 `Lambda`,
    /// above).
    #[test]
    fn the_lanes_cell_mean_is_the_scalar_one() {
        let laws = strip_laws();
        let mut taken = 0;
        // partly saturated, below saturation, saturated throughout from the line's
        // nearest point, saturated at both ends but not between, along the slip
        let mut branches = [0; 5];
        for first in 0..laws.len() {
            let four: [StripLaw; 4] = std::array::from_fn(|l| laws[(first + 3 * l) % laws.len()]);
            let lanes = StripLawX4::of_lanes(
                F64x4(four.map(|law| law.c)),
                F64x4(four.map(|law| law.k)),
                four[0].limiting,
            );
            for &s in &SLIPS {
                for (angle, ratio) in [
                    (0.0, 1.0),
                    (0.3, 0.5),
                    (1.2, 3.0),
                    (2.9, 10.0),
                    (1.5707, 0.3),
                    // along the slip: through zero, and from zero
                    (f64::NAN, -3.0),
                    (f64::NAN, 0.0),
                ] {
                    let mut v = Vec3x4::ZERO;
                    let mut span = Vec3x4::ZERO;
                    for l in 0..4 {
                        let slip = Vector3::new(s, 0.1 * s * l as f64, 0.0);
                        let size = s * ratio * (1.0 + l as f64);
                        let turn = angle + 0.7 * l as f64;
                        let (slip, cell) = if angle.is_nan() && ratio == 0.0 {
                            (Vector3::zeros(), 2.0 * s * slip.normalize())
                        } else if angle.is_nan() {
                            (slip, ratio * (1.0 + l as f64) * slip)
                        } else {
                            (
                                slip,
                                Vector3::new(size * turn.cos(), size * turn.sin(), 0.2 * size),
                            )
                        };
                        v.set_lane(l, &slip);
                        span.set_lane(l, &cell);
                    }
                    let point = lanes.takes_point_value(v.norm_squared(), span.norm_squared());
                    let (got, huge) = lanes.cell_mean(v, span);
                    for l in 0..4 {
                        if point[l] || huge[l] {
                            continue;
                        }
                        let (vl, sl, law) = (v.lane(l), span.lane(l), four[l]);
                        let want = StripCellLaw { law }.cell_mean(vl, sl);
                        let off = (got.lane(l) - want).norm();
                        assert!(
                            off <= 1e-12 * law.limiting,
                            "{law:?} v {vl} span {sl}: {} against {want}",
                            got.lane(l)
                        );
                        taken += 1;
                        // which branch the scalar mean took
                        let e = sl.normalize();
                        let t = vl.dot(&e);
                        let d2 = (vl - t * e).norm_squared();
                        let r_s = law.saturation_slip();
                        let r = |t: f64| (d2 + t * t).sqrt();
                        let l2 = sl.norm();
                        let (r_lo, r_hi) = (r(t - 0.5 * l2), r(t + 0.5 * l2));
                        let (near, far) = (r_lo.min(r_hi), r_lo.max(r_hi));
                        if d2 <= 1e-30 * l2 * l2 {
                            branches[4] += 1;
                        } else if r_s * r_s <= d2 {
                            branches[2] += 1;
                        } else if far > r_s && near < r_s {
                            branches[0] += 1;
                        } else if far < r_s {
                            branches[1] += 1;
                        } else {
                            branches[3] += 1;
                        }
                    }
                }
            }
        }
        assert!(
            taken > 500 && branches.iter().all(|&n| n > 10),
            "{taken} {branches:?}"
        );
    }

    fn law_1n() -> StripLaw {
        law(1.0, 9.21).strip_law(1.0)
    }
}
