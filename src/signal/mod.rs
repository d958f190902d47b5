//! Vibration analysis: characteristic frequencies, envelope spectra, DTCWT, identification.
