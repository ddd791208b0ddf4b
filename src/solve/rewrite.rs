//! The recipe text rewritten with the optimised numbers, comments kept.

use super::*;

/// A number as the recipe writes it: 6 decimals, trailing zeros dropped.
pub(super) fn fmt(x: f64) -> String {
    let s = format!("{x:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    let s = if s == "-0" { "0" } else { s };
    if s.contains('.') {
        s.to_string()
    } else {
        format!("{s}.0")
    }
}

pub(super) fn list(v: &[f64]) -> String {
    format!(
        "[{}]",
        v.iter().map(|x| fmt(*x)).collect::<Vec<_>>().join(", ")
    )
}

/// The recipe text with each slot's numbers replaced, everything else kept.
pub(super) fn rewrite(p: &Problem, d: &Design, source: &str, _x: &[f64]) -> String {
    let mut edits: Vec<(Range<usize>, String)> = Vec::new();
    let mut seed_text = None;
    for slot in &p.space.slots {
        match slot {
            Slot::Angle { rows, span } => {
                if let Some(Direction::Angles {
                    angle_deg,
                    tilt_deg,
                }) = d.rows[rows[0]].direction
                {
                    let text = if d.dim == 3 {
                        format!("[{}, {}]", fmt(angle_deg), fmt(tilt_deg))
                    } else {
                        fmt(angle_deg)
                    };
                    edits.push((span.clone(), text));
                }
            }
            Slot::Front { rows, span, .. } => {
                if let Some(f) = &d.rows[rows[0]].front {
                    edits.push((span.clone(), front_text(f)));
                }
            }
            Slot::Fit { angles, .. } => {
                if let Some(f) = &d.fit {
                    let (values, span, name) = if *angles {
                        (f.angles.as_ref(), f.spans.angles.clone(), "angles")
                    } else {
                        (f.steps.as_ref(), f.spans.steps.clone(), "steps")
                    };
                    let text = list(values.map_or(&[][..], |v| v.as_slice()));
                    match span {
                        Some(span) => edits.push((span, text)),
                        None => {
                            // A new line at the end of the [lattice.fit] table:
                            // before the next table header, after its last line.
                            let from = f.spans.table.end.min(source.len());
                            let next = source[from..]
                                .find("\n[")
                                .map_or(source.len(), |i| from + i);
                            let end = source[..next].trim_end().len();
                            edits.push((end..end, format!("\n{name} = {text}")));
                        }
                    }
                }
            }
            Slot::Seed | Slot::Rim { .. } => seed_text = Some(()),
        }
    }
    edits.sort_by_key(|e| std::cmp::Reverse(e.0.start));
    let mut out = source.to_string();
    for (range, text) in edits {
        out.replace_range(range, &text);
    }
    if seed_text.is_some() {
        // Seed spans are of the original text; the seed is rewritten first
        // when it comes after the rows, else re-parse to find it.
        if let Ok(again) = crate::design::parse(&out, &d.name)
            && let Some(t) = again.with_seed(&out, &d.points, &d.kappa)
        {
            out = t;
        }
    }
    out
}

/// `front = { ... }` as the recipe writes it.
pub(super) fn front_text(f: &FrontMoves) -> String {
    let mut parts = Vec::new();
    if let Some(t) = &f.turn {
        parts.push(format!("turn = {}", list(t)));
    }
    if let Some(b) = &f.bend {
        parts.push(format!("bend = {}", list(b)));
    }
    if let Some(t) = &f.twist {
        parts.push(format!("twist = {}", list(t)));
    }
    // Written to the last digit, not to `fmt`'s six decimals: it lays the
    // whole front, and rounded it would not grow the lattice that was tuned.
    if let Some(s) = f.saddle {
        parts.push(format!("saddle = [{:?}, {:?}]", s.c, s.d));
    }
    if !f.pivots.is_empty() {
        let p: Vec<String> = f
            .pivots
            .iter()
            .map(|p| match p.axis {
                Some(a) => format!(
                    "{{ at = {}, axis = {}, angle = {} }}",
                    p.at,
                    list(&a.to_array()),
                    fmt(p.angle_deg)
                ),
                None => format!("{{ at = {}, angle = {} }}", p.at, fmt(p.angle_deg)),
            })
            .collect();
        parts.push(format!("pivot = [{}]", p.join(", ")));
    }
    if !f.cranks.is_empty() {
        let c: Vec<String> = f
            .cranks
            .iter()
            .map(|c| {
                format!(
                    "{{ from = {}, to = {}, angle = {} }}",
                    c.from,
                    c.to,
                    fmt(c.angle_deg)
                )
            })
            .collect();
        parts.push(format!("crank = [{}]", c.join(", ")));
    }
    format!("{{ {} }}", parts.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::Saddle;

    /// A saddle front rewritten by `tune` keeps its amplitudes exactly,
    /// beside its angles.
    #[test]
    fn a_saddle_front_is_written_back_whole() {
        let f = FrontMoves {
            saddle: Some(Saddle {
                c: 0.003435384253332836,
                d: -8.349061163664547e-6,
            }),
            pivots: vec![crate::lattice::PivotMove {
                at: 0,
                axis: None,
                angle_deg: 2.5,
            }],
            ..FrontMoves::default()
        };
        let text = front_text(&f);
        assert!(
            text.contains("saddle = [0.003435384253332836, -8.349061163664547e-6]"),
            "{text}"
        );
        let parsed: toml::Value = toml::from_str(&format!("front = {text}")).expect(&text);
        let amplitudes = parsed["front"]["saddle"].as_array().expect("saddle");
        assert_eq!(amplitudes[1].as_float(), Some(-8.349061163664547e-6));
    }
}
