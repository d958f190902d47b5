//! Ball-race contacts of one race four at a time, under the rheology law: what
//! [`race_contact`] gives each, within rounding, in the lanes of [`F64x4`].
//!
//! The defects stay one contact at a time (their branches differ from ball to ball); the
//! geometry, the Hertz load, the film, the strip laws, the rolling resistance and the
//! moments run side by side. A strip whose slip is short beside its cell's, on a law steep
//! on the cell's scale, takes its cell mean: such strips are few, so a pass of sixteen
//! balls queues them and takes four at a time ([`CellQueue`]); one whose Eyring argument
//! passes 1e150 takes the scalar law's. Compiled twice, as `race_contact` is
//! (`super::cpu`).

use super::cpu::twice_compiled;
use super::frames::Azimuth;
use super::lanes::{F64x4, Vec3x4, LANES};
use super::race_contact::{
    defects_effect_at, race_contact, BallMotion, ContactParams, ContactResult, Race, RingMotion,
};
use super::rheology_traction::{RheologyTraction, StripLawX4};
use super::rolling_resistance::ENTRAINMENT_REGULARIZATION;
use super::traction::TractionLaw;
use nalgebra::Vector3;

/// The contacts of `balls` with `race` on `ring`, into `out` (as long as `balls`): each
/// [`race_contact`]'s result, within rounding.
pub fn race_contacts(
    race: &Race,
    ring: &RingMotion,
    balls: &[BallMotion],
    p: &ContactParams,
    out: &mut [ContactResult],
) {
    debug_assert_eq!(balls.len(), out.len());
    let TractionLaw::Rheology(law) = &race.traction else {
        for (ball, o) in balls.iter().zip(out.iter_mut()) {
            *o = race_contact(race, ring, ball, p);
        }
        return;
    };
    for (pass, o) in balls.chunks(PASS).zip(out.chunks_mut(PASS)) {
        contacts_of_pass(race, law, ring, pass, p, o);
    }
}

/// [`race_contacts`] in its baseline copy on any processor: for the test that compares the
/// two copies to the bit (`dynamics::rhs`).
#[cfg(test)]
pub(crate) fn race_contacts_baseline(
    race: &Race,
    ring: &RingMotion,
    balls: &[BallMotion],
    p: &ContactParams,
    out: &mut [ContactResult],
) {
    let TractionLaw::Rheology(law) = &race.traction else {
        panic!("the baseline copy is the rheology law's");
    };
    for (pass, o) in balls.chunks(PASS).zip(out.chunks_mut(PASS)) {
        contacts_body(race, law, ring, pass, p, o);
    }
}

/// Balls per pass: four groups of four, whose strips that take their cell mean are
/// gathered four at a time ([`CellQueue`]): about one strip in eleven takes it, so one
/// group's four lanes seldom hold more than one.
pub const PASS: usize = 4 * LANES;

twice_compiled! {
    /// One pass, in the copy this processor runs (`super::cpu`).
    fn contacts_of_pass(
        race: &Race,
        law: &RheologyTraction,
        ring: &RingMotion,
        balls: &[BallMotion],
        p: &ContactParams,
        out: &mut [ContactResult],
    ) = contacts_body, wide contacts_avx2;
}

/// One pass of up to [`PASS`] balls: each group's forces, the cell means, each group's
/// results.
#[inline(always)]
fn contacts_body(
    race: &Race,
    law: &RheologyTraction,
    ring: &RingMotion,
    balls: &[BallMotion],
    p: &ContactParams,
    out: &mut [ContactResult],
) {
    // a group's state only once it has a loaded contact: zeroing four 1.2 kB states a
    // pass (a `memset`, 1.1 % of the Table-1 case's instructions) bought nothing, as a
    // group without one writes no result
    let mut states: [Option<GroupState>; PASS / LANES] = [None; PASS / LANES];
    let mut queue = CellQueue::default();
    let groups = balls.chunks(LANES).zip(out.chunks_mut(LANES));
    for (g, (group, o)) in groups.enumerate() {
        group_forces(race, law, ring, group, p, o, &mut states, g, &mut queue);
    }
    queue.flush(law.limiting, &mut states);
    for (state, o) in states.iter().zip(out.chunks_mut(LANES)) {
        if let Some(state) = state {
            state.write(o);
        }
    }
}

/// What one group's results need after its strips: the contacts' frames and forces, and
/// the strip sums, which the cell means correct.
#[derive(Clone, Copy, Default)]
struct GroupState {
    loaded: [bool; LANES],
    u: Vec3x4,
    s_hat: Vec3x4,
    ball_to_ring: Vec3x4,
    r_contact: Vec3x4,
    normal_force_on_ball: Vec3x4,
    um: Vec3x4,
    rb: f64,
    /// The rolling resistance over the entrainment speed, N/(m/s).
    rolling_per_speed: Option<F64x4>,
    f_tr: Vec3x4,
    f_h: Vec3x4,
    f_y: Vec3x4,
}

/// Strips waiting for their cell mean: four fill the lanes.
#[derive(Default)]
struct CellQueue {
    jobs: [CellJob; LANES],
    len: usize,
}

/// One strip's cell mean to take: its law, slip and span, its load share, and where its
/// traction went in with its point value.
#[derive(Clone, Copy, Default)]
struct CellJob {
    group: usize,
    lane: usize,
    /// The strip's distance from the ball centre and its signed position `-+y`, m.
    h: f64,
    y: f64,
    c: f64,
    k: f64,
    v: Vector3<f64>,
    span: Vector3<f64>,
    /// The load share times the load, N.
    qw: f64,
    /// The traction summed for it with its point value, N.
    point: Vector3<f64>,
}

impl CellQueue {
    #[inline(always)]
    fn push(&mut self, job: CellJob, limiting: f64, states: &mut [Option<GroupState>]) {
        self.jobs[self.len] = job;
        self.len += 1;
        if self.len == LANES {
            self.flush(limiting, states);
        }
    }

    /// The waiting strips' cell means side by side; each replaces its strip's point value
    /// in its group's sums.
    #[inline(always)]
    fn flush(&mut self, limiting: f64, states: &mut [Option<GroupState>]) {
        if self.len == 0 {
            return;
        }
        let job = |i: usize| &self.jobs[i.min(self.len - 1)];
        let c = F64x4(std::array::from_fn(|i| job(i).c));
        let k = F64x4(std::array::from_fn(|i| job(i).k));
        let mut v = Vec3x4::ZERO;
        let mut span = Vec3x4::ZERO;
        for i in 0..LANES {
            v.set_lane(i, &job(i).v);
            span.set_lane(i, &job(i).span);
        }
        let law = StripLawX4::of_lanes(c, k, limiting);
        let (mean, huge) = law.cell_mean(v, span);
        for (i, j) in self.jobs[..self.len].iter().enumerate() {
            let m = if huge[i] {
                law.lane(i).cell_mean(j.v, j.span)
            } else {
                mean.lane(i)
            };
            let correction = j.qw * m - j.point;
            let st = states[j.group]
                .as_mut()
                .expect("a queued strip's group has its state");
            st.f_tr.add_to_lane(j.lane, &correction);
            st.f_h.add_to_lane(j.lane, &(j.h * correction));
            st.f_y.add_to_lane(j.lane, &(j.y * correction));
        }
        self.len = 0;
    }
}

/// Group `g` of a pass: its contacts' geometry, loads and strip sums into `states[g]`, its
/// strips that take their cell mean into `queue`; the unloaded contacts' results into
/// `out`.
#[inline(always)]
#[allow(clippy::too_many_arguments)] // the hot path's context, passed as it stands
fn group_forces(
    race: &Race,
    law: &RheologyTraction,
    ring: &RingMotion,
    balls: &[BallMotion],
    p: &ContactParams,
    out: &mut [ContactResult],
    states: &mut [Option<GroupState>],
    g: usize,
    queue: &mut CellQueue,
) {
    // The group's balls in lanes (a short group repeats its last ball, whose extra lanes
    // are not read).
    let mut centre = Vec3x4::ZERO;
    let mut velocity = Vec3x4::ZERO;
    let mut omega = Vec3x4::ZERO;
    for l in 0..LANES {
        let b = &balls[l.min(balls.len() - 1)];
        centre.set_lane(l, &b.centre);
        velocity.set_lane(l, &b.velocity);
        omega.set_lane(l, &b.omega);
    }
    // eqs. 2-7 as `contact_geometry`, side by side
    let rel = centre - Vec3x4::splat(&ring.centre);
    let pos = if ring.tilted {
        rel.rotated_back(&ring.rot)
    } else {
        rel
    };
    let zero = F64x4::splat(0.0);
    let rho = (pos.y * pos.y + pos.z * pos.z).sqrt();
    let off_axis = zero.lt(rho);
    let sin = F64x4::select(off_axis, -pos.y / rho, zero);
    let cos = F64x4::select(off_axis, pos.z / rho, F64x4::splat(1.0));
    let dx = pos.x - F64x4::splat(race.centre_axial);
    let dr = rho - F64x4::splat(race.centre_radius);
    let dist = (dx * dx + dr * dr).sqrt();
    let delta0 = dist - F64x4::splat(race.free_distance);
    let normal_sign = if race.inner { -1.0 } else { 1.0 };
    let alpha_sin = normal_sign * dx / dist;
    let alpha_cos = normal_sign * dr / dist;
    let u_body = Vec3x4 {
        x: dx / dist,
        y: -sin * dr / dist,
        z: cos * dr / dist,
    };
    let t_body = Vec3x4 {
        x: zero,
        y: -cos,
        z: -sin,
    };
    let (u, t) = if ring.tilted {
        (u_body.rotated(&ring.rot), t_body.rotated(&ring.rot))
    } else {
        (u_body, t_body)
    };

    // One at a time: the defects (eqs. 33-36), whose branches differ from ball to ball.
    let mut drop = zero;
    let mut psi = zero;
    let mut touching = [false; LANES];
    for (l, o) in out.iter_mut().enumerate() {
        let azimuth = Azimuth {
            sin: sin.0[l],
            cos: cos.0[l],
        };
        *o = ContactResult {
            alpha: Azimuth {
                sin: alpha_sin.0[l],
                cos: alpha_cos.0[l],
            },
            azimuth,
            delta: delta0.0[l],
            ..Default::default()
        };
        if delta0.0[l] <= 0.0 {
            continue;
        }
        let eff = defects_effect_at(race, ring, &azimuth);
        let delta = delta0.0[l] - eff.drop;
        o.delta = delta;
        o.defect_drop = eff.drop;
        o.psi = eff.psi;
        (drop.0[l], psi.0[l]) = (eff.drop, eff.psi);
        touching[l] = delta > 0.0;
    }
    if touching.iter().all(|t| !t) {
        return;
    }

    // Side by side: the Hertz load with damping (eq. 8), as `race_contact`.
    let k = race.hertz.k;
    let delta = delta0 - drop;
    let sq = delta.sqrt();
    let ddelta = u.dot(velocity - Vec3x4::splat(&ring.velocity));
    let c_damp = (2.0 * p.damping_ratio) * ((1.5 * k) * sq * F64x4::splat(p.ball_mass)).sqrt();
    let load = (k * delta * sq + c_damp * ddelta).max(zero);
    let mut loaded = [false; LANES];
    // unloaded lanes run on a unit load, and are not read
    let mut q = F64x4::splat(1.0);
    let mut sin_psi = zero;
    let mut cos_psi = F64x4::splat(1.0);
    for l in 0..out.len() {
        if !touching[l] {
            continue;
        }
        out[l].load = load.0[l];
        loaded[l] = load.0[l] != 0.0;
        if loaded[l] {
            q.0[l] = load.0[l];
            if psi.0[l] != 0.0 {
                (sin_psi.0[l], cos_psi.0[l]) = psi.0[l].sin_cos();
            }
        }
    }
    if loaded.iter().all(|l| !l) {
        return;
    }
    // the load direction, turned by psi towards +t at a defect edge (eq. 36)
    let normal_force_on_ball = u.scale(-q * cos_psi) + t.scale(q * sin_psi);
    let rb = race.ball_radius;
    let r_contact = rel + u.scale(F64x4::splat(rb));
    // the entrainment velocity (`entrainment_velocity`)
    let ring_axis = Vec3x4::splat(&(ring.rot * Vector3::x()));
    let spin = F64x4::splat(ring.spin);
    let v_ball = omega.cross(u.scale(F64x4::splat(rb)));
    let v_ring = Vec3x4::splat(&ring.velocity) + ring_axis.cross(r_contact).scale(spin) - velocity;
    let um_full = (v_ball + v_ring).scale(F64x4::splat(0.5));
    let tangential = |v: Vec3x4| v - u.scale(v.dot(u));
    let um = tangential(um_full);
    let speed = F64x4::select(loaded, um.norm_squared().sqrt(), F64x4::splat(1.0));
    // eqs. 10-12 as in `strip_traction`: the slip `c0 + h c1 + y c2`
    let s_hat = u.cross(t);
    let ball_to_ring = rel;
    let c0 = tangential(
        Vec3x4::splat(&ring.velocity) + ring_axis.cross(ball_to_ring).scale(spin) - velocity,
    );
    let c1 = tangential(ring_axis.cross(u).scale(spin) - omega.cross(u));
    let c2 = tangential(ring_axis.cross(s_hat).scale(spin) - omega.cross(s_hat));

    // Side by side: the load's cube root and logarithm, the speed's logarithm (`ContactLoad`).
    let q13 = q.cube_root();
    let ln_q = q.ln();
    let floored = speed.max(F64x4::splat(ENTRAINMENT_REGULARIZATION));
    let ln_floored = floored.ln();
    let film = law.at_load_lanes(q13, ln_floored, ln_q);
    // the ellipse (as `strip_traction`)
    let rp = race.r_prime;
    let a_eff = (race.hertz.a_coef * q13).min(F64x4::splat(0.999 * rb));
    let a2 = a_eff * a_eff;
    let base = (F64x4::splat(rb * rb) - a2).sqrt() - (F64x4::splat(rp * rp) - a2).sqrt();
    states[g] = Some(GroupState {
        loaded,
        u,
        s_hat,
        ball_to_ring,
        r_contact,
        normal_force_on_ball,
        um,
        rb,
        rolling_per_speed: None,
        f_tr: Vec3x4::ZERO,
        f_h: Vec3x4::ZERO,
        f_y: Vec3x4::ZERO,
    });
    for pair in &p.strips.pairs {
        let strip = film.strip_law(pair.chord);
        let y = pair.xi * a_eff;
        let root = (F64x4::splat(rp * rp) - y * y).sqrt();
        let h = root + base;
        let mid = c0 + c1.scale(h);
        let across = c2.scale(y);
        let cell = pair.cell * a_eff;
        // the slip's change across the cell, `(-y/root) cell c1 + cell c2` at -y and +y
        let slope = y / root * cell;
        let cell_c2 = c2.scale(cell);
        // one side of the pair, `sign` -1 at -y and +1 at +y: written out twice with
        // constants, so each copy folds its side's choices (a loop over the two left them to
        // run time; a closure is compiled without the AVX2 copy's features)
        macro_rules! side {
            ($sign:expr, $v:expr, $weight:expr) => {{
                let (sign, v, weight): (f64, Vec3x4, f64) = ($sign, $v, $weight);
                let span = c1.scale(-sign * slope) + cell_c2;
                let s2 = v.norm_squared();
                let l2 = span.norm_squared();
                let point = strip.takes_point_value(s2, l2);
                let (mu, huge) = strip.mu_over_s(s2.sqrt());
                let qw = weight * q;
                let mut traction = v.scale(mu).scale(qw);
                for l in 0..LANES {
                    if !loaded[l] || (point[l] && !huge[l]) {
                        continue;
                    }
                    if huge[l] {
                        let mean = qw.0[l] * strip.lane(l).cell_mean(v.lane(l), span.lane(l));
                        traction.set_lane(l, &mean);
                    } else {
                        // its point value now, its cell mean with three others' later
                        let job = CellJob {
                            group: g,
                            lane: l,
                            h: h.0[l],
                            y: sign * y.0[l],
                            c: strip.c_of(l),
                            k: strip.k_of(l),
                            v: v.lane(l),
                            span: span.lane(l),
                            qw: qw.0[l],
                            point: traction.lane(l),
                        };
                        queue.push(job, law.limiting, states);
                    }
                }
                traction
            }};
        }
        let tr = [
            side!(-1.0, mid - across, pair.weight_minus),
            side!(1.0, mid + across, pair.weight_plus),
        ];
        let both = tr[0] + tr[1];
        let st = states[g].as_mut().expect("a loaded group has its state");
        st.f_tr = st.f_tr + both;
        st.f_h = st.f_h + both.scale(h);
        st.f_y = st.f_y + (tr[1] - tr[0]).scale(y);
    }
    if let Some(st) = &mut states[g] {
        st.rolling_per_speed = race
            .rolling
            .as_ref()
            .map(|rr| rr.force_lanes(q, q13, ln_floored) / floored);
    }
}

impl GroupState {
    /// The group's loaded contacts' forces and moments into `out` (eq. 18): side by side,
    /// then out lane by lane.
    #[inline(always)]
    fn write(&self, out: &mut [ContactResult]) {
        let GroupState {
            u,
            s_hat,
            ball_to_ring,
            r_contact,
            normal_force_on_ball,
            um,
            rb,
            f_tr,
            f_h,
            f_y,
            ..
        } = *self;

        let m_ball = u.cross(f_h) + s_hat.cross(f_y);
        let m_ring = -(ball_to_ring.cross(f_tr) + m_ball);
        let f_ball = normal_force_on_ball + f_tr;
        let mut force_on_ball = f_ball;
        let mut moment_on_ball = m_ball;
        let mut force_on_ring = -f_ball;
        let mut moment_on_ring = m_ring + r_contact.cross(-normal_force_on_ball);
        if let Some(per_speed) = self.rolling_per_speed {
            let f = um.scale(per_speed);
            let r_b = u.scale(F64x4::splat(rb));
            force_on_ball = force_on_ball + f;
            moment_on_ball = moment_on_ball - r_b.cross(f);
            force_on_ring = force_on_ring - f;
            moment_on_ring = moment_on_ring - r_contact.cross(f);
        }
        for (l, o) in out.iter_mut().enumerate() {
            if self.loaded[l] {
                o.force_on_ball = force_on_ball.lane(l);
                o.moment_on_ball = moment_on_ball.lane(l);
                o.force_on_ring = force_on_ring.lane(l);
                o.moment_on_ring = moment_on_ring.lane(l);
            }
        }
    }
}

// Tested against `race_contact` in `dynamics::rhs` (on a model's states).
