//! Which instruction set the hot contact code runs in, decided once per process.
//!
//! The release build targets the baseline x86-64 (SSE2), so that the binary runs on any
//! x86-64 processor, and under Debian's valgrind 3.19, which stopped on an instruction of a
//! whole build for x86-64-v3. The hot functions (`race_contact::race_contact`, a pass of
//! `race_contact_lanes::race_contacts`, a group of `cage_pocket_lanes::pocket_contacts`,
//! `frames::azimuths` and `frames::angles`, and the defect step bound,
//! `dynamics::step_bound::defect_step_bound`, whose `trunc` and `mul_add` are library calls
//! in the baseline) are declared with [`twice_compiled!`]: compiled a second time with
//! AVX2 and FMA enabled, and that copy chosen here (valgrind runs it);
//! `BEARING_SIM_CPU=baseline` keeps the baseline copy (since 2026-11-30 its fused steps
//! and `floor` are libm calls, one a lane, so its instruction counts are no longer those
//! of earlier builds' baseline copy). Measured: docs/lab/benchmarks.md, "AVX2".

use std::sync::atomic::{AtomicU8, Ordering};

/// 0: not decided yet, 1: baseline, 2: AVX2 and FMA.
static CHOICE: AtomicU8 = AtomicU8::new(0);

/// Declares `fn name(args) -> ret` running `body(args)` (an `#[inline(always)]` function),
/// compiled twice: as it is, and as `wide` with AVX2 and FMA enabled (x86-64 only; unsafe
/// to call where the processor lacks them), the copy chosen at run time by
/// [`wide_vectors`]. The two copies give the same numbers: neither reorders an operation,
/// and they fuse only where the code asks (`mul_add`, rounded once in both: an FMA
/// instruction in the wide copy, libm's `fma` in the baseline one; Rust contracts nothing
/// into FMA by itself); tests compare them to the bit (`race_contact`, `race_contacts`,
/// `azimuths`, `angles`).
macro_rules! twice_compiled {
    ($(#[$meta:meta])* $vis:vis fn $name:ident($($arg:ident: $ty:ty),* $(,)?) $(-> $ret:ty)?
        = $body:path, wide $wide:ident;) => {
        $(#[$meta])*
        #[inline]
        $vis fn $name($($arg: $ty),*) $(-> $ret)? {
            #[cfg(target_arch = "x86_64")]
            if $crate::physics::cpu::wide_vectors() {
                // SAFETY: the processor has AVX2 and FMA, checked at run time.
                return unsafe { $wide($($arg),*) };
            }
            $body($($arg),*)
        }

        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn $wide($($arg: $ty),*) $(-> $ret)? {
            $body($($arg),*)
        }
    };
}
pub(crate) use twice_compiled;

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
