//! The Jones-Harris solve: every ball in its own equilibrium (nested), the inner ring by
//! Newton-Levenberg on the ring force (and moment) balance.

use super::cage_balance::{cage_balance, CageBalance};
use super::error::QsError;
use super::pocket_cycle::PocketCycleSettings;
use crate::model::Model;
use crate::physics::frames::{e_r, tilt_matrix, to_azimuth};
use crate::physics::hertz;
use crate::physics::kinematics::rolling_kinematics;
use crate::physics::race_contact::{contact_geometry, RingMotion};
use crate::scene::ValidScene;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Equilibrium of one ball.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct QsBall {
    /// Azimuth of the ball centre, rad.
    pub azimuth: f64,
    /// Inner-race normal contact load, N.
    pub inner_load: f64,
    /// Outer-race normal contact load, N.
    pub outer_load: f64,
    /// Inner contact angle, rad.
    pub inner_contact_angle: f64,
    /// Outer contact angle, rad.
    pub outer_contact_angle: f64,
    /// Centrifugal force on the ball, N.
    pub centrifugal_force: f64,
    /// Gyroscopic moment on the ball, N m.
    pub gyroscopic_moment: f64,
}

/// Quasi-static solution of a scene at one shaft speed.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct QuasiStaticSolution {
    /// Shaft (inner-ring) speed, rad/s.
    pub shaft_speed: f64,
    /// Inner-ring displacement relative to the outer ring (x axial, y, z), m.
    pub inner_ring_displacement: [f64; 3],
    /// Inner-ring tilt about Y and Z, rad (0 when locked).
    pub inner_ring_tilt: [f64; 2],
    /// Cage speed, rad/s: where the traction on the balls balances (every ball orbiting
    /// with the cage, the cage carrying no net torque; `quasi_static::cage_balance`); the
    /// epicyclic speed where no balance was found (`traction_balanced` false). A dynamic
    /// run starts from it. At the paper's point a running cage settles 0.28 % above it under
    /// the paper's curve and 0.65 % below it under the preset's rheology law; `pocket_cycle`
    /// is closer under both (docs/reference/model.md, "Cage speed by the pocket cycle").
    pub cage_speed: f64,
    /// Whether `cage_speed` is the traction balance.
    pub traction_balanced: bool,
    /// Pure-rolling cage speed at the load-weighted contact angles with outer-race control
    /// (the dynamic summary's `epicyclic_cage_speed`), rad/s: the kinematic reference the
    /// cage slip is measured against.
    pub epicyclic_cage_speed: f64,
    /// Ball spin about its own axis, rad/s.
    pub ball_spin_speed: f64,
    /// Inner groove curvature factor used, -.
    pub inner_groove_curvature: f64,
    /// Outer groove curvature factor used, -.
    pub outer_groove_curvature: f64,
    /// Newton iterations taken.
    pub iterations: u32,
    /// Largest force residual at the solution, N.
    pub residual: f64,
    pub balls: Vec<QsBall>,
    /// The cage speed by the pocket cycle, when asked for (absent otherwise): the balance
    /// with the balls' drift through their pockets' clearance, which `cage_speed`'s steady
    /// balance leaves out. Within 0.11 % of a running cage under the paper's curve; 0.21 %
    /// above it at the paper's point under the preset's rheology law, where the root sits
    /// just above a step in the torque, the speed at which loaded balls begin to press their
    /// pocket faces (docs/reference/model.md, "Cage speed by the pocket cycle").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pocket_cycle: Option<super::pocket_cycle::PocketCycle>,
}

/// Solve the scene's bearing at `shaft_rpm` under its operating loads.
pub fn solve(scene: &ValidScene, shaft_rpm: f64) -> Result<QuasiStaticSolution, QsError> {
    if !(shaft_rpm.is_finite() && shaft_rpm >= 0.0) {
        return Err(QsError::InvalidSpeed { rpm: shaft_rpm });
    }
    let model = Model::new(scene);
    let w = shaft_rpm * 2.0 * std::f64::consts::PI / 60.0;
    let st = solve_model(&model, w)?;
    Ok(st.to_solution(&model, w))
}

/// Equilibrium in the model's own variables (also the dynamic initial state).
#[derive(Debug, Clone)]
pub struct QsState {
    /// Inner ring x, y, z (m) and tilt about Y, Z (rad).
    pub ring: [f64; 5],
    /// Per ball: axial x, radial r (m).
    pub balls: Vec<[f64; 2]>,
    /// Per ball: orbital speed, w_x, w_r (rad/s) from rolling kinematics.
    pub kinematics: Vec<[f64; 3]>,
    /// Pure-rolling cage speed at the load-weighted contact angles (outer-race control),
    /// rad/s: the dynamic summary's `epicyclic_cage_speed`.
    pub epicyclic_cage_speed: f64,
    /// Cage speed and ball spins at which the traction balances ([`cage_balance`]);
    /// `None` where Newton found no balance.
    pub balance: Option<CageBalance>,
    pub iterations: u32,
    /// Largest residual, N.
    pub residual: f64,
}

struct Eval {
    inner_load: f64,
    outer_load: f64,
    inner_alpha: f64,
    outer_alpha: f64,
    centrifugal: f64,
    gyro: f64,
}

fn azimuths(m: &Model) -> Vec<f64> {
    m.pocket_angles.clone()
}

fn ring_unknowns(m: &Model) -> usize {
    if m.tilt_free {
        5
    } else {
        3
    }
}

fn inner_ring(m: &Model, u: &[f64], w: f64) -> RingMotion {
    let rot = if m.tilt_free {
        tilt_matrix(u[3], u[4])
    } else {
        nalgebra::Matrix3::identity()
    };
    RingMotion::new(
        Vector3::new(u[0], u[1], u[2]),
        rot,
        Vector3::zeros(),
        w,
        0.0,
    )
}

fn outer_ring() -> RingMotion {
    RingMotion::new(
        Vector3::zeros(),
        nalgebra::Matrix3::identity(),
        Vector3::zeros(),
        0.0,
        0.0,
    )
}

/// Forces on one ball at azimuth `th` and position (x, r): residual in (axial, radial),
/// the force the inner race takes, and the details.
fn ball_forces(
    m: &Model,
    inner: &RingMotion,
    w: f64,
    th: f64,
    x: f64,
    r: f64,
) -> ([f64; 2], Vector3<f64>, Vector3<f64>, Eval, [f64; 3]) {
    let rb = 0.5 * m.ball_diameter;
    let er = e_r(th);
    let centre = Vector3::new(x, 0.0, 0.0) + r * er;
    let gi = contact_geometry(&m.inner_race, inner, &centre);
    let go = contact_geometry(&m.outer_race, &outer_ring(), &centre);
    let (di, ai, ui) = (gi.delta, gi.alpha.angle(), gi.normal);
    let (do_, ao, uo) = (go.delta, go.alpha.angle(), go.normal);
    let qi = hertz::load(m.inner_race.hertz.k, di);
    let qo = hertz::load(m.outer_race.hertz.k, do_);
    let loaded = qi > 0.0 && qo > 0.0;
    let (ai_k, ao_k) = if loaded {
        (ai, ao)
    } else {
        (m.free_contact_angle, m.free_contact_angle)
    };
    let kin = rolling_kinematics(r, ai_k, ao_k, rb, w);
    let [thd, _wx, wr] = kin;
    let fc = m.ball_mass * r * thd * thd;
    // outer-race control: the outer contact's friction supplies the gyroscopic moment
    // (an unloaded ball has no rolling to speak of and carries none)
    let gyro = if loaded {
        -m.ball_inertia * thd * wr / rb
    } else {
        0.0
    };
    let f_i = -qi * ui;
    let f_o = -qo * uo;
    let s_o = Vector3::new(ao.cos(), 0.0, 0.0) + (-ao.sin()) * er;
    let f_ball = f_i + f_o + gyro * s_o + fc * er;
    let fa = to_azimuth(&f_ball, th);
    let contact = centre + rb * ui - inner.centre;
    let ev = Eval {
        inner_load: qi,
        outer_load: qo,
        inner_alpha: ai,
        outer_alpha: ao,
        centrifugal: fc,
        gyro: gyro.abs() * rb,
    };
    ([fa.x, fa.y], f_i, contact, ev, kin)
}

/// Equilibrium position of one ball for a given inner-ring position.
pub(super) fn solve_ball(
    m: &Model,
    inner: &RingMotion,
    w: f64,
    th: f64,
    warm: Option<[f64; 2]>,
) -> [f64; 2] {
    let er = e_r(th);
    let co = Vector3::new(m.outer_race.centre_axial, 0.0, 0.0) + m.outer_race.centre_radius * er;
    // An unloaded ball rests at the outer groove bottom under its centrifugal force.
    let rb = 0.5 * m.ball_diameter;
    let r_bottom = m.outer_race.centre_radius + m.outer_race.free_distance;
    let thd0 = rolling_kinematics(r_bottom, m.free_contact_angle, m.free_contact_angle, rb, w)[0];
    let fc = m.ball_mass * r_bottom * thd0 * thd0;
    let free = [co.x, r_bottom + hertz::deflection(m.outer_race.hertz.k, fc)];
    let fc_centre = Vector3::new(free[0], 0.0, 0.0) + free[1] * er;
    if contact_geometry(&m.inner_race, inner, &fc_centre).delta <= 0.0 {
        return free;
    }
    // Otherwise start on the line between the curvature centres, sharing the overlap by
    // compliance, or from the previous solution.
    let start = warm.unwrap_or_else(|| {
        let rot = inner.rot;
        let ci = inner.centre
            + rot
                * (Vector3::new(m.inner_race.centre_axial, 0.0, 0.0)
                    + m.inner_race.centre_radius * er);
        let dvec = ci - co;
        let dist = dvec.norm();
        let overlap = dist - (m.inner_race.free_distance + m.outer_race.free_distance);
        let ratio = (m.outer_race.hertz.k / m.inner_race.hertz.k).powf(2.0 / 3.0);
        let delta_o = overlap.max(0.0) / (1.0 + ratio);
        let p = co + (m.outer_race.free_distance + delta_o) * dvec / dist;
        [p.x, p.dot(&er)]
    });
    let mut p = start;
    let h = 1e-11;
    for _ in 0..100 {
        let (r0, ..) = ball_forces(m, inner, w, th, p[0], p[1]);
        let n0 = r0[0].hypot(r0[1]);
        if n0 < 1e-11 {
            break;
        }
        let (rx, ..) = ball_forces(m, inner, w, th, p[0] + h, p[1]);
        let (rr, ..) = ball_forces(m, inner, w, th, p[0], p[1] + h);
        let j = nalgebra::Matrix2::new(
            (rx[0] - r0[0]) / h,
            (rr[0] - r0[0]) / h,
            (rx[1] - r0[1]) / h,
            (rr[1] - r0[1]) / h,
        );
        let Some(step) = j.lu().solve(&nalgebra::Vector2::new(-r0[0], -r0[1])) else {
            break;
        };
        // backtracking keeps the Newton step from overshooting the Hertz kink
        let mut lam = 1.0;
        let mut moved = false;
        for _ in 0..30 {
            let q = [p[0] + lam * step[0], p[1] + lam * step[1]];
            let (r1, ..) = ball_forces(m, inner, w, th, q[0], q[1]);
            if r1[0].hypot(r1[1]) < n0 {
                p = q;
                moved = true;
                break;
            }
            lam *= 0.5;
        }
        if !moved {
            break;
        }
    }
    p
}

/// Ball positions for a ring position, and the ring's force (and moment) residual.
fn ring_residual(
    m: &Model,
    w: f64,
    u: &[f64],
    moment_scale: f64,
    warm: &[[f64; 2]],
    balls: &mut Vec<[f64; 2]>,
) -> [f64; 5] {
    let inner = inner_ring(m, u, w);
    let mut f_ring = Vector3::new(m.applied_force[0], m.applied_force[1], m.applied_force[2]);
    let mut m_ring = Vector3::new(
        0.0,
        moment_scale * m.applied_moment[0],
        moment_scale * m.applied_moment[1],
    );
    balls.clear();
    for (j, th) in azimuths(m).into_iter().enumerate() {
        let p = solve_ball(m, &inner, w, th, warm.get(j).copied());
        let (_, f_i, contact, ..) = ball_forces(m, &inner, w, th, p[0], p[1]);
        f_ring -= f_i;
        m_ring += contact.cross(&(-f_i));
        balls.push(p);
    }
    [f_ring.x, f_ring.y, f_ring.z, m_ring.y, m_ring.z]
}

/// Ring equilibrium: Newton with Levenberg damping, every residual evaluation putting each
/// ball in its own equilibrium first (Jones-Harris nesting). With a free tilt under an
/// applied moment that the direct solve misses, the moment is applied by continuation from
/// the moment-free equilibrium.
pub fn solve_model(m: &Model, w: f64) -> Result<QsState, QsError> {
    let guess = initial_guess(m);
    let direct = newton(m, w, guess, 1.0);
    let (u, balls, iterations, residual) = match direct {
        Ok(sol) => sol,
        Err(fail) if m.tilt_free && m.applied_moment != [0.0, 0.0] => {
            match continuation(m, w, guess) {
                Ok(sol) => sol,
                Err(None) => return Err(no_equilibrium(m, fail, None)),
                Err(Some(reached)) => return Err(no_equilibrium(m, fail, Some(reached))),
            }
        }
        Err(fail) => return Err(no_equilibrium(m, fail, None)),
    };
    let inner = inner_ring(m, &u, w);
    let (kinematics, evals): (Vec<[f64; 3]>, Vec<Eval>) = azimuths(m)
        .into_iter()
        .zip(&balls)
        .map(|(th, p)| {
            let f = ball_forces(m, &inner, w, th, p[0], p[1]);
            (f.4, f.3)
        })
        .unzip();
    let epicyclic = epicyclic_cage_speed(m, &evals, w);
    let balance = cage_balance(
        m,
        &inner,
        &outer_ring(),
        &balls,
        &azimuths(m),
        &kinematics,
        epicyclic,
    );
    Ok(QsState {
        ring: u,
        balls,
        kinematics,
        epicyclic_cage_speed: epicyclic,
        balance,
        iterations,
        residual,
    })
}

/// Pure-rolling cage speed at the contact angles of the load zone, each ball's angle
/// weighted by its contact load (as the dynamic summary defines it), rad/s.
fn epicyclic_cage_speed(m: &Model, evals: &[Eval], w: f64) -> f64 {
    let weighted = |load: fn(&Eval) -> f64, angle: fn(&Eval) -> f64| {
        let (mut sw, mut sum) = (0.0, 0.0);
        for e in evals {
            sw += load(e);
            sum += load(e) * angle(e);
        }
        if sw > 0.0 {
            sum / sw
        } else {
            m.free_contact_angle
        }
    };
    let ai = weighted(|e| e.inner_load, |e| e.inner_alpha);
    let ao = weighted(|e| e.outer_load, |e| e.outer_alpha);
    rolling_kinematics(0.5 * m.pitch_diameter, ai, ao, 0.5 * m.ball_diameter, w)[0]
}

/// A converged ring state: unknowns, ball positions, iterations, largest force residual (N).
type RingSolution = ([f64; 5], Vec<[f64; 2]>, u32, f64);

/// Apply the moment in growing fractions, each solve starting from the last equilibrium.
/// On failure returns the largest fraction of the moment found to have an equilibrium.
/// (`None` when even the moment-free ring has no equilibrium.)
fn continuation(m: &Model, w: f64, guess: [f64; 5]) -> Result<RingSolution, Option<f64>> {
    let mut sol = newton(m, w, guess, 0.0).map_err(|_| None)?;
    let (mut done, mut step) = (0.0_f64, 0.25_f64);
    let mut total_iterations = sol.2;
    while done < 1.0 {
        let next = (done + step).min(1.0);
        // from the last equilibrium, else afresh (near the limit the warm start can stall)
        match newton(m, w, sol.0, next).or_else(|_| newton(m, w, guess, next)) {
            Ok(s) => {
                total_iterations += s.2;
                sol = s;
                done = next;
                step = (2.0 * step).min(0.5);
            }
            Err(_) if next - done > 1.0 / 256.0 => step = 0.5 * (next - done),
            Err(_) => return Err(Some(done)),
        }
    }
    sol.2 = total_iterations;
    Ok(sol)
}

fn no_equilibrium(m: &Model, (residual, iterations): (f64, u32), reached: Option<f64>) -> QsError {
    let [fx, fy, fz] = m.applied_force;
    let (axial_load, radial_load) = (fx.abs(), fy.hypot(fz));
    let needed = radial_load * m.free_contact_angle.tan();
    QsError::NoEquilibrium {
        residual,
        iterations,
        moment_reached: reached,
        applied_moment: m.applied_moment,
        axial_load,
        radial_load,
        // The hint applies near and below the limit (the exact limit moves with speed and
        // the loaded contact angles: at 1000 rpm, 300 N radial it lies between 80 and 90 N).
        axial_load_needed: (!m.tilt_free && radial_load > 0.0 && axial_load < 1.25 * needed)
            .then_some(needed),
    }
}

/// Newton-Levenberg on the ring unknowns from `u0`, with `moment_scale` times the applied
/// moment. Moments enter the residual divided by the pitch radius and tilts the unknowns
/// times it, so every row and column is a force or a displacement of like size. On
/// failure returns the largest ring force residual (N) and the iterations spent.
fn newton(m: &Model, w: f64, u0: [f64; 5], moment_scale: f64) -> Result<RingSolution, (f64, u32)> {
    let nr = ring_unknowns(m);
    let lever = m.pocket.pocket_radius;
    let row = |r: [f64; 5]| [r[0], r[1], r[2], r[3] / lever, r[4] / lever];
    let eval = |u: &[f64; 5], warm: &[[f64; 2]], out: &mut Vec<[f64; 2]>| {
        row(ring_residual(m, w, u, moment_scale, warm, out))
    };
    let mut u = u0;
    let mut balls = Vec::new();
    let mut trial_balls = Vec::new();
    let fref = (m.applied_force.iter().map(|f| f * f).sum::<f64>())
        .sqrt()
        .max(1.0);
    let tol = 1e-10 * fref;
    let mut res = eval(&u, &[], &mut balls);
    let norm = |r: &[f64; 5]| r[..nr].iter().map(|x| x * x).sum::<f64>();
    let mut cost = norm(&res);
    let mut lambda = 1e-6;
    let mut iterations = 0;
    // ring displacements are micrometres: difference steps of 1e-12 m (tilts: 1e-12 m at
    // the pitch radius)
    // (translations keep a factor of exactly 1 so a locked tilt solves as before)
    let unit = |k: usize| if k < 3 { 1.0 } else { 1.0 / lever };
    for it in 0..200 {
        iterations = it;
        if res[..nr].iter().all(|x| x.abs() < tol) {
            break;
        }
        let mut jac = nalgebra::DMatrix::<f64>::zeros(nr, nr);
        for k in 0..nr {
            let mut up = u;
            up[k] += 1e-12 * unit(k);
            let r1 = eval(&up, &balls, &mut trial_balls);
            for i in 0..nr {
                // derivative per scaled unknown (tilt times the pitch radius)
                jac[(i, k)] = (r1[i] - res[i]) / 1e-12;
            }
        }
        let rv = nalgebra::DVector::from_column_slice(&res[..nr]);
        let mut improved = false;
        for _ in 0..40 {
            let mut a = jac.clone();
            for i in 0..nr {
                a[(i, i)] += lambda * jac[(i, i)].abs().max(1.0);
            }
            let Some(step) = a.lu().solve(&(-&rv)) else {
                lambda = lambda * 10.0 + 1e-9;
                continue;
            };
            let mut cand = u;
            for i in 0..nr {
                cand[i] += step[i] * unit(i);
            }
            let r2 = eval(&cand, &balls, &mut trial_balls);
            let c2 = norm(&r2);
            if c2.is_finite() && c2 < cost {
                u = cand;
                res = r2;
                cost = c2;
                std::mem::swap(&mut balls, &mut trial_balls);
                lambda = (lambda * 0.1).max(1e-12);
                improved = true;
                break;
            }
            lambda = lambda * 10.0 + 1e-9;
        }
        if !improved {
            break;
        }
    }
    let residual = res[..nr].iter().fold(0.0f64, |a, x| a.max(x.abs()));
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // a NaN residual fails too
    if !(residual < 1e-6 * fref) || u.iter().any(|x| !x.is_finite()) {
        return Err((residual, iterations));
    }
    Ok((u, balls, iterations, residual))
}

/// Rigid guess for the inner ring from a stiffness estimate.
fn initial_guess(m: &Model) -> [f64; 5] {
    let mut u = [0.0; 5];
    let z = m.z as f64;
    let a0 = m.free_contact_angle;
    let kn =
        (m.inner_race.hertz.k.powf(-2.0 / 3.0) + m.outer_race.hertz.k.powf(-2.0 / 3.0)).powf(-1.5);
    let fa = m.applied_force[0].abs();
    let fr = (m.applied_force[1].powi(2) + m.applied_force[2].powi(2)).sqrt();
    let q = (fa / (z * a0.sin().max(0.1)) + 2.5 * fr / z).max(1.0);
    let d = (q / kn).powf(2.0 / 3.0);
    u[0] = if fa > 0.0 {
        d / a0.sin().max(0.1) * m.applied_force[0].signum()
    } else {
        // No axial load: the ring centred between the grooves, where the loaded balls'
        // axial forces cancel (a bearing with clearance, e.g. a deep groove one under a
        // radial load; an angular contact bearing has no equilibrium there anyway). The ring
        // origin puts the inner groove's curvature centres half the axial clearance aside.
        m.outer_race.centre_axial - m.inner_race.centre_axial
    };
    if fr > 0.0 {
        // centred, the ring first crosses the radial play A (1 - cos a0) before a ball carries
        let play = if fa > 0.0 {
            0.0
        } else {
            (m.inner_race.free_distance + m.outer_race.free_distance) * (1.0 - a0.cos())
        };
        u[1] = (0.5 * d + play) * m.applied_force[1] / fr;
        u[2] = (0.5 * d + play) * m.applied_force[2] / fr;
    }
    u
}

impl QsState {
    fn to_solution(&self, m: &Model, w: f64) -> QuasiStaticSolution {
        let inner = inner_ring(m, &self.ring, w);
        let ev: Vec<Eval> = azimuths(m)
            .into_iter()
            .zip(&self.balls)
            .map(|(th, p)| ball_forces(m, &inner, w, th, p[0], p[1]).3)
            .collect();
        let cage = self
            .balance
            .as_ref()
            .map_or(self.epicyclic_cage_speed, |b| b.cage_speed);
        // mean spin of the balls the races carry
        let loaded: Vec<f64> = self
            .kinematics
            .iter()
            .zip(&ev)
            .enumerate()
            .filter(|(_, (_, e))| e.inner_load > 0.0)
            .map(|(j, (k, _))| match &self.balance {
                Some(b) => {
                    let [x, r, t] = b.spins[j];
                    (x * x + r * r + t * t).sqrt()
                }
                None => (k[1] * k[1] + k[2] * k[2]).sqrt(),
            })
            .collect();
        let spin = if loaded.is_empty() {
            0.0
        } else {
            loaded.iter().sum::<f64>() / loaded.len() as f64
        };
        QuasiStaticSolution {
            shaft_speed: w,
            inner_ring_displacement: [self.ring[0], self.ring[1], self.ring[2]],
            inner_ring_tilt: [self.ring[3], self.ring[4]],
            cage_speed: cage,
            traction_balanced: self.balance.is_some(),
            epicyclic_cage_speed: self.epicyclic_cage_speed,
            ball_spin_speed: spin,
            inner_groove_curvature: (m.inner_race.free_distance / m.ball_diameter) + 0.5,
            outer_groove_curvature: (m.outer_race.free_distance / m.ball_diameter) + 0.5,
            iterations: self.iterations,
            residual: self.residual,
            pocket_cycle: None,
            balls: azimuths(m)
                .into_iter()
                .zip(ev)
                .map(|(az, e)| QsBall {
                    azimuth: az,
                    inner_load: e.inner_load,
                    outer_load: e.outer_load,
                    inner_contact_angle: e.inner_alpha,
                    outer_contact_angle: e.outer_alpha,
                    centrifugal_force: e.centrifugal,
                    gyroscopic_moment: e.gyro,
                })
                .collect(),
        }
    }
}

/// Azimuths at which the pocket cycle's ball centre is solved, over one orbit: 360 moved the
/// curve's balanced cage speed at the paper's point by 3e-6 against 720 (2026-11-28).
const POCKET_CYCLE_GRID: usize = 720;

/// The cage speed by the pocket cycle ([`super::pocket_cycle`]) at `shaft_rpm`: one ball
/// carried round its orbit at the equilibrium's ball positions, in a pocket turning with the
/// cage, from the steady balance's cage speed and spins (or the kinematics where that found
/// none). Takes about 0.5 s under the paper's curve, several seconds under the rheology law.
pub fn pocket_cycle(
    scene: &ValidScene,
    shaft_rpm: f64,
) -> Result<super::pocket_cycle::PocketCycle, QsError> {
    pocket_cycle_until(scene, shaft_rpm, &|| false)
}

/// [`pocket_cycle`], giving up (an error) when `stop` says so; it is asked before each trial
/// cage speed, every 0.05-0.5 s of work.
pub fn pocket_cycle_until(
    scene: &ValidScene,
    shaft_rpm: f64,
    stop: &dyn Fn() -> bool,
) -> Result<super::pocket_cycle::PocketCycle, QsError> {
    pocket_cycle_with(scene, shaft_rpm, &PocketCycleSettings::default(), stop)
}

/// [`pocket_cycle_until`] with the cycle's numerical settings given; settings that cannot
/// run are an error naming the setting ([`PocketCycleSettings::check`]).
pub fn pocket_cycle_with(
    scene: &ValidScene,
    shaft_rpm: f64,
    settings: &PocketCycleSettings,
    stop: &dyn Fn() -> bool,
) -> Result<super::pocket_cycle::PocketCycle, QsError> {
    if !(shaft_rpm.is_finite() && shaft_rpm > 0.0) {
        return Err(QsError::InvalidSpeed { rpm: shaft_rpm });
    }
    settings
        .check()
        .map_err(|reason| QsError::PocketCycle { reason })?;
    let m = Model::new(scene);
    let w = shaft_rpm * 2.0 * std::f64::consts::PI / 60.0;
    let st = solve_model(&m, w)?;
    let inner = inner_ring(&m, &st.ring, w);
    let mut warm = None;
    let grid: Vec<[f64; 2]> = (0..POCKET_CYCLE_GRID)
        .map(|k| {
            let th = k as f64 * std::f64::consts::TAU / POCKET_CYCLE_GRID as f64;
            let p = solve_ball(&m, &inner, w, th, warm);
            warm = Some(p);
            p
        })
        .collect();
    let (cage0, w0) = match &st.balance {
        Some(b) => (b.cage_speed, b.spins[0]),
        None => {
            let k = st.kinematics[0];
            (st.epicyclic_cage_speed, [k[1], k[2], 0.0])
        }
    };
    super::pocket_cycle::pocket_cycle(&m, &inner, &outer_ring(), &grid, cage0, w0, settings, stop)
        .map_err(|reason| QsError::PocketCycle { reason })
}
