//! Helpers shared by the engine's integration tests: synthetic signals and the committed
//! recordings in `tests/fixtures/`.
#![allow(dead_code)]

use std::f64::consts::PI;

/// Deterministic xorshift64* generator with Box-Muller normals (no dependency, reproducible).
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.max(1))
    }
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545F4914F6CDD1D);
        ((v >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    pub fn normal(&mut self) -> f64 {
        let (u1, u2) = (self.uniform(), self.uniform());
        (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
    }
}

/// Impulses at `t_k = phase + k / rate` (continuous times, so the rate is exact), each exciting a
/// decaying resonance `amp_k exp(-2 pi zeta fn (t - t_k)) sin(2 pi fn_d (t - t_k))`, with
/// `amp_k = 1 + am_depth cos(2 pi am_hz t_k)` (load-zone modulation; 0 for none).
#[allow(clippy::too_many_arguments)]
pub fn impulse_train(
    n: usize,
    fs: f64,
    rate: f64,
    phase: f64,
    resonance_hz: f64,
    zeta: f64,
    am_depth: f64,
    am_hz: f64,
) -> Vec<f64> {
    let mut x = vec![0.0; n];
    let decay = 2.0 * PI * zeta * resonance_hz;
    let wd = 2.0 * PI * resonance_hz * (1.0 - zeta * zeta).sqrt();
    let ring = (12.0 / decay * fs) as usize; // until exp(-12) ~ 6e-6
    let duration = n as f64 / fs;
    let mut k = 0;
    loop {
        let tk = phase + k as f64 / rate;
        if tk >= duration {
            break;
        }
        let amp = 1.0 + am_depth * (2.0 * PI * am_hz * tk).cos();
        let i0 = (tk * fs).ceil() as usize;
        for (i, xi) in x.iter_mut().enumerate().skip(i0).take(ring) {
            let t = i as f64 / fs - tk;
            *xi += amp * (-decay * t).exp() * (wd * t).sin();
        }
        k += 1;
    }
    x
}

pub fn add_noise(x: &mut [f64], sigma: f64, rng: &mut Rng) {
    for v in x.iter_mut() {
        *v += sigma * rng.normal();
    }
}

pub fn read_f32le(path: &str) -> Vec<f64> {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    let b = std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    b.chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64)
        .collect()
}
