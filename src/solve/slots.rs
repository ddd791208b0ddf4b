//! The optimiser's variables: which recipe numbers `[optimise] vary`
//! frees, and where they start.

use super::*;

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
                slots.push(Slot::Front {
                    rows: vec![i],
                    span,
                    magnitudes,
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
