//! One explicit Runge-Kutta stepper for every tableau of [`super::tableau`]: fixed-step
//! (no estimate, or no error control asked for) or controlled by the solver through the
//! tableau's error estimate, the [`ErrorNorm`] and the [`Controller`]. It owns every
//! buffer: a step does not allocate.

use super::controller::{Controller, StepEnd};
use super::error_norm::ErrorNorm;
use super::method::Method;
use super::problem::OdeSystem;
use super::stats::StepStats;
use super::tableau::{Estimate, ExplicitTableau, Row, Sum};

/// A row prepared for evaluation: `h / den` times the sum of `terms` from `start`.
struct Combination {
    den: f64,
    start: f64,
    terms: Vec<(usize, f64)>,
}

impl Combination {
    fn new(row: &Row, sum: Sum) -> Self {
        Combination {
            den: row.den,
            start: sum.start(),
            terms: sum.terms(row),
        }
    }

    /// `out = sum_j num_j k_j`, each component summed in term order (a pass per term
    /// keeps every loop a plain, vectorisable one over the components).
    fn sum_into(&self, k: &[Vec<f64>], out: &mut [f64]) {
        let Some((&(j0, w0), rest)) = self.terms.split_first() else {
            out.fill(self.start);
            return;
        };
        for (o, kj) in out.iter_mut().zip(&k[j0]) {
            *o = self.start + w0 * kj;
        }
        for &(j, w) in rest {
            for (o, kj) in out.iter_mut().zip(&k[j]) {
                *o += w * kj;
            }
        }
    }
}

/// `out = y + hd * out`.
fn advance(y: &[f64], hd: f64, out: &mut [f64]) {
    for (o, yi) in out.iter_mut().zip(y) {
        *o = yi + hd * *o;
    }
}

/// Error control of a controlled stepper.
struct Control {
    norm: ErrorNorm,
    controller: Controller,
    /// The estimate's weights: `b_hat` (embedded) or `b - b_hat` (first same as last).
    estimate: Combination,
    fsal: bool,
}

/// Buffers of an explicit Runge-Kutta method.
pub struct ExplicitRk {
    c: &'static [f64],
    rows: Vec<Combination>,
    b: Combination,
    control: Option<Control>,
    /// Stages; with a first-same-as-last estimate, one more: `f(t + h, y_new)`.
    k: Vec<Vec<f64>>,
    tmp: Vec<f64>,
    y_new: Vec<f64>,
    /// Local error estimate of the last attempt, per component.
    err: Vec<f64>,
}

impl ExplicitRk {
    /// A fixed-step method over `n` components (any estimate the tableau has is unused).
    pub fn fixed(tableau: &ExplicitTableau, n: usize) -> Self {
        Self::with_control(tableau, n, None)
    }

    /// A method controlled through the tableau's error estimate, measured with `norm`.
    pub fn adaptive(tableau: &ExplicitTableau, n: usize, norm: ErrorNorm) -> Self {
        let (estimate, fsal) = match tableau.estimate {
            Estimate::None => panic!("an adaptive method needs a tableau with an estimate"),
            Estimate::Embedded { b_hat, .. } => {
                assert_eq!(b_hat.den, tableau.b.den, "b and b_hat share a denominator");
                (b_hat, false)
            }
            Estimate::Fsal { e, .. } => (e, true),
        };
        let control = Control {
            norm,
            controller: Controller::new(tableau.estimate.order().unwrap()),
            estimate: Combination::new(&estimate, tableau.sum),
            fsal,
        };
        Self::with_control(tableau, n, Some(control))
    }

    fn with_control(tableau: &ExplicitTableau, n: usize, control: Option<Control>) -> Self {
        let s = tableau.stages();
        let fsal = control.as_ref().is_some_and(|c| c.fsal);
        ExplicitRk {
            c: tableau.c,
            rows: tableau
                .a
                .iter()
                .map(|r| Combination::new(r, tableau.sum))
                .collect(),
            b: Combination::new(&tableau.b, tableau.sum),
            control,
            k: vec![vec![0.0; n]; s + usize::from(fsal)],
            tmp: vec![0.0; n],
            y_new: vec![0.0; n],
            err: vec![0.0; n],
        }
    }

    /// The proposed state of the last attempt.
    pub fn y_new(&self) -> &[f64] {
        &self.y_new
    }

    /// `f(t + h, y_new)` of the last attempt, for a first-same-as-last estimate.
    pub fn f_new(&self) -> Option<&[f64]> {
        let fsal = self.control.as_ref().is_some_and(|c| c.fsal);
        fsal.then(|| &self.k[self.c.len()][..])
    }

    /// The step-size controller, for a controlled method.
    pub fn controller(&mut self) -> Option<&mut Controller> {
        self.control.as_mut().map(|c| &mut c.controller)
    }

    /// One attempted step from `(t, y)` with `f0 = f(t, y)` to `t_end = t + h` (exactly
    /// the end time on the last step). Leaves the advanced solution in `y_new` and, for a
    /// first-same-as-last estimate, `f(t_end, y_new)` through
    /// [`OdeSystem::rhs_at_step_end`]; returns the scaled error norm (accept when <= 1),
    /// 0 for a fixed-step method.
    #[allow(clippy::too_many_arguments)]
    pub fn attempt_step<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64],
        f0: &[f64],
        h: f64,
        t_end: f64,
        stats: &mut StepStats,
    ) -> f64 {
        let s = self.c.len();
        self.k[0].copy_from_slice(f0);
        for st in 1..s {
            let row = &self.rows[st];
            row.sum_into(&self.k, &mut self.tmp);
            advance(y, h / row.den, &mut self.tmp);
            sys.rhs(t + self.c[st] * h, &self.tmp, &mut self.k[st]);
            stats.rhs_evals += 1;
        }
        // y_new holds sum b_j k_j until it is advanced
        self.b.sum_into(&self.k, &mut self.y_new);
        let hb = h / self.b.den;
        let Some(ctl) = &self.control else {
            advance(y, hb, &mut self.y_new);
            return 0.0;
        };
        let he = h / ctl.estimate.den;
        if ctl.fsal {
            advance(y, hb, &mut self.y_new);
            sys.rhs_at_step_end(t_end, &self.y_new, &mut self.k[s]);
            stats.rhs_evals += 1;
            ctl.estimate.sum_into(&self.k, &mut self.err);
            self.err.iter_mut().for_each(|e| *e *= he);
        } else {
            // (h / den) (sum b_hat_j k_j - sum b_j k_j), before y_new is advanced
            ctl.estimate.sum_into(&self.k, &mut self.err);
            for (e, d) in self.err.iter_mut().zip(&self.y_new) {
                *e = he * (*e - d);
            }
            advance(y, hb, &mut self.y_new);
        }
        ctl.norm.rms(y, &self.y_new, &self.err)
    }
}

impl<S: OdeSystem> Method<S> for ExplicitRk {
    fn attempt(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64],
        f0: &[f64],
        h: f64,
        t_end: f64,
        stats: &mut StepStats,
    ) -> f64 {
        self.attempt_step(sys, t, y, f0, h, t_end, stats)
    }
    fn y_new(&self) -> &[f64] {
        &self.y_new
    }
    fn f_new(&self) -> Option<&[f64]> {
        ExplicitRk::f_new(self)
    }
    fn accept_factor(&mut self, err: f64, end: StepEnd) -> f64 {
        self.controller().map_or(1.0, |c| c.accept_factor(err, end))
    }
    fn reject_factor(&mut self, err: f64) -> f64 {
        self.controller().map_or(1.0, |c| c.reject_factor(err))
    }
    fn controlled(&self) -> bool {
        self.control.is_some()
    }
}

#[cfg(test)]
// The reference formulas index the state and the stages at one component, as written.
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;
    use crate::ode::tableau::{CASH_KARP, CLASSICAL_RK4, RK4_FSAL};

    /// Undamped oscillator x'' = -w^2 x.
    struct Osc {
        w: f64,
        calls: u64,
    }
    impl OdeSystem for Osc {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) {
            self.calls += 1;
            dy[0] = y[1];
            dy[1] = -self.w * self.w * y[0];
        }
    }

    /// One period of the oscillator from `(1, 0)` with `tableau` at `rtol`; the step
    /// sized by the elementary controller alone, or by the PI controller and its rejection
    /// rule. Returns the error after the period, the statistics and the evaluations made.
    fn run(tableau: &ExplicitTableau, rtol: f64, elementary: bool) -> (f64, StepStats, u64) {
        let mut sys = Osc {
            w: 2.0 * std::f64::consts::PI,
            calls: 0,
        };
        let mut st = StepStats::default();
        let norm = ErrorNorm::new(rtol, rtol, vec![1.0, 6.3], vec![false, false]);
        let mut rk = ExplicitRk::adaptive(tableau, 2, norm);
        let (mut t, mut y, mut h): (f64, Vec<f64>, f64) = (0.0, vec![1.0, 0.0], 1e-3);
        let mut f = vec![0.0; 2];
        sys.rhs(t, &y, &mut f);
        st.rhs_evals += 1;
        while t < 1.0 {
            h = h.min(1.0 - t);
            let err = rk.attempt_step(&mut sys, t, &y, &f.clone(), h, t + h, &mut st);
            let accepted = err <= 1.0;
            if accepted {
                t += h;
                y.copy_from_slice(rk.y_new());
                match rk.f_new() {
                    Some(f_new) => f.copy_from_slice(f_new),
                    None => {
                        sys.rhs(t, &y, &mut f);
                        st.rhs_evals += 1;
                    }
                }
                st.record(h);
            } else {
                st.rejected += 1;
            }
            let c = rk.controller().unwrap();
            h *= match (elementary, accepted) {
                (true, _) => c.elementary_factor(err),
                (false, true) => c.accept_factor(err, StepEnd::Chosen),
                (false, false) => c.reject_factor(err),
            };
        }
        ((y[0] - 1.0).abs().max(y[1].abs() / 6.3), st, sys.calls)
    }

    fn run_adaptive(rtol: f64) -> (f64, StepStats, u64) {
        run(&CASH_KARP, rtol, true)
    }

    #[test]
    fn adaptive_meets_tolerance_and_counts_are_pinned() {
        let (e1, s1, calls) = run_adaptive(1e-6);
        // after one period the global error stays within ~100x the local tolerance
        assert!(e1 < 1e-4, "{e1}");
        assert_eq!(s1.rhs_evals, calls, "every evaluation is counted");
        // Pinned counts (diffsol practice): a change here means the controller changed.
        assert_eq!(
            (s1.accepted, s1.rejected),
            (PIN_ACCEPTED, PIN_REJECTED),
            "{s1:?}"
        );
        let (e2, s2, _) = run_adaptive(1e-8);
        assert!(
            e2 < e1 / 10.0,
            "tighter tolerance must reduce the error: {e1} -> {e2}"
        );
        assert!(s2.accepted > s1.accepted);
    }
    const PIN_ACCEPTED: u64 = 21;
    const PIN_REJECTED: u64 = 0;

    #[test]
    fn fixed_rk4_is_fourth_order() {
        let err = |h: f64| {
            let mut sys = Osc { w: 1.0, calls: 0 };
            let mut st = StepStats::default();
            let mut rk = ExplicitRk::fixed(&CLASSICAL_RK4, 2);
            let mut y = vec![1.0, 0.0];
            let mut f = vec![0.0; 2];
            let n = (1.0 / h).round() as usize;
            for k in 0..n {
                sys.rhs(k as f64 * h, &y, &mut f);
                let t = k as f64 * h;
                rk.attempt_step(&mut sys, t, &y, &f, h, t + h, &mut st);
                y.copy_from_slice(rk.y_new());
            }
            (y[0] - 1f64.cos()).abs()
        };
        let ratio = err(0.02) / err(0.01);
        // 4th order: halving h divides the error by 2^4 = 16 (asymptotically; 14-18 allowed)
        assert!((14.0..18.0).contains(&ratio), "{ratio}");
    }

    fn run_fsal(rtol: f64) -> (f64, StepStats, u64) {
        run(&RK4_FSAL, rtol, false)
    }

    #[test]
    fn fsal_rk4_meets_tolerance_with_four_evaluations_per_step() {
        let (e1, s1, calls) = run_fsal(1e-6);
        // the controller bounds the 3rd-order estimate while the 4th-order solution is
        // advanced, so the global error after one period stays below ~10x the tolerance
        assert!(e1 < 1e-5, "{e1}");
        assert_eq!(s1.rhs_evals, calls, "every evaluation is counted");
        assert_eq!(
            s1.rhs_evals,
            1 + 4 * (s1.accepted + s1.rejected),
            "four evaluations per attempt, the last one reused as the next first stage"
        );
        // Pinned counts: a change here means the controller changed.
        assert_eq!(
            (s1.accepted, s1.rejected),
            (FSAL_ACCEPTED, FSAL_REJECTED),
            "{s1:?}"
        );
        let (e2, s2, _) = run_fsal(1e-8);
        assert!(e2 < e1 / 10.0, "{e1} -> {e2}");
        assert!(s2.accepted > s1.accepted);
    }
    const FSAL_ACCEPTED: u64 = 83;
    const FSAL_REJECTED: u64 = 0;

    #[test]
    fn fsal_rk4_estimate_scales_as_h_to_the_fourth() {
        let est = |h: f64| {
            let mut sys = Osc { w: 1.0, calls: 0 };
            let mut st = StepStats::default();
            let norm = ErrorNorm::new(1.0, 0.0, vec![1.0, 1.0], vec![false, false]);
            let mut rk = ExplicitRk::adaptive(&RK4_FSAL, 2, norm);
            let y = [1.0, 0.0];
            let mut f = [0.0; 2];
            sys.rhs(0.0, &y, &mut f);
            rk.attempt_step(&mut sys, 0.0, &y, &f, h, h, &mut st)
        };
        // the estimate is the local error of the 3rd-order solution, O(h^4): halving h
        // divides it by 16 (asymptotically; 14-18 allowed)
        let ratio = est(0.02) / est(0.01);
        assert!((14.0..18.0).contains(&ratio), "{ratio}");
    }

    /// A nonlinear system with components held at `-0` and `+0` (the sign of a zero can
    /// matter downstream, in `atan2` for one).
    struct Signed;
    impl OdeSystem for Signed {
        fn dim(&self) -> usize {
            5
        }
        fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
            dy[0] = y[1] * (1.0 + 0.3 * y[0] * y[0]).sqrt();
            dy[1] = -(y[0] + 0.1 * t).sin() / 3.0 - 1e-3 * y[1];
            dy[2] = -0.0;
            dy[3] = 0.0;
            dy[4] = -0.0 * y[0];
        }
    }

    /// The scaled RMS norm as the replaced steppers wrote it.
    fn reference_norm(y: &[f64], yn: &[f64], est: &[f64], tol: f64) -> f64 {
        let mut sum = 0.0;
        for i in 0..y.len() {
            let sc = tol * 1.0 + tol * y[i].abs().max(yn[i].abs());
            let e = est[i] / sc;
            sum += e * e;
        }
        (sum / y.len() as f64).sqrt()
    }

    /// The tableau-driven stepper gives, bit for bit, what the hand-written steppers it
    /// replaced gave (their formulas below, verbatim in evaluation order): classical RK4
    /// `y + c h k` stages and `y + h/6 (k1 + 2 k2 + 2 k3 + k4)`, its first-same-as-last
    /// estimate `h/6 (k4 - k5)`, and Cash-Karp's sums from zero over every weight.
    #[test]
    fn steps_reproduce_the_replaced_formulas_bit_for_bit() {
        let y = [0.7, -0.2, -0.0, -0.0, 0.0];
        let (t, h, tol) = (0.3, 0.05, 1e-6);
        let mut f0 = [0.0; 5];
        Signed.rhs(t, &y, &mut f0);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let norm = || ErrorNorm::new(tol, tol, vec![1.0; 5], vec![false; 5]);
        let mut st = StepStats::default();

        // classical RK4
        let mut k = [[0.0; 5]; 4];
        k[0] = f0;
        let mut tmp = [0.0; 5];
        for (s, c) in [(1usize, 0.5), (2, 0.5), (3, 1.0)] {
            for i in 0..5 {
                tmp[i] = y[i] + c * h * k[s - 1][i];
            }
            Signed.rhs(t + c * h, &tmp, &mut k[s]);
        }
        let mut rk4 = [0.0; 5];
        for i in 0..5 {
            rk4[i] = y[i] + h / 6.0 * (k[0][i] + 2.0 * k[1][i] + 2.0 * k[2][i] + k[3][i]);
        }
        let mut fixed = ExplicitRk::fixed(&CLASSICAL_RK4, 5);
        fixed.attempt_step(&mut Signed, t, &y, &f0, h, t + h, &mut st);
        assert_eq!(bits(fixed.y_new()), bits(&rk4));
        assert_eq!(rk4[2].to_bits(), (-0.0f64).to_bits(), "-0 stays -0");

        // its first-same-as-last estimate
        let mut f_new = [0.0; 5];
        Signed.rhs(t + h, &rk4, &mut f_new);
        let est: Vec<f64> = (0..5).map(|i| h / 6.0 * (k[3][i] - f_new[i])).collect();
        let mut fsal = ExplicitRk::adaptive(&RK4_FSAL, 5, norm());
        let err = fsal.attempt_step(&mut Signed, t, &y, &f0, h, t + h, &mut st);
        assert_eq!(bits(fsal.y_new()), bits(&rk4));
        assert_eq!(bits(fsal.f_new().unwrap()), bits(&f_new));
        assert_eq!(err.to_bits(), reference_norm(&y, &rk4, &est, tol).to_bits());

        // Cash-Karp
        let (a, b4, b5) = (
            |i: usize, j: usize| CASH_KARP.a[i].num[j],
            CASH_KARP.b.num,
            match CASH_KARP.estimate {
                Estimate::Embedded { b_hat, .. } => b_hat.num,
                _ => unreachable!(),
            },
        );
        let mut k = [[0.0; 5]; 6];
        k[0] = f0;
        for s in 1..6 {
            for i in 0..5 {
                let mut acc = 0.0;
                for j in 0..s {
                    acc += a(s, j) * k[j][i];
                }
                tmp[i] = y[i] + h * acc;
            }
            Signed.rhs(t + CASH_KARP.c[s] * h, &tmp, &mut k[s]);
        }
        let (mut ck, mut est) = ([0.0; 5], [0.0; 5]);
        for i in 0..5 {
            let (mut d4, mut d5) = (0.0, 0.0);
            for s in 0..6 {
                d4 += b4[s] * k[s][i];
                d5 += b5[s] * k[s][i];
            }
            ck[i] = y[i] + h * d4;
            est[i] = h * (d5 - d4);
        }
        let mut cash_karp = ExplicitRk::adaptive(&CASH_KARP, 5, norm());
        let err = cash_karp.attempt_step(&mut Signed, t, &y, &f0, h, t + h, &mut st);
        assert_eq!(bits(cash_karp.y_new()), bits(&ck));
        assert_eq!(err.to_bits(), reference_norm(&y, &ck, &est, tol).to_bits());
        assert_eq!(
            ck[2].to_bits(),
            0.0f64.to_bits(),
            "the sum from +0 gives +0"
        );
    }
}
