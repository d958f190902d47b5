//! Exact Hertz constants against an independent computation: the curvature-difference
//! form of the ellipticity relation (algebraically Biboulet & Houpert 2010, Part 2, eq. 43,
//! checked numerically) with Carlson's symmetric elliptic integrals
//! (DLMF 19.36) and a bracketing solve, where the engine uses the same relation in its
//! `Ry/Rx` form (Biboulet & Houpert's App. 2, eq. 43), the arithmetic-geometric mean and a log-space
//! bisection. Two routes, one answer.

use bearing_core::physics::hertz::{effective_modulus, elliptic_ke, exact, hamrock_brewe};
use std::f64::consts::PI;

/// Carlson's R_F(x, y, z) by the duplication theorem (DLMF 19.36.1).
fn carlson_rf(mut x: f64, mut y: f64, mut z: f64) -> f64 {
    for _ in 0..100 {
        let l = (x * y).sqrt() + (y * z).sqrt() + (z * x).sqrt();
        x = 0.25 * (x + l);
        y = 0.25 * (y + l);
        z = 0.25 * (z + l);
        let mu = (x + y + z) / 3.0;
        if ((x - mu).abs().max((y - mu).abs()).max((z - mu).abs())) / mu < 1e-4 {
            break;
        }
    }
    let mu = (x + y + z) / 3.0;
    let (dx, dy, dz) = (1.0 - x / mu, 1.0 - y / mu, 1.0 - z / mu);
    let e2 = dx * dy + dy * dz + dz * dx;
    let e3 = dx * dy * dz;
    // series to fifth order (error ~ eps^6 with eps < 1e-4)
    (1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0) / mu.sqrt()
}

/// Carlson's R_D(x, y, z) by the duplication theorem (DLMF 19.36.2).
fn carlson_rd(mut x: f64, mut y: f64, mut z: f64) -> f64 {
    let mut sum = 0.0;
    let mut fac = 1.0;
    for _ in 0..100 {
        let l = (x * y).sqrt() + (y * z).sqrt() + (z * x).sqrt();
        sum += fac / (z.sqrt() * (z + l));
        fac *= 0.25;
        x = 0.25 * (x + l);
        y = 0.25 * (y + l);
        z = 0.25 * (z + l);
        let mu = (x + y + 3.0 * z) / 5.0;
        if ((x - mu).abs().max((y - mu).abs()).max((z - mu).abs())) / mu < 1e-4 {
            break;
        }
    }
    let mu = (x + y + 3.0 * z) / 5.0;
    let (dx, dy, dz) = (1.0 - x / mu, 1.0 - y / mu, 1.0 - z / mu);
    let ea = dx * dy;
    let eb = dz * dz;
    let ec = ea - eb;
    let ed = ea - 6.0 * eb;
    let ee = ed + ec + ec;
    let s = ed * (-3.0 / 14.0 + 9.0 / 88.0 * ed - 4.5 / 26.0 * dz * ee)
        + dz * (ee / 6.0 + dz * (-9.0 / 22.0 * ec + dz * 3.0 / 26.0 * ea));
    3.0 * sum + fac * (1.0 + s) / (mu * mu.sqrt())
}

/// K(m) and E(m) from Carlson's integrals.
fn ke(m: f64) -> (f64, f64) {
    let k = carlson_rf(0.0, 1.0 - m, 1.0);
    (k, k - m / 3.0 * carlson_rd(0.0, 1.0 - m, 1.0))
}

/// The curvature-difference form (named after Harris, whose book was not read; algebraically
/// Biboulet & Houpert's eq. 43, checked numerically): F(rho) = (1/Rx - 1/Ry)/(1/Rx + 1/Ry) = ((k^2 + 1) E - 2 K) / ((k^2 - 1) E) fixes
/// the ellipticity k = a/b; then a = (6 k^2 E Q / (pi S E'))^(1/3),
/// b = (6 E Q / (pi k S E'))^(1/3), delta = K (9 S / (2 E) (Q / (pi k E'))^2)^(1/3) with
/// S = 1/Rx + 1/Ry. Returns (K_load, a, b) for Q = 1 N.
fn harris(rx: f64, ry: f64, e_prime: f64) -> (f64, f64, f64) {
    let sum = 1.0 / rx + 1.0 / ry;
    let target = (1.0 / rx - 1.0 / ry) / sum;
    let f = |kappa: f64| {
        let (k, e) = ke(1.0 - 1.0 / (kappa * kappa));
        ((kappa * kappa + 1.0) * e - 2.0 * k) / ((kappa * kappa - 1.0) * e) - target
    };
    // F grows with kappa: Illinois regula falsi on a bracket
    let (mut lo, mut hi) = (1.0 + 1e-7, 200.0);
    let (mut flo, mut fhi) = (f(lo), f(hi));
    assert!(flo < 0.0 && fhi > 0.0);
    let mut side = 0;
    for _ in 0..500 {
        let x = (lo * fhi - hi * flo) / (fhi - flo);
        let fx = f(x);
        if fx == 0.0 || (hi - lo) < 1e-15 * x {
            lo = x;
            hi = x;
            break;
        }
        if fx < 0.0 {
            lo = x;
            flo = fx;
            if side == -1 {
                fhi *= 0.5;
            }
            side = -1;
        } else {
            hi = x;
            fhi = fx;
            if side == 1 {
                flo *= 0.5;
            }
            side = 1;
        }
    }
    let kappa = 0.5 * (lo + hi);
    let (kk, ee) = ke(1.0 - 1.0 / (kappa * kappa));
    let a = (6.0 * kappa * kappa * ee / (PI * sum * e_prime)).cbrt();
    let b = (6.0 * ee / (PI * kappa * sum * e_prime)).cbrt();
    let delta = kk * (9.0 * sum / (2.0 * ee) * (1.0 / (PI * kappa * e_prime)).powi(2)).cbrt();
    (delta.powf(-1.5), a, b)
}

#[test]
fn carlson_integrals_match_published_values() {
    // Abramowitz & Stegun table 17.1 (15 digits): the independent route itself is right.
    for (m, k, e) in [
        (0.1, 1.612_441_348_720_219, 1.530_757_636_897_763),
        (0.5, 1.854_074_677_301_372, 1.350_643_881_047_675),
        (0.9, 2.578_092_113_348_173, 1.104_774_732_704_073),
    ] {
        let (kc, ec) = ke(m);
        assert!(
            (kc - k).abs() < 1e-13 && (ec - e).abs() < 1e-13,
            "m {m}: {kc} {ec}"
        );
        let (ka, ea) = elliptic_ke(m);
        assert!(
            (ka - k).abs() < 1e-13 && (ea - e).abs() < 1e-13,
            "AGM m {m}: {ka} {ea}"
        );
    }
}

#[test]
fn exact_hertz_matches_an_independent_computation_to_1e_9() {
    let ep = effective_modulus(208e9, 0.3, 208e9, 0.3);
    let d = 5.556e-3;
    let gamma = d * 15f64.to_radians().cos() / 35.9935e-3;
    let mut cases = vec![
        // H7005C inner and outer race contacts (f = 0.53, 0.536)
        (0.5 * d * (1.0 - gamma), 0.53 * d / (2.0 * 0.53 - 1.0)),
        (0.5 * d * (1.0 + gamma), 0.536 * d / (2.0 * 0.536 - 1.0)),
    ];
    // and ratios Ry/Rx from near-circular to very slender ellipses
    for ratio in [1.5, 3.0, 10.0, 30.0, 100.0] {
        cases.push((1e-3, 1e-3 * ratio));
    }
    for (rx, ry) in cases {
        let e = exact(rx, ry, ep);
        let (k, a, b) = harris(rx, ry, ep);
        // 1e-9: the bound; both routes converge to ~1e-13 here
        for (name, x, y) in [("K", e.k, k), ("a", e.a_coef, a), ("b", e.b_coef, b)] {
            let rel = (x - y).abs() / y;
            assert!(
                rel < 1e-9,
                "Ry/Rx {}: {name} {x:e} vs {y:e} ({rel:e})",
                ry / rx
            );
        }
        // what the Hamrock-Brewe fits cost in accuracy (docs/reference/model.md quotes these)
        let hb = hamrock_brewe(rx, ry, ep);
        eprintln!(
            "Ry/Rx {:8.3}: Hamrock-Brewe K {:+.2} %, a {:+.2} %, b {:+.2} %",
            ry / rx,
            100.0 * (hb.k / k - 1.0),
            100.0 * (hb.a_coef / a - 1.0),
            100.0 * (hb.b_coef / b - 1.0)
        );
    }
}
