//! A step's block on the page: its layout (picture beside or above the
//! text) and the block itself: heading, words, pictures.

use super::labels::Placer;
use super::stacking;
use super::step_labels::{LABEL_ROOM, Shown, step_labels};
use super::step_pictures::{
    STEP_PICTURE, StepPictures, corners, detail_camera, details, details_height, step_camera,
};
use super::step_text::step_text;
use super::{NEW, rect};
use crate::assembly::Step;
use crate::drawing::flow::{BLACK, FAINT, GREY, MARGIN, PageFlow, SMALL, text_item, wrap};
use crate::drawing::picture::{Fit, RodStyle, crossing_rods, pivots_and_vertices, rods};
use crate::drawing::{Align, Font, Ink, Item};
use crate::pipeline::Build;
use glam::DVec2;

/// How this guide lays out its steps: the picture beside the text for steps
/// of up to 3 cells (several steps a page), above it for wider rows.
pub(super) struct StepLayout {
    pub(super) side: bool,
    /// Rows of more than a few cells: the whole-lattice picture is small and
    /// unlabelled, and zoomed pictures of the row follow, a few cells each.
    pub(super) detail: bool,
    /// The picture's box (mm).
    pub(super) size: DVec2,
    /// Beside the text, the whole lattice takes the box's left part and a
    /// zoomed picture of the step starts this far (mm) from its left.
    pub(super) zoom_x: f64,
}

impl StepLayout {
    /// The box of the whole-lattice picture.
    pub(super) fn overview(&self) -> DVec2 {
        if self.side {
            DVec2::new(self.zoom_x - 3.0, self.size.y)
        } else {
            self.size
        }
    }
}

impl StepLayout {
    pub(super) fn new(b: &Build, steps: &[Step], text_width: f64) -> Self {
        let widest = steps.iter().map(|s| s.cells.len()).max().unwrap_or(0);
        // Beside the text only for a cell or few a step: a picture half
        // the page wide has no room for the labels of a wider row.
        let side = widest <= 3;
        let pw = if side {
            (0.5 * text_width).floor()
        } else {
            text_width
        };
        let cap = if side { 40.0 } else { STEP_PICTURE };
        // The lattice's height on the page when fitted to the width alone.
        let fit = Fit::new(
            &b.assembled,
            step_camera(b),
            DVec2::ZERO,
            DVec2::new(pw, 1e4),
        );
        let ys = b
            .assembled
            .vertices
            .iter()
            .map(|v| fit.map(v.pos).y)
            .chain(b.assembled.cells.iter().map(|c| fit.map(c.pivot).y));
        let (lo, hi) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), y| {
            (l.min(y), h.max(y))
        });
        let ph = if hi > lo { hi - lo } else { cap }.clamp(25.0, cap);
        // A row of more than a few cells is labelled in zoomed pictures:
        // in the whole lattice its cells are too small, or hidden behind
        // the rows before it (a torus's inner rings).
        let detail = !side;
        Self {
            side,
            detail,
            size: DVec2::new(pw, if detail { ph.min(50.0) } else { ph }),
            zoom_x: if side { (0.4 * pw).round() } else { 0.0 },
        }
    }
}

#[allow(clippy::too_many_arguments)]
pub(super) fn step_block(
    w: &mut PageFlow,
    b: &Build,
    step: &Step,
    count: usize,
    pictures: &StepPictures,
    layout: &StepLayout,
    side: &stacking::Side,
    spots: &super::finding::Spots,
) {
    let helix = b.lattice.kind == crate::lattice::Kind::Helix;
    let orders = stacking::orders(&b.lattice, step);
    let lines = step_text(b, step, side, orders.as_deref(), spots);
    let text_x = if layout.side {
        MARGIN + layout.size.x + 5.0
    } else {
        MARGIN
    };
    let text_w = MARGIN + w.width() - text_x;
    let line_h = SMALL * 1.35;
    let wrap_all = |lines: &[(String, bool, [u8; 3])]| -> Vec<(String, bool, [u8; 3])> {
        lines
            .iter()
            .flat_map(|(t, bold, c)| {
                let font = if *bold { Font::Bold } else { Font::Regular };
                wrap(t, font, SMALL, text_w)
                    .into_iter()
                    .map(move |x| (x, *bold, *c))
            })
            .collect()
    };
    let wrapped = wrap_all(&lines);
    let title_h = 6.0;
    let pic_h = layout.size.y + 2.0 * LABEL_ROOM;
    let room = w.bottom() - MARGIN;
    let details_h = if layout.detail {
        details_height(b, step, w.width())
    } else {
        0.0
    };
    let whole = |wrapped: &[(String, bool, [u8; 3])]| {
        title_h + pic_h + details_h + wrapped.len() as f64 * line_h
    };
    // A step never runs over a page boundary unless it alone is longer
    // than a page, and then it says so under its title, on the page it
    // starts (after its pictures the note would sit on the next page).
    let too_long = !layout.side && whole(&wrapped) > room;
    let note_h = if too_long { line_h } else { 0.0 };
    let text_h = title_h + wrapped.len() as f64 * line_h;
    let beside = layout.side && pic_h.max(text_h) <= room;
    let block = if beside {
        pic_h.max(text_h)
    } else if too_long {
        title_h + note_h + pic_h + (text_h - title_h).min(30.0)
    } else {
        whole(&wrapped)
    };
    w.need(block + 3.0);
    w.close_group();
    let title_y = w.y;
    // The picture: beside the text, or under the title.
    let top = if beside { w.y } else { w.y + title_h + note_h };
    // The lattice so far: earlier steps grey, this one in colour on top,
    // with a gap in each strip A where B crosses it; then the dots.
    let at = DVec2::new(MARGIN, top + LABEL_ROOM);
    let k = step.number - 1;
    w.place(pictures.prefix(&pictures.faint, &pictures.faint_blocks, k, at));
    let fit = StepPictures::fit(b, at, layout.overview());
    let width = pictures.width;
    w.push(crossing_rods(&b.assembled, &fit, &step.cells, |_| {
        Some(RodStyle {
            colour: NEW,
            width: width * 1.3,
        })
    }));
    w.place(pictures.prefix(&pictures.dots, &pictures.dot_blocks, k + 1, at));
    let named: Vec<usize> = if orders.is_none() {
        step.joints
            .iter()
            .flat_map(|j| j.ends.iter().map(|e| e.rod))
            .collect()
    } else {
        Vec::new()
    };
    if layout.side {
        w.push(side_zoom(b, step, layout, top, pic_h, &named));
    }
    w.group_id = Some(format!("step-{}-labels", step.number));
    w.close_group();
    w.group_id = Some(format!("step-{}-text", step.number));
    let what = if helix { "cell" } else { "row" };
    let title = format!("Step {} of {count} - {what} {}", step.number, step.row);
    w.items.push(text_item(
        DVec2::new(text_x, title_y + 4.5),
        4.5,
        &title,
        Font::Bold,
        Align::Left,
        BLACK,
    ));
    if too_long {
        w.items.push(text_item(
            DVec2::new(text_x, title_y + title_h + SMALL * 0.8),
            SMALL,
            "This step is longer than a page: it continues on the next page.",
            Font::Regular,
            Align::Left,
            GREY,
        ));
    }
    if beside {
        let mut y = title_y + title_h;
        for (line, bold, colour) in &wrapped {
            let font = if *bold { Font::Bold } else { Font::Regular };
            w.items.push(text_item(
                DVec2::new(text_x, y + SMALL * 0.8),
                SMALL,
                line,
                font,
                Align::Left,
                *colour,
            ));
            y += line_h;
        }
        w.y = top + pic_h.max(text_h);
    } else {
        w.y = top + pic_h;
        w.close_group();
        if layout.detail {
            details(w, b, step, &named);
            w.group_id = Some(format!("step-{}-text", step.number));
        }
        w.running_head = Some(format!("Step {}", step.number));
        for (line, bold, colour) in &wrapped {
            let font = if *bold { Font::Bold } else { Font::Regular };
            w.need(line_h);
            w.text_at(MARGIN, line, SMALL, font, *colour);
            w.y += line_h;
        }
        w.running_head = None;
    }
    w.close_group();
    w.group_id = None;
    w.y += 2.0;
    w.rule();
    w.y += 1.0;
}

/// Beside the text the whole lattice is small: the step's cells and the
/// cells they join drawn again, zoomed, right of it, and labelled there.
fn side_zoom(
    b: &Build,
    step: &Step,
    layout: &StepLayout,
    top: f64,
    pic_h: f64,
    named: &[usize],
) -> Vec<Item> {
    // The whole lattice is small beside the text: the step's cells and
    // the cells they join are drawn again, zoomed, right of it, and
    // labelled there.
    let l = &b.assembled;
    let mut corner = vec![false; l.vertices.len()];
    for &c in &step.cells {
        let cell = &l.cells[c];
        for v in cell.corner_ids() {
            corner[v as usize] = true;
        }
    }
    let k0 = step.number - 1;
    let around: Vec<usize> = (0..l.cells.len())
        .filter(|&c| {
            let cell = &l.cells[c];
            l.step_of(c) < k0 && cell.corner_ids().iter().any(|&v| corner[v as usize])
        })
        .collect();
    let all: Vec<usize> = step.cells.iter().chain(&around).copied().collect();
    let vertices = corners(l, &all);
    let camera = detail_camera(b, &step.cells).unwrap_or_else(|| step_camera(b));
    let zoom_at = DVec2::new(MARGIN + layout.zoom_x, top + LABEL_ROOM);
    let zoom_size = DVec2::new(layout.size.x - layout.zoom_x, layout.size.y);
    let points = vertices
        .iter()
        .map(|&v| l.vertices[v].pos)
        .chain(all.iter().map(|&c| l.cells[c].pivot));
    let zfit = Fit::around(points, camera, zoom_at, zoom_size);
    let zw = (0.6 * zfit.scale() * b.design.fabrication.material.width).clamp(0.4, 2.0);
    let mut items = vec![Item::art(
        Ink::line(FAINT, 0.2),
        rect(MARGIN + layout.zoom_x - 1.5, top, zoom_size.x + 1.5, pic_h),
    )];
    items.extend(rods(l, &zfit, &around, |_| {
        Some(RodStyle {
            colour: FAINT,
            width: zw,
        })
    }));
    items.extend(crossing_rods(l, &zfit, &step.cells, |_| {
        Some(RodStyle {
            colour: NEW,
            width: zw * 1.3,
        })
    }));
    items.extend(pivots_and_vertices(l, &zfit, &all, &vertices, zw * 0.8));
    let mut placer = Placer::new(
        DVec2::new(MARGIN + layout.zoom_x - 1.0, top),
        DVec2::new(MARGIN + layout.size.x + 1.0, top + pic_h),
    );
    let shown = Shown {
        cells: &step.cells,
        joints: step.joints.iter().collect(),
        first_row: 0,
        vertices: Some(&vertices),
    };
    items.extend(step_labels(b, step, &zfit, &mut placer, named, &shown));
    items.extend(placer.items);
    items
}
