//! The recipe's fabrication tables parsed (the model they fill is
//! `crate::fabrication`): `[material]`, `[eyelet]`, `[strip]`, `[laser]`,
//! `[sheet]` validated into `Fabrication`, with command-line overrides
//! applied first so every check sees the values that will be used.

use super::fabrication_bounds::*;
use super::raw::{Num, RawDesign};
use crate::diagnostic::{Diagnostic, ErrorKind, shown};
use crate::fabrication::{
    ColourPreset, DEFAULT_MAT, EYELET_PRESETS, Fabrication, LabelStyle, MATS, Machine,
    MachinePreset, PLOTTER_MIN_HOLE, Paper, PlotterSetup, SHEET_AUTO, SHEET_PRESETS, STOCK_PRESETS,
    StockPreset, eyelet_preset, longest_preset, preset_names, sheet_size, stock_preset,
};
use toml::Spanned;

/// A length from `low` (allowed when `low_allowed`) to `max` (allowed).
fn length(
    n: &Num,
    what: &str,
    (low, low_allowed): (f64, bool),
    max: f64,
) -> Result<f64, Diagnostic> {
    let v = *n.get_ref();
    let above = if low_allowed { v >= low } else { v > low };
    if v.is_finite() && above && v <= max {
        Ok(v)
    } else {
        let bound = if low == 0.0 && !low_allowed {
            let positive = "positive".to_string();
            if max.is_finite() {
                format!("{positive} and at most {}", shown(max))
            } else {
                positive
            }
        } else {
            super::values::range(low, low_allowed, max, true)
        };
        Err(Diagnostic::new(
            ErrorKind::LengthOutOfRange,
            format!("{what} is {}, but must be {bound} (mm)", shown(v)),
        )
        .at(n.span())
        .hint(format!("give {what} a length in mm, {bound}")))
    }
}

fn non_negative(n: &Num, what: &str, max: f64) -> Result<f64, Diagnostic> {
    let v = *n.get_ref();
    if v.is_finite() && (0.0..=max).contains(&v) {
        Ok(v)
    } else {
        Err(Diagnostic::new(
            ErrorKind::LengthOutOfRange,
            format!(
                "{what} is {}, but must be at least 0 and at most {} (mm)",
                shown(v),
                shown(max)
            ),
        )
        .at(n.span())
        .hint(format!(
            "give {what} a length in mm from 0 to {}",
            shown(max)
        )))
    }
}

fn from_override(v: f64, what: &str, max: f64) -> Result<f64, Diagnostic> {
    if v.is_finite() && (0.0..=max).contains(&v) {
        Ok(v)
    } else {
        Err(Diagnostic::new(
            ErrorKind::FlagOutOfRange,
            format!(
                "--{what} is {}, but must be a length from 0 to {} (mm)",
                shown(v),
                shown(max)
            ),
        ))
    }
}

/// A `[material] preset` by its key.
fn stock(key: &Spanned<String>) -> Result<&'static StockPreset, Diagnostic> {
    stock_preset(key.get_ref()).ok_or_else(|| {
        let keys: Vec<String> = STOCK_PRESETS.iter().map(|p| format!("\"{}\"", p.key)).collect();
        Diagnostic::new(
            ErrorKind::UnknownMaterial,
            format!("unknown material preset \"{}\"", key.get_ref()),
        )
        .at(key.span())
        .hint(format!(
            "use one of {}, or leave `preset` out and give the stock's `name` and `thickness` (see docs/fabrication.md, Strip stock)",
            keys.join(", ")
        ))
    })
}

/// A preset's stock is sold and bends well within its thickness range.
fn stock_thickness(p: &StockPreset, t: f64, at: &Num) -> Result<(), Diagnostic> {
    let (lo, hi) = p.thickness;
    if (lo..=hi).contains(&t) {
        return Ok(());
    }
    Err(Diagnostic::new(
        ErrorKind::ThicknessOutsidePreset,
        format!(
            "material.thickness is {} mm, but {} strips are {} to {} mm thick",
            shown(t),
            p.name,
            shown(lo),
            shown(hi)
        ),
    )
    .at(at.span())
    .hint(format!(
        "give a thickness from {} to {} mm, or leave `preset` out and name the stock yourself",
        shown(lo),
        shown(hi)
    )))
}

pub(crate) fn fabrication(
    raw: &RawDesign,
    o: &Overrides,
) -> Result<(Fabrication, FabricationSpans), Diagnostic> {
    let mut f = Fabrication::default();
    let mut spans = FabricationSpans::default();

    material_settings(&mut f, &mut spans, raw, o)?;
    // The default end margin follows the strip width (half of it).
    f.end_margin = f.material.width / 2.0;
    eyelet_settings(&mut f, &mut spans, raw, o)?;
    strip_settings(&mut f, &mut spans, raw, o)?;
    laser_settings(&mut f, &mut spans, raw, o)?;
    machine_settings(&mut f, &mut spans, raw, o)?;
    if f.plotter.is_some() {
        mat_settings(&mut f, &mut spans, raw, o)?;
    } else {
        sheet_settings(&mut f, &mut spans, raw, o)?;
    }
    paper_settings(&mut f, raw, o)?;

    parts_settings(&mut f, raw, o)?;
    cutting_settings(&mut f, raw, o)?;
    super::fabrication_checks::check_settings(&f, raw, o, &spans)?;
    Ok((f, spans))
}

/// The material: its preset, name, thickness and strip width, recipe
/// then command line.
fn material_settings(
    f: &mut Fabrication,
    spans: &mut FabricationSpans,
    raw: &RawDesign,
    o: &Overrides,
) -> Result<(), Diagnostic> {
    if let Some(m) = &raw.material {
        let m = m.get_ref();
        let preset = m.preset.as_ref().map(stock).transpose()?;
        if let Some(p) = preset {
            f.material.name = p.name.into();
            f.material.preset = Some(p);
            f.material.thickness = p.default_thickness;
        }
        if let Some(n) = &m.name {
            f.material.name = n.get_ref().clone();
            // A name alone is stock karigami knows nothing about.
            if preset.is_none() {
                f.material.preset = None;
            }
        }
        if let Some(t) = &m.thickness {
            f.material.thickness = length(
                t,
                "material.thickness",
                (MIN_THICKNESS, true),
                MAX_THICKNESS,
            )?;
            if let Some(p) = preset {
                stock_thickness(p, f.material.thickness, t)?;
            }
        }
        if let Some(w) = &m.width {
            f.material.width = length(w, "material.width", (0.0, false), MAX_STRIP_WIDTH)?;
            spans.width = Some(w.span());
        }
    }
    if let Some(w) = o.strip_width {
        f.material.width = from_override(w, "strip-width", MAX_STRIP_WIDTH)?;
        spans.width = None;
    }
    Ok(())
}

/// The eyelet: a preset or a custom hole and flange, recipe then
/// command line.
fn eyelet_settings(
    f: &mut Fabrication,
    spans: &mut FabricationSpans,
    raw: &RawDesign,
    o: &Overrides,
) -> Result<(), Diagnostic> {
    if let Some(e) = &raw.eyelet {
        spans.eyelet = Some(e.span());
        let e = e.get_ref();
        if let Some(p) = &e.preset {
            f.eyelet = eyelet_preset(p.get_ref()).ok_or_else(|| {
                Diagnostic::new(
                    ErrorKind::UnknownEyelet,
                    format!("unknown eyelet preset \"{}\"", p.get_ref()),
                )
                .at(p.span())
                .hint(format!(
                    "use one of {}, or give `hole` and `flange` in mm",
                    preset_names(EYELET_PRESETS)
                ))
            })?;
        }
        if e.hole.is_some() || e.flange.is_some() {
            f.eyelet.name = "custom".into();
        }
        if let Some(h) = &e.hole {
            f.eyelet.hole = length(h, "eyelet.hole", (MIN_HOLE, true), MAX_EYELET)?;
        }
        if let Some(fl) = &e.flange {
            f.eyelet.flange = length(fl, "eyelet.flange", (0.0, false), 2.0 * MAX_EYELET)?;
        }
    }
    if let Some(name) = &o.eyelet {
        f.eyelet = eyelet_preset(name).ok_or_else(|| {
            Diagnostic::new(
                ErrorKind::UnknownEyeletFlag,
                format!("unknown eyelet preset \"{name}\""),
            )
            .hint(format!("use one of {}", preset_names(EYELET_PRESETS)))
        })?;
        spans.eyelet = None;
    }
    Ok(())
}

/// The strips' end margin and label style, recipe then command line.
fn strip_settings(
    f: &mut Fabrication,
    spans: &mut FabricationSpans,
    raw: &RawDesign,
    o: &Overrides,
) -> Result<(), Diagnostic> {
    if let Some(s) = &raw.strip {
        let s = s.get_ref();
        if let Some(m) = &s.end_margin {
            f.end_margin = length(m, "strip.end_margin", (0.0, false), MAX_END_MARGIN)?;
            spans.end_margin = Some(m.span());
        }
        if let Some(l) = &s.label {
            f.label = LabelStyle::parse(l.get_ref()).ok_or_else(|| {
                Diagnostic::new(
                    ErrorKind::UnknownLabel,
                    format!("unknown label style \"{}\"", l.get_ref()),
                )
                .at(l.span())
                .hint("use \"id\" (e.g. R03-C05-A), \"compact\" (e.g. 3.5A) or \"none\"")
            })?;
        }
    }
    if let Some(l) = &o.label {
        f.label = LabelStyle::parse(l).ok_or_else(|| {
            Diagnostic::new(
                ErrorKind::UnknownLabelFlag,
                format!("unknown label style \"{l}\""),
            )
            .hint("use id, compact or none")
        })?;
    }
    Ok(())
}

/// The laser: kerf, its compensation, flat cutting and the machine,
/// recipe then command line.
fn laser_settings(
    f: &mut Fabrication,
    spans: &mut FabricationSpans,
    raw: &RawDesign,
    o: &Overrides,
) -> Result<(), Diagnostic> {
    if let Some(l) = &raw.laser {
        let l = l.get_ref();
        if let Some(k) = &l.kerf {
            f.kerf = non_negative(k, "laser.kerf", MAX_KERF)?;
            spans.kerf = Some(k.span());
        }
        if let Some(c) = &l.compensate {
            f.compensate_kerf = *c.get_ref();
        }
        if let Some(flat) = &l.flat {
            f.flat = *flat.get_ref();
        }
        if let Some(m) = &l.machine {
            f.machine = Machine::parse(m.get_ref()).ok_or_else(|| {
                Diagnostic::new(
                    ErrorKind::UnknownMachine,
                    format!("unknown laser machine \"{}\"", m.get_ref()),
                )
                .at(m.span())
                .hint("use \"co2\" (a 40-60 W CO2 laser) or \"diode\" (a 5-10 W diode laser)")
            })?;
        }
    }
    if let Some(k) = o.kerf {
        f.kerf = from_override(k, "kerf", MAX_KERF)?;
        spans.kerf = None;
    }
    if let Some(c) = o.compensate_kerf {
        f.compensate_kerf = c;
    }
    if let Some(flat) = o.flat {
        f.flat = flat;
    }
    Ok(())
}

/// The sheet: a preset, "auto" or a size, with its margin and gap,
/// recipe then command line.
fn sheet_settings(
    f: &mut Fabrication,
    spans: &mut FabricationSpans,
    raw: &RawDesign,
    o: &Overrides,
) -> Result<(), Diagnostic> {
    if let Some(s) = &raw.sheet {
        spans.sheet = Some(s.span());
        let s = s.get_ref();
        if s.preset.as_ref().is_some_and(|p| p.get_ref() == SHEET_AUTO) {
            f.sheet_auto = true;
            let (_, w, h) = longest_preset();
            (f.sheet.name, f.sheet.width, f.sheet.height) = (SHEET_AUTO.into(), w, h);
            if let Some(size) = s.width.as_ref().or(s.height.as_ref()) {
                return Err(Diagnostic::new(
                    ErrorKind::SheetAutoWithSize,
                    "the sheet is preset = \"auto\" and also given a width or height",
                )
                .at(size.span())
                .hint("remove sheet.width and sheet.height to let karigami pick the preset, or remove preset = \"auto\""));
            }
        } else if let Some(p) = &s.preset {
            let (name, w, h) = sheet_size(p.get_ref()).ok_or_else(|| {
                Diagnostic::new(
                    ErrorKind::UnknownSheet,
                    format!("unknown sheet preset \"{}\"", p.get_ref()),
                )
                .at(p.span())
                .hint(format!(
                    "use one of {}, \"auto\" (the smallest that holds the job), or \"WxH\" in mm such as \"500x300\"",
                    preset_names(SHEET_PRESETS)
                ))
            })?;
            (f.sheet.name, f.sheet.width, f.sheet.height) = (name, w, h);
        }
        if let Some(w) = &s.width {
            f.sheet.width = length(w, "sheet.width", (0.0, false), f64::INFINITY)?;
            f.sheet.name = "custom".into();
        }
        if let Some(h) = &s.height {
            f.sheet.height = length(h, "sheet.height", (0.0, false), f64::INFINITY)?;
            f.sheet.name = "custom".into();
        }
        margin_and_gap(f, s)?;
    }
    if let Some(name) = &o.sheet {
        f.sheet_auto = name == SHEET_AUTO;
        let (n, w, h) = if f.sheet_auto {
            let (_, w, h) = longest_preset();
            (SHEET_AUTO.to_string(), w, h)
        } else {
            sheet_size(name).ok_or_else(|| {
                Diagnostic::new(ErrorKind::UnknownSheetFlag, format!("unknown sheet \"{name}\"")).hint(format!(
                    "use one of {}, auto (the smallest that holds the job), or WxH in mm such as 500x300",
                    preset_names(SHEET_PRESETS)
                ))
            })?
        };
        (f.sheet.name, f.sheet.width, f.sheet.height) = (n, w, h);
        spans.sheet = None;
    }
    Ok(())
}

fn margin_and_gap(f: &mut Fabrication, s: &super::raw::RawSheet) -> Result<(), Diagnostic> {
    if let Some(m) = &s.margin {
        f.sheet.margin = non_negative(m, "sheet.margin", MAX_SHEET_MARGIN)?;
    }
    if let Some(g) = &s.gap {
        f.sheet.gap = non_negative(g, "sheet.gap", MAX_SHEET_MARGIN)?;
    }
    Ok(())
}

/// The machine: `[machine] preset` (a laser, or a cutting plotter and its
/// smallest hole), then `--machine`. A laser preset must agree with
/// `[laser] machine`; a plotter cuts with a blade, so its kerf is 0 unless
/// given, and its SVGs are flat (the plotters' importers are not known to
/// read `<use>`).
fn machine_settings(
    f: &mut Fabrication,
    spans: &mut FabricationSpans,
    raw: &RawDesign,
    o: &Overrides,
) -> Result<(), Diagnostic> {
    let laser_machine = raw
        .laser
        .as_ref()
        .and_then(|l| l.get_ref().machine.as_ref());
    let table = raw.machine.as_ref().map(|m| m.get_ref());
    let mut min_hole = None;
    let mut chosen = None;
    if let Some(m) = table {
        if let Some(p) = &m.preset {
            let preset = MachinePreset::parse(p.get_ref()).ok_or_else(|| {
                Diagnostic::new(
                    ErrorKind::UnknownMachinePreset,
                    format!("unknown machine preset \"{}\"", p.get_ref()),
                )
                .at(p.span())
                .hint(format!(
                    "use one of {} (a laser, or a cutting plotter; see docs/fabrication.md, Cutting plotters)",
                    MachinePreset::names()
                ))
            })?;
            if let Some(lm) = laser_machine {
                let agrees = matches!(preset, MachinePreset::Laser(m) if m == f.machine);
                if !agrees {
                    return Err(Diagnostic::new(
                        ErrorKind::MachineConflict,
                        format!(
                            "laser.machine is \"{}\", but machine.preset is \"{}\"",
                            lm.get_ref(),
                            p.get_ref()
                        ),
                    )
                    .at(lm.span())
                    .hint("remove laser.machine: machine.preset names the machine"));
                }
            }
            chosen = Some((preset, p.span()));
        }
        if let Some(h) = &m.min_hole {
            min_hole = Some((
                length(h, "machine.min_hole", (MIN_HOLE, true), MAX_EYELET)?,
                h.span(),
            ));
        }
    }
    if let Some(name) = &o.machine {
        let preset = MachinePreset::parse(name).ok_or_else(|| {
            Diagnostic::new(
                ErrorKind::UnknownMachinePresetFlag,
                format!("unknown machine \"{name}\""),
            )
            .hint(format!(
                "use one of {}",
                MachinePreset::names().replace('"', "")
            ))
        })?;
        chosen = Some((preset, 0..0));
    }
    match chosen {
        Some((MachinePreset::Plotter(plotter), span)) => {
            let from_recipe = o.machine.is_none();
            let (min, min_span) = match min_hole {
                Some((h, s)) => (h, Some(s)),
                None => (PLOTTER_MIN_HOLE, from_recipe.then_some(span)),
            };
            f.plotter = Some(PlotterSetup {
                plotter,
                mat: MATS[DEFAULT_MAT].0,
                min_hole: min,
            });
            spans.plotter = min_span;
            if spans.kerf.is_none() && o.kerf.is_none() {
                f.kerf = 0.0;
            }
            f.flat = true;
        }
        other => {
            if let Some(MachinePreset::Laser(m)) = other.map(|c| c.0) {
                f.machine = m;
            }
            if let (Some((_, span)), None) = (min_hole, &o.machine) {
                return Err(Diagnostic::new(
                    ErrorKind::MachineConflict,
                    "machine.min_hole is a cutting plotter's, but the machine is a laser",
                )
                .at(span)
                .hint(
                    "remove machine.min_hole, or set machine.preset = \"cricut\" or \"silhouette\"",
                ));
            }
        }
    }
    Ok(())
}

/// A cutting plotter's sheet: the cutting area of a mat, named by
/// `[sheet] preset` or `--sheet` (default the 12 x 12 in mat). A plotter
/// chosen by `--machine` takes the recipe's sheet only when it is a mat;
/// one chosen by the recipe refuses any other sheet there.
fn mat_settings(
    f: &mut Fabrication,
    spans: &mut FabricationSpans,
    raw: &RawDesign,
    o: &Overrides,
) -> Result<(), Diagnostic> {
    let mats = preset_names(MATS);
    let mat = |name: &str| MATS.iter().position(|m| m.0 == name);
    let mut chosen = DEFAULT_MAT;
    let strict = o.machine.is_none();
    if let Some(s) = &raw.sheet {
        let s = s.get_ref();
        if let Some(p) = &s.preset {
            match mat(p.get_ref()) {
                Some(i) => {
                    chosen = i;
                    spans.sheet = Some(p.span());
                }
                None if strict => {
                    return Err(Diagnostic::new(
                        ErrorKind::SheetNotAMat,
                        format!(
                            "sheet.preset is \"{}\", but a cutting plotter cuts on a mat",
                            p.get_ref()
                        ),
                    )
                    .at(p.span())
                    .hint(format!(
                        "use one of {mats} (the mat's cutting area is the sheet), or a laser machine.preset"
                    )));
                }
                None => {}
            }
        }
        if let Some(size) = s.width.as_ref().or(s.height.as_ref()).filter(|_| strict) {
            return Err(Diagnostic::new(
                ErrorKind::SheetNotAMat,
                "sheet.width or sheet.height is given, but a cutting plotter cuts on a mat",
            )
            .at(size.span())
            .hint(format!(
                "remove sheet.width and sheet.height and name the mat: sheet.preset = one of {mats}"
            )));
        }
        margin_and_gap(f, s)?;
    }
    if let Some(name) = &o.sheet {
        chosen = mat(name).ok_or_else(|| {
            Diagnostic::new(
                ErrorKind::SheetNotAMatFlag,
                format!("--sheet {name}: a cutting plotter cuts on a mat"),
            )
            .hint(format!("use one of {}", mats.replace('"', "")))
        })?;
        spans.sheet = None;
    }
    let (name, w, h) = MATS[chosen];
    (f.sheet.name, f.sheet.width, f.sheet.height) = (name.into(), w, h);
    f.sheet_auto = false;
    if let Some(p) = &mut f.plotter {
        p.mat = name;
    }
    Ok(())
}

/// The guide's paper, recipe then command line.
fn paper_settings(f: &mut Fabrication, raw: &RawDesign, o: &Overrides) -> Result<(), Diagnostic> {
    if let Some(g) = &raw.guide
        && let Some(p) = &g.get_ref().paper
    {
        f.paper = Paper::parse(p.get_ref()).ok_or_else(|| {
            Diagnostic::new(
                ErrorKind::UnknownPaper,
                format!("unknown paper \"{}\"", p.get_ref()),
            )
            .at(p.span())
            .hint("use \"a4\" or \"letter\"")
        })?;
    }
    if let Some(p) = &o.paper {
        f.paper = Paper::parse(p).ok_or_else(|| {
            Diagnostic::new(
                ErrorKind::UnknownPaperFlag,
                format!("unknown paper \"{p}\""),
            )
            .hint("use a4 or letter")
        })?;
    }
    Ok(())
}

/// Part types, the test piece and the colour preset (issue 13), recipe
/// then command line.
fn parts_settings(f: &mut Fabrication, raw: &RawDesign, o: &Overrides) -> Result<(), Diagnostic> {
    let presets = || {
        ColourPreset::ALL
            .iter()
            .map(|p| format!("\"{}\"", p.name()))
            .collect::<Vec<_>>()
            .join(" or ")
    };
    if let Some(t) = raw
        .strip
        .as_ref()
        .and_then(|s| s.get_ref().part_tolerance.as_ref())
    {
        f.part_tolerance = non_negative(t, "strip.part_tolerance", MAX_PART_TOLERANCE)?;
    }
    if let Some(t) = raw
        .sheet
        .as_ref()
        .and_then(|s| s.get_ref().test_piece.as_ref())
    {
        f.test_piece = *t.get_ref();
    }
    if let Some(t) = o.test_piece {
        f.test_piece = t;
    }
    if let Some(c) = raw
        .laser
        .as_ref()
        .and_then(|l| l.get_ref().colours.as_ref())
    {
        f.colours = ColourPreset::parse(c.get_ref()).ok_or_else(|| {
            Diagnostic::new(
                ErrorKind::UnknownColours,
                format!("unknown colour preset \"{}\"", c.get_ref()),
            )
            .at(c.span())
            .hint(format!("use {}", presets()))
        })?;
    }
    if let Some(c) = &o.colours {
        f.colours = ColourPreset::parse(c).ok_or_else(|| {
            Diagnostic::new(
                ErrorKind::UnknownColoursFlag,
                format!("unknown colour preset \"{c}\""),
            )
            .hint(format!("use {}", presets()))
        })?;
    }
    Ok(())
}

/// Grouping by assembly step and holding tabs (issue 13), recipe then
/// command line.
fn cutting_settings(f: &mut Fabrication, raw: &RawDesign, o: &Overrides) -> Result<(), Diagnostic> {
    if let Some(g) = raw.sheet.as_ref().and_then(|s| s.get_ref().group.as_ref()) {
        f.group_by_step = super::choice(
            g,
            "sheet grouping",
            &[("step", true), ("none", false)],
            ErrorKind::UnknownGrouping,
            "use \"step\" (each assembly step's strips in lanes of their own, steps in order) or \"none\"",
        )?;
        // Either choice replaces the default (by step where it is free).
        f.group_if_free = false;
    }
    if let Some(g) = o.group_by_step {
        f.group_by_step = g;
        f.group_if_free = false;
    }
    let tab_limit = f.material.width;
    if let Some(t) = raw.laser.as_ref().and_then(|l| l.get_ref().tabs.as_ref()) {
        f.tabs = non_negative(t, "laser.tabs", MAX_STRIP_WIDTH)?;
        if f.tabs > tab_limit {
            return Err(Diagnostic::new(
                ErrorKind::TabsWiderThanStrip,
                format!(
                    "laser.tabs is {} mm, wider than the {} mm strips",
                    shown(f.tabs),
                    shown(tab_limit)
                ),
            )
            .at(t.span())
            .hint("holding tabs are small bridges: 0.3 to 1 mm holds ABS and breaks by hand"));
        }
    }
    if let Some(t) = o.tabs {
        f.tabs = from_override(t, "tabs", MAX_STRIP_WIDTH)?;
        if f.tabs > tab_limit {
            return Err(Diagnostic::new(
                ErrorKind::TabsWiderThanStripFlag,
                format!(
                    "--tabs is {} mm, wider than the {} mm strips",
                    shown(f.tabs),
                    shown(tab_limit)
                ),
            )
            .hint("holding tabs are small bridges: 0.3 to 1 mm holds ABS and breaks by hand"));
        }
    }
    Ok(())
}
