//! Compact binary form of sampled data: little-endian f32, 4 bytes a sample.
//!
//! Channels and spectra are plotted, not re-integrated, so single precision (7 digits)
//! halves the storage at no visible cost.

pub fn encode_f32le(data: &[f64]) -> Vec<u8> {
    let mut out = Vec::with_capacity(data.len() * 4);
    for &x in data {
        out.extend_from_slice(&(x as f32).to_le_bytes());
    }
    out
}

pub fn decode_f32le(bytes: &[u8]) -> Vec<f64> {
    bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64)
        .collect()
}

/// Analysis inputs keep full precision: they are the measurement itself.
pub fn encode_f64le(data: &[f64]) -> Vec<u8> {
    data.iter().flat_map(|x| x.to_le_bytes()).collect()
}

pub fn decode_f64le(bytes: &[u8]) -> Vec<f64> {
    bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips() {
        let x = [0.0, -1.5, 0.25, 1e6];
        assert_eq!(decode_f32le(&encode_f32le(&x)), x.to_vec());
        let y = [std::f64::consts::PI, -1e-300];
        assert_eq!(decode_f64le(&encode_f64le(&y)), y.to_vec());
    }
}
