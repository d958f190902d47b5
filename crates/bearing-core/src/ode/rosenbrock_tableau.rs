//! The Rosenbrock-W method ROS34PW2 (Rang and Angermann, BIT Numer. Math. 45, 2005, not
//! read; the coefficients are PETSc's `TSROSWRA34PW2` table, read) as data: its coefficients
//! and their form in the transformed variables the stepper ([`super::rosenbrock`]) works in.

// the tableau keeps the digits as published
#![allow(clippy::excessive_precision)]
// the transformation indexes rows and columns as the matrix formulas do
#![allow(clippy::needless_range_loop)]

/// Stages.
pub const S: usize = 4;
const GAMMA: f64 = 4.358_665_215_084_590_0e-1;
// Propagation table A (strictly lower), stage table Gamma (lower, GAMMA on the diagonal),
// completion weights b and embedded weights b2, as published.
const A: [[f64; S]; S] = [
    [0.0; S],
    [8.717_330_430_169_180_1e-1, 0.0, 0.0, 0.0],
    [
        8.445_706_001_536_942_3e-1,
        -1.129_906_423_648_418_5e-1,
        0.0,
        0.0,
    ],
    [0.0, 0.0, 1.0, 0.0],
];
const G: [[f64; S]; S] = [
    [GAMMA, 0.0, 0.0, 0.0],
    [-8.717_330_430_169_180_1e-1, GAMMA, 0.0, 0.0],
    [
        -9.033_805_701_304_408_2e-1,
        5.418_067_238_809_532_6e-2,
        GAMMA,
        0.0,
    ],
    [
        2.421_238_070_609_534_6e-1,
        -1.223_250_583_904_514_7,
        5.452_602_553_351_021_4e-1,
        GAMMA,
    ],
];
const B: [f64; S] = [
    2.421_238_070_609_534_6e-1,
    -1.223_250_583_904_514_7,
    1.545_260_255_335_102_0,
    GAMMA,
];
const B2: [f64; S] = [
    3.781_090_314_581_936_9e-1,
    -9.604_229_221_242_317_8e-2,
    0.5,
    2.179_332_607_542_295_0e-1,
];

/// The tableau in transformed variables.
#[derive(Debug, Clone, Copy)]
pub struct Tableau {
    /// The diagonal of Gamma.
    pub gamma: f64,
    /// Stage abscissae, row sums of A.
    pub alpha: [f64; S],
    /// `A Gamma^-1`, strictly lower.
    pub a: [[f64; S]; S],
    /// `diag(1/gamma) - Gamma^-1`, strictly lower.
    pub c: [[f64; S]; S],
    /// `b Gamma^-1`.
    pub m: [f64; S],
    /// `(b - b2) Gamma^-1`: the error estimate's weights.
    pub e: [f64; S],
}

impl Tableau {
    pub fn ros34pw2() -> Tableau {
        // inverse of the lower-triangular Gamma by forward substitution
        let mut gi = [[0.0; S]; S];
        for col in 0..S {
            for row in col..S {
                let mut v = if row == col { 1.0 } else { 0.0 };
                for k in col..row {
                    v -= G[row][k] * gi[k][col];
                }
                gi[row][col] = v / G[row][row];
            }
        }
        let mut t = Tableau {
            gamma: GAMMA,
            alpha: [0.0; S],
            a: [[0.0; S]; S],
            c: [[0.0; S]; S],
            m: [0.0; S],
            e: [0.0; S],
        };
        for i in 0..S {
            t.alpha[i] = A[i].iter().sum();
            for j in 0..S {
                t.a[i][j] = (0..S).map(|k| A[i][k] * gi[k][j]).sum();
                if j < i {
                    t.c[i][j] = -gi[i][j];
                }
            }
            t.m[i] = (0..S).map(|k| B[k] * gi[k][i]).sum();
            t.e[i] = (0..S).map(|k| (B[k] - B2[k]) * gi[k][i]).sum();
        }
        t
    }
}
