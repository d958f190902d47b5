//! A ball driven across a raceway defect: contact-load drop and load-direction change
//! (eqs. 33-36, Figure 8), for both rings.

use bearing_core::model::Model;
use bearing_core::physics::race_contact::{race_contact, BallMotion, RingMotion};
use bearing_core::physics::Vector3;
use bearing_core::quasi_static::solve_model;
use bearing_core::scene::{fault_case_scene, FaultCase};
use nalgebra::Matrix3;

/// Sweep the defect past ball 0 (at azimuth 0, the defect's home angle) by rotating the
/// ring body; returns (offset along the race in m, load in N, tangential force on ball in N).
fn sweep(case: FaultCase, inner: bool) -> Vec<(f64, f64, f64)> {
    let scene = fault_case_scene("h7005c", case).unwrap();
    let m = Model::new(&scene.validated().unwrap());
    let qs = solve_model(&m, 0.0).unwrap();
    let [x, r] = qs.balls[0];
    let ball = BallMotion {
        centre: Vector3::new(x, 0.0, r),
        velocity: Vector3::zeros(),
        omega: Vector3::zeros(),
    };
    let race = if inner { &m.inner_race } else { &m.outer_race };
    let centre = if inner {
        Vector3::new(qs.ring[0], qs.ring[1], qs.ring[2])
    } else {
        Vector3::zeros()
    };
    let half = race.defects[0].half_angle;
    let mut out = Vec::new();
    for k in -60..=60 {
        // ring spun by phi puts the defect at azimuth phi; the ball sits at -phi relative
        let phi = -(k as f64) / 40.0 * half;
        let ring = RingMotion::new(centre, Matrix3::identity(), Vector3::zeros(), 0.0, phi);
        let c = race_contact(race, &ring, &ball, &m.contact);
        // tangential direction at azimuth 0 is e_t = (0, -1, 0)
        out.push((-phi * race.path_radius, c.load, -c.force_on_ball.y));
    }
    out
}

fn check(case: FaultCase, inner: bool) {
    let s = sweep(case, inner);
    let healthy = s[0].1;
    assert!(healthy > 50.0, "ball 0 sits in the load zone: {healthy} N");
    let width = 0.2e-3;
    for &(pos, load, ft) in &s {
        if pos.abs() >= 0.5 * width {
            // outside the defect: the healthy load, no tangential push (stationary ball)
            assert!((load - healthy).abs() < 1e-9 * healthy, "at {pos}: {load}");
            assert!(ft.abs() < 1e-9 * healthy);
        } else {
            assert!(load < healthy, "load must drop inside the defect at {pos}");
        }
    }
    // Deepest drop at the centre: a 0.2 mm pit lets the ball sink ~1.6-2.1 um, most of a
    // ~3 um Hertz deflection at ~80 N, so the load falls by well over half.
    let centre = s.iter().find(|p| p.0.abs() < 1e-9).unwrap();
    assert!(
        centre.1 < 0.5 * healthy,
        "centre load {} vs {healthy}",
        centre.1
    );
    // Direction change (eq. 36): while the ball bears on an edge at distance
    // d = w/2 - |s| from its centre line, the load points from the edge to the ball
    // centre, tilted by psi = asin(d / r_ball) in the rolling plane: forward (+e_t) when
    // entering, backward when leaving. The tangential force must be Q sin(psi) exactly
    // (up to rounding, 1e-9 relative) with that sign.
    let rb = 0.5 * 5.556e-3;
    let mut turned = 0;
    for &(pos, load, ft) in s
        .iter()
        .filter(|p| p.0.abs() < 0.5 * width - 1e-9 && p.0.abs() > 1e-9)
    {
        let psi = ((0.5 * width - pos.abs()) / rb).asin();
        let expected = -pos.signum() * load * psi.sin();
        assert!(
            (ft - expected).abs() < 1e-9 * healthy,
            "at {pos}: {ft} vs {expected}"
        );
        turned += 1;
    }
    assert!(turned > 20);
}

#[test]
fn outer_defect_drops_and_turns_the_load() {
    check(FaultCase::Outer, false);
}

#[test]
fn inner_defect_drops_and_turns_the_load() {
    check(FaultCase::Inner, true);
}
