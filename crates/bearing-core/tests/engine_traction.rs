//! The rheology traction law against an independent implementation of the same cited
//! formulas (`scripts/fixtures/rheology_traction.py`, written from the formulas alone,
//! without the Rust code): `tests/fixtures/rheology_traction.csv`, loaded and nearly
//! unloaded contacts, two entrainment speeds, three strips, slips from zero to sliding, and
//! a second oil.

use bearing_core::physics::hertz::HertzContact;
use bearing_core::physics::rheology_traction::{roelands_z, Rheology, RheologyTraction};

fn rows() -> Vec<std::collections::HashMap<String, f64>> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/rheology_traction.csv");
    let text = std::fs::read_to_string(path).expect("fixture");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines
        .map(|l| {
            header
                .iter()
                .zip(l.split(','))
                .map(|(k, v)| (k.to_string(), v.parse::<f64>().expect("a number")))
                .collect()
        })
        .collect()
}

/// Every intermediate and the coefficient equal the fixture's within 1e-12 relative: both
/// evaluate the same closed forms in f64 (the engine with an exponential within 2 ulp of
/// libm's and its own operation order), so they differ by rounding, amplified at most by
/// the exponent of Roelands' viscosity (ln eta ~ 7 at 1.3 GPa: 7 x 1e-15).
#[test]
fn rheology_law_matches_the_independent_fixture() {
    let rows = rows();
    assert!(rows.len() >= 100, "{} rows", rows.len());
    let close = |what: &str, got: f64, want: f64, r: &std::collections::HashMap<String, f64>| {
        let tol = 1e-12 * want.abs().max(1e-300);
        assert!(
            (got - want).abs() <= tol,
            "{what}: {got:e} against {want:e} at q {} um {} xi {} s {}",
            r["q_n"],
            r["um_m_s"],
            r["xi"],
            r["s_m_s"]
        );
    };
    let mut capped = 0;
    let mut linear = 0;
    for r in &rows {
        let q = r["q_n"];
        let q13 = q.cbrt();
        let hertz = HertzContact {
            k: 0.0, // not read by the law
            a_coef: r["a_m"] / q13,
            b_coef: r["b_m"] / q13,
        };
        let z = roelands_z(r["eta0_pa_s"], r["alpha0_per_pa"]);
        close("z", z, r["z"], r);
        let law = RheologyTraction::new(
            r["e_prime_pa"],
            r["rx_m"],
            &hertz,
            &Rheology {
                eta0: r["eta0_pa_s"],
                alpha0: r["alpha0_per_pa"],
                z,
                limiting: r["lambda"],
            },
        );
        let c = law.at(q, r["um_m_s"]);
        close("h_c", c.h, r["h_c_m"], r);
        let f = c.strip(r["xi"]);
        close("p_strip", f.pressure, r["p_strip_pa"], r);
        close("eta", f.viscosity, r["eta_pa_s"], r);
        close("alpha_local", f.alpha, r["alpha_local_per_pa"], r);
        close("tau_e", f.eyring_stress, r["tau_e_pa"], r);
        close("slope", c.mu_over_s(r["xi"], 0.0), r["slope_s_per_m"], r);
        close("mu", c.mu(r["xi"], r["s_m_s"]), r["mu"], r);
        if r["mu"] == r["lambda"] {
            capped += 1;
        } else if r["s_m_s"] > 0.0 && r["mu"] < 0.5 * r["lambda"] {
            linear += 1;
        }
    }
    // the fixture covers both regimes: at the limiting shear and below it
    assert!(
        capped > 10 && linear > 10,
        "{capped} capped, {linear} below"
    );
}

/// The engine's exact Hertz semi-axes equal the fixture's, which the script derives
/// independently from Biboulet & Houpert's ellipticity relation (2010, Part 2, App. 2,
/// eqs. 41-43) and their dimensionless load, for the H7005C inner contact (Rx 2.364 mm,
/// Ry 49.07 mm, E' 228.6 GPa). 1e-9 relative: both solve for the ellipticity to
/// ~1e-12 and integrate the elliptic integrals to ~1e-12 (the script by the trapezoid rule,
/// exponentially convergent for a periodic integrand; the engine by the AGM).
#[test]
fn exact_hertz_semi_axes_match_the_fixture() {
    let r = &rows()[0];
    let hz = bearing_core::physics::hertz::exact(r["rx_m"], 49.07e-3, r["e_prime_pa"]);
    let q13 = r["q_n"].cbrt();
    let (a, b) = (r["a_m"] / q13, r["b_m"] / q13);
    assert!((hz.a_coef / a - 1.0).abs() < 1e-9, "{} {a}", hz.a_coef);
    assert!((hz.b_coef / b - 1.0).abs() < 1e-9, "{} {b}", hz.b_coef);
}
