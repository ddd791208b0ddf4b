//! The optimiser's variables: which recipe numbers `[optimise] vary`
//! frees, and where they start.

use super::*;

/// One unit of a saddle amplitude (1/mm), as one degree is of an angle:
/// the search's steps are in units (`optimise.step`, 3 by default). It
/// lifts a front of radius 60 mm (examples/saddle-ring.toml's seed) by
/// r^2 x 1e-4 = 0.36 mm at its rim, about what one degree of a row's leg
/// angle moves the end of that recipe's shortest leg (21.8 mm: 0.38 mm).
pub(super) const SADDLE_UNIT: f64 = 1e-4;

/// Build the variables of `design` as its `[optimise]` table frees them.
pub(super) fn slots(
    design: &Design,
    source: &str,
    opt: &Optimise,
) -> (Vec<Slot>, Vec<f64>, Vec<f64>) {
    let mut slots: Vec<Slot> = Vec::new();
    let (mut x0, mut unit) = (Vec::new(), Vec::new());
    let group = |span: Range<usize>, row: usize, kind: u8, slots: &mut Vec<Slot>| -> bool {
        for s in slots.iter_mut() {
            match s {
                Slot::Angle { rows, span: sp } if kind == 0 && *sp == span => {
                    rows.push(row);
                    return false;
                }
                Slot::Front { rows, span: sp, .. } if kind == 1 && *sp == span => {
                    rows.push(row);
                    return false;
                }
                _ => {}
            }
        }
        true
    };
    for (i, row) in design.rows.iter().enumerate() {
        if opt.vary.contains(&Vary::Angle)
            && let Some(Direction::Angles {
                angle_deg,
                tilt_deg,
            }) = row.direction
        {
            let span = design.row_direction_span(i);
            let written = source.get(span.clone()).unwrap_or("");
            if written.trim_start().starts_with([
                '[', '-', '+', '0', '1', '2', '3', '4', '5', '6', '7', '8', '9',
            ]) && group(span.clone(), i, 0, &mut slots)
            {
                slots.push(Slot::Angle {
                    rows: vec![i],
                    span,
                });
                x0.push(angle_deg);
                unit.push(1.0);
                if design.dim == 3 {
                    x0.push(tilt_deg);
                    unit.push(1.0);
                }
            }
        }
        if opt.vary.contains(&Vary::Front)
            && let Some(f) = &row.front
        {
            let span = design.row_front_span(i);
            if source
                .get(span.clone())
                .is_some_and(|t| t.trim_start().starts_with('{'))
                && group(span.clone(), i, 1, &mut slots)
            {
                let mut magnitudes: Vec<f64> = Vec::new();
                map_front(&mut f.clone(), |a| {
                    if !magnitudes.iter().any(|m| (m - a.abs()).abs() < 1e-9) {
                        magnitudes.push(a.abs());
                    }
                    a
                });
                x0.extend(&magnitudes);
                unit.extend(std::iter::repeat_n(1.0, magnitudes.len()));
                if let Some(s) = f.saddle {
                    x0.extend([s.c, s.d]);
                    unit.extend([SADDLE_UNIT; 2]);
                }
                slots.push(Slot::Front {
                    rows: vec![i],
                    span,
                    magnitudes,
                    saddle: f.saddle.is_some(),
                });
            }
        }
    }
    if opt.vary.contains(&Vary::Fit)
        && let Some(fit) = &design.fit
    {
        if let Some(a) = fit
            .angles
            .clone()
            .or_else(|| fit::searched_angles(design, fit))
        {
            unit.extend(std::iter::repeat_n(1.0, a.len()));
            slots.push(Slot::Fit {
                angles: true,
                rows: a.len(),
            });
            x0.extend(a);
        } else if let Some(s) = fit.steps.clone().or_else(|| default_steps(design)) {
            unit.extend(std::iter::repeat_n(1.0, s.len()));
            slots.push(Slot::Fit {
                angles: false,
                rows: s.len(),
            });
            x0.extend(s);
        }
    }
    if opt.vary.contains(&Vary::Seed) && design.kind == Kind::Helix {
        slots.push(Slot::Seed);
    }
    // A disk's seed stays on its circle (its points are boundary
    // vertices): the points move along it, and each edge's kappa.
    if opt.vary.contains(&Vary::Seed)
        && design.kind == Kind::Sheet
        && let Some(fit) = &design.fit
        && let crate::design::fit::Surface::Disk { radius } = fit.surface
    {
        let n = design.points.len();
        x0.extend(design.points.iter().map(|p| p.y.atan2(p.x).to_degrees()));
        x0.extend(&design.kappa);
        unit.extend(std::iter::repeat_n(1.0, 2 * n - 1));
        slots.push(Slot::Rim { radius, points: n });
    }
    (slots, x0, unit)
}

/// An ellipsoid loop's ring steps as grown by default: one front edge each.
pub(super) fn default_steps(design: &Design) -> Option<Vec<f64>> {
    let fit = design.fit.as_ref()?;
    if design.kind != Kind::Loop
        || !matches!(fit.surface, crate::design::fit::Surface::Ellipsoid { .. })
    {
        return None;
    }
    let lattice = design.grow().ok()?;
    let n = lattice.width;
    Some(
        (0..fit.rows)
            .map(|i| {
                lattice.vertices[i * n]
                    .pos
                    .distance(lattice.vertices[i * n + 1].pos)
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two rows from one entry (`repeat = 2`: one written front) and a row
    /// of its own whose saddle a pivot follows.
    const RECIPE: &str = r#"
name = "saddle-slots"
[lattice]
seed = "loop"
kappa = 0.0
[lattice.circle]
center = [0.0, 0.0, 0.0]
radius = 60.0
points = 12
[[lattice.rows]]
repeat = 2
angle = [44.0, 23.57]
front = { saddle = [0.0005, 0.0] }
[[lattice.rows]]
angle = [44.0, 23.57]
front = { saddle = [0.0015, -0.0002], pivot = [{ at = 3, angle = 2.0 }] }
[optimise]
vary = ["front"]
"#;

    /// A saddle's amplitudes are variables of one `SADDLE_UNIT` each, after
    /// its front's angles; rows written by one entry share them, and the
    /// design at a point carries them to every such row.
    #[test]
    fn a_saddle_front_varies_its_amplitudes() {
        let design = crate::design::parse(RECIPE, "saddle-slots").expect("parses");
        let opt = design.optimise.as_ref().expect("[optimise]");
        let (slots, x0, unit) = slots(&design, RECIPE, opt);
        let fronts: Vec<(Vec<usize>, usize, bool)> = slots
            .iter()
            .map(|s| match s {
                Slot::Front {
                    rows,
                    magnitudes,
                    saddle,
                    ..
                } => (rows.clone(), magnitudes.len(), *saddle),
                other => panic!("only fronts vary: {other:?}"),
            })
            .collect();
        assert_eq!(fronts, vec![(vec![0, 1], 0, true), (vec![2], 1, true)]);
        assert_eq!(x0, vec![0.0005, 0.0, 2.0, 0.0015, -0.0002]);
        assert_eq!(
            unit,
            vec![SADDLE_UNIT, SADDLE_UNIT, 1.0, SADDLE_UNIT, SADDLE_UNIT]
        );
        let space = Space {
            design: &design,
            opt,
            slots,
            x0,
            unit,
            frame: None,
            seed0: None,
        };
        let d = space.design_at(&[1.0, -2.0, 0.5, 3.0, 0.0]);
        let front = |r: usize| d.rows[r].front.clone().expect("a front");
        for r in [0, 1] {
            let s = front(r).saddle.expect("a saddle");
            assert!((s.c - 0.0006).abs() < 1e-15, "row {r}: {s:?}");
            assert!((s.d + 0.0002).abs() < 1e-15, "row {r}: {s:?}");
        }
        let f = front(2);
        let s = f.saddle.expect("a saddle");
        assert!((s.c - 0.0018).abs() < 1e-15, "{s:?}");
        assert!((s.d + 0.0002).abs() < 1e-15, "{s:?}");
        assert_eq!(f.pivots[0].angle_deg, 2.5);
        // At the recipe's point, the recipe's design.
        let d = space.design_at(&[0.0; 5]);
        assert_eq!(d.rows[2].front, design.rows[2].front);
    }
}
