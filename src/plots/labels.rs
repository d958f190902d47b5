//! How every chart words and places its text, the same as the lab page's plot.js: tick
//! numbers, marker labels, and label placement that never lets two labels overlap.

/// A number as the axes print it: four significant digits without trailing zeros, or one
/// decimal of an exponent outside [1e-3, 1e5) (plot.js: `fmt`).
pub fn tick_label(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    if !(1e-3..1e5).contains(&a) {
        return format!("{v:.1e}");
    }
    let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The name a characteristic line is printed with, from its API name (`bpfo` -> `BPFO`).
pub fn line_name(name: &str) -> String {
    match name {
        "bsf2" => "2BSF".into(),
        "shaft" => "shaft".into(),
        other => other.to_uppercase(),
    }
}

/// `BPFO`, `BPFO×2` (plot.js: `markerLabel`).
pub fn marker_label(name: &str, harmonic: usize) -> String {
    if harmonic > 1 {
        format!("{}×{harmonic}", line_name(name))
    } else {
        line_name(name)
    }
}

/// A text box in pixels: top-left corner, width, height.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextBox {
    pub x: f64,
    pub y: f64,
    pub w: f64,
    pub h: f64,
}

impl TextBox {
    fn overlaps(&self, o: &TextBox) -> bool {
        self.x < o.x + o.w && o.x < self.x + self.w && self.y < o.y + o.h && o.y < self.y + self.h
    }

    fn inside(&self, b: &TextBox) -> bool {
        self.x >= b.x
            && self.y >= b.y
            && self.x + self.w <= b.x + b.w
            && self.y + self.h <= b.y + b.h
    }
}

/// Width of `text` at `font` px, erring wide (DejaVu Sans, the widest common sans-serif:
/// capitals up to 0.79 em, digits 0.64, lower case about 0.6).
pub fn text_width(text: &str, font: f64) -> f64 {
    let em: f64 = text
        .chars()
        .map(|c| match c {
            ' ' => 0.33,
            'a'..='z' => {
                if "ilj".contains(c) {
                    0.3
                } else if "mw".contains(c) {
                    0.92
                } else {
                    0.62
                }
            }
            '0'..='9' | '.' | ',' | '+' | '-' => 0.64,
            'I' => 0.3,
            _ => 0.8,
        })
        .sum();
    em * font + 2.0
}

/// For each label (in priority order) the first candidate box inside `bounds` and clear of
/// every box placed before it, or `None`: that label is left out (plot.js: `placeLabels`).
pub fn place(candidates: &[Vec<TextBox>], bounds: TextBox) -> Vec<Option<TextBox>> {
    let mut taken: Vec<TextBox> = Vec::new();
    candidates
        .iter()
        .map(|cands| {
            let spot = cands
                .iter()
                .find(|c| c.inside(&bounds) && !taken.iter().any(|t| t.overlaps(c)))
                .copied();
            taken.extend(spot);
            spot
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_read_as_the_page_prints_them() {
        assert_eq!(tick_label(10.0), "10");
        assert_eq!(tick_label(5.0), "5");
        assert_eq!(tick_label(0.25), "0.25");
        assert_eq!(tick_label(1234.5678), "1235");
        assert_eq!(tick_label(-0.0015), "-0.0015");
        assert_eq!(tick_label(2.5e-5), "2.5e-5");
        assert_eq!(tick_label(120000.0), "1.2e5");
        assert_eq!(marker_label("bpfo", 1), "BPFO");
        assert_eq!(marker_label("bsf2", 3), "2BSF×3");
    }

    #[test]
    fn a_label_takes_the_next_free_candidate_or_none() {
        let b = |x, y| TextBox {
            x,
            y,
            w: 30.0,
            h: 10.0,
        };
        let bounds = TextBox {
            x: 0.0,
            y: 0.0,
            w: 100.0,
            h: 40.0,
        };
        let placed = place(
            &[
                vec![b(10.0, 0.0)],
                vec![b(20.0, 0.0), b(20.0, 12.0)],
                vec![b(15.0, 0.0), b(15.0, 12.0), b(90.0, 0.0)],
            ],
            bounds,
        );
        assert_eq!(placed[0], Some(b(10.0, 0.0)));
        assert_eq!(placed[1], Some(b(20.0, 12.0)));
        // both lanes are taken and the third candidate leaves the bounds
        assert_eq!(placed[2], None);
    }
}
