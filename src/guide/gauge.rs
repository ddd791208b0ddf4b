//! The inspection gauge: the folded lattice at 1:1 (docs/assembly.md).
//! Folded flat, every hole lies on one line at its collapsed coordinate z;
//! the gauge is that line, printed full size down the long side of as many
//! pages as it takes. Consecutive tiles overlap by `GAUGE_OVERLAP` and carry
//! the same two numbered registration marks there, so that the cut tiles
//! taped mark on mark make one continuous line.

use super::{BLACK, GREY, MARGIN, SMALL, Writer, key, text_item};
use crate::build::Build;
use crate::drawing::picture::{PIVOT, VERTEX};
use crate::drawing::{Align, Font, Ink, Item, Shape};
use glam::DVec2;

/// How far consecutive tiles overlap (mm).
pub const GAUGE_OVERLAP: f64 = 12.0;
/// Label size (mm) and the least distance between two labels' baselines.
const LABEL: f64 = 2.6;
const PITCH: f64 = 3.1;
/// A label further than this from its tick joins the label above as "+n".
const DRIFT: f64 = 9.0;

/// The gauge's ticks: (z from the first hole, labels, vertex pivot?).
fn ticks(b: &Build) -> Vec<(f64, Vec<String>, bool)> {
    let l = &b.lattice;
    let helix = l.kind == crate::lattice::Kind::Helix;
    let z0 = l
        .vertices
        .iter()
        .map(|v| v.z)
        .chain(l.cells.iter().map(|c| c.z_pivot))
        .fold(f64::INFINITY, f64::min);
    let mut marks: Vec<(f64, String, bool)> = l
        .vertices
        .iter()
        .map(|v| {
            let name = if helix {
                format!("[{}]", v.key.col)
            } else {
                key(v.key)
            };
            (v.z - z0, name, true)
        })
        .collect();
    marks.extend(l.cells.iter().enumerate().map(|(i, c)| {
        let name = if helix {
            format!("({i})")
        } else {
            format!("({},{})", c.row, c.col)
        };
        (c.z_pivot - z0, name, false)
    }));
    marks.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.2.cmp(&a.2)));
    // Holes closer than 0.05 mm share a tick.
    let mut ticks: Vec<(f64, Vec<String>, bool)> = Vec::new();
    for (z, label, vertex) in marks {
        match ticks
            .iter_mut()
            .rev()
            .take(4)
            .find(|t| (z - t.0).abs() < 0.05 && t.2 == vertex)
        {
            Some(t) => t.1.push(label),
            None => ticks.push((z, vec![label], vertex)),
        }
    }
    ticks
}

/// The tiles of a gauge of length `total`, given each page's room: the
/// stretch [from, to] of the line each tile shows.
pub fn gauge_tiles(total: f64, first: f64, rest: f64) -> Vec<(f64, f64)> {
    let mut tiles = Vec::new();
    let mut from = 0.0;
    let mut room = first;
    loop {
        let to = (from + room).min(total);
        tiles.push((from, to));
        if to >= total {
            return tiles;
        }
        from = to - GAUGE_OVERLAP;
        room = rest;
    }
}

pub(super) fn gauge(w: &mut Writer, b: &Build) {
    // It starts on the last step's page when there is room for a useful
    // first tile.
    w.need(110.0);
    w.y += 4.0;
    w.heading("Inspection gauge: the folded lattice (1:1)");
    let ticks = ticks(b);
    let total = ticks.last().map_or(0.0, |t| t.0);
    let first = b
        .lattice
        .vertices
        .iter()
        .min_by(|a, b| a.z.total_cmp(&b.z))
        .map_or(String::new(), |v| key(v.key));
    let head = 14.0;
    let rest = w.bottom() - MARGIN - head - 6.0;
    // Tiles after the first get a page each; the first shares its page
    // with the heading and this paragraph.
    let count = {
        let probe = gauge_tiles(total, rest, rest);
        probe.len()
    };
    w.paragraph(
        &format!(
            "Folded flat, every strip of the lattice lies along one line and every hole sits at a fixed \
             distance along it. This gauge is that line at full size ({total:.1} mm{}). Blue ticks are \
             vertex pivots [row,column], orange ticks scissor pivots (row,column); the ruler beside it is \
             1:1 from the same 0. Print at 100 %{} Fold a finished part of the lattice flat, lay it on the \
             line with vertex {first} on 0, and check that its holes fall on the ticks before setting the \
             last eyelets.",
            if count > 1 {
                format!(", on {count} pages")
            } else {
                String::new()
            },
            if count > 1 {
                format!(
                    ", cut each page's tile along its top mark line and tape it over the tile before, \
                     crosses on the crosses of the same number (the tiles overlap by {GAUGE_OVERLAP:.0} mm)."
                )
            } else {
                ".".to_string()
            },
        ),
        SMALL,
        GREY,
    );
    let first_room = (w.bottom() - w.y - 6.0).max(40.0);
    let tiles = gauge_tiles(total, first_room, rest);
    let x_line = MARGIN + 75.0;
    let x_ruler = MARGIN + 25.0;
    for (n, &(from, to)) in tiles.iter().enumerate() {
        if n > 0 {
            w.new_page();
            w.text(
                &format!(
                    "Inspection gauge, tile {} of {} (1:1): {from:.0} to {to:.0} mm",
                    n + 1,
                    tiles.len()
                ),
                4.0,
                Font::Bold,
                BLACK,
            );
        }
        w.close_group();
        let y0 = w.y + 4.0;
        let y = |z: f64| y0 + z - from;
        // The line itself first: tests read its length from here.
        let mut items = vec![Item::art(
            Ink::line(BLACK, 0.3),
            Shape::polyline(
                &[DVec2::new(x_line, y(from)), DVec2::new(x_line, y(to))],
                false,
            ),
        )];
        // The 1:1 ruler: millimetre ticks, numbers every 10 mm.
        items.push(Item::art(
            Ink::line(GREY, 0.2),
            Shape::polyline(
                &[DVec2::new(x_ruler, y(from)), DVec2::new(x_ruler, y(to))],
                false,
            ),
        ));
        let mut k = from.ceil() as i64;
        while k as f64 <= to + 1e-9 {
            let tick = if k % 10 == 0 {
                4.0
            } else if k % 5 == 0 {
                2.5
            } else {
                1.3
            };
            items.push(Item::art(
                Ink::line(GREY, 0.12),
                Shape::polyline(
                    &[
                        DVec2::new(x_ruler, y(k as f64)),
                        DVec2::new(x_ruler + tick, y(k as f64)),
                    ],
                    false,
                ),
            ));
            if k % 10 == 0 {
                items.push(text_item(
                    DVec2::new(x_ruler - 1.5, y(k as f64) + LABEL * 0.35),
                    LABEL,
                    &k.to_string(),
                    Font::Regular,
                    Align::Right,
                    GREY,
                ));
            }
            k += 1;
        }
        // Ticks: vertex pivots to the right, scissor pivots to the left;
        // labels in a column each, pushed down to stay apart, with a leader
        // back to the tick.
        let mut last = [f64::NEG_INFINITY; 2];
        let mut open: [Option<(usize, Vec<String>, usize)>; 2] = [None, None];
        let mut labels: Vec<(f64, f64, f64, String, bool)> = Vec::new();
        for (z, names, vertex) in ticks
            .iter()
            .filter(|t| t.0 >= from - 1e-9 && t.0 <= to + 1e-9)
        {
            let ty = y(*z);
            let (colour, dir) = if *vertex {
                (VERTEX, 1.0)
            } else {
                (PIVOT, -1.0)
            };
            let reach = if *vertex { 7.0 } else { 5.0 };
            items.push(Item::art(
                Ink::line(colour, 0.3),
                Shape::polyline(
                    &[DVec2::new(x_line, ty), DVec2::new(x_line + dir * reach, ty)],
                    false,
                ),
            ));
            let slot = *vertex as usize;
            let ly = ty.max(last[slot] + PITCH);
            if ly - ty > DRIFT {
                if let Some((_, _, more)) = open[slot].as_mut() {
                    *more += names.len();
                    continue;
                }
            }
            if let Some((i, first_names, more)) = open[slot].take() {
                labels[i].3 = label_text(&first_names, more);
            }
            last[slot] = ly;
            labels.push((ty, ly, dir * reach, String::new(), *vertex));
            open[slot] = Some((labels.len() - 1, names.clone(), names.len() - 1));
        }
        for (i, names, more) in open.into_iter().flatten() {
            labels[i].3 = label_text(&names, more);
        }
        for (ty, ly, reach, text, vertex) in labels {
            let colour = if vertex { VERTEX } else { PIVOT };
            let x_end = x_line + reach;
            let x_text = x_end + reach.signum() * 4.0;
            items.push(Item::art(
                Ink::line(colour, 0.12),
                Shape::polyline(
                    &[
                        DVec2::new(x_end, ty),
                        DVec2::new(x_text - reach.signum(), ly),
                    ],
                    false,
                ),
            ));
            items.push(text_item(
                DVec2::new(x_text, ly + LABEL * 0.35),
                LABEL,
                &text,
                Font::Regular,
                if vertex { Align::Left } else { Align::Right },
                colour,
            ));
        }
        // Registration marks where this tile overlaps the next and the one
        // before: the same numbered crosses on both.
        let marks = |m: usize, a: f64, b: f64| [(m, a, "a"), (m, b, "b")];
        let mut regs = Vec::new();
        if n > 0 {
            regs.extend(marks(n, from, tiles[n - 1].1));
        }
        if n + 1 < tiles.len() {
            regs.extend(marks(n + 1, tiles[n + 1].0, to));
        }
        for (m, z, which) in regs {
            let yy = y(z);
            items.push(Item::art(
                Ink::line(BLACK, 0.15),
                Shape::polyline(
                    &[
                        DVec2::new(x_ruler - 12.0, yy),
                        DVec2::new(x_line + 60.0, yy),
                    ],
                    false,
                ),
            ));
            for x in [x_ruler - 12.0, x_line + 60.0] {
                items.push(Item::art(
                    Ink::line(BLACK, 0.3),
                    Shape::polyline(&[DVec2::new(x, yy - 3.0), DVec2::new(x, yy + 3.0)], false),
                ));
            }
            items.push(text_item(
                DVec2::new(x_line + 62.0, yy + LABEL * 0.35),
                LABEL,
                &format!("mark {m}{which}"),
                Font::Bold,
                Align::Left,
                BLACK,
            ));
        }
        w.push(items);
        w.group_id = Some(format!("gauge-tile-{}", n + 1));
        w.close_group();
        w.group_id = None;
        w.y = y(to) + 6.0;
    }
}

fn label_text(names: &[String], more: usize) -> String {
    if more == 0 {
        names[0].clone()
    } else {
        format!("{} +{more}", names[0])
    }
}
