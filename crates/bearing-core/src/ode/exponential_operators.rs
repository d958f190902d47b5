//! The `phi` functions of exponential integrators and the step operators `g(tau L)` built
//! from them on the blocks [`super::etd_rk4::EtdRk4`] takes exactly: an oscillator mode,
//! undamped or damped, any real 2x2 block, and a single relaxing component. Each operator
//! is stored as the few numbers its block needs, so a step applies it without a matrix.

/// The operators of a step, in the order their factors are stored ([`super::etd_rk4`]'s
/// stages at a third and two thirds of the step, then its end and its weights).
pub(super) const PHI1_THIRD: usize = 0;
pub(super) const PHI1_TWO_THIRDS: usize = 1;
pub(super) const PHI2_TWO_THIRDS: usize = 2;
pub(super) const PHI1_STEP: usize = 3;
pub(super) const PHI2_STEP: usize = 4;
pub(super) const B2: usize = 5;
pub(super) const B3: usize = 6;
pub(super) const B4: usize = 7;
pub(super) const OPS: usize = 8;
/// Each operator with `L` zero (`phi_k(0) = 1/k!`; the weights are the 3/8 rule's).
pub(super) const WITHOUT_L: [f64; OPS] = [1.0, 1.0, 0.5, 1.0, 0.5, 3.0 / 8.0, 3.0 / 8.0, 1.0 / 8.0];

/// An operator `g(tau L)` on one mode `(q, q')`, `L = [[0, 1], [-w^2, -c]]`, as the
/// matrix `[[m00, m01], [m10, m11]]` stored row by row. Undamped, with
/// `g(i w tau) = A + i B`, it is `[[A, B / w], [-w B, A]]`.
pub(super) type ModeOperator = [f64; 4];

/// `1 / n!` for n = 0..39 ([`phis_imaginary`]'s series reach 36!).
const INV_FACTORIAL: [f64; 40] = {
    let mut t = [1.0; 40];
    let mut n = 1;
    while n < 40 {
        t[n] = t[n - 1] / n as f64;
        n += 1;
    }
    t
};

/// `phi_k(z) = sum_j z^j / (j + k)!` for k = 0..=3 on complex `z = x + i y`, as `(re, im)`
/// pairs. Near 0 (`|z| < 1/2`) `phi_3` by its series to 12 terms (the first left out is
/// below `2^-12 / 15!`, 2e-16 of `phi_3`) and the others by `phi_k = 1/k! + z phi_{k+1}`;
/// elsewhere `phi_0 = e^z` and `phi_{k+1} = (phi_k - 1/k!) / z`, which loses at most
/// about a digit at `|z| = 1/2`.
fn phis(x: f64, y: f64) -> [(f64, f64); 4] {
    phis_with(x, y, || y.sin_cos())
}

/// [`phis`], with `(sin y, cos y)` from `trig` where it needs them (away from 0).
#[inline]
fn phis_with(x: f64, y: f64, trig: impl FnOnce() -> (f64, f64)) -> [(f64, f64); 4] {
    let mul = |a: (f64, f64), b: (f64, f64)| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
    let mut out = [(0.0, 0.0); 4];
    if x * x + y * y < 0.25 {
        let mut p = (INV_FACTORIAL[14], 0.0);
        for j in (0..11).rev() {
            p = mul(p, (x, y));
            p.0 += INV_FACTORIAL[j + 3];
        }
        out[3] = p;
        for k in (0..3).rev() {
            let zp = mul(out[k + 1], (x, y));
            out[k] = (INV_FACTORIAL[k] + zp.0, zp.1);
        }
        return out;
    }
    // an undamped mode's `z` is imaginary: the library's `exp(0)` gives exactly 1 and
    // costs ~40 instructions (real `z` takes [`phis_real`])
    let ex = if x == 0.0 { 1.0 } else { x.exp() };
    let (sn, cs) = trig();
    out[0] = (ex * cs, ex * sn);
    let d = x * x + y * y;
    let inv = (x / d, -y / d);
    for k in 0..3 {
        out[k + 1] = mul((out[k].0 - INV_FACTORIAL[k], out[k].1), inv);
    }
    out
}

/// How far [`phis_imaginary`] sums its series, `|y|`: past the bearing's alias bound on
/// every mode's `omega tau` (`LinearPart::alias_limit`, 1.35 pi = 4.24).
const SERIES_REACH: f64 = 4.5;

/// `phi_1`, `phi_2`, `phi_3` at `z = i y` (an undamped mode's), as `(re, im)` pairs, for
/// the dense output at every sample and mode. Up to `|y|` = [`SERIES_REACH`] `phi_3`'s
/// even and odd terms as two real series in `y^2`, to `y^32 / 35!` and `y^33 / 36!` (at
/// `|y|` = 4.5 the first terms left out are below 2e-20 of each part, and the terms'
/// magnitudes sum to at most 7.4 times the part; `phi_1`, two products by `y` from
/// `phi_3`, comes within 2.4e-15 of itself there, 1.7e-15 to 4.24: float64 against 40
/// digits, scanned from 3), then
/// `phi_k = 1/k! + i y phi_{k+1}`: no sine or cosine, no division, no branch in the
/// bearing's use. Beyond, `phi_{k+1} = (phi_k - 1/k!) / (i y)` from the library's
/// `sin_cos`.
#[inline]
pub(super) fn phis_imaginary(y: f64) -> [(f64, f64); 3] {
    if y.abs() <= SERIES_REACH {
        let y2 = y * y;
        let (mut re, mut im) = (0.0, 0.0);
        for k in (0..17).rev() {
            re = re * -y2 + INV_FACTORIAL[2 * k + 3];
            im = im * -y2 + INV_FACTORIAL[2 * k + 4];
        }
        let p3 = (re, y * im);
        let p2 = (0.5 - y * p3.1, y * p3.0);
        let p1 = (1.0 - y * p2.1, y * p2.0);
        return [p1, p2, p3];
    }
    let (sn, cs) = y.sin_cos();
    let r = 1.0 / y;
    let p1 = (sn * r, (1.0 - cs) * r);
    let p2 = (p1.1 * r, (1.0 - p1.0) * r);
    let p3 = (p2.1 * r, (0.5 - p2.0) * r);
    [p1, p2, p3]
}

/// [`phis`] on the real axis, as the relaxing components' and the overdamped modes'
/// operators take it: the same real parts to the bit (with `y` = 0 every complex product's
/// imaginary terms are zeros, and subtracting a zero from a real part leaves it as it is),
/// without those products: the relaxing components' `phis` were 1.6 % of the Table-1
/// case's instructions.
fn phis_real(x: f64) -> [(f64, f64); 4] {
    let mut out = [(0.0, 0.0); 4];
    if x * x < 0.25 {
        let mut p = INV_FACTORIAL[14];
        for j in (0..11).rev() {
            p = p * x + INV_FACTORIAL[j + 3];
        }
        out[3] = (p, 0.0);
        for k in (0..3).rev() {
            out[k] = (INV_FACTORIAL[k] + out[k + 1].0 * x, 0.0);
        }
        return out;
    }
    let inv = x / (x * x);
    out[0] = (x.exp(), 0.0);
    for k in 0..3 {
        out[k + 1] = ((out[k].0 - INV_FACTORIAL[k]) * inv, 0.0);
    }
    out
}

/// Each operator's `tau` over `h`, and its combination of `phi_0..phi_3` at `tau L`: the
/// one table every block's operators are built from.
const OPERATOR_FORMS: [(f64, [f64; 4]); OPS] = [
    (1.0 / 3.0, [0.0, 1.0, 0.0, 0.0]),
    (2.0 / 3.0, [0.0, 1.0, 0.0, 0.0]),
    (2.0 / 3.0, [0.0, 0.0, 1.0, 0.0]),
    (1.0, [0.0, 1.0, 0.0, 0.0]),
    (1.0, [0.0, 0.0, 1.0, 0.0]),
    (1.0, [0.0, 0.0, 3.75, -9.0]),
    (1.0, [0.0, 0.0, 0.75, 0.0]),
    (1.0, [0.0, 0.0, -0.75, 3.0]),
];

/// Which of the `phi` values at a third, two thirds and the whole step each operator
/// takes (0, 1, 2), read off its `tau` in [`OPERATOR_FORMS`] when the crate compiles: a
/// `tau` that is none of the three stops the build.
const PHIS_AT: [usize; OPS] = {
    let mut at = [0; OPS];
    let mut k = 0;
    while k < OPS {
        let frac = OPERATOR_FORMS[k].0;
        at[k] = if frac == 1.0 / 3.0 {
            0
        } else if frac == 2.0 / 3.0 {
            1
        } else if frac == 1.0 {
            2
        } else {
            panic!("an operator's tau is a third, two thirds or the whole step")
        };
        k += 1;
    }
    at
};

/// `sum_k form_k phi_k` from the `phi` values `p` (complex, as `(re, im)`).
fn form_sum(p: &[(f64, f64); 4], form: &[f64; 4]) -> (f64, f64) {
    let re = (0..4).map(|k| form[k] * p[k].0).sum::<f64>();
    let im = (0..4).map(|k| form[k] * p[k].1).sum::<f64>();
    (re, im)
}

/// Each operator's form at its `tau`, from the `phi` values at a third, two thirds and
/// the whole of the step. (Plain loops here and in the callers: the arrays' `map` was left
/// a call, 0.5 % of the Table-1 case's time.)
#[inline]
fn step_forms(phis_at: &[[(f64, f64); 4]; 3]) -> [(f64, f64); OPS] {
    let mut out = [(0.0, 0.0); OPS];
    for ((o, (_, form)), at) in out.iter_mut().zip(&OPERATOR_FORMS).zip(PHIS_AT) {
        *o = form_sum(&phis_at[at], form);
    }
    out
}

/// `g(tau L)` for `g = sum_k form_k phi_k` on a mode of `w` rad/s damped at `c` 1/s, one
/// form at a time, for the tests ([`block_operators`] does the work).
#[cfg(test)]
pub(super) fn damped_operator(w: f64, c: f64, tau: f64, form: [f64; 4]) -> ModeOperator {
    block_operators(mode_matrix(w, c), tau, [form])[0]
}

/// `L` of a mode of `w` rad/s damped at `c` 1/s.
fn mode_matrix(w: f64, c: f64) -> [[f64; 2]; 2] {
    [[0.0, 1.0], [-(w * w), -c]]
}

/// `g(tau A)` for each `g = sum_k form_k phi_k` of `forms` on any real 2x2 matrix `A` (a
/// damped mode's `L = [[0, 1], [-w^2, -c]]` among them). The `phi` functions are evaluated
/// once, at the points the branch needs, for all the forms.
///
/// `tau A` has the eigenvalues `m +- s`, `m = tau alpha`, `alpha` half `A`'s trace,
/// `s^2 = tau^2 (alpha^2 - det)`; on a 2x2 matrix `g(tau A) = E I + D tau (A - alpha I)` with
/// `E = (g(m+s) + g(m-s)) / 2` and `D = (g(m+s) - g(m-s)) / (2 s)`, both even in `s`:
/// functions `F(s^2)`. With complex eigenvalues (`s = i y`; an underdamped mode) both come
/// from one complex value, `E = Re g`, `D = Im g / y`, without cancellation however small
/// `y` is (a complex step). With real ones, by the real difference while `|s|` >= 1e-3 (it
/// loses `eps |g| / (|s| |D|)`, up to ~1e-10 of the operator where it is small beside the
/// `phi`'s); nearer the meeting point, by `F(s^2) = 2 F(0) - F(-s^2) + O(s^4)`, the complex
/// step at `i |s|` reflected about it.
fn block_operators<const K: usize>(
    a: [[f64; 2]; 2],
    tau: f64,
    forms: [[f64; 4]; K],
) -> [ModeOperator; K] {
    let sum = form_sum;
    if tau == 0.0 {
        // g(0) = sum form_k / k! (the complex step below would divide by zero)
        return forms.map(|form| {
            let e = (0..4).map(|k| form[k] * INV_FACTORIAL[k]).sum::<f64>();
            [e, 0.0, 0.0, e]
        });
    }
    let alpha = 0.5 * (a[0][0] + a[1][1]);
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    // `alpha^2 - det` without its cancellation: two nearly equal rates of ~1e5 1/s
    // lost their discriminant's sign that way
    let half_gap = 0.5 * (a[0][0] - a[1][1]);
    let disc = half_gap * half_gap + a[0][1] * a[1][0];
    // the complex step's scale where the eigenvalues meet
    let scale = (2.0 * alpha.abs()).max(det.abs().sqrt());
    let m = tau * alpha;
    // (E, D) by the complex step at s = i y, y != 0, from the phi's at m + i y
    let complex_step = |p: &[(f64, f64); 4], y: f64, form: &[f64; 4]| {
        let (re, im) = sum(p, form);
        (re, im / y)
    };
    let ed: [(f64, f64); K] = if disc <= 0.0 {
        // at exactly critical a step of 1e-9 of the rates, O(1e-18) off
        let y = tau * (-disc).sqrt().max(1e-9 * scale);
        let p = phis(m, y);
        forms.map(|form| complex_step(&p, y, &form))
    } else if (tau * disc.sqrt()).abs() >= 1e-3 {
        let s = tau * disc.sqrt();
        let (pp, pm) = (phis_real(m + s), phis_real(m - s));
        forms.map(|form| {
            let (gp, gm) = (sum(&pp, &form).0, sum(&pm, &form).0);
            (0.5 * (gp + gm), (gp - gm) / (2.0 * s))
        })
    } else {
        let (y0, y1) = (tau * 1e-9 * scale, tau * disc.sqrt());
        let (p0, p1) = (phis(m, y0), phis(m, y1));
        forms.map(|form| {
            let (e0, d0) = complex_step(&p0, y0, &form);
            let (e1, d1) = complex_step(&p1, y1, &form);
            (2.0 * e0 - e1, 2.0 * d0 - d1)
        })
    };
    ed.map(|(e, d)| {
        let b = d * tau;
        [
            e + b * (a[0][0] - alpha),
            b * a[0][1],
            b * a[1][0],
            e + b * (a[1][1] - alpha),
        ]
    })
}

/// The operators of a step of `h` on one oscillator mode of `w` rad/s, damped at `c` 1/s.
pub(super) fn mode_operators(w: f64, c: f64, h: f64) -> [ModeOperator; OPS] {
    if c != 0.0 {
        return block_step_operators(mode_matrix(w, c), h);
    }
    // g(i w tau) = A + i B -> [[A, B / w], [-w B, A]]
    let op = |(a, b): (f64, f64)| [a, if w == 0.0 { 0.0 } else { b / w }, -(w * b), a];
    // the sines and cosines at two thirds and the whole step from the third's by the
    // double and the sum angle (within a few 1e-16 of the library's), where the `phi`s
    // need them: one library call a mode instead of three
    let third = w * h / 3.0;
    let mut trig = None;
    let mut third_trig = || *trig.get_or_insert_with(|| third.sin_cos());
    let p1 = phis_with(0.0, third, &mut third_trig);
    let p2 = phis_with(0.0, 2.0 * third, || {
        let (s, c) = third_trig();
        (2.0 * s * c, (c - s) * (c + s))
    });
    let p3 = phis_with(0.0, w * h, || {
        let (s, c) = third_trig();
        let (s2, c2) = (2.0 * s * c, (c - s) * (c + s));
        (s2 * c + c2 * s, c2 * c - s2 * s)
    });
    let mut ops = [[0.0; 4]; OPS];
    for (o, g) in ops.iter_mut().zip(step_forms(&[p1, p2, p3])) {
        *o = op(g);
    }
    if w == 0.0 {
        // a free mode, L = [[0, 1], [0, 0]] nilpotent: g(tau L) = g(0) I + g'(0) tau L,
        // g'(0) = sum form_k / (k + 1)!
        let slope = [0.5, 0.5, 1.0 / 6.0, 0.5, 1.0 / 6.0, 0.25, 0.125, 0.0];
        for k in 0..OPS {
            let tau = OPERATOR_FORMS[k].0 * h;
            ops[k] = [WITHOUT_L[k], tau * slope[k], 0.0, WITHOUT_L[k]];
        }
    }
    ops
}

/// The dense output's three operators on a mode of `w` rad/s damped at `c` 1/s at
/// `tau = theta h` inside a step of `h`: `phi_1(tau L)`, `theta phi_2(tau L)` and
/// `2 theta^2 phi_3(tau L)`, the weights of the remainder's quadratic's three coefficients
/// in the step's continuous extension ([`super::etd_rk4::EtdRk4`]'s `refine_dense`, at
/// every sample and mode). An undamped mode's from [`phis_imaginary`] (`g(i w tau) = A + i
/// B` gives `[[A, B / w], [-w B, A]]`), each one `phi` times its factor; a damped one's by
/// [`block_operators`].
#[inline]
pub(super) fn dense_operators(w: f64, c: f64, tau: f64, theta: f64) -> [ModeOperator; 3] {
    let factors = [1.0, theta, 2.0 * theta * theta];
    if c == 0.0 {
        let p = phis_imaginary(w * tau);
        let inv_w = 1.0 / w;
        return std::array::from_fn(|k| {
            let (a, b) = (factors[k] * p[k].0, factors[k] * p[k].1);
            [a, b * inv_w, -(w * b), a]
        });
    }
    let [f1, f2, f3] = factors;
    let forms = [
        [0.0, f1, 0.0, 0.0],
        [0.0, 0.0, f2, 0.0],
        [0.0, 0.0, 0.0, f3],
    ];
    block_operators(mode_matrix(w, c), tau, forms)
}

/// The operators of a step of `h` under the real 2x2 block `a` (1/s): a pair of
/// components relaxing together, or a damped mode ([`mode_operators`]).
pub(super) fn block_step_operators(a: [[f64; 2]; 2], h: f64) -> [ModeOperator; OPS] {
    // by `tau`: the third's operator, the two thirds', then the whole step's five
    let form = |k: usize| OPERATOR_FORMS[k].1;
    let [p1_third] = block_operators(a, h / 3.0, [form(PHI1_THIRD)]);
    let [p1_two, p2_two] = block_operators(
        a,
        2.0 * h / 3.0,
        [form(PHI1_TWO_THIRDS), form(PHI2_TWO_THIRDS)],
    );
    let [p1, p2, b2, b3, b4] = block_operators(
        a,
        h,
        [
            form(PHI1_STEP),
            form(PHI2_STEP),
            form(B2),
            form(B3),
            form(B4),
        ],
    );
    [p1_third, p1_two, p2_two, p1, p2, b2, b3, b4]
}

/// The operators of a step of `h` on a component relaxing at `rate` (1/s, < 0).
pub(super) fn relax_operators(rate: f64, h: f64) -> [f64; OPS] {
    let third = rate * h / 3.0;
    let phis_at = [
        phis_real(third),
        phis_real(2.0 * third),
        phis_real(rate * h),
    ];
    let mut ops = [0.0; OPS];
    for (o, (re, _)) in ops.iter_mut().zip(step_forms(&phis_at)) {
        *o = re;
    }
    ops
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`phis_imaginary`] against 40-digit values (mpmath, `(e^z - 1 - ...) / z^k`) inside
    /// its series' reach and beyond: within 3e-15 of `|phi_k|`; and against [`phis`] on the
    /// imaginary axis within 1e-14 (whose recurrence loses about a digit just above `|y|` =
    /// 1/2: 1.9-2.6e-15 of `|phi_3|` off at y = -0.5566).
    #[test]
    fn imaginary_axis_phis_match_exact_values_and_the_complex_ones() {
        let exact: [(f64, [(f64, f64); 3]); 8] = [
            (
                0.25,
                [
                    (0.989_615_837_018_091_7, 0.124_350_313_157_420_86),
                    (0.497_401_252_629_683_45, 0.041_536_651_927_633_126),
                    (0.166_146_607_710_532_5, 0.010_394_989_481_266_185),
                ],
            ),
            (
                -0.5566,
                [
                    (0.949_160_017_679_220_4, -0.271_188_926_559_645_47),
                    (0.487_224_086_524_695_4, -0.091_340_248_510_204_04),
                    (0.164_103_931_926_345_75, -0.022_953_491_691_168_864),
                ],
            ),
            (
                0.5,
                [
                    (0.958_851_077_208_406, 0.244_834_876_219_254_57),
                    (0.489_669_752_438_509_14, 0.082_297_845_583_188),
                    (0.164_595_691_166_376, 0.020_660_495_122_981_73),
                ],
            ),
            (
                2.5,
                [
                    (0.239_388_857_641_582_6, 0.720_457_446_218_773_5),
                    (0.288_182_978_487_509_4, 0.304_244_456_943_366_96),
                    (0.121_697_782_777_346_78, 0.084_726_808_604_996_24),
                ],
            ),
            (
                3.2,
                [
                    (-0.018_241_919_821_118_722, 0.624_467_117_435_860_3),
                    (0.195_145_974_198_706_36, 0.318_200_599_944_099_6),
                    (0.099_437_687_482_531_13, 0.095_266_883_062_904_26),
                ],
            ),
            (
                3.5,
                [
                    (-0.100_223_779_339_891_39, 0.553_273_339_225_941_8),
                    (0.158_078_096_921_697_66, 0.314_349_651_239_968_97),
                    (0.089_814_186_068_562_56, 0.097_691_972_308_086_38),
                ],
            ),
            (
                4.7,
                [
                    (-0.212_749_629_268_957_63, 0.215_401_843_289_976_75),
                    (0.045_830_179_423_399_309, 0.258_031_836_014_671_84),
                    (0.054_900_390_641_419_54, 0.096_631_876_718_425_679),
                ],
            ),
            (
                5.0,
                [
                    (-0.191_784_854_932_627_69, 0.143_267_562_907_354_75),
                    (0.028_653_512_581_470_949, 0.238_356_970_986_525_54),
                    (0.047_671_394_197_305_108, 0.094_269_297_483_705_81),
                ],
            ),
        ];
        let off = |a: (f64, f64), b: (f64, f64)| {
            (a.0 - b.0).abs().max((a.1 - b.1).abs()) / b.0.hypot(b.1)
        };
        for (y, want) in exact {
            for (a, b) in phis_imaginary(y).iter().zip(want) {
                assert!(off(*a, b) <= 3e-15, "{y}: {a:?} against {b:?}");
            }
        }
        for k in -4_200..4_200 {
            let y = k as f64 * 1.2e-3 + 1e-9 * (k as f64).sin();
            let own = phis_imaginary(y);
            for (a, b) in own.iter().zip(&phis(0.0, y)[1..]) {
                assert!(off(*a, *b) <= 1e-14, "{y}: {a:?} against {b:?}");
            }
        }
    }

    /// The dense output's operators against the augmented matrix exponential (as
    /// [`damped_operators_match_the_augmented_matrix_exponential`]: 1e-9 of the largest
    /// scaled entry, that test's bound for the Pade exponential's own error) inside the step
    /// and at its end, on undamped, underdamped and overdamped modes; at `theta = 1` they
    /// recombine into the step's own weights (`B2 = 15/4 g1 - 9/2 g2`, `B3 = 3/4 g1`,
    /// `B4 = 3/2 g2 - 3/4 g1`, and `phi_1 = g0`) to rounding (1e-13 of the scaled entries: operators of size ~1,
    /// a few roundings each); and an undamped mode's operators, from [`phis_imaginary`],
    /// equal the general ones of [`block_operators`] to rounding.
    #[test]
    fn dense_operators_match_the_exponential_and_end_at_the_step_weights() {
        for (w, c, h) in [
            (300.0_f64, 0.0, 0.01),
            (300.0, 40.0, 0.01),
            (30.0, 200.0, 0.02),
            (3.7e5, 0.0, 8.5e-6),
            (3.7e5, 3.7e4, 8.5e-6),
        ] {
            let scaled = |m: ModeOperator| [m[0], m[1] * w, m[2] / w, m[3]];
            let largest = |m: ModeOperator| m.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            let close = |a: ModeOperator, b: ModeOperator, tol: f64, what: &str| {
                let (a, b) = (scaled(a), scaled(b));
                let bound = tol * largest(b).max(1e-3);
                for k in 0..4 {
                    assert!((a[k] - b[k]).abs() <= bound, "{what}: {a:?} against {b:?}");
                }
            };
            for theta in [0.1, 0.5, 0.9, 1.0] {
                let tau = theta * h;
                let ops = dense_operators(w, c, tau, theta);
                let forms = [
                    [0.0, 1.0, 0.0, 0.0],
                    [0.0, 0.0, theta, 0.0],
                    [0.0, 0.0, 0.0, 2.0 * theta * theta],
                ];
                let what = format!("w {w}, c {c}, theta {theta}");
                for (op, form) in ops.iter().zip(forms) {
                    let expect = augmented_operator(mode_matrix(w, c), tau, form);
                    close(*op, expect, 1e-9, &what);
                }
                if c == 0.0 {
                    let general = block_operators(mode_matrix(w, 0.0), tau, forms);
                    for (op, g) in ops.iter().zip(general) {
                        close(*op, g, 1e-13, &what);
                    }
                }
            }
            let [g0, g1, g2] = dense_operators(w, c, h, 1.0);
            let step = mode_operators(w, c, h);
            let mix = |a: f64, b: f64, d: f64| -> ModeOperator {
                std::array::from_fn(|k| a * g0[k] + b * g1[k] + d * g2[k])
            };
            let what = format!("w {w}, c {c}, the step's weights");
            close(mix(1.0, 0.0, 0.0), step[PHI1_STEP], 1e-13, &what);
            close(mix(0.0, 3.75, -4.5), step[B2], 1e-13, &what);
            close(mix(0.0, 0.75, 0.0), step[B3], 1e-13, &what);
            close(mix(0.0, -0.75, 1.5), step[B4], 1e-13, &what);
        }
    }

    /// The real-axis `phi`s are the complex ones' real parts to the bit, across both forms
    /// (series and recurrence), their meeting at 1/2, both zeros, and the rates' far end.
    #[test]
    fn the_real_axis_phis_are_the_complex_ones_to_the_bit() {
        for k in -40_000..40_000 {
            let x = k as f64 * 2.7e-4 + 1e-9 * (k as f64).sin();
            for (r, c) in phis_real(x).iter().zip(phis(x, 0.0)) {
                assert_eq!(r.0.to_bits(), c.0.to_bits(), "{x}");
            }
        }
        for x in [0.0, -0.0, 0.5, -0.5, 0.499_999_999, -700.0, 1e-300, -1e-300] {
            for (r, c) in phis_real(x).iter().zip(phis(x, 0.0)) {
                assert_eq!(r.0.to_bits(), c.0.to_bits(), "{x}");
            }
        }
    }

    /// The series and the recurrence meet at |z| = 1/2 within 5e-14 (relative; the
    /// recurrence loses about a digit there), and both agree with `phi_1 = (e^z - 1)/z` in
    /// closed form away from it.
    #[test]
    fn phi_functions_agree_across_their_two_forms() {
        for (x, y) in [
            (0.5, 0.0),
            (0.0, 0.5),
            (-0.3, 0.4),
            (0.0, -0.5),
            (-0.5, 0.0),
        ] {
            let near = phis(x * (1.0 - 1e-15), y * (1.0 - 1e-15));
            let far = phis(x, y);
            for k in 0..4 {
                let scale = near[k].0.hypot(near[k].1);
                let diff = (near[k].0 - far[k].0).hypot(near[k].1 - far[k].1);
                assert!(
                    diff < 5e-14 * scale,
                    "z = ({x}, {y}), phi_{k}: {near:?} vs {far:?}"
                );
            }
        }
        // phi_1(i 3) = (e^{3i} - 1) / (3i)
        let p = phis(0.0, 3.0);
        let expect = ((3.0f64).sin() / 3.0, (1.0 - (3.0f64).cos()) / 3.0);
        assert!(
            (p[1].0 - expect.0).abs() < 1e-15 && (p[1].1 - expect.1).abs() < 1e-15,
            "{p:?}"
        );
        // phi_3(0) = 1/6
        assert_eq!(phis(0.0, 0.0)[3], (1.0 / 6.0, 0.0));
    }

    /// Every operator of a damped mode (and of two other 2x2 matrices) against the top row of the exponential of the
    /// augmented matrix `[[tau L, I, 0, 0], [0, 0, I, 0], [0, 0, 0, I], [0, 0, 0, 0]]`, which
    /// is `[e^{tau L}, phi_1, phi_2, phi_3]` (nalgebra's Pade exponential): underdamped,
    /// exactly critical and just under, overdamped on both sides of the switch to the
    /// reflected complex step (`|s|` = 1e-3; the shorter `tau`s see a third and two thirds
    /// of the `s`),
    /// stiff, free, and backwards in time as the dense output uses it.
    #[test]
    fn damped_operators_match_the_augmented_matrix_exponential() {
        let near_critical = |w: f64, s: f64, tau: f64| {
            // c^2/4 - w^2 = (s / tau)^2
            2.0 * (w * w + (s / tau) * (s / tau)).sqrt()
        };
        let mode = |w: f64, c: f64| [[0.0, 1.0], [-(w * w), -c]];
        let modes = [
            (100.0, 30.0, 0.05),
            (100.0, 200.0, 0.05),
            (100.0, 200.0 * (1.0 - 1e-12), 0.05),
            (100.0, near_critical(100.0, 2e-3, 0.05), 0.05),
            (100.0, near_critical(100.0, 5e-4, 0.05), 0.05),
            (100.0, near_critical(100.0, 1e-6, 0.05), 0.05),
            (3.7e5, 1.2e6, 8.5e-6),
            (3.7e5, 3.7e4, 8.5e-6),
            (0.0, 50.0, 0.05),
            (100.0, 30.0, -0.05),
            (3.5e4, 1.2e6, -4e-6),
        ];
        // and two matrices that are no mode's: a whirl (complex pair) and a coupled pair
        // of real rates
        let others = [
            ([[-1e4, 3e4], [-2e4, -5e3]], 1e-4),
            ([[-2e3, 5e2], [8e2, -6e3]], 1e-3),
        ];
        let cases = modes
            .map(|(w, c, h)| (mode(w, c), h))
            .into_iter()
            .chain(others);
        for (a, h) in cases {
            // scaled so that the off-diagonal entries compare with the diagonal ones
            // (for a mode, velocities divided by w)
            let sc = (a[1][0] / a[0][1]).abs().sqrt().max(1.0);
            let scaled = |m: ModeOperator| [m[0], m[1] * sc, m[2] / sc, m[3]];
            for (k, &(frac, form)) in OPERATOR_FORMS.iter().enumerate() {
                let tau = frac * h;
                let op = scaled(block_operators(a, tau, [form])[0]);
                let expect = scaled(augmented_operator(a, tau, form));
                let size = expect.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                let diff = (0..4).fold(0.0f64, |a, r| a.max((op[r] - expect[r]).abs()));
                // the Pade exponential's own error, and the real difference's loss of
                // eps |g| / (|s| |D|): 8.9e-12 of the largest scaled entry measured at
                // |s| = 2e-3, where the operator is ~1e3 times smaller than the phi's it
                // differences (m = -5; everything else below 1e-12). 1e-9 of an operator is three orders below the tightest
                // tolerance the solver is run at (1e-6 relative per step, benches).
                assert!(
                    diff <= 1e-9 * size,
                    "{a:?} h {h} operator {k}: {op:?} vs {expect:?}"
                );
            }
        }
        // at tau = 0, g(0)
        let form = OPERATOR_FORMS[B2].1;
        let g0 = 3.75 / 2.0 - 9.0 / 6.0;
        assert_eq!(damped_operator(100.0, 30.0, 0.0, form), [g0, 0.0, 0.0, g0]);
    }

    /// `sum_k form_k phi_k(tau A)` by the exponential of the augmented 8x8 matrix
    /// `[[tau A, I, 0, 0], [0, 0, I, 0], [0, 0, 0, I], [0, 0, 0, 0]]` (nalgebra's Pade),
    /// whose first block row holds `phi_0..phi_3` of `tau A`.
    fn augmented_operator(a: [[f64; 2]; 2], tau: f64, form: [f64; 4]) -> ModeOperator {
        let mut m = nalgebra::SMatrix::<f64, 8, 8>::zeros();
        for r in 0..2 {
            for c in 0..2 {
                m[(r, c)] = a[r][c] * tau;
            }
        }
        for i in 0..6 {
            m[(i, i + 2)] = 1.0;
        }
        let e = m.exp();
        let mut expect = [0.0; 4];
        for (j, f) in form.iter().enumerate() {
            for (r, x) in expect.iter_mut().enumerate() {
                *x += f * e[(r / 2, 2 * j + r % 2)];
            }
        }
        expect
    }

    /// A relaxing pair's operators match the augmented matrix exponential, on every branch:
    /// the bearing's block of a loaded ball's orbital speed and axial spin at 0.01 s of the
    /// Table-1 ramp (1/s; real eigenvalues about -2.8e5 and -9.0e5), the same with one
    /// coupling's sign turned (real, -4.8e5 and -7.0e5), with a stronger turned coupling
    /// (complex), and a block whose eigenvalues nearly meet (the near-critical branch),
    /// over `|lambda| h` from 0.01 to 20. Tolerance 1e-10 of the largest entry: the real
    /// difference branch loses up to ~1e-10 where it is small beside the `phi`s (the
    /// damped modes' doc); the Pade exponential's own error is far below.
    #[test]
    fn pair_operators_match_the_augmented_matrix_exponential() {
        let blocks = [
            [[-3.58e5, 2.0e4], [2.10e6, -8.23e5]],
            [[-3.58e5, -2.0e4], [2.10e6, -8.23e5]],
            [[-3.58e5, -2.0e5], [2.10e6, -8.23e5]],
            [[-5.0e5, 1.0e-3], [-1.0e-3, -5.0e5 * (1.0 + 1e-9)]],
        ];
        for a in blocks {
            for h in [1e-7, 1e-6, 8.5e-6, 2.2e-5] {
                let ops = block_step_operators(a, h);
                for (k, &(frac, form)) in OPERATOR_FORMS.iter().enumerate() {
                    let expect = augmented_operator(a, frac * h, form);
                    let size = expect.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                    let diff = (0..4).fold(0.0f64, |m, r| m.max((ops[k][r] - expect[r]).abs()));
                    assert!(
                        diff <= 1e-10 * size,
                        "{a:?} h {h} operator {k}: {:?} against {expect:?}",
                        ops[k]
                    );
                }
            }
        }
    }

    /// An undamped mode's operators (the sines and cosines at two thirds and the whole step
    /// by the double and the sum angle from the third's) match the augmented matrix
    /// exponential from `omega h` = 0.3 (every `tau` by the series) and 0.9 (the third by
    /// the series, the others from its sine) to pi, 1.35 pi (the alias bound), 1.5 pi and
    /// past it. Velocities scaled by `w`; tolerance 1e-13 of the largest entry: the angle
    /// formulas' few 1e-16 and the Pade exponential's own error, far below the 1e-9 the
    /// damped modes' test allows (a sine 1e-12 off fails it).
    #[test]
    fn undamped_operators_match_the_augmented_matrix_exponential() {
        let (w, mode) = (3.7e5, [[0.0, 1.0], [-(3.7e5f64 * 3.7e5), 0.0]]);
        let pi = std::f64::consts::PI;
        for wh in [0.3, 0.9, 1.0, 1.5, 2.8, pi, 1.35 * pi, 1.5 * pi, 6.5] {
            let h = wh / w;
            let ops = mode_operators(w, 0.0, h);
            let scaled = |m: ModeOperator| [m[0], m[1] * w, m[2] / w, m[3]];
            for (k, &(frac, form)) in OPERATOR_FORMS.iter().enumerate() {
                let (op, expect) = (
                    scaled(ops[k]),
                    scaled(augmented_operator(mode, frac * h, form)),
                );
                let size = expect.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                let diff = (0..4).fold(0.0f64, |a, r| a.max((op[r] - expect[r]).abs()));
                assert!(
                    diff <= 1e-13 * size,
                    "w h {wh} operator {k}: {op:?} vs {expect:?}"
                );
            }
        }
    }

    /// A mode of vanishing frequency tends to the free mode's operators (the `w = 0`
    /// branch, `g(0) I + g'(0) tau L`): at 1e-9 rad/s and h = 1e-3 s they agree to rounding.
    #[test]
    fn a_free_mode_is_the_limit_of_a_slow_one() {
        let h = 1e-3;
        let (free, slow) = (mode_operators(0.0, 0.0, h), mode_operators(1e-9, 0.0, h));
        for k in 0..OPS {
            for j in 0..4 {
                assert!(
                    (free[k][j] - slow[k][j]).abs() < 1e-15,
                    "operator {k}: {:?} vs {:?}",
                    free[k],
                    slow[k]
                );
            }
        }
    }
}
