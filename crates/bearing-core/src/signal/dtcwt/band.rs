//! The frequency band a DTCWT level covers.

/// Nominal pass band of level `level` (1-based) for sample rate `fs`, Hz: `[fs/2^(k+1), fs/2^k]`.
pub fn nominal_band(level: usize, fs: f64) -> [f64; 2] {
    let hi = fs / 2f64.powi(level as i32);
    [hi / 2.0, hi]
}
