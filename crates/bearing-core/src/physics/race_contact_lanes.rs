//! Four ball-race contacts of one race at once, under the rheology law: what
//! [`race_contact`] gives each, within rounding, with the laws' logarithms and
//! exponentials in the lanes of [`F64x4`].
//!
//! The defects stay one contact at a time (their branches differ from ball to ball);
//! the geometry, the Hertz load, the four contacts' film, strip laws and rolling resistance
//! and their moments run side by side. A strip whose slip is short beside its
//! cell's, on a law steep on the cell's scale (or whose Eyring argument passes 1e150),
//! takes its cell mean, lane by lane, from the scalar law
//! ([`StripCellLaw::cell_mean`](super::rheology_traction::StripCellLaw)). Compiled twice,
//! as `race_contact` is (`super::cpu`).

use super::frames::Azimuth;
use super::lanes::{F64x4, Vec3x4, LANES};
use super::race_contact::{
    defects_effect_at, race_contact, BallMotion, ContactParams, ContactResult, Race, RingMotion,
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

#[inline(always)]
fn contacts_body(
    race: &Race,
    law: &RheologyTraction,
    ring: &RingMotion,
    balls: &[BallMotion],
    p: &ContactParams,
    out: &mut [ContactResult],
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
    // eqs. 2-7 as `contact_geometry`, lane by lane
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
    let sign = if race.inner { -1.0 } else { 1.0 };
    let alpha_sin = sign * dx / dist;
    let alpha_cos = sign * dr / dist;
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
                if loaded[l] && (!point[l] || huge[l]) {
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

    // The moments and the reactions (eq. 18), side by side, then out lane by lane.
    let m_ball = u.cross(f_h) + s_hat.cross(f_y);
    let m_ring = -(ball_to_ring.cross(f_tr) + m_ball);
    let f_ball = normal_force_on_ball + f_tr;
    let mut force_on_ball = f_ball;
    let mut moment_on_ball = m_ball;
    let mut force_on_ring = -f_ball;
    let mut moment_on_ring = m_ring + r_contact.cross(-normal_force_on_ball);
    if let Some(per_speed) = rolling {
        let f = um.scale(per_speed);
        let r_b = u.scale(F64x4::splat(rb));
        force_on_ball = force_on_ball + f;
        moment_on_ball = moment_on_ball - r_b.cross(f);
        force_on_ring = force_on_ring - f;
        moment_on_ring = moment_on_ring - r_contact.cross(f);
    }
    for (l, o) in out.iter_mut().enumerate() {
        if loaded[l] {
            o.force_on_ball = force_on_ball.lane(l);
            o.moment_on_ball = moment_on_ball.lane(l);
            o.force_on_ring = force_on_ring.lane(l);
            o.moment_on_ring = moment_on_ring.lane(l);
        }
    }
}

// Tested against `race_contact` in `dynamics::rhs` (on a model's states).
