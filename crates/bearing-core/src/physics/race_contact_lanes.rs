//! Four ball-race contacts of one race at once, under the rheology law: what
//! [`race_contact`] gives each, within rounding, with the laws' logarithms and
//! exponentials in the lanes of [`F64x4`].
//!
//! The geometry, the defects and the Hertz load stay one contact at a time (their
//! branches differ from ball to ball); from the load on, the four contacts' film, strip
//! laws and rolling resistance run side by side. A strip whose slip is short beside its
//! cell's, on a law steep on the cell's scale (or whose Eyring argument passes 1e150),
//! takes its cell mean, lane by lane, from the scalar law
//! ([`StripCellLaw::cell_mean`](super::rheology_traction::StripCellLaw)). Compiled twice,
//! as `race_contact` is (`super::cpu`).

use super::lanes::{F64x4, Vec3x4, LANES};
use super::race_contact::{
    contact_geometry, defects_effect_at, race_contact, BallMotion, ContactParams, ContactResult,
    Race, RingMotion,
};
use super::rheology_traction::RheologyTraction;
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
    for (group, o) in balls.chunks(LANES).zip(out.chunks_mut(LANES)) {
        #[cfg(target_arch = "x86_64")]
        if super::cpu::wide_vectors() {
            // SAFETY: the processor has AVX2 and FMA, checked at run time.
            unsafe { contacts_avx2(race, law, ring, group, p, o) };
            continue;
        }
        contacts_body(race, law, ring, group, p, o);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn contacts_avx2(
    race: &Race,
    law: &RheologyTraction,
    ring: &RingMotion,
    balls: &[BallMotion],
    p: &ContactParams,
    out: &mut [ContactResult],
) {
    contacts_body(race, law, ring, balls, p, out)
}

/// One loaded contact's geometry and load, what its lane needs after them.
#[derive(Clone, Copy)]
struct Loaded {
    u: Vector3<f64>,
    s_hat: Vector3<f64>,
    ball_to_ring: Vector3<f64>,
    r_contact: Vector3<f64>,
    normal_force_on_ball: Vector3<f64>,
    um: Vector3<f64>,
}

#[inline(always)]
fn contacts_body(
    race: &Race,
    law: &RheologyTraction,
    ring: &RingMotion,
    balls: &[BallMotion],
    p: &ContactParams,
    out: &mut [ContactResult],
) {
    // One at a time: geometry, defects, load (as `race_contact` does).
    let mut loaded: [Option<Loaded>; LANES] = [None; LANES];
    // unloaded lanes run on a unit load and speed, and are not read
    let mut q = F64x4::splat(1.0);
    let mut speed = F64x4::splat(1.0);
    let mut c0 = Vec3x4::ZERO;
    let mut c1 = Vec3x4::ZERO;
    let mut c2 = Vec3x4::ZERO;
    let ring_axis = ring.rot * Vector3::x();
    for (l, ball) in balls.iter().enumerate() {
        let g = contact_geometry(race, ring, &ball.centre);
        let (delta0, u, t) = (g.delta, g.normal, g.tangent);
        let o = &mut out[l];
        *o = ContactResult {
            alpha: g.alpha,
            azimuth: g.azimuth,
            delta: delta0,
            ..Default::default()
        };
        if delta0 <= 0.0 {
            continue;
        }
        let eff = defects_effect_at(race, ring, &g.azimuth);
        let delta = delta0 - eff.drop;
        o.delta = delta;
        o.defect_drop = eff.drop;
        o.psi = eff.psi;
        if delta <= 0.0 {
            continue;
        }
        let k = race.hertz.k;
        let sq = delta.sqrt();
        let ddelta = u.dot(&(ball.velocity - ring.velocity));
        let c_damp = 2.0 * p.damping_ratio * (1.5 * k * sq * p.ball_mass).sqrt();
        let load = (k * delta * sq + c_damp * ddelta).max(0.0);
        o.load = load;
        if load == 0.0 {
            continue;
        }
        let (sp, cp) = if eff.psi == 0.0 {
            (0.0, 1.0)
        } else {
            eff.psi.sin_cos()
        };
        let r_contact = ball.centre - ring.centre + race.ball_radius * u;
        let um =
            super::race_contact::entrainment_velocity(ring, ball, &u, race.ball_radius, &r_contact);
        q.0[l] = load;
        speed.0[l] = um.norm();
        // eqs. 10-12 as in `strip_traction`: the slip `c0 + h c1 + y c2`
        let s_hat = u.cross(&t);
        let ball_to_ring = ball.centre - ring.centre;
        let tangential = |v: Vector3<f64>| v - v.dot(&u) * u;
        c0.set_lane(
            l,
            &tangential(ring.velocity + ring.spin * ring_axis.cross(&ball_to_ring) - ball.velocity),
        );
        c1.set_lane(
            l,
            &tangential(ring.spin * ring_axis.cross(&u) - ball.omega.cross(&u)),
        );
        c2.set_lane(
            l,
            &tangential(ring.spin * ring_axis.cross(&s_hat) - ball.omega.cross(&s_hat)),
        );
        loaded[l] = Some(Loaded {
            u,
            s_hat,
            ball_to_ring,
            r_contact,
            normal_force_on_ball: -load * cp * u + load * sp * t,
            um,
        });
    }
    if loaded.iter().all(Option::is_none) {
        return;
    }

    // Side by side: the load's cube root and logarithm, the speed's logarithm (`ContactLoad`).
    let q13 = q.cube_root();
    let ln_q = q.ln();
    let floored = speed.max(F64x4::splat(ENTRAINMENT_REGULARIZATION));
    let ln_floored = floored.ln();
    let film = law.at_load_lanes(q13, ln_floored, ln_q);
    // the ellipse (as `strip_traction`)
    let rb = race.ball_radius;
    let rp = race.r_prime;
    let a_eff = (race.hertz.a_coef * q13).min(F64x4::splat(0.999 * rb));
    let a2 = a_eff * a_eff;
    let base = (F64x4::splat(rb * rb) - a2).sqrt() - (F64x4::splat(rp * rp) - a2).sqrt();
    let mut f_tr = Vec3x4::ZERO;
    let mut f_h = Vec3x4::ZERO;
    let mut f_y = Vec3x4::ZERO;
    for pair in &p.strips.pairs {
        let strip = film.strip_law(pair.chord);
        let y = pair.xi * a_eff;
        let root = (F64x4::splat(rp * rp) - y * y).sqrt();
        let h = root + base;
        let centre = c0 + c1.scale(h);
        let across = c2.scale(y);
        let cell = pair.cell * a_eff;
        // the slip's change across the cell, `(-y/root) cell c1 + cell c2` at -y and +y
        let slope = y / root * cell;
        let cell_c2 = c2.scale(cell);
        let mut tr = [Vec3x4::ZERO; 2];
        for (side, sign) in [(0, -1.0), (1, 1.0)] {
            let v = if side == 0 {
                centre - across
            } else {
                centre + across
            };
            let span = c1.scale(-sign * slope) + cell_c2;
            let s2 = v.norm_squared();
            let l2 = span.norm_squared();
            let point = strip.takes_point_value(s2, l2);
            let (mu, huge) = strip.mu_over_s(s2.sqrt());
            let weight = if side == 0 {
                pair.weight_minus
            } else {
                pair.weight_plus
            };
            let qw = weight * q;
            let mut traction = v.scale(mu).scale(qw);
            for l in 0..LANES {
                if loaded[l].is_some() && (!point[l] || huge[l]) {
                    let mean = qw.0[l] * strip.lane(l).cell_mean(v.lane(l), span.lane(l));
                    traction.set_lane(l, &mean);
                }
            }
            tr[side] = traction;
        }
        let both = tr[0] + tr[1];
        f_tr = f_tr + both;
        f_h = f_h + both.scale(h);
        f_y = f_y + (tr[1] - tr[0]).scale(y);
    }
    let rolling = race
        .rolling
        .as_ref()
        .map(|rr| rr.force_lanes(q, q13, ln_floored) / floored);

    // One at a time again: the moments and the reactions (eq. 18).
    for (l, lane) in loaded.iter().enumerate() {
        let Some(c) = lane else { continue };
        let (tr, fh, fy) = (f_tr.lane(l), f_h.lane(l), f_y.lane(l));
        let m_ball = c.u.cross(&fh) + c.s_hat.cross(&fy);
        let m_ring = -(c.ball_to_ring.cross(&tr) + m_ball);
        let f_ball = c.normal_force_on_ball + tr;
        let o = &mut out[l];
        o.force_on_ball = f_ball;
        o.moment_on_ball = m_ball;
        o.force_on_ring = -f_ball;
        o.moment_on_ring = m_ring + c.r_contact.cross(&(-c.normal_force_on_ball));
        if let Some(per_speed) = rolling {
            let f = per_speed.0[l] * c.um;
            let r_b = rb * c.u;
            o.force_on_ball += f;
            o.moment_on_ball -= r_b.cross(&f);
            o.force_on_ring -= f;
            o.moment_on_ring -= c.r_contact.cross(&f);
        }
    }
}

// Tested against `race_contact` in `dynamics::rhs` (on a model's states).
