//! Ball-race contact: geometry (eqs. 2-7), Hertz load (eq. 8), EHL traction by strips
//! over the contact ellipse (eqs. 9-18) and the defect modification (eqs. 34-36).

use super::cpu::twice_compiled;
use super::defect::{race_defects_effect, DefectEffect, RaceDefect};
use super::frames::Azimuth;
use super::hertz::{cube_root, HertzContact};
use super::rheology_traction::{ContactRheology, FILM_SPEED_FLOOR};
use super::rolling_resistance::{RollingResistance, ENTRAINMENT_REGULARIZATION};
use super::strips::Strips;
use super::traction::TractionLaw;
use nalgebra::{Matrix3, Vector3};

/// Constant data of one raceway.
#[derive(Debug, Clone, PartialEq)]
pub struct Race {
    /// True for the inner race (ball outside the groove's curvature centre circle).
    pub inner: bool,
    /// Radius of the circle of groove curvature centres in the ring frame, m.
    pub centre_radius: f64,
    /// Axial position of that circle in the ring frame, m.
    pub centre_axial: f64,
    /// Groove radius minus ball radius, `(f - 0.5) D`, m (eq. 7).
    pub free_distance: f64,
    /// Hertz constants of this ball-race pair.
    pub hertz: HertzContact,
    /// Radius of the deformed contact surface across the groove, `2 f D / (2 f + 1)`, m (eq. 9).
    pub r_prime: f64,
    /// Ball radius, m.
    pub ball_radius: f64,
    /// Radius of the contact path (for arc lengths along the race), m.
    pub path_radius: f64,
    /// Relative radius of ball and race in the rolling direction, m (defect drop).
    pub rx: f64,
    /// Defects on this race, in its body frame.
    pub defects: Vec<RaceDefect>,
    /// EHL traction law of this ball-race pair (eqs. 14-15 or the film law).
    pub traction: TractionLaw,
    /// EHL rolling resistance of this ball-race pair; None to leave it out.
    pub rolling: Option<RollingResistance>,
}

/// Motion of a ring.
#[derive(Debug, Clone, Copy)]
pub struct RingMotion {
    /// Centre position, m.
    pub centre: Vector3<f64>,
    /// Body-to-inertial rotation for tilt (spin excluded: the race is axisymmetric).
    pub rot: Matrix3<f64>,
    /// Centre velocity, m/s.
    pub velocity: Vector3<f64>,
    /// Spin about the ring axis, rad/s.
    pub spin: f64,
    /// Spin angle (for defect positions), rad.
    pub spin_angle: f64,
    /// The spin angle as sine and cosine.
    pub spin_azimuth: Azimuth,
    /// False when `rot` is the identity (the outer ring always, the inner ring unless its
    /// tilt is free), so the contact geometry skips three matrix products.
    pub tilted: bool,
}

impl RingMotion {
    pub fn new(
        centre: Vector3<f64>,
        rot: Matrix3<f64>,
        velocity: Vector3<f64>,
        spin: f64,
        spin_angle: f64,
    ) -> RingMotion {
        RingMotion::with_spin_azimuth(
            centre,
            rot,
            velocity,
            spin,
            spin_angle,
            Azimuth::new(spin_angle),
        )
    }

    /// [`RingMotion::new`] with the spin angle's azimuth given (the right-hand side takes
    /// it with the cage's angles in one call of the lanes' `sin_cos`).
    pub fn with_spin_azimuth(
        centre: Vector3<f64>,
        rot: Matrix3<f64>,
        velocity: Vector3<f64>,
        spin: f64,
        spin_angle: f64,
        spin_azimuth: Azimuth,
    ) -> RingMotion {
        RingMotion {
            centre,
            rot,
            velocity,
            spin,
            spin_angle,
            spin_azimuth,
            tilted: rot != Matrix3::identity(),
        }
    }
}

/// Motion of a ball.
#[derive(Debug, Clone, Copy, Default)]
pub struct BallMotion {
    /// Centre position, m.
    pub centre: Vector3<f64>,
    /// Centre velocity, m/s.
    pub velocity: Vector3<f64>,
    /// Angular velocity, rad/s.
    pub omega: Vector3<f64>,
}

/// Contact parameters shared by all race contacts.
#[derive(Debug, Clone)]
pub struct ContactParams {
    pub strips: Strips,
    /// Normal contact damping ratio, -.
    pub damping_ratio: f64,
    /// Ball mass, kg (for the damping coefficient).
    pub ball_mass: f64,
}

/// Forces and geometry of one ball-race contact, all inertial.
#[derive(Debug, Clone, Copy, Default)]
pub struct ContactResult {
    /// Elastic deformation after any defect drop, m (<= 0: no contact).
    pub delta: f64,
    /// Normal load, N.
    pub load: f64,
    /// Contact angle (eq. 5) as sine and cosine.
    pub alpha: Azimuth,
    /// Ball azimuth in the ring's tilt frame (eq. 3) as sine and cosine.
    pub azimuth: Azimuth,
    /// Defect drop applied, m.
    pub defect_drop: f64,
    /// Load direction tilt at a defect edge, rad.
    pub psi: f64,
    /// Force on the ball, N.
    pub force_on_ball: Vector3<f64>,
    /// Moment on the ball about its centre, N m.
    pub moment_on_ball: Vector3<f64>,
    /// Force on the ring, N.
    pub force_on_ring: Vector3<f64>,
    /// Moment on the ring about its centre, N m.
    pub moment_on_ring: Vector3<f64>,
}

/// Geometry of one ball-race pair (eqs. 2-7). The angles are kept as sines and cosines,
/// which is what the forces need; `Azimuth::angle` gives the angle where one is wanted.
#[derive(Debug, Clone, Copy)]
pub struct ContactGeometry {
    /// Deformation before any defect, m (<= 0: no contact).
    pub delta: f64,
    /// Contact angle, eq. 5.
    pub alpha: Azimuth,
    /// Ball azimuth in the ring's tilt frame, eq. 3.
    pub azimuth: Azimuth,
    /// Unit normal from the ball centre towards the contact (inertial).
    pub normal: Vector3<f64>,
    /// Rolling direction, the ring's tangential unit vector at the ball (inertial).
    pub tangent: Vector3<f64>,
}

/// Effect of the race's defects (eqs. 33-36) on a ball contact at `azimuth` (in the
/// ring's tilt frame, eq. 3) of a ring turning with `ring`; none without defects.
#[inline]
pub fn defects_effect_at(race: &Race, ring: &RingMotion, azimuth: &Azimuth) -> DefectEffect {
    if race.defects.is_empty() {
        return DefectEffect::default();
    }
    race_defects_effect(
        &race.defects,
        &azimuth.minus(&ring.spin_azimuth),
        race.path_radius,
        race.rx,
        race.ball_radius,
    )
}

/// Geometry only (eqs. 2-7): deformation, contact angle, azimuth and the unit normal
/// from the curvature centre through the ball centre (inertial).
#[inline(always)]
pub fn contact_geometry(
    race: &Race,
    ring: &RingMotion,
    ball_centre: &Vector3<f64>,
) -> ContactGeometry {
    // eq. 2: ball relative to the ring, in ring (tilt) coordinates
    let rel = ball_centre - ring.centre;
    let p = if ring.tilted {
        ring.rot.transpose() * rel
    } else {
        rel
    };
    // eq. 3, sin and cos of theta straight from the coordinates
    let rho = (p.y * p.y + p.z * p.z).sqrt();
    let (s, c) = if rho > 0.0 {
        (-p.y / rho, p.z / rho)
    } else {
        // a ball centre on the axis: no geometry can hold it there; any azimuth will do
        (0.0, 1.0)
    };
    // eq. 4: from the curvature centre to the ball centre, in the azimuth plane
    let dx = p.x - race.centre_axial;
    let dr = rho - race.centre_radius;
    let dist = (dx * dx + dr * dr).sqrt();
    // eq. 7
    let delta = dist - race.free_distance;
    // eq. 5: the normal points from ball centre to contact; for the outer race that is
    // (sin a, cos a) in (axial, radial), for the inner race -(sin a, cos a).
    let sign = if race.inner { -1.0 } else { 1.0 };
    let alpha = Azimuth {
        sin: sign * dx / dist,
        cos: sign * dr / dist,
    };
    let u_body = Vector3::new(dx / dist, -s * dr / dist, c * dr / dist);
    let t_body = Vector3::new(0.0, -c, -s);
    let (normal, tangent) = if ring.tilted {
        (ring.rot * u_body, ring.rot * t_body)
    } else {
        (u_body, t_body)
    };
    ContactGeometry {
        delta,
        alpha,
        azimuth: Azimuth { sin: s, cos: c },
        normal,
        tangent,
    }
}

twice_compiled! {
    /// Full contact: Hertz load with damping, defect modification, traction by strips.
    ///
    /// Compiled twice (`super::cpu`): with AVX2 and FMA the strip loop's arithmetic runs in
    /// wider vectors; the two copies give the same numbers.
    pub fn race_contact(
        race: &Race,
        ring: &RingMotion,
        ball: &BallMotion,
        p: &ContactParams,
    ) -> ContactResult = race_contact_body, wide race_contact_avx2;
}

#[inline(always)]
fn race_contact_body(
    race: &Race,
    ring: &RingMotion,
    ball: &BallMotion,
    p: &ContactParams,
) -> ContactResult {
    let g = contact_geometry(race, ring, &ball.centre);
    let (delta0, u, t) = (g.delta, g.normal, g.tangent);
    let mut out = ContactResult {
        alpha: g.alpha,
        azimuth: g.azimuth,
        delta: delta0,
        ..Default::default()
    };
    if delta0 <= 0.0 {
        return out;
    }
    let eff = defects_effect_at(race, ring, &g.azimuth);
    let delta = delta0 - eff.drop;
    out.delta = delta;
    out.defect_drop = eff.drop;
    out.psi = eff.psi;
    if delta <= 0.0 {
        return out;
    }
    let k = race.hertz.k;
    let sq = delta.sqrt();
    // normal approach rate: ball centre moving away from the curvature centre compresses
    let ddelta = u.dot(&(ball.velocity - ring.velocity));
    let c_damp = 2.0 * p.damping_ratio * (1.5 * k * sq * p.ball_mass).sqrt();
    let q = (k * delta * sq + c_damp * ddelta).max(0.0);
    out.load = q;
    if q == 0.0 {
        return out;
    }
    // Load direction: normal, turned by psi towards +t at a defect edge (eq. 36).
    let (sp, cp) = if eff.psi == 0.0 {
        (0.0, 1.0)
    } else {
        eff.psi.sin_cos()
    };
    let normal_force_on_ball = -q * cp * u + q * sp * t;

    let r_contact = ball.centre - ring.centre + race.ball_radius * u;
    // entrainment velocity, only when the film law or the rolling resistance reads it
    let (um, load) = if race.traction.needs_entrainment() || race.rolling.is_some() {
        let um = entrainment_velocity(ring, ball, &u, race.ball_radius, &r_contact);
        (um, ContactLoad::new(q, um.norm()))
    } else {
        (Vector3::zeros(), ContactLoad::without_entrainment(q))
    };
    let (f_tr, m_ball, m_ring_strips) = strip_traction(race, ring, ball, p, &load, &u, &t);
    // eq. 18
    let f_ball = normal_force_on_ball + f_tr;
    out.force_on_ball = f_ball;
    out.moment_on_ball = m_ball;
    out.force_on_ring = -f_ball;
    out.moment_on_ring = m_ring_strips + r_contact.cross(&(-normal_force_on_ball));
    if let Some(rr) = &race.rolling {
        rolling_resistance(rr, &load, &um, race.ball_radius * u, &r_contact, &mut out);
    }
    out
}

/// What the laws of one contact read of its load and entrainment, computed once for all of
/// them: the ellipse's size, the film and the rolling resistance.
#[derive(Debug, Clone, Copy)]
pub struct ContactLoad {
    /// Normal load, N (> 0).
    pub q: f64,
    /// Its cube root, N^(1/3).
    pub q13: f64,
    /// Entrainment speed, m/s.
    pub speed: f64,
    /// The speed floored at [`ENTRAINMENT_REGULARIZATION`], m/s: at or below every law's
    /// own floor, which [`RheologyTraction`](super::rheology_traction::RheologyTraction)
    /// applies again to the logarithm.
    pub floored: f64,
    /// `ln` of `floored` (of m/s).
    pub ln_floored: f64,
}

/// `ln` [`ENTRAINMENT_REGULARIZATION`] (of m/s), what [`ContactLoad::without_entrainment`]
/// holds (tested against `f64::ln`).
const LN_ENTRAINMENT_REGULARIZATION: f64 = -6.907_755_278_982_137;

// the film's logarithm is the contact's floored again at the film's floor (see `floored`),
// which gives the film's own only if the contact's floor is the lower
const _: () = assert!(ENTRAINMENT_REGULARIZATION <= FILM_SPEED_FLOOR);

impl ContactLoad {
    /// At load `q` (N, > 0) and entrainment speed `speed` (m/s).
    #[inline(always)]
    pub fn new(q: f64, speed: f64) -> ContactLoad {
        let floored = speed.max(ENTRAINMENT_REGULARIZATION);
        ContactLoad {
            q,
            q13: cube_root(q),
            speed,
            floored,
            ln_floored: floored.ln(),
        }
    }

    /// At load `q` (N, > 0) where no law reads the entrainment (the traction curve without
    /// rolling resistance): a zero speed, as the contact took before it shared the
    /// logarithm, without taking one.
    #[inline(always)]
    pub fn without_entrainment(q: f64) -> ContactLoad {
        ContactLoad {
            q,
            q13: cube_root(q),
            speed: 0.0,
            floored: ENTRAINMENT_REGULARIZATION,
            ln_floored: LN_ENTRAINMENT_REGULARIZATION,
        }
    }
}

/// Entrainment velocity of a contact: the mean of the two surfaces' velocities at the
/// contact point relative to the ball centre (which the contact moves with), in the
/// tangent plane, m/s. `r_contact` is the contact point from the ring centre.
#[inline]
pub(crate) fn entrainment_velocity(
    ring: &RingMotion,
    ball: &BallMotion,
    u: &Vector3<f64>,
    ball_radius: f64,
    r_contact: &Vector3<f64>,
) -> Vector3<f64> {
    let ring_axis = ring.rot * Vector3::x();
    let v_ball = ball.omega.cross(&(ball_radius * u));
    let v_ring = ring.velocity + ring.spin * ring_axis.cross(r_contact) - ball.velocity;
    let um = 0.5 * (v_ball + v_ring);
    um - um.dot(u) * u
}

/// Add the EHL rolling resistance of a contact carrying `q` (N) with entrainment velocity
/// `um` (m/s) to its forces; `r_b` is the contact point from the ball centre (m).
///
/// An assumption (attributed to Bălan et al. 2015, not read; docs/reference/model.md): the
/// film's shear brakes each surface with `F_R` at the contact,
/// against its motion relative to the contact, and the film pressure pushes the ball's
/// centre with `2 F_R` the other way. On the ball that is a net force `F_R` along the
/// entrainment velocity (backwards for a rolling ball) and the moment of the shear about
/// its centre; the ring takes the opposite net force at the contact, so momentum is kept.
///
/// Always inlined, so it is compiled into the contact's AVX2 copy too: as a call it ran
/// baseline code, 8.9 % of a Table-1 run (perf, 2026-11-29).
#[inline(always)]
fn rolling_resistance(
    rr: &RollingResistance,
    load: &ContactLoad,
    um: &Vector3<f64>,
    r_b: Vector3<f64>,
    r_contact: &Vector3<f64>,
    out: &mut ContactResult,
) {
    let f = rr.force_along_given(load.q, load.q13, um, load.floored, load.ln_floored);
    out.force_on_ball += f;
    out.moment_on_ball -= r_b.cross(&f);
    out.force_on_ring -= f;
    out.moment_on_ring -= r_contact.cross(&f);
}

/// EHL traction of one contact carrying `load` with unit normal `u` and rolling direction
/// `t` (its entrainment speed read by the film laws only), by strips across the
/// ellipse's major axis (eqs. 9-16): the force on the ball (N), its moment about the ball
/// centre and the reaction's moment about the ring centre (N m).
#[inline(always)]
pub fn strip_traction(
    race: &Race,
    ring: &RingMotion,
    ball: &BallMotion,
    p: &ContactParams,
    load: &ContactLoad,
    u: &Vector3<f64>,
    t: &Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    // s_hat spans the axial-radial plane across the rolling direction.
    let s_hat = u.cross(t);
    let (q, q13) = (load.q, load.q13);
    let a = race.hertz.a_coef * q13;
    let rb = race.ball_radius;
    let a_eff = a.min(0.999 * rb);
    let rp = race.r_prime;
    let base = -(rp * rp - a_eff * a_eff).sqrt() + (rb * rb - a_eff * a_eff).sqrt();
    let ring_axis = ring.rot * Vector3::x();
    let ball_to_ring = ball.centre - ring.centre;
    // eqs. 10-12: the slip of the ring relative to the ball at the strip point
    // r_pb = h u + y s_hat is linear in (h, y), so it is `c0 + h c1 + y c2`, and so is its
    // part in the tangent plane: three vectors per contact instead of two cross products and
    // a projection per strip.
    let tangential = |v: Vector3<f64>| v - v.dot(u) * u;
    let c0 = tangential(ring.velocity + ring.spin * ring_axis.cross(&ball_to_ring) - ball.velocity);
    let c1 = tangential(ring.spin * ring_axis.cross(u) - ball.omega.cross(u));
    let c2 = tangential(ring.spin * ring_axis.cross(&s_hat) - ball.omega.cross(&s_hat));
    // Sum the tractions and their first moments in h and y: the moments of all strips about
    // the ball centre are then `u x sum(h tr) + s_hat x sum(y tr)`. One loop per law
    // (monomorphised), so the strips do not branch on it.
    let strips = StripSums {
        p,
        a_eff,
        rp,
        base,
        q,
        c: [c0, c1, c2],
    };
    // (matched on the pair's law, so the curve builds no per-contact state)
    let (f_tr, f_h, f_y) = match &race.traction {
        TractionLaw::Curve(curve) => strips.sum(|_| (), |_, s| curve.mu_over_s(s)),
        TractionLaw::Film(law) => {
            let film = law.at(q, load.speed);
            strips.sum(|_| (), |_, s| film.mu_over_s(0.0, s))
        }
        TractionLaw::Rheology(law) => {
            let film = law.at_load(q, q13, load.ln_floored);
            // the film of a strip depends on its pressure, so on |xi| alone: once per pair;
            // where the law is steep on a cell's scale, its mean over the cell
            strips.sum_cells(&film)
        }
    };
    let m_ball = u.cross(&f_h) + s_hat.cross(&f_y);
    // the ring takes each strip's reaction at r_pr = ball_to_ring + r_pb
    let m_ring = -(ball_to_ring.cross(&f_tr) + m_ball);
    (f_tr, m_ball, m_ring)
}

/// What the strip loop of one contact needs: the strips, the ellipse's effective semi-axis
/// (m), the deformed surface's radius and offset (m), the load (N) and the slip's linear
/// coefficients `c0 + h c1 + y c2` (m/s, 1/s).
struct StripSums<'a> {
    p: &'a ContactParams,
    a_eff: f64,
    rp: f64,
    base: f64,
    q: f64,
    c: [Vector3<f64>; 3],
}

/// Mirror pairs of strips per pass of [`StripSums::sum`]: its stack arrays' length.
const PAIR_CHUNK: usize = 4;

impl StripSums<'_> {
    /// Sum of the strip tractions on the ball and their first moments in h and y (eqs. 9-16).
    ///
    /// Pair by pair (`Strips::pairs`): the strips at `-y` and `+y` share their distance `h`
    /// from the ball centre, so their slips are `c0 + h c1 -+ y c2`, and whatever the law
    /// computes from `|xi|` alone (`pair_law`, given the pair's half-chord ratio) is
    /// computed once for both. In passes of up to [`PAIR_CHUNK`] pairs, each in three
    /// loops: the slips and their speeds, the traction coefficients, the sums. The strips
    /// are independent until they are summed, so the processor overlaps their square roots,
    /// exponentials and divisions, which in one fused loop waited on each other around the
    /// calls into libm. Each strip's slip and coefficient are those of the strip alone; the
    /// sums take a pair's tractions together (`sum tr`, `h sum tr`, `y (tr+ - tr-)`).
    #[inline(always)]
    fn sum<L: Copy>(
        &self,
        pair_law: impl Fn(f64) -> L,
        mu_over_s: impl Fn(L, f64) -> f64,
    ) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
        let [c0, c1, c2] = self.c;
        let mut f_tr = Vector3::zeros();
        let mut f_h = Vector3::zeros();
        let mut f_y = Vector3::zeros();
        for pass in self.p.strips.pairs.chunks(PAIR_CHUNK) {
            let mut h = [0.0; PAIR_CHUNK];
            let mut y = [0.0; PAIR_CHUNK];
            let mut v_minus = [Vector3::zeros(); PAIR_CHUNK];
            let mut v_plus = [Vector3::zeros(); PAIR_CHUNK];
            let mut s_minus = [0.0; PAIR_CHUNK];
            let mut s_plus = [0.0; PAIR_CHUNK];
            for (k, pair) in pass.iter().enumerate() {
                y[k] = self.a_eff * pair.xi;
                // eq. 9: strip position relative to the ball centre
                h[k] = (self.rp * self.rp - y[k] * y[k]).sqrt() + self.base;
                let centre = c0 + h[k] * c1;
                let across = y[k] * c2;
                v_minus[k] = centre - across;
                v_plus[k] = centre + across;
                s_minus[k] = v_minus[k].norm();
                s_plus[k] = v_plus[k].norm();
            }
            // eqs. 13-16: traction on the ball along the slip of the ring relative to the ball
            let mut g_minus = [0.0; PAIR_CHUNK];
            let mut g_plus = [0.0; PAIR_CHUNK];
            for (k, pair) in pass.iter().enumerate() {
                let law = pair_law(pair.chord);
                g_minus[k] = self.q * pair.weight_minus * mu_over_s(law, s_minus[k]);
                g_plus[k] = self.q * pair.weight_plus * mu_over_s(law, s_plus[k]);
            }
            for k in 0..pass.len() {
                let tr_minus = g_minus[k] * v_minus[k];
                let tr_plus = g_plus[k] * v_plus[k];
                let tr = tr_minus + tr_plus;
                f_tr += tr;
                f_h += h[k] * tr;
                f_y += y[k] * (tr_plus - tr_minus);
            }
        }
        (f_tr, f_h, f_y)
    }

    /// [`StripSums::sum`] with each strip's law averaged over its cell
    /// ([`cell_mean`](super::rheology_traction::StripCellLaw::cell_mean)): the slip at `y`
    /// changes along the strip line by `dv/dy = h'(y) c1 + c2`,
    /// `h'(y) = -y / sqrt(r'^2 - y^2)`, so across the cell by `dv/dy a cell`. Given the contact's film rather than a closure making each pair's law
    /// of it: as a closure the film was compiled out of line for the baseline processor and
    /// called from the AVX2 copy of the contact, 11 % of a Table-1 run (perf, 2026-11-29).
    #[inline(always)]
    fn sum_cells(&self, film: &ContactRheology) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
        let [c0, c1, c2] = self.c;
        let mut f_tr = Vector3::zeros();
        let mut f_h = Vector3::zeros();
        let mut f_y = Vector3::zeros();
        for pair in &self.p.strips.pairs {
            let y = self.a_eff * pair.xi;
            let root = (self.rp * self.rp - y * y).sqrt();
            let h = root + self.base;
            let centre = c0 + h * c1;
            let across = y * c2;
            let cell = self.a_eff * pair.cell;
            let law = film.strip_cell_law(pair.chord);
            let tr_minus = (self.q * pair.weight_minus)
                * law.cell_mean(centre - across, self.slip_change(-y, root, cell));
            let tr_plus = (self.q * pair.weight_plus)
                * law.cell_mean(centre + across, self.slip_change(y, root, cell));
            f_tr += tr_minus + tr_plus;
            f_h += h * (tr_minus + tr_plus);
            f_y += y * (tr_plus - tr_minus);
        }
        (f_tr, f_h, f_y)
    }

    /// The slip's change across a cell of length `cell` (m) centred on the strip at `y`
    /// (m/s): `dv/dy cell` with `dv/dy = h'(y) c1 + c2` and `h'(y) = -y / root`, `root`
    /// being `sqrt(r'^2 - y^2)`, which a strip and its mirror share.
    #[inline(always)]
    fn slip_change(&self, y: f64, root: f64, cell: f64) -> Vector3<f64> {
        let [_, c1, c2] = self.c;
        (-y / root * cell) * c1 + cell * c2
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::rheology_traction::{roelands_z, Rheology, RheologyTraction};
    use crate::physics::strips::StripRule;
    use crate::physics::traction::TractionCurve;

    /// The preset's oil: 4.44 mPa s, 1.5e-8 1/Pa, Lambda 0.047.
    fn oil() -> Rheology {
        Rheology {
            eta0: 4.44e-3,
            alpha0: 1.5e-8,
            z: roelands_z(4.44e-3, 1.5e-8),
            limiting: 0.047,
        }
    }

    /// The cell's slip change is the slip's derivative along the strip line times the
    /// cell, at both strips of a pair, with every coefficient nonzero: against a central
    /// difference of `c0 + h(y) c1 + y c2` over a cell of 1e-4 of the semi-axis, whose
    /// error is `O(cell^2)` of the change, ~1e-8 here, so 1e-7.
    #[test]
    fn cell_slip_change_is_the_slips_derivative() {
        let params = params();
        let (a_eff, rp, base) = (2.0e-4, 2.9e-3, -1.0e-5);
        let sums = StripSums {
            p: &params,
            a_eff,
            rp,
            base,
            q: 100.0,
            c: [
                Vector3::new(0.3, -0.2, 0.01),
                Vector3::new(40.0, 25.0, -3.0),
                Vector3::new(-12.0, 5.0, 8.0),
            ],
        };
        let slip = |y: f64| {
            let [c0, c1, c2] = sums.c;
            c0 + ((rp * rp - y * y).sqrt() + base) * c1 + y * c2
        };
        let cell = 1e-4 * a_eff;
        for xi in [0.0, 0.3, 0.9] {
            for y in [xi * a_eff, -xi * a_eff] {
                let root = (rp * rp - y * y).sqrt();
                let got = sums.slip_change(y, root, cell);
                let want = slip(y + 0.5 * cell) - slip(y - 0.5 * cell);
                assert!(
                    (got - want).norm() <= 1e-7 * want.norm(),
                    "y {y}: {got} against {want}"
                );
            }
        }
    }

    /// One fused loop over the mirror pairs in which every strip computes its own slip and
    /// coefficient `mu_over_s(xi, s)` from its own `xi`, summed in the pairs' order.
    fn fused_pairs(
        sums: &StripSums,
        mu_over_s: impl Fn(f64, f64) -> f64,
    ) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
        let (strips, c) = (&sums.p.strips, sums.c);
        let n = strips.len();
        let strip = |i: usize| {
            let y = sums.a_eff * strips.xi[i];
            let h = (sums.rp * sums.rp - y * y).sqrt() + sums.base;
            let v = c[0] + h * c[1] + y * c[2];
            let tr = (sums.q * strips.weight[i] * mu_over_s(strips.xi[i], v.norm())) * v;
            (y, h, tr)
        };
        let (mut f_tr, mut f_h, mut f_y) = (Vector3::zeros(), Vector3::zeros(), Vector3::zeros());
        for i in 0..n.div_ceil(2) {
            let j = n - 1 - i;
            let (y, h, tr_plus) = strip(j);
            let tr_minus = if i == j { Vector3::zeros() } else { strip(i).2 };
            f_tr += tr_minus + tr_plus;
            f_h += h * (tr_minus + tr_plus);
            f_y += y * (tr_plus - tr_minus);
        }
        (f_tr, f_h, f_y)
    }

    /// The strips in passes of mirror pairs give exactly the sums of one fused loop over
    /// the pairs in which every strip computes its own slip and coefficient from its own
    /// `xi` (as the loop did before the pairs), for strip counts below, at and across the
    /// pass length, odd and even, both rules; under the curve and under the rheology law,
    /// whose film the pair shares.
    #[test]
    fn passes_sum_exactly_as_one_fused_loop() {
        let curve = TractionCurve {
            a: 0.05,
            b: 0.2,
            c: 8.0,
            d: 0.03,
        };
        let film = {
            let (rx, ep) = (2.364e-3, 2.286e11);
            RheologyTraction::new(ep, rx, &crate::physics::hertz::exact(rx, 20e-3, ep), &oil())
                .at(80.0, 9.0)
        };
        // slips of 0.1-0.5 m/s across the strips, and some in the regularised zone
        let c = [
            Vector3::new(0.3, -0.2, 0.01),
            Vector3::new(40.0, 25.0, -3.0),
            Vector3::new(-12.0, 5.0, 8.0),
        ];
        let slow = [
            Vector3::new(2e-4, 0.0, 0.0),
            Vector3::zeros(),
            Vector3::new(1.0, 0.0, 0.0),
        ];
        for rule in [StripRule::Equal, StripRule::Gauss] {
            for n in [1usize, 7, 8, 9, 10, 17, 200] {
                for c in [c, slow] {
                    let p = ContactParams {
                        strips: Strips::new(n, rule),
                        damping_ratio: 0.0,
                        ball_mass: 0.0,
                    };
                    let sums = StripSums {
                        p: &p,
                        a_eff: 2e-4,
                        rp: 3.6e-3,
                        base: -1e-4,
                        q: 80.0,
                        c,
                    };
                    let got = sums.sum(|_| (), |_, s| curve.mu_over_s(s));
                    let want = fused_pairs(&sums, |_, s| curve.mu_over_s(s));
                    assert_eq!(got, want, "curve, {rule:?} {n} strips");
                    let got = sums.sum(|chord| film.strip_law(chord), |l, s| l.mu_over_s(s));
                    let want = fused_pairs(&sums, |xi, s| film.mu_over_s(xi, s));
                    assert_eq!(got, want, "rheology, {rule:?} {n} strips");
                }
            }
        }
    }

    /// Traction along the rolling direction (N) of a contact of the H7005C's inner race
    /// carrying `q` (N), whose slip is `s0` (m/s) at the centre strip and grows by `g` (m/s)
    /// per semi-axis across the ellipse (the ball's spin), by the strips of `p`: as sampled
    /// at the strips (`cells` false) or as the rheology law's strip loop takes it (cell
    /// means).
    fn rolling_traction(p: &ContactParams, q: f64, s0: f64, g: f64, cells: bool) -> f64 {
        let (rx, ep) = (2.364e-3, 2.286e11);
        let hz = crate::physics::hertz::exact(rx, 49.07e-3, ep);
        let film = RheologyTraction::new(ep, rx, &hz, &oil()).at(q, 9.21);
        let a = hz.a_coef * q.cbrt();
        let t_hat = Vector3::x();
        let sums = StripSums {
            p,
            a_eff: a,
            rp: 1.0,
            base: -1.0,
            q,
            c: [s0 * t_hat, Vector3::zeros(), (g / a) * t_hat],
        };
        let (f, _, _) = if cells {
            sums.sum_cells(&film)
        } else {
            sums.sum(|chord| film.strip_law(chord), |l, s| l.mu_over_s(s))
        };
        f.x
    }

    /// At ten times Table 1's load a loaded strip saturates within micrometres per second
    /// of slip, so 10 point samples make the contact's traction a staircase in the ball's
    /// slip: nearly flat between samples, nearly vertical where one changes sign. The cell
    /// means follow the integral's slope instead. Slip at the centre over +-0.3 of the spin's
    /// spread `g` (0.5 m/s per semi-axis), on a grid of 6001 points:
    /// - the point samples' steepest slope is over 50 times the converged integral's (200
    ///   strips with cell means, whose centre cells are about 17 times narrower; measured
    ///   1.9e3 times);
    /// - the cell means' steepest slope is within 2 times the converged one's (measured
    ///   1.5: a cell mean is the integral of a strip law that ignores the load's and the
    ///   pressure's change within the cell);
    /// - the cell means' traction is within 3 % of `Lambda q` of the converged one
    ///   (measured 0.65 %), where the point samples' is off by up to 20 % (measured).
    #[test]
    fn cell_means_follow_the_integral_where_point_samples_make_a_staircase() {
        let (q, g) = (1000.0, 0.5);
        let grid: Vec<f64> = (0..=6000)
            .map(|i| -0.3 * g + 0.6 * g * i as f64 / 6000.0)
            .collect();
        let slopes = |f: &dyn Fn(f64) -> f64| -> (Vec<f64>, Vec<f64>) {
            let v: Vec<f64> = grid.iter().map(|&s| f(s)).collect();
            let d = v
                .windows(2)
                .zip(grid.windows(2))
                .map(|(v, s)| (v[1] - v[0]) / (s[1] - s[0]))
                .collect();
            (v, d)
        };
        let strips = |n| ContactParams {
            strips: Strips::new(n, StripRule::Gauss),
            damping_ratio: 0.0,
            ball_mass: 0.0,
        };
        let (fine, ten) = (strips(200), strips(10));
        let (reference, ref_slope) = slopes(&|s| rolling_traction(&fine, q, s, g, true));
        let (cells, cell_slope) = slopes(&|s| rolling_traction(&ten, q, s, g, true));
        let (points, point_slope) = slopes(&|s| rolling_traction(&ten, q, s, g, false));
        let max = |v: &[f64]| v.iter().cloned().fold(f64::MIN, f64::max);
        let worst = |v: &[f64]| {
            v.iter()
                .zip(&reference)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
                / (0.047 * q)
        };
        let steepest = max(&ref_slope);
        eprintln!(
            "steepest slope: points {:.3e}, cells {:.3e}, reference {:.3e} N s/m; worst error: cells {:.4}, points {:.4} of Lambda q",
            max(&point_slope), max(&cell_slope), steepest, worst(&cells), worst(&points)
        );
        assert!(max(&point_slope) > 50.0 * steepest);
        assert!(max(&cell_slope) < 2.0 * steepest);
        assert!(worst(&cells) < 0.03);
    }

    /// The strip loop as it was written before it was factored: every strip's slip from its
    /// own cross products and projection (kept to check the factored one).
    fn reference_strip_traction(
        race: &Race,
        ring: &RingMotion,
        ball: &BallMotion,
        p: &ContactParams,
        q: f64,
        u: &Vector3<f64>,
        t: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
        // the curve law of the test race (no entrainment speed needed)
        let law = race.traction.at(q, 0.0);
        let s_hat = u.cross(t);
        let a = race.hertz.a_coef * q.cbrt();
        let rb = race.ball_radius;
        let a_eff = a.min(0.999 * rb);
        let rp = race.r_prime;
        let base = -(rp * rp - a_eff * a_eff).sqrt() + (rb * rb - a_eff * a_eff).sqrt();
        let n = p.strips.len();
        let dy = 2.0 * a_eff / n as f64;
        let mut wsum = 0.0;
        for i in 0..n {
            let y = -a_eff + (i as f64 + 0.5) * dy;
            wsum += 1.0 - (y * y) / (a_eff * a_eff);
        }
        let ring_axis = ring.rot * Vector3::x();
        let (mut f_tr, mut m_ball, mut m_ring) =
            (Vector3::zeros(), Vector3::zeros(), Vector3::zeros());
        let ball_to_ring = ball.centre - ring.centre;
        for i in 0..n {
            let y = -a_eff + (i as f64 + 0.5) * dy;
            let w = (1.0 - (y * y) / (a_eff * a_eff)) / wsum;
            let h = (rp * rp - y * y).sqrt() + base;
            let r_pb = h * u + y * s_hat;
            let v_ball = ball.velocity + ball.omega.cross(&r_pb);
            let r_pr = ball_to_ring + r_pb;
            let v_ring = ring.velocity + ring.spin * ring_axis.cross(&r_pr);
            let mut v = v_ring - v_ball;
            v -= v.dot(u) * u;
            let tr = (q * w * law.mu_over_s(y / a_eff, v.norm())) * v;
            f_tr += tr;
            m_ball += r_pb.cross(&tr);
            m_ring -= r_pr.cross(&tr);
        }
        (f_tr, m_ball, m_ring)
    }

    // H7005C-like outer race: 41.562 mm groove, f = 0.536, 5.556 mm ball.
    const D: f64 = 5.556e-3;
    const F: f64 = 0.536;

    fn outer_race() -> Race {
        Race {
            inner: false,
            centre_radius: 0.5 * 41.562e-3 - F * D,
            centre_axial: 0.0,
            free_distance: (F - 0.5) * D,
            hertz: HertzContact {
                k: 8.0e9,
                a_coef: 1.0e-4,
                b_coef: 1.5e-5,
            },
            r_prime: 2.0 * F * D / (2.0 * F + 1.0),
            ball_radius: 0.5 * D,
            path_radius: 0.5 * 41.562e-3,
            rx: 0.5 * D,
            defects: vec![],
            // constant mu = 0.05 above 1 mm/s
            traction: TractionLaw::Curve(TractionCurve {
                a: 0.0,
                b: 0.0,
                c: 0.0,
                d: 0.05,
            }),
            rolling: None,
        }
    }

    fn ring_at_rest(spin: f64) -> RingMotion {
        RingMotion::new(
            Vector3::zeros(),
            Matrix3::identity(),
            Vector3::zeros(),
            spin,
            0.0,
        )
    }

    fn params() -> ContactParams {
        ContactParams {
            strips: Strips::new(10, StripRule::Equal),
            damping_ratio: 0.05,
            ball_mass: 0.7e-3,
        }
    }

    /// Ball at azimuth 0 (+Z), its centre `free_distance + delta` from the curvature centre
    /// at the contact angle `alpha`: outwards (+Z) and axially (+X) towards the groove.
    fn ball_at(race: &Race, alpha: f64, delta: f64, omega: Vector3<f64>) -> BallMotion {
        let d = race.free_distance + delta;
        BallMotion {
            centre: Vector3::new(
                race.centre_axial + d * alpha.sin(),
                0.0,
                race.centre_radius + d * alpha.cos(),
            ),
            velocity: Vector3::zeros(),
            omega,
        }
    }

    /// The contact floors the speed's logarithm at the rolling resistance's regularization
    /// speed, below the film's floor; the film law floors it again at its own, which gives
    /// the film of the speed floored at the film's floor exactly (the logarithm is
    /// monotonic), on either side of both floors. And the constant logarithm of a contact
    /// without entrainment is the floor's.
    #[test]
    fn film_from_the_contacts_logarithm_is_the_films_of_the_speed() {
        let (rx, ry, ep) = (2.364e-3, 20e-3, 2.286e11);
        let oil = oil();
        let law = RheologyTraction::new(ep, rx, &crate::physics::hertz::exact(rx, ry, ep), &oil);
        let q = 37.0;
        for um in [0.0, 5e-4, 1e-3, 5e-3, 0.01, 0.0100001, 2.0, 9.21] {
            let load = ContactLoad::new(q, um);
            assert_eq!(
                law.at_load(q, load.q13, load.ln_floored),
                law.at(q, um),
                "{um}"
            );
        }
        assert_eq!(
            LN_ENTRAINMENT_REGULARIZATION,
            ENTRAINMENT_REGULARIZATION.ln()
        );
        let still = ContactLoad::without_entrainment(q);
        assert_eq!(still.ln_floored, still.floored.ln());
    }

    #[test]
    fn factored_strip_loop_equals_the_direct_one() {
        // Slip terms factored per contact (c0 + h c1 + y c2) are the same sums as each
        // strip's own cross products, up to rounding: 1e-12 of the force and moment scales.
        let race = outer_race();
        let p = params();
        for i in 0..6 {
            let f = (i + 1) as f64;
            let alpha = 0.15 + 0.04 * f;
            let mut ball = ball_at(
                &race,
                alpha,
                2e-6,
                Vector3::new(50.0 * f, 3000.0, -700.0 / f),
            );
            ball.velocity = Vector3::new(0.01 * f, -0.3, 0.02);
            let ring = RingMotion::new(
                Vector3::new(1e-6 * f, -2e-6, 3e-6),
                Matrix3::new(1.0, -1e-3, 2e-3, 1e-3, 1.0, 0.0, -2e-3, 0.0, 1.0),
                Vector3::new(0.0, 0.05, -0.02),
                300.0 * f,
                0.0,
            );
            // any unit normal and rolling direction will do for the identity
            let u = Vector3::new(alpha.sin(), 0.1 * f.sin(), alpha.cos()).normalize();
            let t = u.cross(&Vector3::new(0.3, 1.0, -0.2)).normalize();
            let q = 20.0 * f;
            let new = strip_traction(&race, &ring, &ball, &p, &ContactLoad::new(q, 0.0), &u, &t);
            let old = reference_strip_traction(&race, &ring, &ball, &p, q, &u, &t);
            let ms = q * race.ball_radius;
            for (name, a, b, scale) in [
                ("force", new.0, old.0, q),
                ("moment on ball", new.1, old.1, ms),
                // about the ring centre, ~20 mm away
                ("moment on ring", new.2, old.2, q * 0.03),
            ] {
                assert!(a.norm() > 1e-3 * scale, "case {i}: no {name} to compare");
                assert!(
                    (a - b).norm() < 1e-12 * scale,
                    "case {i} {name}: {a} vs {b}"
                );
            }
        }
    }

    /// Unit normal from the ball centre to the outer-race contact at `alpha`.
    fn normal(alpha: f64) -> Vector3<f64> {
        Vector3::new(alpha.sin(), 0.0, alpha.cos())
    }

    #[test]
    fn geometry_gives_the_deformation_angle_and_hertz_load() {
        // 4 um of approach at 15 deg: Q = K delta^1.5 = 8e9 * (4e-6)^1.5 = 64 N, along the
        // line of centres, the ring getting the opposite force.
        let race = outer_race();
        let alpha = 15f64.to_radians();
        let ball = ball_at(&race, alpha, 4e-6, Vector3::zeros());
        let r = race_contact(&race, &ring_at_rest(0.0), &ball, &params());
        assert!((r.delta - 4e-6).abs() < 1e-15, "{}", r.delta);
        assert!((r.alpha.angle() - alpha).abs() < 1e-12, "{:?}", r.alpha);
        assert!(r.azimuth.angle().abs() < 1e-12);
        assert!((r.load - 64.0).abs() < 1e-9, "{}", r.load);
        // a ball at rest on a ring at rest: no slip, so no traction; the force is normal
        let n = normal(alpha);
        assert!(
            (r.force_on_ball + 64.0 * n).norm() < 1e-9,
            "{:?}",
            r.force_on_ball
        );
        assert!((r.force_on_ring + r.force_on_ball).norm() < 1e-12);
    }

    #[test]
    fn ball_inside_the_clearance_carries_nothing() {
        let race = outer_race();
        let ball = ball_at(&race, 0.2, -1e-6, Vector3::zeros());
        let r = race_contact(&race, &ring_at_rest(0.0), &ball, &params());
        assert!(r.delta < 0.0);
        assert_eq!(r.load, 0.0);
        assert_eq!(r.force_on_ball.norm() + r.force_on_ring.norm(), 0.0);
    }

    #[test]
    fn the_avx2_copy_gives_the_baseline_numbers_to_the_bit() {
        // The copy chosen on AVX2 processors must not change a result: no operation is fused
        // (Rust never contracts a * b + c) or reordered. Both laws, a spinning and sliding
        // ball with a rolling film, several loads.
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            let mut rheology = outer_race();
            rheology.traction = TractionLaw::Rheology(RheologyTraction::new(
                2.286e11,
                rheology.rx,
                &rheology.hertz,
                &oil(),
            ));
            let p = ContactParams {
                strips: Strips::new(10, StripRule::Gauss),
                ..params()
            };
            for race in [outer_race(), rheology] {
                for (delta, spin) in [(1e-6, 800.0), (4e-6, 1047.0), (9e-6, -300.0)] {
                    let mut ball = ball_at(&race, 15f64.to_radians(), delta, Vector3::zeros());
                    ball.omega = Vector3::new(-2900.0, 150.0, 40.0);
                    ball.velocity = Vector3::new(1e-3, 8.0, -2e-3);
                    let ring = ring_at_rest(spin);
                    let base = race_contact_body(&race, &ring, &ball, &p);
                    // SAFETY: AVX2 and FMA were detected above.
                    let wide = unsafe { race_contact_avx2(&race, &ring, &ball, &p) };
                    let bits = |r: &ContactResult| {
                        [
                            r.force_on_ball,
                            r.moment_on_ball,
                            r.force_on_ring,
                            r.moment_on_ring,
                        ]
                        .iter()
                        .flat_map(|v| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>())
                        .chain([r.load.to_bits()])
                        .collect::<Vec<_>>()
                    };
                    assert!(base.load > 0.0);
                    assert_eq!(bits(&base), bits(&wide), "delta {delta}, spin {spin}");
                }
            }
        } else {
            // the copy is never chosen on this processor, so there is nothing to compare
            eprintln!("no AVX2 and FMA here: the AVX2 copy was not compared");
        }
    }

    #[test]
    fn sliding_ball_is_dragged_by_the_ring_with_mu_q() {
        // A non-rotating ball on a race spinning at 100 rad/s about X: every strip slides at
        // ~2 m/s, so the traction is mu Q = 0.05 * 64 = 3.2 N (the strips' slips differ by
        // their radius, < 1 %), along the ring's surface velocity (X x Z = -Y).
        let race = outer_race();
        let ball = ball_at(&race, 15f64.to_radians(), 4e-6, Vector3::zeros());
        let r = race_contact(&race, &ring_at_rest(100.0), &ball, &params());
        let tr = r.force_on_ball + r.load * normal(15f64.to_radians());
        assert!((tr.norm() - 3.2).abs() < 0.01 * 3.2, "{:?}", tr);
        assert!(tr.y < -0.99 * tr.norm(), "{:?}", tr);
        // angular momentum balance about the ring centre: M_ring + M_ball + r_ball x F_ball = 0
        let total = r.moment_on_ring + r.moment_on_ball + ball.centre.cross(&r.force_on_ball);
        assert!(
            total.norm() < 1e-12 * r.load * race.path_radius,
            "{:?}",
            total
        );
    }
}
