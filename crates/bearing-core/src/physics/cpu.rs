//! Which instruction set the hot contact code runs in, decided once per process.
//!
//! The release build targets the baseline x86-64 (SSE2), so that the binary runs on any
//! x86-64 processor, and under Debian's valgrind 3.19, which stopped on an instruction of a
//! whole build for x86-64-v3. `physics::race_contact::race_contact` (and
//! `physics::race_contact_lanes::race_contacts`, and `physics::cage_pocket_lanes::pocket_contacts`)
//! is compiled a second time with AVX2 and FMA enabled and chosen here (valgrind runs that
//! copy);
//! `BEARING_SIM_CPU=baseline` keeps the baseline copy, for instruction counts comparable
//! with builds before it. Measured: docs/lab/benchmarks.md, "AVX2".

use std::sync::atomic::{AtomicU8, Ordering};

/// 0: not decided yet, 1: baseline, 2: AVX2 and FMA.
static CHOICE: AtomicU8 = AtomicU8::new(0);

/// True when the contact code should run its AVX2 and FMA copy.
#[inline]
pub fn wide_vectors() -> bool {
    match CHOICE.load(Ordering::Relaxed) {
        0 => decide(),
        c => c == 2,
    }
}

#[cold]
fn decide() -> bool {
    let forced_baseline = std::env::var("BEARING_SIM_CPU").is_ok_and(|v| v == "baseline");
    #[cfg(target_arch = "x86_64")]
    let wide = !forced_baseline
        && std::arch::is_x86_feature_detected!("avx2")
        && std::arch::is_x86_feature_detected!("fma");
    #[cfg(not(target_arch = "x86_64"))]
    let wide = {
        let _ = forced_baseline;
        false
    };
    CHOICE.store(if wide { 2 } else { 1 }, Ordering::Relaxed);
    wide
}
