//! The steady window of a run: chosen once, here, for the summary's averages and for the
//! analysis of the simulated signal.

/// Shortest window worth averaging over or analysing, s (a few shaft turns at spindle speeds).
pub const MIN_WINDOW: f64 = 0.005;

/// `[start, end]` (s) of the steady part of a run `duration` s long whose speed ramp lasts
/// `ramp` s: after the ramp plus a settling time of a quarter of the rest, at most 0.1 s (the
/// start-up transient of the cage and the pedestal dies out within ~40 ms for the H7005C at
/// 10000 rpm). A run that ends before its speed settles, or leaves less than
/// [`MIN_WINDOW`], is averaged and analysed over its second half instead.
pub fn steady_window(ramp: f64, duration: f64) -> [f64; 2] {
    let settle = (0.25 * (duration - ramp)).min(0.1);
    let start = ramp + settle;
    if start < duration && duration - start >= MIN_WINDOW {
        [start, duration]
    } else {
        [0.5 * duration, duration]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn after_the_ramp_and_its_transient() {
        // Table 1: 0.1 s ramp, 0.5 s run -> settle min(0.1, 0.1) = 0.1 s
        assert_eq!(steady_window(0.1, 0.5), [0.2, 0.5]);
        // constant speed, 60 ms: a quarter of the run settles
        assert_eq!(steady_window(0.0, 0.06), [0.015, 0.06]);
    }

    #[test]
    fn second_half_when_the_speed_never_settles_or_too_little_is_left() {
        assert_eq!(steady_window(0.1, 0.02), [0.01, 0.02]);
        // 6 ms after the ramp leaves 4.5 ms once settled: below MIN_WINDOW
        assert_eq!(steady_window(0.1, 0.106), [0.053, 0.106]);
    }
}
