//! A block-diagonal approximation of the Jacobian `df/dy`, built by coloured finite
//! differences, and the factorisation of `I / (h gamma) - J` that a linearly implicit
//! step solves with.
//!
//! Why block-diagonal: when the stiff modes are local to one body (in the bearing, a ball
//! on its two race contacts, a ring on all its contacts, the cage on its film), the
//! diagonal blocks carry the eigenvalues that limit an explicit step, while a
//! Rosenbrock-W method stays consistent with any approximation of the Jacobian. Small
//! blocks (9 to 12 rows in the bearing) refactor after every step-size change in a few
//! microseconds; nothing here allocates after construction.

use std::ops::Range;

/// Storage and factors of a block-diagonal matrix.
pub struct BlockJacobian {
    blocks: Vec<Range<usize>>,
    /// Start of each block's dense, row-major entries in `jac` and `lu`.
    offsets: Vec<usize>,
    /// The Jacobian blocks, `d f_i / d y_j` for i, j in one block.
    jac: Vec<f64>,
    /// LU factors of `I / (h gamma) - J`, row-major, unit lower part implied.
    lu: Vec<f64>,
    /// Row permutation of each block's factorisation (indices local to the block).
    pivots: Vec<usize>,
    /// Block of every state component.
    block_of: Vec<usize>,
    /// Column groups perturbed together: no two columns of a group share a block, and no
    /// column of a group moves another group member's block rows.
    groups: Vec<Vec<usize>>,
    /// Scratch: perturbed state and derivative.
    y_work: Vec<f64>,
    f_work: Vec<f64>,
    step: Vec<f64>,
    /// Number of Jacobian evaluations and of factorisations.
    pub evaluations: u64,
    pub factorisations: u64,
    /// Per block: every entry is zero, so `I / (h gamma) - J` is `I / (h gamma)` there and
    /// neither factored nor solved with (a partial Jacobian, [`BlockJacobian::clear`]).
    zero: Vec<bool>,
    /// `h gamma` of the last factorisation.
    h_gamma: f64,
}

impl BlockJacobian {
    /// A matrix over `n = blocks.last().end` components with the given diagonal blocks
    /// (contiguous, in order) and column colouring; every column in a group.
    pub fn new(blocks: Vec<Range<usize>>, groups: Vec<Vec<usize>>) -> Self {
        Self::build(blocks, groups, true)
    }

    /// As [`BlockJacobian::new`], but only the columns in `groups` are evaluated: every
    /// other column stays zero, so a block none of whose columns is grouped is neither
    /// factored nor solved with. For a method implicit only in the part of the system
    /// where the stiffness is (a W-method keeps its order with any approximation).
    pub fn partial(blocks: Vec<Range<usize>>, groups: Vec<Vec<usize>>) -> Self {
        Self::build(blocks, groups, false)
    }

    fn build(blocks: Vec<Range<usize>>, groups: Vec<Vec<usize>>, complete: bool) -> Self {
        let n = blocks.last().map_or(0, |b| b.end);
        let mut offsets = Vec::with_capacity(blocks.len());
        let mut block_of = vec![0; n];
        let mut total = 0;
        let mut expect = 0;
        for (k, b) in blocks.iter().enumerate() {
            assert_eq!(b.start, expect, "blocks must be contiguous and ordered");
            expect = b.end;
            offsets.push(total);
            total += b.len() * b.len();
            for i in b.clone() {
                block_of[i] = k;
            }
        }
        for g in &groups {
            let mut seen: Vec<usize> = g.iter().map(|&c| block_of[c]).collect();
            seen.sort_unstable();
            seen.dedup();
            assert_eq!(
                seen.len(),
                g.len(),
                "a colour group has two columns in one block"
            );
        }
        let mut covered = vec![false; n];
        for &c in groups.iter().flatten() {
            assert!(!covered[c], "column {c} in two colour groups");
            covered[c] = true;
        }
        assert!(
            !complete || covered.iter().all(|&c| c),
            "every column needs a colour group"
        );
        let n_blocks = blocks.len();
        BlockJacobian {
            blocks,
            offsets,
            jac: vec![0.0; total],
            lu: vec![0.0; total],
            pivots: vec![0; n],
            block_of,
            groups,
            y_work: vec![0.0; n],
            f_work: vec![0.0; n],
            step: vec![0.0; n],
            evaluations: 0,
            factorisations: 0,
            zero: vec![false; n_blocks],
            h_gamma: f64::NAN,
        }
    }

    /// Number of right-hand sides one evaluation costs.
    pub fn cost_in_rhs(&self) -> usize {
        self.groups.len()
    }

    /// Forward differences of `rhs` at `(t, y)` with `f0 = f(t, y)`; `scale` gives each
    /// component's natural size, which sets its increment (sqrt(eps) relative).
    pub fn evaluate(
        &mut self,
        t: f64,
        y: &[f64],
        f0: &[f64],
        scale: &[f64],
        mut rhs: impl FnMut(f64, &[f64], &mut [f64]),
    ) {
        for gi in 0..self.groups.len() {
            self.y_work.copy_from_slice(y);
            for &c in &self.groups[gi] {
                (self.y_work[c], self.step[c]) = difference_step(y[c], scale[c]);
            }
            rhs(t, &self.y_work, &mut self.f_work);
            for &c in &self.groups[gi] {
                let k = self.block_of[c];
                let b = &self.blocks[k];
                let s = b.len();
                let col = c - b.start;
                let base = self.offsets[k];
                let inv = 1.0 / self.step[c];
                for (r, row) in b.clone().enumerate() {
                    self.jac[base + r * s + col] = (self.f_work[row] - f0[row]) * inv;
                }
            }
        }
        self.evaluations += 1;
    }

    /// Set every entry to zero, before filling in a partial Jacobian with
    /// [`BlockJacobian::set`].
    pub fn clear(&mut self) {
        self.jac.iter_mut().for_each(|v| *v = 0.0);
        self.evaluations += 1;
    }

    /// Set the entry `d f_row / d y_col`; both must lie in one block.
    pub fn set(&mut self, row: usize, col: usize, value: f64) {
        let k = self.block_of[row];
        assert_eq!(
            k, self.block_of[col],
            "entry ({row}, {col}) is off the blocks"
        );
        let b = &self.blocks[k];
        self.jac[self.offsets[k] + (row - b.start) * b.len() + (col - b.start)] = value;
    }

    /// Factor `I / (h gamma) - J` block by block (partial pivoting). Returns false when a
    /// block is singular.
    pub fn factor(&mut self, h_gamma: f64) -> bool {
        let d = 1.0 / h_gamma;
        self.factorisations += 1;
        self.h_gamma = h_gamma;
        for (k, b) in self.blocks.iter().enumerate() {
            let s = b.len();
            let base = self.offsets[k];
            self.zero[k] = self.jac[base..base + s * s].iter().all(|&v| v == 0.0);
            if self.zero[k] {
                continue;
            }
            let a = &mut self.lu[base..base + s * s];
            for (dst, src) in a.iter_mut().zip(&self.jac[base..base + s * s]) {
                *dst = -src;
            }
            for i in 0..s {
                a[i * s + i] += d;
            }
            let piv = &mut self.pivots[b.clone()];
            let factored = match s {
                6 => lu_in_place_of::<6>(a, piv),
                9 => lu_in_place_of::<9>(a, piv),
                _ => lu_in_place(a, s, piv),
            };
            if !factored {
                return false;
            }
        }
        true
    }

    /// Solve `(I / (h gamma) - J) x = rhs` in place with the last factorisation.
    pub fn solve(&self, x: &mut [f64]) {
        for (k, b) in self.blocks.iter().enumerate() {
            if self.zero[k] {
                x[b.clone()].iter_mut().for_each(|v| *v *= self.h_gamma);
                continue;
            }
            let s = b.len();
            let base = self.offsets[k];
            let (lu, piv, x) = (
                &self.lu[base..base + s * s],
                &self.pivots[b.clone()],
                &mut x[b.clone()],
            );
            match s {
                6 => lu_solve_of::<6>(lu, piv, x),
                9 => lu_solve_of::<9>(lu, piv, x),
                _ => lu_solve(lu, s, piv, x),
            }
        }
    }
}

/// A forward difference's perturbed value of a component `y` of natural size `scale`
/// (sqrt(eps) relative), and the increment actually represented in floating point.
pub fn difference_step(y: f64, scale: f64) -> (f64, f64) {
    let perturbed = y + f64::EPSILON.sqrt() * y.abs().max(scale);
    (perturbed, perturbed - y)
}

/// [`lu_in_place`] of an `N x N` block, `N` known when compiling: a ball's velocities (6,
/// the blocks of `auto_slip` and `slip_implicit`) or a whole ball (9, `rosenbrock_w`). The
/// same operations in the same order, so the same numbers to the bit; with the size known
/// the compiler can unroll the loops and drop their bounds checks. As generic loops the
/// factorisations and solves took a sixth of a Table-1 run's instructions, with the size
/// known half as many (callgrind, 2026-11-29, docs/lab/benchmarks.md).
fn lu_in_place_of<const N: usize>(a: &mut [f64], piv: &mut [usize]) -> bool {
    lu_in_place(&mut a[..N * N], N, &mut piv[..N])
}

/// [`lu_solve`] of an `N x N` block (see [`lu_in_place_of`]).
fn lu_solve_of<const N: usize>(lu: &[f64], piv: &[usize], x: &mut [f64]) {
    lu_solve(&lu[..N * N], N, &piv[..N], &mut x[..N])
}

/// LU factorisation with partial pivoting of the `s x s` row-major `a`, in place;
/// `piv[i]` is the row swapped with row i at step i.
#[inline(always)]
fn lu_in_place(a: &mut [f64], s: usize, piv: &mut [usize]) -> bool {
    for i in 0..s {
        let mut p = i;
        let mut best = a[i * s + i].abs();
        for r in i + 1..s {
            let v = a[r * s + i].abs();
            if v > best {
                best = v;
                p = r;
            }
        }
        if best == 0.0 || !best.is_finite() {
            return false;
        }
        piv[i] = p;
        if p != i {
            for c in 0..s {
                a.swap(i * s + c, p * s + c);
            }
        }
        let inv = 1.0 / a[i * s + i];
        for r in i + 1..s {
            let l = a[r * s + i] * inv;
            a[r * s + i] = l;
            if l != 0.0 {
                for c in i + 1..s {
                    a[r * s + c] -= l * a[i * s + c];
                }
            }
        }
    }
    true
}

#[inline(always)]
fn lu_solve(lu: &[f64], s: usize, piv: &[usize], x: &mut [f64]) {
    for (i, &p) in piv[..s].iter().enumerate() {
        x.swap(i, p);
    }
    for i in 0..s {
        let mut v = x[i];
        for c in 0..i {
            v -= lu[i * s + c] * x[c];
        }
        x[i] = v;
    }
    for i in (0..s).rev() {
        let mut v = x[i];
        for c in i + 1..s {
            v -= lu[i * s + c] * x[c];
        }
        x[i] = v / lu[i * s + i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A partial Jacobian: cleared, one entry set. The zero block solves as `h gamma x`
    /// without a factorisation; the other still inverts `I / (h gamma) - J`.
    #[test]
    fn a_cleared_block_solves_as_the_scaled_identity() {
        let mut j = BlockJacobian::new(vec![0..2, 2..4], vec![vec![0, 2], vec![1, 3]]);
        j.clear();
        j.set(2, 3, -5.0);
        let hg = 0.1;
        assert!(j.factor(hg));
        // the cleared block is marked and not factored
        assert_eq!(j.zero, [true, false]);
        assert!(j.lu[..4].iter().all(|&v| v == 0.0), "{:?}", &j.lu[..4]);
        let mut x = [1.0, 2.0, 3.0, 4.0];
        j.solve(&mut x);
        assert_eq!(&x[..2], &[0.1, 0.2]);
        // second block: [[10, 5], [0, 10]] u = [3, 4] -> u = [(3 - 5 * 0.4) / 10, 0.4]
        assert!(
            (x[3] - 0.4).abs() < 1e-15 && (x[2] - 0.1).abs() < 1e-15,
            "{x:?}"
        );
    }

    #[test]
    fn block_solve_inverts_the_shifted_matrix() {
        // Two blocks of a linear map f = J y; coloured FD is exact for a linear f up to
        // rounding, and the solve must give x with (I/(h g) - J) x = r.
        let j = [
            [-3.0, 1.0, 0.0, 0.0, 0.0],
            [2.0, -5.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, -1.0, 4.0, 0.5],
            [0.0, 0.0, 0.0, -2.0, 1.0],
            [0.0, 0.0, 7.0, 0.0, -9.0],
        ];
        let f = |_t: f64, y: &[f64], dy: &mut [f64]| {
            for r in 0..5 {
                dy[r] = (0..5).map(|c| j[r][c] * y[c]).sum();
            }
        };
        let mut bj = BlockJacobian::new(vec![0..2, 2..5], vec![vec![0, 2], vec![1, 3], vec![4]]);
        let y = [0.3, -0.2, 1.0, 0.5, -0.7];
        let mut f0 = [0.0; 5];
        f(0.0, &y, &mut f0);
        bj.evaluate(0.0, &y, &f0, &[1.0; 5], f);
        let hg = 0.1;
        assert!(bj.factor(hg));
        let r = [1.0, 2.0, -1.0, 0.5, 3.0];
        let mut x = r;
        bj.solve(&mut x);
        for row in 0..5 {
            let mut lhs = x[row] / hg;
            for c in 0..5 {
                lhs -= j[row][c] * x[c];
            }
            // forward differences of a linear map: exact to ~1e-8 relative (the
            // sqrt(eps) increment's rounding)
            assert!(
                (lhs - r[row]).abs() < 1e-6,
                "row {row}: {lhs} vs {}",
                r[row]
            );
        }
    }

    /// The fixed-size factorisation and solve give the generic loops' numbers to the bit,
    /// on 6 x 6 and 9 x 9 blocks whose pivots move rows (a small diagonal, large entries
    /// below it), so the runs that use them are the same runs. Today the fixed sizes call
    /// the same loops; this guards any hand-written form that replaces them.
    #[test]
    fn fixed_size_blocks_give_the_generic_numbers_to_the_bit() {
        fn check<const N: usize>() {
            let a: Vec<f64> = (0..N * N)
                .map(|k| {
                    let (r, c) = (k / N, k % N);
                    let v = ((r * 7 + c * 13) % 11) as f64 - 5.0 + 0.1 * (r as f64 - c as f64);
                    if r == c {
                        1e-3 * v
                    } else {
                        v
                    }
                })
                .collect();
            let (mut generic, mut fixed) = (a.clone(), a.clone());
            let (mut piv_g, mut piv_f) = (vec![0; N], vec![0; N]);
            assert!(lu_in_place(&mut generic, N, &mut piv_g));
            assert!(lu_in_place_of::<N>(&mut fixed, &mut piv_f));
            assert_eq!(piv_g, piv_f);
            assert!(
                piv_g.iter().enumerate().any(|(i, &p)| p != i),
                "no row moved"
            );
            assert!(generic
                .iter()
                .zip(&fixed)
                .all(|(g, f)| g.to_bits() == f.to_bits()));
            let r: Vec<f64> = (0..N).map(|i| 1.0 + i as f64 * 0.37).collect();
            let (mut x_g, mut x_f) = (r.clone(), r.clone());
            lu_solve(&generic, N, &piv_g, &mut x_g);
            lu_solve_of::<N>(&fixed, &piv_f, &mut x_f);
            assert!(x_g
                .iter()
                .zip(&x_f)
                .all(|(g, f)| g.to_bits() == f.to_bits()));
            // and it is a solve: A x = r to rounding. Partial pivoting is backward stable,
            // the residual a few times n eps of |A| |x| row by row; 1e-13 of it leaves room
            // for a growth factor of about 50 at n = 9
            for (i, want) in r.iter().enumerate() {
                let got: f64 = (0..N).map(|c| a[i * N + c] * x_f[c]).sum();
                let scale: f64 = (0..N).map(|c| (a[i * N + c] * x_f[c]).abs()).sum();
                assert!(
                    (got - want).abs() <= 1e-13 * scale,
                    "row {i}: {got} vs {want} (scale {scale})"
                );
            }
        }
        check::<6>();
        check::<9>();
    }

    /// A partial Jacobian evaluates only its grouped columns: a block without one stays
    /// zero (solved as `h gamma x`), and in a block with some, the other columns stay zero.
    #[test]
    fn a_partial_jacobian_evaluates_only_its_grouped_columns() {
        // f = J y with every entry nonzero inside the blocks
        let j = [
            [-3.0, 1.0, 0.0, 0.0],
            [2.0, -5.0, 0.0, 0.0],
            [0.0, 0.0, -1.0, 4.0],
            [0.0, 0.0, 6.0, -2.0],
        ];
        let f = |_t: f64, y: &[f64], dy: &mut [f64]| {
            for r in 0..4 {
                dy[r] = (0..4).map(|c| j[r][c] * y[c]).sum();
            }
        };
        let mut bj = BlockJacobian::partial(vec![0..2, 2..4], vec![vec![3]]);
        assert_eq!(bj.cost_in_rhs(), 1);
        let y = [0.3, -0.2, 1.0, 0.5];
        let mut f0 = [0.0; 4];
        f(0.0, &y, &mut f0);
        bj.evaluate(0.0, &y, &f0, &[1.0; 4], f);
        // column 3 only: rows 2 and 3 of block 2 (forward differences of a linear map,
        // ~1e-8 relative)
        assert_eq!(&bj.jac[..4], &[0.0; 4]);
        assert_eq!([bj.jac[4], bj.jac[6]], [0.0, 0.0]);
        assert!((bj.jac[5] - 4.0).abs() < 1e-6 && (bj.jac[7] + 2.0).abs() < 1e-6);
        assert!(bj.factor(0.1));
        assert_eq!(bj.zero, [true, false]);
    }
}
