//! Where a ball-race contact's traction is sampled across the contact ellipse, and what
//! share of the normal load each sample carries (eq. 13).
//!
//! Eq. 13 spreads the normal load over the major axis as `(1 - x^2/a^2)` and sums the
//! strip tractions: a quadrature of `integral mu(x) (1 - x^2) dx` over `-1..1`. The
//! paper's form is a Riemann sum over equal strips, and on the Table-1 case 10 strips
//! still leave the mean cage speed 0.016 % and the band RMS below 20 kHz 11.5 % from the
//! converged integral (docs/reference/model.md, "Traction quadrature"). Gauss quadrature with the
//! weight `1 - x^2` (Gauss-Jacobi, alpha = beta = 1) converges faster: the integrand has
//! kinks (where the slip passes through zero, and at the slip regularisation), so not
//! spectrally, but the balls' traction moments are 0.14 % from converged with 10 nodes
//! against 1.7 % with 10 equal strips.

/// How the traction samples are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StripRule {
    /// Gauss-Jacobi nodes and weights for the weight `1 - x^2` (exact for polynomials of
    /// degree `2n - 1`).
    Gauss,
    /// The centres of `n` equal strips, weighted `1 - x^2` there (eq. 13 as printed).
    Equal,
}

/// Traction samples across the contact ellipse's major axis (eq. 13 uses m per
/// semi-axis; this is the total): their positions as fractions of the semi-axis, and
/// their shares of the normal load, summing to 1. Both depend only on the count and the
/// rule, so they are computed once per model.
///
/// The samples sit in mirror pairs about the ellipse's centre (`xi[n-1-i] == -xi[i]` and
/// equal weights, to the bit), so a pair shares what depends on `|xi|` alone: the strip's
/// distance from the ball centre and, under the rheology law, its pressure and film.
#[derive(Debug, Clone, PartialEq)]
pub struct Strips {
    /// Sample positions, -1..1 of the semi-major axis, ascending.
    pub xi: Vec<f64>,
    /// Load shares, summing to 1.
    pub weight: Vec<f64>,
    /// The mirror pairs, from the outermost in; with an odd count the last is the centre
    /// sample alone.
    pub pairs: Vec<StripPair>,
}

/// Two samples at `-xi` and `+xi`, or the centre sample alone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StripPair {
    /// Position of the sample at `+xi` (>= 0), fraction of the semi-major axis.
    pub xi: f64,
    /// The strip's half-chord along the rolling direction over the centre strip's,
    /// `sqrt(1 - xi^2)`.
    pub chord: f64,
    /// Load share of the sample at `-xi`: zero for the centre sample, which has no twin.
    pub weight_minus: f64,
    /// Load share of the sample at `+xi`.
    pub weight_plus: f64,
    /// Length of the sample's cell, fraction of the semi-major axis: centred on the sample,
    /// as long as the larger of its gaps to the neighbours (or twice its distance to the
    /// ellipse's edge), so it reaches past both midpoints: the cells overlap a little and
    /// leave no gap. Centred, so a law linear in slip has
    /// its point value as its cell mean (the rule keeps Gauss's exactness there); without
    /// gaps, so the traction has no flat step where the zero slip falls between two cells.
    pub cell: f64,
}

impl Strips {
    /// `n` samples (at least one) placed by `rule`.
    pub fn new(n: usize, rule: StripRule) -> Strips {
        let n = n.max(1);
        let (mut xi, mut weight) = match rule {
            StripRule::Equal => Strips::equal(n),
            StripRule::Gauss => Strips::gauss_jacobi(n),
        };
        // Both rules are symmetric in exact arithmetic; the eigen-solver and the strip
        // centres' sums leave the mirror samples a few ulp apart. Averaging makes them
        // mirror to the bit, so a pair can share its `|xi|` terms.
        for i in 0..n / 2 {
            let j = n - 1 - i;
            let x = 0.5 * (xi[j] - xi[i]);
            let w = 0.5 * (weight[i] + weight[j]);
            (xi[i], xi[j], weight[i], weight[j]) = (-x, x, w, w);
        }
        if n % 2 == 1 {
            xi[n / 2] = 0.0;
        }
        let pairs = (0..n.div_ceil(2))
            .map(|i| {
                let j = n - 1 - i;
                StripPair {
                    xi: xi[j],
                    chord: (1.0 - xi[j] * xi[j]).max(0.0).sqrt(),
                    weight_minus: if i == j { 0.0 } else { weight[i] },
                    weight_plus: weight[j],
                    cell: {
                        // to the edge and back, where there is no neighbour
                        let edge = 2.0 * (1.0 - xi[j].abs());
                        let left = if j > 0 { xi[j] - xi[j - 1] } else { edge };
                        let right = if j + 1 < n { xi[j + 1] - xi[j] } else { edge };
                        left.max(right)
                    },
                }
            })
            .collect();
        Strips { xi, weight, pairs }
    }

    fn equal(n: usize) -> (Vec<f64>, Vec<f64>) {
        let xi: Vec<f64> = (0..n)
            .map(|i| -1.0 + (i as f64 + 0.5) * 2.0 / n as f64)
            .collect();
        let raw: Vec<f64> = xi.iter().map(|x| 1.0 - x * x).collect();
        let sum: f64 = raw.iter().sum();
        (xi, raw.iter().map(|w| w / sum).collect())
    }

    /// The Golub-Welsch method (docs/reference/model.md says where it was read): the nodes
    /// are the eigenvalues of the symmetric tridiagonal Jacobi matrix of the orthogonal
    /// polynomials for the weight,
    /// and each weight is the total mass times the square of its eigenvector's first
    /// component. For `1 - x^2` (Gegenbauer, lambda = 3/2) the monic recurrence has zero
    /// diagonal and `beta_k = k (k + 2) / ((2k + 1)(2k + 3))`.
    fn gauss_jacobi(n: usize) -> (Vec<f64>, Vec<f64>) {
        let mut t = nalgebra::DMatrix::<f64>::zeros(n, n);
        for k in 1..n {
            let kf = k as f64;
            let b = (kf * (kf + 2.0) / ((2.0 * kf + 1.0) * (2.0 * kf + 3.0))).sqrt();
            t[(k, k - 1)] = b;
            t[(k - 1, k)] = b;
        }
        let eig = t.symmetric_eigen();
        let mut nodes: Vec<(f64, f64)> = (0..n)
            .map(|i| (eig.eigenvalues[i], eig.eigenvectors[(0, i)].powi(2)))
            .collect();
        nodes.sort_by(|a, b| a.0.total_cmp(&b.0));
        let sum: f64 = nodes.iter().map(|p| p.1).sum();
        (
            nodes.iter().map(|p| p.0).collect(),
            nodes.iter().map(|p| p.1 / sum).collect(),
        )
    }

    pub fn len(&self) -> usize {
        self.xi.len()
    }

    pub fn is_empty(&self) -> bool {
        self.xi.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `integral x^k (1 - x^2) dx / integral (1 - x^2) dx` over -1..1: zero for odd k,
    /// `3 / ((k + 1)(k + 3))` for even k.
    fn moment(k: u32) -> f64 {
        if k % 2 == 1 {
            0.0
        } else {
            3.0 / ((k as f64 + 1.0) * (k as f64 + 3.0))
        }
    }

    fn apply(s: &Strips, f: impl Fn(f64) -> f64) -> f64 {
        s.xi.iter().zip(&s.weight).map(|(&x, &w)| w * f(x)).sum()
    }

    /// Gauss with n nodes integrates every polynomial of degree up to 2n - 1 exactly
    /// against `1 - x^2` (to rounding: 1e-13 leaves room for the eigen-solver's
    /// ~1e-15 per node at n = 40), and misses degree 2n, where the equal strips miss
    /// already degree 2.
    #[test]
    fn gauss_nodes_are_exact_to_degree_2n_minus_1() {
        for n in [1usize, 2, 3, 4, 7, 10, 40] {
            let s = Strips::new(n, StripRule::Gauss);
            assert_eq!(s.len(), n);
            assert!((s.weight.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            assert!(s.xi.windows(2).all(|p| p[0] < p[1]) && s.xi[0] > -1.0);
            for k in 0..2 * n as u32 {
                let got = apply(&s, |x| x.powi(k as i32));
                assert!((got - moment(k)).abs() < 1e-13, "n {n} x^{k}: {got}");
            }
            if n <= 10 {
                // the first degree a rule of n nodes misses (6e-7 at n = 10)
                let k = 2 * n as u32;
                let miss = apply(&s, |x| x.powi(k as i32)) - moment(k);
                assert!(miss.abs() > 1e-10, "n {n} x^{k} exact by chance: {miss}");
            }
        }
        // two nodes: the roots of P3' = (15 x^2 - 3) / 2, equal weights
        let s = Strips::new(2, StripRule::Gauss);
        assert!((s.xi[1] - 0.2f64.sqrt()).abs() < 1e-15 && (s.weight[0] - 0.5).abs() < 1e-15);
        let e = Strips::new(10, StripRule::Equal);
        assert!((apply(&e, |x| x * x) - moment(2)).abs() > 1e-3);
    }

    /// The samples mirror to the bit, and the pairs list each sample once with its weight.
    #[test]
    fn samples_come_in_exact_mirror_pairs() {
        for rule in [StripRule::Gauss, StripRule::Equal] {
            for n in [1usize, 2, 5, 10, 11, 40, 200] {
                let s = Strips::new(n, rule);
                for i in 0..n {
                    assert_eq!(s.xi[n - 1 - i], -s.xi[i], "{rule:?} {n}: xi {i}");
                    assert_eq!(s.weight[n - 1 - i], s.weight[i], "{rule:?} {n}: weight {i}");
                }
                assert_eq!(s.pairs.len(), n.div_ceil(2));
                let total: f64 = s.pairs.iter().map(|p| p.weight_minus + p.weight_plus).sum();
                assert!((total - 1.0).abs() < 1e-14, "{rule:?} {n}: {total}");
                for (i, p) in s.pairs.iter().enumerate() {
                    assert_eq!(
                        (p.xi, p.weight_plus),
                        (s.xi[n - 1 - i], s.weight[n - 1 - i])
                    );
                    assert!(p.xi >= 0.0 && (p.chord * p.chord + p.xi * p.xi - 1.0).abs() < 1e-15);
                }
                if n % 2 == 1 {
                    assert_eq!(s.pairs[n / 2].weight_minus, 0.0);
                }
            }
        }
    }

    /// Each sample's cell is centred on it and reaches both neighbouring samples' midpoints
    /// (so the cells leave no gap anywhere in -1..1), and no cell is more than twice as long
    /// as the gaps it must span.
    #[test]
    fn cells_are_centred_and_leave_no_gap() {
        for rule in [StripRule::Gauss, StripRule::Equal] {
            for n in [1usize, 2, 5, 10, 11, 40] {
                let s = Strips::new(n, rule);
                let mut cells: Vec<(f64, f64)> = s
                    .pairs
                    .iter()
                    .flat_map(|p| [(-p.xi, p.cell), (p.xi, p.cell)])
                    .collect();
                cells.sort_by(|a, b| a.0.total_cmp(&b.0));
                cells.dedup();
                assert_eq!(cells.len(), n, "{rule:?} {n}");
                assert!(
                    cells[0].0 - 0.5 * cells[0].1 <= -1.0 + 1e-15,
                    "{rule:?} {n}: left edge"
                );
                assert!(
                    cells[n - 1].0 + 0.5 * cells[n - 1].1 >= 1.0 - 1e-15,
                    "{rule:?} {n}: right edge"
                );
                for w in cells.windows(2) {
                    let ((x0, c0), (x1, c1)) = (w[0], w[1]);
                    let mid = 0.5 * (x0 + x1);
                    assert!(
                        x0 + 0.5 * c0 >= mid && x1 - 0.5 * c1 <= mid,
                        "{rule:?} {n}: gap at {mid}"
                    );
                    assert!(
                        c0 <= 2.0 * (x1 - x0).max(2.0 * (1.0 - x0.abs())),
                        "{rule:?} {n}"
                    );
                }
            }
        }
    }
}
