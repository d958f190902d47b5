//! The verdict in one plain sentence, for a person reading a result: what is indicated, how
//! sure (the probability next to the rate it is compared with) and on which lines.

use super::verdict::{FaultEvidence, FaultType, Verdict};

/// Plain name of a fault type, lower case.
pub fn fault_name(f: FaultType) -> &'static str {
    match f {
        FaultType::OuterRace => "outer race",
        FaultType::InnerRace => "inner race",
        FaultType::RollingElement => "rolling element",
        FaultType::Cage => "cage",
    }
}

/// A probability in two significant digits at most: `1e-8`, `0.0013`, `0.2`.
pub fn format_p(p: f64) -> String {
    if p >= 1e-3 {
        let s = format!("{p:.2}");
        if p >= 0.01 {
            return trim(s);
        }
        return trim(format!("{p:.4}"));
    }
    let e = p.log10().floor();
    let m = p / 10f64.powf(e);
    let m = (m * 10.0).round() / 10.0;
    if (m - 1.0).abs() < 0.05 {
        format!("1e{}", e as i32)
    } else {
        format!("{}e{}", trim(format!("{m:.1}")), e as i32)
    }
}

fn trim(s: String) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_uppercase().collect::<String>() + c.as_str(),
        None => String::new(),
    }
}

/// The lines of one fault type's evidence: `BPFI 161.7 Hz, -0.3 % from 162.2 Hz, 4 of 4
/// harmonics, shaft sidebands`.
fn lines_clause(e: &FaultEvidence) -> String {
    let name = e.fault.line_name();
    let mut s = match (e.fundamental_hz, e.error_pct) {
        (Some(f), Some(err)) => {
            let theory = f / (1.0 + err / 100.0);
            format!("{name} {f:.1} Hz, {err:+.1} % from {theory:.1} Hz")
        }
        _ => format!("no {name} line in the search band"),
    };
    s += &format!(
        ", {} of {} harmonics",
        e.harmonics_found, e.harmonics_searched
    );
    let harmonics = || e.lines.iter().filter(|l| l.order == 0);
    let unresolved: Vec<String> = harmonics()
        .filter_map(|l| {
            l.unresolved_shaft_order
                .map(|k| format!("{}x{name} at shaft order {k}", l.harmonic))
        })
        .collect();
    if !unresolved.is_empty() {
        s += &format!(" ({} not resolved, left out)", unresolved.join(", "));
    }
    // harmonics where a line goes to a fault type accepted before: per type, in order
    for f in FaultType::ALL {
        let shared: Vec<String> = harmonics()
            .filter(|l| l.unresolved_shaft_order.is_none() && l.shared_with == Some(f))
            .map(|l| format!("{}x{name}", l.harmonic))
            .collect();
        if !shared.is_empty() {
            s += &format!(
                " ({} on the {}'s lines, left out)",
                shared.join(" and "),
                fault_name(f)
            );
        }
    }
    if e.sidebands_found > 0 {
        s += match e.fault {
            FaultType::RollingElement => ", cage sidebands",
            _ => ", shaft sidebands",
        };
    }
    s += &format!(" ({})", e.spectrum);
    s
}

/// The verdict's sentence. Names every indicated type with its probability against the
/// false-alarm rate and its lines; with none indicated, the closest type and why it falls short.
pub fn summary(v: &Verdict) -> String {
    let rate = format_p(v.false_alarm_rate);
    let named: Vec<&FaultEvidence> = v
        .faults
        .iter()
        .filter_map(|f| v.evidence.iter().find(|e| e.fault == *f))
        .collect();
    if named.is_empty() {
        let closest = v
            .evidence
            .iter()
            .min_by(|a, b| a.p_value.total_cmp(&b.p_value));
        return match closest {
            Some(e) => match e.impulsiveness {
                Some(i) if e.p_value < v.false_alarm_rate && !i.impulsive(v.false_alarm_rate) => {
                    format!(
                        "No fault indicated (closest: {}, p = {} < {rate}, but on a signal that is not impulsive: kurtosis {:.1}, p = {} >= {rate}; a defect strikes, a smooth line is the bearing's varying compliance: {})",
                        fault_name(e.fault),
                        format_p(e.p_value),
                        i.kurtosis,
                        format_p(i.p_value),
                        lines_clause(e)
                    )
                }
                _ => format!(
                    "No fault indicated (closest: {}, p = {} >= {rate}: {})",
                    fault_name(e.fault),
                    format_p(e.p_value),
                    lines_clause(e)
                ),
            },
            None => format!("No fault indicated (rate {rate})"),
        };
    }
    let types: Vec<&str> = named.iter().map(|e| fault_name(e.fault)).collect();
    let head = if types.len() == 1 {
        format!("{} fault indicated", capitalise(types[0]))
    } else {
        let (last, rest) = types.split_last().expect("two or more");
        format!(
            "{} and {last} faults indicated",
            capitalise(&rest.join(", "))
        )
    };
    if named.len() == 1 {
        let e = named[0];
        return format!(
            "{head} (p = {} < {rate}): {}",
            format_p(e.p_value),
            lines_clause(e)
        );
    }
    let parts: Vec<String> = named
        .iter()
        .map(|e| {
            format!(
                "{} (p = {} < {rate}): {}",
                fault_name(e.fault),
                format_p(e.p_value),
                lines_clause(e)
            )
        })
        .collect();
    format!("{head}: {}", parts.join("; "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probabilities_read_plainly() {
        assert_eq!(format_p(1.02e-8), "1e-8");
        assert_eq!(format_p(2.6e-5), "2.6e-5");
        assert_eq!(format_p(0.0013), "0.0013");
        assert_eq!(format_p(0.001), "0.001");
        assert_eq!(format_p(0.2), "0.2");
        assert_eq!(format_p(1.0), "1");
    }
}
