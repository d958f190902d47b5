//! Analysis speed on 2^20 samples: DTCWT (5 levels) + per-level components + envelope spectra.
//!
//! `cargo bench -p bearing-core --bench analysis`. Prints the
//! median and min of several runs of each stage, on one thread (the library is single-threaded).
//! The target: DTCWT 5 levels + envelope spectrum of 2^20 samples in under 1 s.

use std::hint::black_box;
use std::time::{Duration, Instant};

use bearing_core::signal::dtcwt::Dtcwt1d;
use bearing_core::signal::spectrum::EnvelopeSpectrumPlan;
use bearing_core::signal::{analyze, kinematic_preset, AnalysisOptions};

const N: usize = 1 << 20;
const FS: f64 = 51_200.0;
const RUNS: usize = 7;

fn signal() -> Vec<f64> {
    // impulsive resonance train plus deterministic pseudo-noise, like a faulty bearing
    let mut s: u64 = 0x9E3779B97F4A7C15;
    (0..N)
        .map(|i| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let noise = (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            let t = (i as f64 / FS * 1134.6).fract() / 1134.6;
            noise + (-3000.0 * t).exp() * (2.0 * std::f64::consts::PI * 9000.0 * t).sin()
        })
        .collect()
}

fn time<T>(label: &str, mut f: impl FnMut() -> T) -> Duration {
    let _ = black_box(f()); // warm-up (plans, page faults)
    let mut d: Vec<Duration> = (0..RUNS)
        .map(|_| {
            let t0 = Instant::now();
            black_box(f());
            t0.elapsed()
        })
        .collect();
    d.sort();
    let med = d[RUNS / 2];
    println!(
        "{label:<58} median {:>8.1} ms   min {:>8.1} ms   ({RUNS} runs)",
        ms(med),
        ms(d[0])
    );
    med
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn main() {
    let x = signal();
    let t = Dtcwt1d::default();
    println!(
        "analysis benchmark: n = 2^20 = {N} samples, fs = {FS} Hz, 5 levels, near_sym_b / qshift_b"
    );

    let fwd = time("DTCWT forward, 5 levels", || t.forward(&x, 5).unwrap());
    let p = t.forward(&x, 5).unwrap();
    let comps = time("5 per-level components (single-level inverses)", || {
        (1..=5)
            .map(|l| t.level_component(&p, l))
            .collect::<Vec<_>>()
    });
    let mut plan = EnvelopeSpectrumPlan::new(N);
    let env1 = time(
        "envelope spectrum, one record (planned, buffers reused)",
        || plan.compute(&x, FS, None),
    );
    let plan_cost = time("envelope spectrum incl. planning", || {
        EnvelopeSpectrumPlan::new(N).compute(&x, FS, None)
    });
    let target = time(
        "DTCWT 5 levels + components + envelope spectrum of best",
        || {
            let p = t.forward(&x, 5).unwrap();
            let c: Vec<Vec<f64>> = (1..=5).map(|l| t.level_component(&p, l)).collect();
            let k: Vec<f64> = c
                .iter()
                .map(|v| bearing_core::signal::kurtosis::kurtosis(v))
                .collect();
            let best = (0..5).max_by(|&a, &b| k[a].total_cmp(&k[b])).unwrap();
            plan.compute(&c[best], FS, None)
        },
    );
    let g = kinematic_preset("h7005c").unwrap();
    let full = time(
        "analyze(): + raw and all 5 level envelope spectra + identification",
        || analyze(&x, FS, &g, 10_000.0 / 60.0, &AnalysisOptions::default()).unwrap(),
    );
    println!();
    println!("summary (median, ms): forward {:.1}, components {:.1}, envelope spectrum {:.1} ({:.1} with planning), target pipeline {:.1}, full analyze {:.1}",
        ms(fwd), ms(comps), ms(env1), ms(plan_cost), ms(target), ms(full));
    println!(
        "target < 1000 ms: {}",
        if target < Duration::from_secs(1) {
            "met"
        } else {
            "NOT met"
        }
    );
}
