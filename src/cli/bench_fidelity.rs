//! `bearing-sim bench fidelity`: each fidelity level against the full model on one scene:
//! run time, the identified fault frequencies, mean cage speed, band RMS and peak contact
//! loads.

use super::bench_comparison::{
    comparison_scene, name_of, parse_fidelity, parse_name, read, ComparisonArgs,
};
use super::result::CliResult;
use bearing_core::scene::{Integrator, TractionQuadrature};
use bearing_core::simulation::{simulate, RunControl};

pub fn fidelity(
    on: &ComparisonArgs,
    levels: &[String],
    strips: &[usize],
    integrator: Option<&str>,
    tolerances: &[f64],
    quadratures: &[String],
) -> CliResult {
    let base = comparison_scene(on)?;
    let levels = levels
        .iter()
        .map(|l| parse_fidelity(l).map(|f| (l.as_str(), f)))
        .collect::<Result<Vec<_>, _>>()?;
    // every option parsed before the reference runs
    let quadratures = quadratures
        .iter()
        .map(|q| {
            parse_name::<TractionQuadrature>("--quadratures", "traction quadrature", q).map(Some)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let quadratures = if quadratures.is_empty() {
        vec![None]
    } else {
        quadratures
    };
    let integrator = integrator
        .map(|name| parse_name::<Integrator>("--integrator", "integrator", name))
        .transpose()?;
    eprintln!("reference: full fidelity");
    let full = simulate(&base.clone().validated()?, RunControl::default())?;
    let f = read(&base, &full)?;
    println!("| level | integrator | strips | quadrature | tolerance | wall time (s) | speed-up | RHS evaluations | BPFO (Hz) | BPFI (Hz) | cage speed (rad/s) | band RMS < 20 kHz (m/s^2) | peak inner / outer load, ball 0 (N) |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    let rel = |a: f64, b: f64| 100.0 * (a - b) / b;
    println!(
        "| full | {} | {} | {} | {:.1e} | {:.2} | 1 | {} | {:.2} | {:.2} | {:.3} | {:.3} | {:.1} / {:.1} |",
        name_of(base.solver.integrator),
        base.traction_strips(),
        name_of(base.solver.traction_quadrature),
        base.solver.rtol,
        f.wall,
        f.rhs,
        f.bpfo,
        f.bpfi,
        f.cage,
        f.band_rms,
        f.peak_loads[0],
        f.peak_loads[1]
    );
    // Every combination of level, strip count and tolerance; an empty list keeps the
    // scene's value.
    let strips: Vec<Option<usize>> = if strips.is_empty() {
        vec![None]
    } else {
        strips.iter().copied().map(Some).collect()
    };
    let tolerances: Vec<Option<f64>> = if tolerances.is_empty() {
        vec![None]
    } else {
        tolerances.iter().copied().map(Some).collect()
    };
    for (name, level) in levels {
        for (n, q) in strips
            .iter()
            .flat_map(|n| quadratures.iter().map(move |q| (n, q)))
        {
            for tol in &tolerances {
                let mut s = base.clone();
                s.solver.fidelity = level;
                if let Some(q) = q {
                    s.solver.traction_quadrature = *q;
                }
                if let Some(n) = n {
                    s.solver.traction_strips = Some(*n);
                }
                if let Some(tol) = tol {
                    s.solver.rtol = *tol;
                    s.solver.atol = *tol;
                }
                if let Some(i) = integrator {
                    s.solver.integrator = i;
                }
                eprintln!("{name}");
                let r = simulate(&s.clone().validated()?, RunControl::default())?;
                let g = read(&s, &r)?;
                println!(
                    "| {name} | {} | {} | {} | {:.1e} | {:.2} | {:.1} | {} | {:.2} ({:+.3} %) | {:.2} ({:+.3} %) | {:.3} ({:+.3} %) | {:.3} ({:+.1} %) | {:.1} ({:+.1} %) / {:.1} ({:+.1} %) |",
                    name_of(s.solver.integrator),
                    s.traction_strips(),
                    name_of(s.solver.traction_quadrature),
                    s.solver.rtol,
                    g.wall,
                    f.wall / g.wall,
                    g.rhs,
                    g.bpfo,
                    rel(g.bpfo, f.bpfo),
                    g.bpfi,
                    rel(g.bpfi, f.bpfi),
                    g.cage,
                    rel(g.cage, f.cage),
                    g.band_rms,
                    rel(g.band_rms, f.band_rms),
                    g.peak_loads[0],
                    rel(g.peak_loads[0], f.peak_loads[0]),
                    g.peak_loads[1],
                    rel(g.peak_loads[1], f.peak_loads[1]),
                );
            }
        }
    }
    Ok(())
}
