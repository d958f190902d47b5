//! Four numbers side by side: what lets four ball-race contacts run as one
//! ([`super::race_contact_lanes`]), four ball-pocket interactions
//! ([`super::cage_pocket_lanes`]), and four angles' sines or arctangents
//! ([`super::frames::azimuths`], [`super::frames::angles`]).
//!
//! Why: one contact is a chain of dependent square roots, divisions, logarithms and
//! exponentials, about 16 of them, each waiting on the last (docs/lab/benchmarks.md, "One
//! evaluation's cost"). Four contacts in the lanes of one vector wait on that chain once.
//! The operations are plain loops over `[f64; 4]`, which the compiler turns into vector
//! instructions in the contact's AVX2 copy (and into SSE2 pairs in the baseline one);
//! `ln`, `exp`, `sin_cos` and `atan2` are written here, as libm's are one call per number.

use super::exp::{EXP2_TABLE, EXP_ARG_LIMIT, LN2_64_HI, LN2_64_LO, ROUNDING_SHIFT};
use super::hertz::cube_root_start;
use std::f64::consts::LN_2;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Lanes per vector: four `f64` fill an AVX2 register.
pub const LANES: usize = 4;

/// Four `f64`, one per contact.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[repr(C, align(32))]
pub struct F64x4(pub [f64; LANES]);

/// Four booleans, one per contact.
pub type Mask4 = [bool; LANES];

impl F64x4 {
    /// Every lane `x`.
    #[inline(always)]
    pub fn splat(x: f64) -> F64x4 {
        F64x4([x; LANES])
    }

    /// `f` of each lane.
    #[inline(always)]
    pub fn map(self, f: impl Fn(f64) -> f64) -> F64x4 {
        F64x4([f(self.0[0]), f(self.0[1]), f(self.0[2]), f(self.0[3])])
    }

    /// `f` of each pair of lanes.
    #[inline(always)]
    pub fn zip(self, o: F64x4, f: impl Fn(f64, f64) -> f64) -> F64x4 {
        F64x4([
            f(self.0[0], o.0[0]),
            f(self.0[1], o.0[1]),
            f(self.0[2], o.0[2]),
            f(self.0[3], o.0[3]),
        ])
    }

    /// The square root of each lane.
    #[inline(always)]
    pub fn sqrt(self) -> F64x4 {
        self.map(f64::sqrt)
    }

    /// `self * a + b` of each lane, rounded once: one FMA instruction in the AVX2 copy (a
    /// libm call a lane in the baseline one). The polynomials' Horner steps use it: a
    /// step is one instruction of 4 cycles' latency instead of a multiply and an add of 3
    /// each, and a contact's logarithms wait on their nine steps (fused, the Table-1 case
    /// took about 0.96 of the time an evaluation, docs/lab/benchmarks.md).
    #[inline(always)]
    pub fn mul_add(self, a: F64x4, b: F64x4) -> F64x4 {
        F64x4([
            self.0[0].mul_add(a.0[0], b.0[0]),
            self.0[1].mul_add(a.0[1], b.0[1]),
            self.0[2].mul_add(a.0[2], b.0[2]),
            self.0[3].mul_add(a.0[3], b.0[3]),
        ])
    }

    /// The size of each lane.
    #[inline(always)]
    pub fn abs(self) -> F64x4 {
        self.map(f64::abs)
    }

    /// The largest integer at most each lane.
    #[inline(always)]
    pub fn floor(self) -> F64x4 {
        self.map(f64::floor)
    }

    /// The larger of each pair of lanes (`o`'s where `self` is NaN, as `f64::max`).
    #[inline(always)]
    pub fn max(self, o: F64x4) -> F64x4 {
        self.zip(o, |a, b| if a > b { a } else { b })
    }

    /// The smaller of each pair of lanes (`o`'s where `self` is NaN, as `f64::min`).
    #[inline(always)]
    pub fn min(self, o: F64x4) -> F64x4 {
        self.zip(o, |a, b| if a < b { a } else { b })
    }

    /// Lane by lane, `a` where `mask`, else `b`.
    #[inline(always)]
    pub fn select(mask: Mask4, a: F64x4, b: F64x4) -> F64x4 {
        F64x4([
            if mask[0] { a.0[0] } else { b.0[0] },
            if mask[1] { a.0[1] } else { b.0[1] },
            if mask[2] { a.0[2] } else { b.0[2] },
            if mask[3] { a.0[3] } else { b.0[3] },
        ])
    }

    /// Lane by lane `self < o`.
    #[inline(always)]
    pub fn lt(self, o: F64x4) -> Mask4 {
        [
            self.0[0] < o.0[0],
            self.0[1] < o.0[1],
            self.0[2] < o.0[2],
            self.0[3] < o.0[3],
        ]
    }

    /// Lane by lane `self <= o`.
    #[inline(always)]
    pub fn le(self, o: F64x4) -> Mask4 {
        [
            self.0[0] <= o.0[0],
            self.0[1] <= o.0[1],
            self.0[2] <= o.0[2],
            self.0[3] <= o.0[3],
        ]
    }

    /// `ln x` of each lane, for positive normal `x`; within 2 ulp of `f64::ln` over the
    /// range the contact takes (tested). Table-free, so the four lanes share every
    /// instruction: `x = 2^e m` with `m` in `[sqrt(1/2), sqrt(2))`, and
    /// `ln m = 2 atanh(s)` with `s = (m - 1)/(m + 1)`, `|s| <= 0.172`, by its series
    /// `2 s (1 + s^2/3 + s^4/5 + ...)` to `s^20/21` (the next term is below 1e-18 of the
    /// sum). `x` must be positive and normal (the contact's loads, speeds floored at
    /// 1e-3 m/s, pressure ratios, `asinh` arguments and the cell mean's ratios are, in
    /// every lane whose result is kept): the sign bit would go into the exponent, and a
    /// lane selected away may hold anything.
    #[inline(always)]
    pub fn ln(self) -> F64x4 {
        // the biased exponent as the low bits of 2^52's mantissa, the mantissa in [1, 2):
        // bit operations the lanes share
        let mut exponent = [0.0; LANES];
        let mut mantissa = [0.0; LANES];
        for l in 0..LANES {
            let bits = self.0[l].to_bits();
            exponent[l] = f64::from_bits((bits >> 52) | 0x4330_0000_0000_0000);
            mantissa[l] = f64::from_bits((bits & 0x000f_ffff_ffff_ffff) | 0x3ff0_0000_0000_0000);
        }
        let e = F64x4(exponent) - F64x4::splat(4_503_599_627_370_496.0 + 1023.0);
        let mantissa = F64x4(mantissa);
        // into [sqrt(1/2), sqrt(2))
        let high = F64x4::splat(std::f64::consts::SQRT_2).lt(mantissa);
        let m = F64x4::select(high, 0.5 * mantissa, mantissa);
        let e = e + F64x4::select(high, F64x4::splat(1.0), F64x4::splat(0.0));
        ln_reduced(e, m, m - F64x4::splat(1.0))
    }

    /// `ln(1 + w)` of each lane for `w >= 0`, accurate where `w` is small: `ln u` of
    /// `u = 1 + w` (rounded) corrected by `(w - (u - 1)) / u`, the first-order change of
    /// `ln` over what the rounding lost.
    #[inline(always)]
    pub fn ln_1p(self) -> F64x4 {
        let one = F64x4::splat(1.0);
        let u = one + self;
        u.ln() + (self - (u - one)) / u
    }

    /// `(sin x, cos x)` of each lane, within 2 ulp of `f64::sin_cos` for `|x|` below
    /// [`SIN_COS_REDUCED_BELOW`] (tested; beyond it a lane takes `f64::sin_cos`). Table-free,
    /// so the four lanes share every instruction: `x = n pi/2 + r` with `|r| <= pi/4` (`pi/2`
    /// in three parts, the first two of at most 33 bits, so `n` times them is exact for
    /// `|n| < 2^20`, and `x - n P1` exact by Sterbenz's lemma), then the Taylor series of
    /// `sin r` to `r^19/19!` and of `cos r` to `r^20/20!` (the next terms are below 1e-21 at
    /// `pi/4`), and the quadrant's signs and swap. libm's `sincos` takes ~140 instructions a
    /// call at the angles a ball's orbit reaches (hundreds of radians), 3.5 % of the
    /// Table-1 case.
    #[inline(always)]
    pub fn sin_cos(self) -> (F64x4, F64x4) {
        let near = self.abs().lt(F64x4::splat(SIN_COS_REDUCED_BELOW));
        let x = F64x4::select(near, self, F64x4::splat(0.0));
        let shift = F64x4::splat(ROUNDING_SHIFT);
        let shifted = std::f64::consts::FRAC_2_PI * x + shift;
        let n = shifted - shift;
        let r = ((x - n * F64x4::splat(HALF_PI_1)) - n * F64x4::splat(HALF_PI_2))
            - n * F64x4::splat(HALF_PI_3);
        let r2 = r * r;
        let mut ps = F64x4::splat(SIN_SERIES[SIN_SERIES.len() - 1]);
        for c in SIN_SERIES[..SIN_SERIES.len() - 1].iter().rev() {
            ps = ps.mul_add(r2, F64x4::splat(*c));
        }
        let mut pc = F64x4::splat(COS_SERIES[COS_SERIES.len() - 1]);
        for c in COS_SERIES[..COS_SERIES.len() - 1].iter().rev() {
            pc = pc.mul_add(r2, F64x4::splat(*c));
        }
        let sin_r = r + r * r2 * ps;
        let cos_r = F64x4::splat(1.0) - (0.5 * r2 - r2 * r2 * pc);
        // the quadrant `n mod 4` (exact: `n` is an integer, `n/4` a power-of-two scaling)
        let q = n - 4.0 * (0.25 * n).floor();
        let even = (q - 2.0 * (0.5 * q).floor()).lt(F64x4::splat(0.5));
        let (a, b) = (
            F64x4::select(even, sin_r, cos_r),
            F64x4::select(even, cos_r, sin_r),
        );
        // sin's sign flips in quadrants 2 and 3, cos's in 1 and 2
        let mut sin = F64x4::select(q.lt(F64x4::splat(1.5)), a, -a);
        let mut cos = F64x4::select((q - F64x4::splat(1.5)).abs().lt(F64x4::splat(1.0)), -b, b);
        // sin(x) = x below the smallest normal number, -0 kept (the series gives +0 there)
        sin = F64x4::select(self.abs().lt(F64x4::splat(f64::MIN_POSITIVE)), self, sin);
        if near != [true; LANES] {
            for (l, _) in near.iter().enumerate().filter(|(_, near)| !**near) {
                (sin.0[l], cos.0[l]) = self.0[l].sin_cos();
            }
        }
        (sin, cos)
    }

    /// `atan2(self, x)` of each lane (`self` the ordinate), within 2 epsilon (relative) of
    /// `f64::atan2` (tested) where both are finite, not both zero, and the smaller size over
    /// the larger is zero or above 1e-290; other lanes take `f64::atan2`. That ratio `t`, in
    /// `[0, 1]`, is reduced about the nearest breakpoint `c = tan(k pi/16)` (rounded) by
    /// `atan t = atan c + atan u`, `u = (t - c)/(1 + c t)`, `|u| <= tan(pi/32)`, and
    /// `atan u` summed to `u^17/17` (the next term is below 5e-20 of it); `atan c` in two
    /// parts ([`ATAN_BREAKS`]). Then `pi/2 - r` where the ordinate is the larger, `pi - r`
    /// where `x` is negative, and the ordinate's sign. libm's `atan2` takes ~150
    /// instructions a call, and a step's averages took two a ball.
    #[inline(always)]
    pub fn atan2(self, x: F64x4) -> F64x4 {
        let y = self;
        let (ay, ax) = (y.abs(), x.abs());
        let swap = ax.lt(ay);
        let t = F64x4::select(swap, ax, ay) / F64x4::select(swap, ay, ax);
        let mut c = [0.0; LANES];
        let mut hi = [0.0; LANES];
        let mut lo = [0.0; LANES];
        for l in 0..LANES {
            let k = ATAN_THRESHOLDS.iter().filter(|&&b| t.0[l] >= b).count();
            (c[l], hi[l], lo[l]) = ATAN_BREAKS[k];
        }
        let c = F64x4(c);
        let u = (t - c) / (F64x4::splat(1.0) + c * t);
        let u2 = u * u;
        let mut p = F64x4::splat(ATAN_SERIES[ATAN_SERIES.len() - 1]);
        for k in ATAN_SERIES[..ATAN_SERIES.len() - 1].iter().rev() {
            p = p.mul_add(u2, F64x4::splat(*k));
        }
        let r = F64x4(hi) + (F64x4(lo) + (u + u * u2 * p));
        let r = F64x4::select(
            swap,
            F64x4::splat(FRAC_PI_2_HI) - (r - F64x4::splat(FRAC_PI_2_LO)),
            r,
        );
        let zero = F64x4::splat(0.0);
        let r = F64x4::select(
            x.lt(zero),
            F64x4::splat(PI_HI) - (r - F64x4::splat(PI_LO)),
            r,
        );
        let mut out = F64x4::select(std::array::from_fn(|l| y.0[l].is_sign_negative()), -r, r);
        for l in 0..LANES {
            let (yl, xl, tl) = (y.0[l], x.0[l], t.0[l]);
            let ordinary = yl.is_finite()
                && xl.is_finite()
                && !(yl == 0.0 && xl == 0.0)
                && (tl == 0.0 || tl > 1e-290);
            if !ordinary {
                out.0[l] = yl.atan2(xl);
            }
        }
        out
    }

    /// `e^x` of each lane: the contact's own [`exp`](super::exp::exp) stage by stage, so
    /// that all but its table's reads run in the lanes; the same numbers, to the bit
    /// (tested).
    #[inline(always)]
    pub fn exp(self) -> F64x4 {
        // clamped as `exp` clamps, passing NaN through
        #[allow(clippy::manual_clamp)]
        let x = self.map(|x| {
            if x < -EXP_ARG_LIMIT {
                -EXP_ARG_LIMIT
            } else if x > EXP_ARG_LIMIT {
                EXP_ARG_LIMIT
            } else {
                x
            }
        });
        let shift = F64x4::splat(ROUNDING_SHIFT);
        let shifted = (64.0 / LN_2) * x + shift;
        let nf = shifted - shift;
        let r = (x - LN2_64_HI * nf) - LN2_64_LO * nf;
        let scale = shifted.map(|shifted| {
            let n = (shifted.to_bits() as i64).wrapping_sub(ROUNDING_SHIFT.to_bits() as i64);
            let (j, m) = ((n & 63) as usize, n >> 6);
            f64::from_bits(EXP2_TABLE[j].wrapping_add((m as u64) << 52))
        });
        let r2 = r * r;
        let q = r
            + r2 * (F64x4::splat(0.5) + (1.0 / 6.0) * r)
            + (r2 * r2) * (F64x4::splat(1.0 / 24.0) + (1.0 / 120.0) * r);
        scale + scale * q
    }

    /// [`cube_root`](super::hertz::cube_root) of each lane, for positive normal numbers:
    /// its start lane by lane, its three Halley steps in the lanes; the same numbers, to
    /// the bit (tested).
    #[inline(always)]
    pub fn cube_root(self) -> F64x4 {
        let x = self;
        let mut y = x.map(cube_root_start);
        for _ in 0..3 {
            let y3 = y * y * y;
            y = y * ((y3 + 2.0 * x) / (2.0 * y3 + x));
        }
        y
    }
}

/// `|x|` from which [`F64x4::sin_cos`] leaves a lane to `f64::sin_cos`: its `n` stays
/// far below `2^20`, where the parts' products stop being exact.
pub const SIN_COS_REDUCED_BELOW: f64 = 1e5;

/// The breakpoints of [`F64x4::atan2`]: `c = tan(k pi/16)` rounded, and `atan c` of that
/// rounded value in two parts (`scripts/fixtures/atan_constants.py`).
const ATAN_BREAKS: [(f64, f64, f64); 5] = [
    (0.0, 0.0, 0.0),
    (
        0.198_912_367_379_658,
        0.196_349_540_849_362_07,
        6.846_802_412_842_648e-18,
    ),
    (
        0.414_213_562_373_095_03,
        std::f64::consts::FRAC_PI_8,
        3.060_132_146_563_891e-18,
    ),
    (
        0.668_178_637_919_298_9,
        0.589_048_622_548_086_2,
        -5.412_106_055_318_847e-18,
    ),
    (1.0, std::f64::consts::FRAC_PI_4, 3.061_616_997_868_383e-17),
];

/// Where [`F64x4::atan2`] moves to the next breakpoint: `tan((2k - 1) pi/32)`, k = 1..4.
const ATAN_THRESHOLDS: [f64; 4] = [
    0.098_491_403_357_164_25,
    0.303_346_683_607_342_4,
    0.534_511_135_950_791_7,
    0.820_678_790_828_660_4,
];

/// `(-1)^k / (2k + 1)` for k = 1..8: `(atan u - u) / u^3` in powers of `u^2`.
const ATAN_SERIES: [f64; 8] = [
    -1.0 / 3.0,
    1.0 / 5.0,
    -1.0 / 7.0,
    1.0 / 9.0,
    -1.0 / 11.0,
    1.0 / 13.0,
    -1.0 / 15.0,
    1.0 / 17.0,
];

/// `pi/2` and `pi` in two parts: the double nearest, and the rest.
const FRAC_PI_2_HI: f64 = std::f64::consts::FRAC_PI_2;
const FRAC_PI_2_LO: f64 = 6.123_233_995_736_766e-17;
const PI_HI: f64 = std::f64::consts::PI;
const PI_LO: f64 = 1.224_646_799_147_353_2e-16;

/// `pi/2` in three parts: the first two of at most 33 significant bits (31 and 32), the
/// third the rest to double precision (their sum is `pi/2` to about 1e-37).
const HALF_PI_1: f64 = 1.570_796_326_734_125_6;
const HALF_PI_2: f64 = 6.077_100_506_303_966e-11;
const HALF_PI_3: f64 = 2.022_266_248_795_950_6e-21;

/// `(-1)^k / (2k+1)!` for k = 1..9: `(sin r - r) / r^3` in powers of `r^2`.
const SIN_SERIES: [f64; 9] = [
    -1.0 / 6.0,
    1.0 / 120.0,
    -1.0 / 5040.0,
    1.0 / 362_880.0,
    -1.0 / 39_916_800.0,
    1.0 / 6_227_020_800.0,
    -1.0 / 1_307_674_368_000.0,
    1.0 / 355_687_428_096_000.0,
    -1.0 / 121_645_100_408_832_000.0,
];

/// `(-1)^k / (2k)!` for k = 2..10: `(cos r - 1 + r^2/2) / r^4` in powers of `r^2`.
const COS_SERIES: [f64; 9] = [
    1.0 / 24.0,
    -1.0 / 720.0,
    1.0 / 40_320.0,
    -1.0 / 3_628_800.0,
    1.0 / 479_001_600.0,
    -1.0 / 87_178_291_200.0,
    1.0 / 20_922_789_888_000.0,
    -1.0 / 6_402_373_705_728_000.0,
    1.0 / 2_432_902_008_176_640_000.0,
];

/// `ln 2` in two parts: the high part has 32 significant bits, so `e * LN2_HI` is exact
/// for every exponent `|e| < 2^20`.
const LN2_HI: f64 = 6.931_471_803_691_238e-1;
const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;

/// `1 / (2 k + 1)` for k = 1..10: the coefficients of `atanh(s) / s - 1` in powers of `s^2`.
const ATANH_SERIES: [f64; 10] = [
    1.0 / 3.0,
    1.0 / 5.0,
    1.0 / 7.0,
    1.0 / 9.0,
    1.0 / 11.0,
    1.0 / 13.0,
    1.0 / 15.0,
    1.0 / 17.0,
    1.0 / 19.0,
    1.0 / 21.0,
];

/// `e ln 2 + ln m` for `m` in `[sqrt(1/2), sqrt(2))`, given `m - 1` (exact there).
#[inline(always)]
fn ln_reduced(e: F64x4, m: F64x4, m_minus_1: F64x4) -> F64x4 {
    let s = m_minus_1 / (m + F64x4::splat(1.0));
    let s2 = s * s;
    // 1/3 + s2/5 + ... + s2^9/21, by Horner from the smallest term
    let mut p = F64x4::splat(ATANH_SERIES[9]);
    for c in ATANH_SERIES[..9].iter().rev() {
        p = p.mul_add(s2, F64x4::splat(*c));
    }
    // 2s + 2s s2 p: the small part first, then the exact multiple of ln 2's high part
    let two_s = s + s;
    let small = two_s * s2 * p + e * F64x4::splat(LN2_LO);
    e * F64x4::splat(LN2_HI) + (two_s + small)
}

macro_rules! lanewise {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for F64x4 {
            type Output = F64x4;
            #[inline(always)]
            fn $method(self, o: F64x4) -> F64x4 {
                F64x4([
                    self.0[0] $op o.0[0],
                    self.0[1] $op o.0[1],
                    self.0[2] $op o.0[2],
                    self.0[3] $op o.0[3],
                ])
            }
        }
    };
}
lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);
lanewise!(Div, div, /);

impl Neg for F64x4 {
    type Output = F64x4;
    #[inline(always)]
    fn neg(self) -> F64x4 {
        self.map(|x| -x)
    }
}

impl Mul<F64x4> for f64 {
    type Output = F64x4;
    #[inline(always)]
    fn mul(self, o: F64x4) -> F64x4 {
        F64x4::splat(self) * o
    }
}

impl Neg for Vec3x4 {
    type Output = Vec3x4;
    #[inline(always)]
    fn neg(self) -> Vec3x4 {
        Vec3x4 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

impl Add for Vec3x4 {
    type Output = Vec3x4;
    #[inline(always)]
    fn add(self, o: Vec3x4) -> Vec3x4 {
        Vec3x4 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl Sub for Vec3x4 {
    type Output = Vec3x4;
    #[inline(always)]
    fn sub(self, o: Vec3x4) -> Vec3x4 {
        Vec3x4 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

/// Three components of four vectors, one vector per lane.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Vec3x4 {
    pub x: F64x4,
    pub y: F64x4,
    pub z: F64x4,
}

impl Vec3x4 {
    pub const ZERO: Vec3x4 = Vec3x4 {
        x: F64x4([0.0; LANES]),
        y: F64x4([0.0; LANES]),
        z: F64x4([0.0; LANES]),
    };

    /// Each lane's vector times that lane's `s`.
    #[inline(always)]
    pub fn scale(self, s: F64x4) -> Vec3x4 {
        Vec3x4 {
            x: s * self.x,
            y: s * self.y,
            z: s * self.z,
        }
    }

    /// Lane by lane, `a`'s vector where `mask`, else `b`'s.
    #[inline(always)]
    pub fn select(mask: Mask4, a: Vec3x4, b: Vec3x4) -> Vec3x4 {
        Vec3x4 {
            x: F64x4::select(mask, a.x, b.x),
            y: F64x4::select(mask, a.y, b.y),
            z: F64x4::select(mask, a.z, b.z),
        }
    }

    /// Each lane's vector divided by that lane's `s` (component by component, as
    /// `nalgebra`'s vector over a number).
    #[inline(always)]
    pub fn divided(self, s: F64x4) -> Vec3x4 {
        Vec3x4 {
            x: self.x / s,
            y: self.y / s,
            z: self.z / s,
        }
    }

    /// `v` in every lane.
    #[inline(always)]
    pub fn splat(v: &nalgebra::Vector3<f64>) -> Vec3x4 {
        Vec3x4 {
            x: F64x4::splat(v.x),
            y: F64x4::splat(v.y),
            z: F64x4::splat(v.z),
        }
    }

    /// Each lane's dot product, summed in `nalgebra`'s order.
    #[inline(always)]
    pub fn dot(self, o: Vec3x4) -> F64x4 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Each lane's cross product, as `nalgebra`'s.
    #[inline(always)]
    pub fn cross(self, o: Vec3x4) -> Vec3x4 {
        Vec3x4 {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }

    /// `m v` in each lane, summed as `nalgebra`'s product (column by column).
    #[inline(always)]
    pub fn rotated(self, m: &nalgebra::Matrix3<f64>) -> Vec3x4 {
        let row = |r: usize| {
            F64x4::splat(m[(r, 0)]) * self.x
                + F64x4::splat(m[(r, 1)]) * self.y
                + F64x4::splat(m[(r, 2)]) * self.z
        };
        Vec3x4 {
            x: row(0),
            y: row(1),
            z: row(2),
        }
    }

    /// `m^T v` in each lane.
    #[inline(always)]
    pub fn rotated_back(self, m: &nalgebra::Matrix3<f64>) -> Vec3x4 {
        self.rotated(&m.transpose())
    }

    #[inline(always)]
    pub fn norm_squared(self) -> F64x4 {
        self.x * self.x + self.y * self.y + self.z * self.z
    }

    /// Lane `l`'s vector.
    #[inline(always)]
    pub fn lane(&self, l: usize) -> nalgebra::Vector3<f64> {
        nalgebra::Vector3::new(self.x.0[l], self.y.0[l], self.z.0[l])
    }

    /// Adds `v` to lane `l`'s vector.
    #[inline(always)]
    pub fn add_to_lane(&mut self, l: usize, v: &nalgebra::Vector3<f64>) {
        self.x.0[l] += v.x;
        self.y.0[l] += v.y;
        self.z.0[l] += v.z;
    }

    /// Sets lane `l`'s vector.
    #[inline(always)]
    pub fn set_lane(&mut self, l: usize, v: &nalgebra::Vector3<f64>) {
        self.x.0[l] = v.x;
        self.y.0[l] = v.y;
        self.z.0[l] = v.z;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// How many representable numbers apart `a` and `b` are (of one sign).
    fn ulps(a: f64, b: f64) -> f64 {
        assert_eq!(a.is_sign_negative(), b.is_sign_negative(), "{a} {b}");
        (a.to_bits() as i64 - b.to_bits() as i64).abs() as f64
    }

    /// Within 2 ulp of libm's `ln` (and of `ln_1p`) over every decade a contact's load,
    /// speed, pressure ratio and `asinh` argument take, and beyond. This is measured, not
    /// derived: against exact values these reach about 2 ulp (`ln`) and 2.4 ulp (`ln_1p`;
    /// checked with mpmath by the review of 2026-11-30), libm's about half an ulp.
    #[test]
    fn ln_is_the_library_ln_to_two_ulp() {
        let mut worst: f64 = 0.0;
        for e in -300..300 {
            for k in 0..500 {
                let x = (1.0 + k as f64 / 500.0) * 10f64.powi(e);
                let got = F64x4([x, 2.0 * x, 0.5 * x, 1.1 * x]).ln();
                for (l, want) in [x, 2.0 * x, 0.5 * x, 1.1 * x].iter().enumerate() {
                    if want.ln() != 0.0 {
                        worst = worst.max(ulps(got.0[l], want.ln()));
                    }
                }
            }
        }
        assert!(worst <= 2.0, "worst {worst} ulp");
        // ln 1 is 0 exactly
        assert_eq!(F64x4::splat(1.0).ln().0[0], 0.0);
        let mut worst: f64 = 0.0;
        for k in 1..20000 {
            let w = k as f64 * 1e-5 * (1.0 + 1e-3 * (k % 7) as f64);
            for w in [w, w * 1e-3, w * 10.0, w * 1e4] {
                let got = F64x4::splat(w).ln_1p().0[0];
                worst = worst.max(ulps(got, w.ln_1p()));
            }
        }
        // and every decade the strip law's `asinh` argument takes, up to its 1e150
        for e in -4..150 {
            for k in 0..200 {
                let w = (1.0 + k as f64 / 200.0) * 10f64.powi(e);
                let got = F64x4::splat(w).ln_1p().0[0];
                worst = worst.max(ulps(got, w.ln_1p()));
            }
        }
        assert!(worst <= 2.0, "ln_1p: worst {worst} ulp");
    }

    /// Within 2 ulp of libm's `sin_cos` (relative, in units of `EPSILON |value|`): the
    /// angles a ball's orbit and a cage's spin take over long runs, the multiples of
    /// `pi/2` and their neighbours (where the reduction cancels), past the reduced range,
    /// and both zeros (the sine keeps the sign).
    #[test]
    fn sin_cos_is_the_library_one_to_two_ulp() {
        let mut xs = vec![0.0, -0.0, 1e-300, 1e-8, 0.5, 1e5, -2e5, 1e9];
        for k in -2000i64..2000 {
            let m = k as f64 * std::f64::consts::FRAC_PI_2;
            for d in [-1e-9, -1e-15, 0.0, 1e-15, 1e-9, 0.3, 0.7] {
                xs.push(m + d);
            }
        }
        for k in 0..200_000 {
            xs.push(k as f64 * 0.4999 - 3e4);
        }
        let mut worst: f64 = 0.0;
        for chunk in xs.chunks(LANES) {
            let mut lanes = [0.0; LANES];
            lanes[..chunk.len()].copy_from_slice(chunk);
            let (s, c) = F64x4(lanes).sin_cos();
            for (l, &x) in chunk.iter().enumerate() {
                let (ws, wc) = x.sin_cos();
                for (got, want) in [(s.0[l], ws), (c.0[l], wc)] {
                    assert_eq!(got.is_sign_negative(), want.is_sign_negative(), "{x}");
                    if want != 0.0 {
                        worst = worst.max((got - want).abs() / (f64::EPSILON * want.abs()));
                    } else {
                        assert_eq!(got, 0.0, "{x}");
                    }
                }
            }
        }
        assert!(worst <= 2.0, "worst {worst} ulp");
    }

    /// `atan2` within 2 epsilon (relative; 1.90 at worst) of the library's over every octant
    /// and quadrant, both signs of zero, the breakpoints and thresholds and either side of
    /// them, tiny and huge ratios, and the lanes that fall back (infinities, NaN, both zero,
    /// subnormal ratios): the same to the bit there.
    #[test]
    fn atan2_is_the_library_one_to_two_epsilon() {
        let mut ts = vec![0.0, 1e-300, 1e-280, 1e-20, 1e-9, 0.5, 1.0];
        for &(c, _, _) in &ATAN_BREAKS {
            ts.extend([c, c * (1.0 + 1e-15), c * (1.0 - 1e-15)]);
        }
        for &b in &ATAN_THRESHOLDS {
            ts.extend([b, b * (1.0 + 1e-15), b * (1.0 - 1e-15)]);
        }
        for k in 0..20_000 {
            ts.push(k as f64 / 20_000.0);
        }
        let mut pairs = Vec::new();
        for &t in &ts {
            for (r, sx, sy) in [(1.0, 1.0, 1.0), (3.7e-3, -1.0, 1.0), (2.5e7, 1.0, -1.0)] {
                pairs.push((sy * r * t, sx * r));
                pairs.push((sy * r, sx * r * t));
                pairs.push((-sy * r * t, -sx * r));
            }
        }
        let inf = f64::INFINITY;
        for (y, x) in [
            (0.0, 1.0),
            (-0.0, 1.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (1.0, 0.0),
            (-1.0, -0.0),
            (0.0, 0.0),
            (-0.0, -0.0),
            (inf, 1.0),
            (1.0, -inf),
            (inf, inf),
            (f64::NAN, 1.0),
            (1e-310, 1.0),
        ] {
            pairs.push((y, x));
        }
        let mut worst: f64 = 0.0;
        for chunk in pairs.chunks(LANES) {
            let mut y = [1.0; LANES];
            let mut x = [1.0; LANES];
            for (l, &(yl, xl)) in chunk.iter().enumerate() {
                (y[l], x[l]) = (yl, xl);
            }
            let got = F64x4(y).atan2(F64x4(x));
            for (l, &(yl, xl)) in chunk.iter().enumerate() {
                let want = yl.atan2(xl);
                let g = got.0[l];
                if want.is_nan() {
                    assert!(g.is_nan(), "{yl} {xl}");
                    continue;
                }
                // the lanes that take the library's, as `atan2` picks them
                let t = yl.abs().min(xl.abs()) / yl.abs().max(xl.abs());
                let falls_back = !(yl.is_finite() && xl.is_finite())
                    || (yl == 0.0 && xl == 0.0)
                    || (t != 0.0 && t <= 1e-290);
                if falls_back {
                    assert_eq!(g.to_bits(), want.to_bits(), "{yl} {xl}");
                }
                assert_eq!(g.is_sign_negative(), want.is_sign_negative(), "{yl} {xl}");
                if want == 0.0 {
                    assert_eq!(g, 0.0, "{yl} {xl}");
                } else if g != want {
                    // (a subnormal `want` falls back, and is equal)
                    let ulps = (g - want).abs() / (f64::EPSILON * want.abs());
                    assert!(ulps <= 2.0, "{yl:e} {xl:e}: {g:e} against {want:e}");
                    worst = worst.max(ulps);
                }
            }
        }
        assert!(worst <= 2.0, "worst {worst} ulp");
    }

    /// The lanes' `exp` and cube root are the scalar ones stage by stage: equal to the bit,
    /// over the exponential's whole range (clamped beyond it, NaN passed) and every decade
    /// of load.
    #[test]
    fn exp_and_cube_root_are_the_scalar_ones_to_the_bit() {
        for k in -2000..2000 {
            let x = k as f64 * 0.3712;
            let lanes = F64x4([x, -x, x * 1e-9, x + 0.5]).exp();
            for (l, x) in [x, -x, x * 1e-9, x + 0.5].iter().enumerate() {
                assert_eq!(
                    lanes.0[l].to_bits(),
                    crate::physics::exp::exp(*x).to_bits(),
                    "{x}"
                );
            }
        }
        assert!(F64x4::splat(f64::NAN).exp().0[0].is_nan());
        for e in -300..300 {
            for k in 0..200 {
                let q = (1.0 + k as f64 / 200.0) * 10f64.powi(e);
                let lanes = F64x4([q, 2.0 * q, 3.0 * q, 5.0 * q]).cube_root();
                for (l, q) in [q, 2.0 * q, 3.0 * q, 5.0 * q].iter().enumerate() {
                    assert_eq!(lanes.0[l], crate::physics::hertz::cube_root(*q), "{q}");
                }
            }
        }
    }
}
