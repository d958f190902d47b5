//! The exponential of the traction curve (eq. 14), written out so it inlines into the
//! strip loop.
//!
//! Why not `f64::exp`: on x86-64 it is a call into libm, and the call makes the strip loop
//! spill the vector registers it holds around it. The traction curve calls it once per
//! strip, about 290 times per right-hand side (10 strips x 2 contacts x the balls);
//! docs/lab/benchmarks.md has the profile.
//!
//! Method (Tang's table-driven scheme, as libm's own): `x = (64 m + j) ln2 / 64 + r` with
//! `|r| <= ln2 / 128`, so `e^x = 2^m 2^(j/64) e^r`; `2^(j/64)` comes from a table of 64
//! correctly rounded entries (`scripts/fixtures/exp_table.py` prints it), `e^r - 1` from its Taylor
//! polynomial to degree 5 (truncation `|r|^6 / 6!`, about 3.5e-17 of the result), and `2^m` goes
//! into the exponent bits. The test checks 2 ulp against libm over the whole range.

use std::f64::consts::LN_2;

/// `ln 2 / 64` in two parts (fdlibm's split of `ln 2`, divided by 64, which is exact): the
/// high part has 32 significant bits, so `n * LN2_64_HI` is exact for every `|n| < 2^20`.
pub(crate) const LN2_64_HI: f64 = 6.931_471_803_691_238e-1 / 64.0;
pub(crate) const LN2_64_LO: f64 = 1.908_214_929_270_587_7e-10 / 64.0;

/// `1.5 * 2^52`: adding it to a number below 2^51 rounds it to an integer, which then sits
/// in the low bits of the sum's mantissa.
pub(crate) const ROUNDING_SHIFT: f64 = 6_755_399_441_055_744.0;

/// Arguments are clamped to this magnitude, so `2^m 2^(j/64)` stays a normal number.
pub const EXP_ARG_LIMIT: f64 = 700.0;

/// `e^x` for `|x| <= 700` (beyond it, `x` is clamped: `e^-700` is 1e-304, which is zero for
/// every sum it enters). NaN gives NaN. Within 2 ulp of `f64::exp`.
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    // Two comparisons, which pass NaN through: measured 3 % faster on the Table-1 run than
    // f64::clamp, which checks its bounds and NaN apart.
    #[allow(clippy::manual_clamp)]
    let x = if x < -EXP_ARG_LIMIT {
        -EXP_ARG_LIMIT
    } else if x > EXP_ARG_LIMIT {
        EXP_ARG_LIMIT
    } else {
        x
    };
    let shifted = x * (64.0 / LN_2) + ROUNDING_SHIFT;
    let nf = shifted - ROUNDING_SHIFT;
    let n = (shifted.to_bits() as i64).wrapping_sub(ROUNDING_SHIFT.to_bits() as i64);
    let r = (x - nf * LN2_64_HI) - nf * LN2_64_LO;
    // 2^(n/64) = 2^m 2^(j/64), n = 64 m + j, 0 <= j < 64: m added to the entry's exponent
    let j = (n & 63) as usize;
    let m = n >> 6;
    let scale = f64::from_bits(EXP2_TABLE[j].wrapping_add((m as u64) << 52));
    // e^r - 1
    let r2 = r * r;
    let q = r + r2 * (0.5 + r * (1.0 / 6.0)) + (r2 * r2) * (1.0 / 24.0 + r * (1.0 / 120.0));
    scale + scale * q
}

/// `2^(j/64)` as f64 bits, correctly rounded (printed by `scripts/fixtures/exp_table.py`).
pub(crate) const EXP2_TABLE: [u64; 64] = [
    0x3ff0000000000000, // 2^(0/64)
    0x3ff02c9a3e778061, // 2^(1/64)
    0x3ff059b0d3158574, // 2^(2/64)
    0x3ff0874518759bc8, // 2^(3/64)
    0x3ff0b5586cf9890f, // 2^(4/64)
    0x3ff0e3ec32d3d1a2, // 2^(5/64)
    0x3ff11301d0125b51, // 2^(6/64)
    0x3ff1429aaea92de0, // 2^(7/64)
    0x3ff172b83c7d517b, // 2^(8/64)
    0x3ff1a35beb6fcb75, // 2^(9/64)
    0x3ff1d4873168b9aa, // 2^(10/64)
    0x3ff2063b88628cd6, // 2^(11/64)
    0x3ff2387a6e756238, // 2^(12/64)
    0x3ff26b4565e27cdd, // 2^(13/64)
    0x3ff29e9df51fdee1, // 2^(14/64)
    0x3ff2d285a6e4030b, // 2^(15/64)
    0x3ff306fe0a31b715, // 2^(16/64)
    0x3ff33c08b26416ff, // 2^(17/64)
    0x3ff371a7373aa9cb, // 2^(18/64)
    0x3ff3a7db34e59ff7, // 2^(19/64)
    0x3ff3dea64c123422, // 2^(20/64)
    0x3ff4160a21f72e2a, // 2^(21/64)
    0x3ff44e086061892d, // 2^(22/64)
    0x3ff486a2b5c13cd0, // 2^(23/64)
    0x3ff4bfdad5362a27, // 2^(24/64)
    0x3ff4f9b2769d2ca7, // 2^(25/64)
    0x3ff5342b569d4f82, // 2^(26/64)
    0x3ff56f4736b527da, // 2^(27/64)
    0x3ff5ab07dd485429, // 2^(28/64)
    0x3ff5e76f15ad2148, // 2^(29/64)
    0x3ff6247eb03a5585, // 2^(30/64)
    0x3ff6623882552225, // 2^(31/64)
    0x3ff6a09e667f3bcd, // 2^(32/64)
    0x3ff6dfb23c651a2f, // 2^(33/64)
    0x3ff71f75e8ec5f74, // 2^(34/64)
    0x3ff75feb564267c9, // 2^(35/64)
    0x3ff7a11473eb0187, // 2^(36/64)
    0x3ff7e2f336cf4e62, // 2^(37/64)
    0x3ff82589994cce13, // 2^(38/64)
    0x3ff868d99b4492ed, // 2^(39/64)
    0x3ff8ace5422aa0db, // 2^(40/64)
    0x3ff8f1ae99157736, // 2^(41/64)
    0x3ff93737b0cdc5e5, // 2^(42/64)
    0x3ff97d829fde4e50, // 2^(43/64)
    0x3ff9c49182a3f090, // 2^(44/64)
    0x3ffa0c667b5de565, // 2^(45/64)
    0x3ffa5503b23e255d, // 2^(46/64)
    0x3ffa9e6b5579fdbf, // 2^(47/64)
    0x3ffae89f995ad3ad, // 2^(48/64)
    0x3ffb33a2b84f15fb, // 2^(49/64)
    0x3ffb7f76f2fb5e47, // 2^(50/64)
    0x3ffbcc1e904bc1d2, // 2^(51/64)
    0x3ffc199bdd85529c, // 2^(52/64)
    0x3ffc67f12e57d14b, // 2^(53/64)
    0x3ffcb720dcef9069, // 2^(54/64)
    0x3ffd072d4a07897c, // 2^(55/64)
    0x3ffd5818dcfba487, // 2^(56/64)
    0x3ffda9e603db3285, // 2^(57/64)
    0x3ffdfc97337b9b5f, // 2^(58/64)
    0x3ffe502ee78b3ff6, // 2^(59/64)
    0x3ffea4afa2a490da, // 2^(60/64)
    0x3ffefa1bee615a27, // 2^(61/64)
    0x3fff50765b6e4540, // 2^(62/64)
    0x3fffa7c1819e90d8, // 2^(63/64)
];

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place between two finite positive doubles.
    fn ulps(a: f64, b: f64) -> u64 {
        (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
    }

    #[test]
    fn the_table_holds_the_powers_of_two() {
        for (j, &bits) in EXP2_TABLE.iter().enumerate() {
            let want = (j as f64 / 64.0).exp2();
            // libm's exp2 is within an ulp; the table is correctly rounded
            assert!(ulps(f64::from_bits(bits), want) <= 1, "2^({j}/64)");
        }
    }

    #[test]
    fn within_two_ulp_of_libm_over_the_whole_range() {
        // a dense sweep of [-700, 700] plus the neighbourhood of 0, where the traction
        // curve is read most (c s is small at small slip)
        let mut worst = (0u64, 0.0);
        let mut check = |x: f64| {
            let e = ulps(exp(x), x.exp());
            if e > worst.0 {
                worst = (e, x);
            }
        };
        for i in 0..=2_000_000 {
            check(-700.0 + 1400.0 * i as f64 / 2_000_000.0);
        }
        for i in 0..=100_000 {
            check(1e-3 * (i as f64 / 100_000.0 - 0.5));
        }
        // 2 ulp: the table entry and the final sum are rounded once each (half an ulp
        // each), the polynomial's truncation and rounding are far below an ulp of e^r - 1
        // relative to e^r, and libm's own exp is within an ulp
        assert!(worst.0 <= 2, "{} ulp at x = {}", worst.0, worst.1);
    }

    #[test]
    fn exact_where_it_must_be_and_clamped_beyond_the_range() {
        assert_eq!(exp(0.0), 1.0);
        assert_eq!(exp(-0.0), 1.0);
        assert!(exp(f64::NAN).is_nan());
        assert_eq!(exp(-1e6), exp(-EXP_ARG_LIMIT));
        assert!(exp(-1e6) > 0.0 && exp(-1e6) < 1e-303);
        assert_eq!(exp(1e6), exp(EXP_ARG_LIMIT));
        assert!(exp(f64::NEG_INFINITY) < 1e-303);
    }
}
