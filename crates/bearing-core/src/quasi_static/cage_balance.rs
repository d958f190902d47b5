//! The cage speed and ball spins at which the traction balances, with the balls where the
//! quasi-static equilibrium put them.
//!
//! Pure rolling (outer-race control, `physics::kinematics`) gives each ball its own orbital
//! speed from its own contact angles; the cage cannot follow them all, and under a traction
//! law the balls slip. In steady running every ball orbits at the cage speed, each ball's
//! spin is steady in the frame turning with it (`M / I = Omega_c e_x x w`, the
//! gyroscopic balance of eq. 32), and the pockets pass each ball's tangential traction to
//! the cage, which carries no net torque (with the cavity's windage when the scene has
//! it). Those 3 Z + 1 equations fix the Z spins and the cage speed. Only balls loaded on
//! both races take part: a ball touching one race (or none) has a free spin direction and
//! keeps its rolling kinematics, carrying no tangential force to the cage.

use crate::model::Model;
use crate::physics::cage_land::{land_on_cage, AxisMotion};
use crate::physics::drag::cage_windage_torque;
use crate::physics::frames::Azimuth;
use crate::physics::race_contact::{race_contact, BallMotion, RingMotion};
use nalgebra::{DMatrix, DVector, Vector3};

/// The balanced cage speed and ball spins.
#[derive(Debug, Clone, PartialEq)]
pub struct CageBalance {
    /// Cage (and every ball's orbital) speed, rad/s.
    pub cage_speed: f64,
    /// Per ball: angular velocity (axial, radial, tangential) in its azimuth frame, rad/s.
    pub spins: Vec<[f64; 3]>,
    /// Newton iterations taken.
    pub iterations: u32,
}

/// Solve the balance for balls at `centres` (axial, radial; m) and `azimuths` (rad)
/// between `inner` and `outer`, from the rolling kinematics `start` (orbital speed,
/// `w_x`, `w_r` per ball) and the cage speed `cage0` (rad/s). `None` when Newton does not
/// converge (the caller keeps the kinematics).
pub fn cage_balance(
    m: &Model,
    inner: &RingMotion,
    outer: &RingMotion,
    centres: &[[f64; 2]],
    azimuths: &[f64],
    start: &[[f64; 3]],
    cage0: f64,
) -> Option<CageBalance> {
    let z = centres.len();
    let az: Vec<Azimuth> = azimuths.iter().map(|&a| Azimuth::new(a)).collect();
    let mut spins: Vec<[f64; 3]> = start.iter().map(|k| [k[1], k[2], 0.0]).collect();
    // balls carried by both races take part
    let active: Vec<usize> = (0..z)
        .filter(|&j| {
            let b = motion(&az[j], centres[j], cage0, spins[j]);
            race_contact(&m.inner_race, inner, &b, &m.contact).load > 0.0
                && race_contact(&m.outer_race, outer, &b, &m.contact).load > 0.0
        })
        .collect();
    if active.is_empty() || cage0 == 0.0 {
        return Some(CageBalance {
            cage_speed: cage0,
            spins,
            iterations: 0,
        });
    }
    let n = 3 * active.len() + 1;
    let unknowns = |spins: &[[f64; 3]], cage: f64| {
        let mut u = DVector::zeros(n);
        for (i, &j) in active.iter().enumerate() {
            for k in 0..3 {
                u[3 * i + k] = spins[j][k];
            }
        }
        u[n - 1] = cage;
        u
    };
    let residual = |u: &DVector<f64>| {
        let cage = u[n - 1];
        let mut r = DVector::zeros(n);
        let mut torque = drag_torque(m, inner, outer, cage);
        for (i, &j) in active.iter().enumerate() {
            let w = [u[3 * i], u[3 * i + 1], u[3 * i + 2]];
            let b = motion(&az[j], centres[j], cage, w);
            let ci = race_contact(&m.inner_race, inner, &b, &m.contact);
            let co = race_contact(&m.outer_race, outer, &b, &m.contact);
            let mut f = ci.force_on_ball + co.force_on_ball;
            let mut mo = ci.moment_on_ball + co.moment_on_ball;
            if let Some(drag) = &m.ball_drag {
                f += drag.force(&b.velocity);
                mo += drag.moment(&b.omega);
            }
            let ma = az[j].to_frame(&mo);
            // steady spin in the azimuth frame: M / I = cage e_x x w (eq. 32)
            let ib = m.ball_inertia;
            r[3 * i] = ma.x / ib;
            r[3 * i + 1] = ma.y / ib + cage * w[2];
            r[3 * i + 2] = ma.z / ib - cage * w[1];
            // the pocket passes the ball's tangential force to the cage, at its radius
            torque += centres[j][1] * az[j].to_frame(&f).z;
        }
        // as an angular acceleration of the balls' orbit (their inertia about the axis)
        r[n - 1] = torque / (m.ball_mass * (0.5 * m.pitch_diameter).powi(2) * active.len() as f64);
        r
    };
    let mut u = unknowns(&spins, cage0);
    let mut r = residual(&u);
    let mut iterations = 0;
    // speeds are hundreds to thousands of rad/s: converged when the Newton step moves none
    // by more than 1e-9 of the shaft-speed scale (or no shorter step lowers the residual,
    // rounding having the last word, while the full step is already that small)
    let scale = cage0.abs().max(1.0) * 10.0;
    let mut converged = false;
    for _ in 0..50 {
        iterations += 1;
        let mut jac = DMatrix::zeros(n, n);
        for c in 0..n {
            let d = 1e-7 * u[c].abs().max(scale * 1e-3);
            let mut up = u.clone();
            up[c] += d;
            let rp = residual(&up);
            jac.set_column(c, &((rp - &r) / d));
        }
        let step = jac.lu().solve(&(-&r))?;
        if step.amax() < 1e-9 * scale {
            converged = true;
            break;
        }
        // halve the step until the residual falls (the limiting shear makes the residual
        // flat in places)
        let mut t = 1.0;
        let mut moved = false;
        for _ in 0..30 {
            let trial = &u + t * &step;
            let rt = residual(&trial);
            if rt.iter().all(|v| v.is_finite()) && rt.norm() < r.norm() {
                u = trial;
                r = rt;
                moved = true;
                break;
            }
            t *= 0.5;
        }
        if !moved {
            break;
        }
    }
    if !converged {
        return None;
    }
    for (i, &j) in active.iter().enumerate() {
        spins[j] = [u[3 * i], u[3 * i + 1], u[3 * i + 2]];
    }
    Some(CageBalance {
        cage_speed: u[n - 1],
        spins,
        iterations,
    })
}

/// The torque on a concentric cage at `cage` rad/s from its land film and, when the scene
/// has it, the cavity's windage, N m: what the balls' pockets must balance.
pub(super) fn drag_torque(m: &Model, inner: &RingMotion, outer: &RingMotion, cage: f64) -> f64 {
    m.cage_windage.as_ref().map_or(0.0, |medium| {
        cage_windage_torque(medium, m.cage_radii[0], m.cage_radii[1], cage)
    }) + land_torque(m, inner, outer, cage)
}

/// The land film's torque on a cage running concentric with the ring that guides it, at
/// `cage` rad/s (eqs. 23-28 at zero eccentricity: the film's viscous drag), N m.
fn land_torque(m: &Model, inner: &RingMotion, outer: &RingMotion, cage: f64) -> f64 {
    let Some(lp) = &m.land else {
        return 0.0;
    };
    let ring = if m.land_on_outer { outer } else { inner };
    let axis = |spin: f64| AxisMotion {
        centre: ring.centre,
        velocity: Vector3::zeros(),
        axis: ring.rot * Vector3::x(),
        tilt_rate: Vector3::zeros(),
        spin,
    };
    land_on_cage(lp, &axis(cage), &axis(ring.spin)).torque_on_cage
}

/// A ball at `centre` (axial, radial) on azimuth `az`, orbiting at `cage` (rad/s) with
/// angular velocity `w` in its azimuth frame.
fn motion(az: &Azimuth, centre: [f64; 2], cage: f64, w: [f64; 3]) -> BallMotion {
    let [x, r] = centre;
    BallMotion {
        centre: Vector3::new(x, 0.0, 0.0) + r * az.e_r(),
        velocity: r * cage * az.e_t(),
        omega: az.from_frame(&Vector3::new(w[0], w[1], w[2])),
    }
}
