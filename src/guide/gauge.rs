//! The inspection gauge: the folded lattice at 1:1 (docs/assembly.md).
//! Folded flat, every hole lies on one line at its collapsed coordinate z;
//! the gauge is that line, printed full size in tiles down the long side of
//! the page, as many side by side as the page's width holds (two on A4 and
//! Letter), so that a long gauge takes few pages. Consecutive tiles overlap
//! by `GAUGE_OVERLAP` and carry the same two numbered registration marks
//! there, so that the cut tiles taped mark on mark make one continuous line.

use super::key;
use crate::drawing::flow::{BLACK, FAINT, GREY, MARGIN, PageFlow, SMALL, text_item};
use crate::drawing::picture::{PIVOT, VERTEX};
use crate::drawing::{Align, Font, Ink, Item, Shape, text};
use crate::pipeline::Build;
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

/// Room above a tile's line for its heading, and below it for labels pushed
/// down past its last tick (at most `DRIFT`) and the registration crosses.
const TILE_HEAD: f64 = 7.0;
const TILE_TAIL: f64 = DRIFT + 1.5;
/// Least room worth starting the gauge on a page that has other things.
const FIRST_ROOM: f64 = 60.0;

/// The tiles of a gauge of length `total`, given the room of the i-th tile
/// (mm of line): the stretch [from, to] of the line each tile shows.
pub fn gauge_tiles(total: f64, room: impl Fn(usize) -> f64) -> Vec<(f64, f64)> {
    let mut tiles = Vec::new();
    let mut from = 0.0;
    loop {
        // More room than the overlap, or the tiles would never get anywhere.
        let to = (from + room(tiles.len()).max(GAUGE_OVERLAP + 20.0)).min(total);
        tiles.push((from, to));
        if to >= total {
            return tiles;
        }
        from = to - GAUGE_OVERLAP;
    }
}

/// A tick's label on one tile: the tick's z, the z the label is written at
/// (pushed down to keep clear of the label above), its side and text.
struct Label {
    z: f64,
    at: f64,
    vertex: bool,
    text: String,
}

/// The labels of the ticks in [from, to]: in a column each side, pushed
/// down to stay `PITCH` apart; a label that would drift further than
/// `DRIFT` from its tick joins the label above as "+n".
fn tile_labels(ticks: &[(f64, Vec<String>, bool)], from: f64, to: f64) -> Vec<Label> {
    let mut last = [f64::NEG_INFINITY; 2];
    let mut open: [Option<(usize, Vec<String>, usize)>; 2] = [None, None];
    let mut labels: Vec<Label> = Vec::new();
    for (z, names, vertex) in ticks
        .iter()
        .filter(|t| t.0 >= from - 1e-9 && t.0 <= to + 1e-9)
    {
        let slot = *vertex as usize;
        let at = z.max(last[slot] + PITCH);
        if at - z > DRIFT
            && let Some((_, _, more)) = open[slot].as_mut()
        {
            *more += names.len();
            continue;
        }
        if let Some((i, first_names, more)) = open[slot].take() {
            labels[i].text = label_text(&first_names, more);
        }
        last[slot] = at;
        labels.push(Label {
            z: *z,
            at,
            vertex: *vertex,
            text: String::new(),
        });
        open[slot] = Some((labels.len() - 1, names.clone(), names.len() - 1));
    }
    for (i, names, more) in open.into_iter().flatten() {
        labels[i].text = label_text(&names, more);
    }
    labels
}

/// Where things go across a tile, from its left edge (mm): the ruler's
/// numbers end at `numbers`, the ruler at `ruler`, scissor-pivot labels end
/// 9 mm left of the `line`, vertex labels start 11 mm right of it, the
/// right registration cross at `cross` with its label after it; `width` is
/// the whole tile's. Every column is as wide as its widest text, so a tile
/// is as narrow as its labels allow (about 80 mm).
struct Columns {
    numbers: f64,
    ruler: f64,
    line: f64,
    cross: f64,
    width: f64,
}

impl Columns {
    fn new(total: f64, labels: &[Vec<Label>], tiles: usize) -> Self {
        let widest = |vertex: bool| {
            labels
                .iter()
                .flatten()
                .filter(|l| l.vertex == vertex)
                .map(|l| text::width(&l.text, Font::Regular, LABEL))
                .fold(0.0, f64::max)
        };
        let number = text::width(
            &(((total / 10.0).floor() as i64) * 10).to_string(),
            Font::Regular,
            LABEL,
        );
        let mark = text::width(&format!("mark {tiles}b"), Font::Bold, LABEL);
        let numbers = 1.5 + number;
        let ruler = numbers + 1.5;
        let line = ruler + 4.0 + 1.5 + widest(false) + 9.0;
        let cross = line + 11.0 + widest(true) + 2.0;
        Self {
            numbers,
            ruler,
            line,
            cross,
            width: cross + 2.0 + mark,
        }
    }
}

/// The gauge's plan for `columns` tiles side by side: the tiles, their
/// labels and their columns.
struct Plan {
    columns: usize,
    tiles: Vec<(f64, f64)>,
    labels: Vec<Vec<Label>>,
    layout: Columns,
}

impl Plan {
    fn new(
        ticks: &[(f64, Vec<String>, bool)],
        total: f64,
        columns: usize,
        first: f64,
        rest: f64,
    ) -> Self {
        let tiles = gauge_tiles(total, |i| if i < columns { first } else { rest });
        let labels: Vec<Vec<Label>> = tiles
            .iter()
            .map(|&(from, to)| tile_labels(ticks, from, to))
            .collect();
        let layout = Columns::new(total, &labels, tiles.len());
        Self {
            columns,
            tiles,
            labels,
            layout,
        }
    }
}

pub(super) fn gauge(w: &mut PageFlow, b: &Build) {
    let ticks = ticks(b);
    let total = ticks.last().map_or(0.0, |t| t.0);
    let first = b
        .lattice
        .vertices
        .iter()
        .min_by(|a, b| a.z.total_cmp(&b.z))
        .map_or(String::new(), |v| key(v.key));
    let about = format!(
        "Folded flat, every strip of the lattice lies along one line and every hole sits at a fixed \
         distance along it. This gauge is that line at full size ({total:.1} mm). Blue ticks are \
         vertex pivots [row,column], orange ticks scissor pivots (row,column); holes at one distance \
         share a tick, labelled with one of their keys and \"+N\" for the N others there. The ruler \
         beside it is 1:1 from the same 0. Print at 100 % and check the ruler against a real one."
    );
    let check = format!(
        "Fold a finished part of the lattice flat, lay it on the line with vertex {first} on 0, and \
         check that its holes fall on the ticks before setting the last eyelets."
    );
    let tiled = format!(
        "{about} The line is printed in numbered tiles, each overlapping the next by \
         {GAUGE_OVERLAP:.0} mm. Cut the tiles apart along the faint lines between them. Trim every \
         tile after the first along its top line (mark 1a on tile 2, mark 2a on tile 3, ...), lay it \
         over the end of the tile before with its edge on that tile's line of the same mark and its \
         cross b on the other's cross b, and tape it; the joined tiles make one straight line. {check}"
    );
    let whole = format!("{about} {check}");
    // Heading, paragraph and a first tile of some use on one page.
    let heading = 4.0 + 7.0 * 1.4 + 2.0;
    w.need(heading + w.paragraph_height(&tiled, SMALL) + TILE_HEAD + FIRST_ROOM + TILE_TAIL);
    w.y += 4.0;
    w.heading("Inspection gauge: the folded lattice (1:1)");
    let page_head = BODY_HEAD;
    // A tile's tail may reach into the room kept above the page's footer.
    let floor = w.bottom() + 6.0;
    let rest = floor - MARGIN - page_head - TILE_HEAD - TILE_TAIL;
    let room_after =
        |text: &str| floor - w.y - w.paragraph_height(text, SMALL) - TILE_HEAD - TILE_TAIL;
    // As many tiles side by side as the page's width holds.
    let plan_for = |text: &str| {
        (1..=3)
            .rev()
            .map(|columns| Plan::new(&ticks, total, columns, room_after(text), rest))
            .find(|p| {
                p.columns == 1
                    || p.columns as f64 * p.layout.width + (p.columns - 1) as f64 * 6.0 <= w.width()
            })
            .expect("one column always fits")
    };
    let mut plan = plan_for(&tiled);
    let text = if plan.tiles.len() > 1 {
        tiled
    } else {
        // With room for the shorter paragraph it still fits one tile.
        plan = plan_for(&whole);
        whole
    };
    w.paragraph(&text, SMALL, GREY);
    let n = plan.tiles.len();
    let pitch = w.width() / plan.columns as f64;
    let mut bottom = w.y;
    for (i, (&(from, to), labels)) in plan.tiles.iter().zip(&plan.labels).enumerate() {
        let column = i % plan.columns;
        if column == 0 {
            if i > 0 {
                w.new_page();
                w.text(
                    "Inspection gauge (continued): print at 100 %, 1:1",
                    BODY_HEAD_SIZE,
                    Font::Bold,
                    GREY,
                );
                w.y = MARGIN + page_head;
            }
            // The cut lines between this page's tiles.
            w.close_group();
            let on_page = (n - i).min(plan.columns);
            let longest = plan.tiles[i..i + on_page]
                .iter()
                .map(|t| t.1 - t.0)
                .fold(0.0, f64::max);
            bottom = w.y + TILE_HEAD + longest + TILE_TAIL;
            let cuts = (1..on_page)
                .map(|c| {
                    let x = MARGIN + c as f64 * pitch;
                    Item::art(
                        Ink::line(FAINT, 0.2),
                        Shape::polyline(&[DVec2::new(x, w.y), DVec2::new(x, bottom)], false),
                    )
                })
                .collect();
            w.push(cuts);
            w.close_group();
        }
        let x0 = MARGIN + column as f64 * pitch + (pitch - plan.layout.width).max(0.0) / 2.0;
        let marks = registration(&plan.tiles, i);
        let items = tile(
            &plan.layout,
            x0,
            w.y,
            (from, to),
            labels,
            &ticks,
            &marks,
            i,
            n,
        );
        w.push(items);
        w.group_id = Some(format!("gauge-tile-{}", i + 1));
        w.close_group();
        w.group_id = None;
    }
    w.y = bottom;
}

/// The page head of a gauge continuation page: its text size and height.
const BODY_HEAD_SIZE: f64 = 3.6;
const BODY_HEAD: f64 = BODY_HEAD_SIZE * 1.4 + 2.0;

/// The registration marks on tile `i`: (number, z, "a" or "b"), the same
/// two where it overlaps the tile before and where it overlaps the next.
fn registration(tiles: &[(f64, f64)], i: usize) -> Vec<(usize, f64, &'static str)> {
    let mut marks = Vec::new();
    if i > 0 {
        marks.push((i, tiles[i].0, "a"));
        marks.push((i, tiles[i - 1].1, "b"));
    }
    if i + 1 < tiles.len() {
        marks.push((i + 1, tiles[i + 1].0, "a"));
        marks.push((i + 1, tiles[i].1, "b"));
    }
    marks
}

/// One tile's drawing, its top-left corner at (x0, top): the line first
/// (tests read its length from there), then its heading, the ruler, the
/// ticks and their labels, and the registration marks.
#[allow(clippy::too_many_arguments)]
fn tile(
    c: &Columns,
    x0: f64,
    top: f64,
    (from, to): (f64, f64),
    labels: &[Label],
    ticks: &[(f64, Vec<String>, bool)],
    marks: &[(usize, f64, &str)],
    i: usize,
    n: usize,
) -> Vec<Item> {
    let f = Frame {
        x0,
        y0: top + TILE_HEAD,
        from,
        to,
        x_line: x0 + c.line,
    };
    let (x_line, y) = (f.x_line, |z: f64| f.y(z));
    let mut items = vec![Item::art(
        Ink::line(BLACK, 0.3),
        Shape::polyline(
            &[DVec2::new(x_line, y(from)), DVec2::new(x_line, y(to))],
            false,
        ),
    )];
    let title = if n > 1 {
        format!("Tile {} of {n}: {from:.0} to {to:.0} mm", i + 1)
    } else {
        format!("0 to {to:.0} mm")
    };
    items.push(text_item(
        DVec2::new(x0, top + SMALL * 0.75 + 0.5),
        SMALL,
        &title,
        Font::Bold,
        Align::Left,
        BLACK,
    ));
    draw_ruler(&f, c, marks, &mut items);
    draw_ticks(&f, ticks, &mut items);
    let boxes = draw_labels(&f, labels, &mut items);
    draw_marks(&f, c, marks, &boxes, &mut items);
    items
}

/// Where a tile sits: its left edge, the page y of its first millimetre,
/// the span it shows and the x of its line.
struct Frame {
    x0: f64,
    y0: f64,
    from: f64,
    to: f64,
    x_line: f64,
}

impl Frame {
    /// The page y of the point `z` mm along the line.
    #[inline]
    fn y(&self, z: f64) -> f64 {
        self.y0 + z - self.from
    }
}

/// The 1:1 ruler beside the line, with its numbers.
fn draw_ruler(f: &Frame, c: &Columns, marks: &[(usize, f64, &str)], items: &mut Vec<Item>) {
    let (x0, from, to) = (f.x0, f.from, f.to);
    let x_ruler = x0 + c.ruler;
    let y = |z: f64| f.y(z);
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
        // A number the registration line would cross is left out.
        if k % 10 == 0 && marks.iter().all(|m| (m.1 - k as f64).abs() > 1.6) {
            items.push(text_item(
                DVec2::new(x0 + c.numbers, y(k as f64) + LABEL * 0.35),
                LABEL,
                &k.to_string(),
                Font::Regular,
                Align::Right,
                GREY,
            ));
        }
        k += 1;
    }
}

/// The pivot ticks on the line.
fn draw_ticks(f: &Frame, ticks: &[(f64, Vec<String>, bool)], items: &mut Vec<Item>) {
    let (from, to, x_line) = (f.from, f.to, f.x_line);
    let y = |z: f64| f.y(z);
    // Ticks: vertex pivots to the right, scissor pivots to the left.
    for (z, _, vertex) in ticks
        .iter()
        .filter(|t| t.0 >= from - 1e-9 && t.0 <= to + 1e-9)
    {
        let (colour, reach) = if *vertex {
            (VERTEX, 7.0)
        } else {
            (PIVOT, -5.0)
        };
        items.push(Item::art(
            Ink::line(colour, 0.3),
            Shape::polyline(
                &[DVec2::new(x_line, y(*z)), DVec2::new(x_line + reach, y(*z))],
                false,
            ),
        ));
    }
}

/// The labels; returns their boxes (x from, x to, y from, y to).
fn draw_labels(f: &Frame, labels: &[Label], items: &mut Vec<Item>) -> Vec<(f64, f64, f64, f64)> {
    let x_line = f.x_line;
    let y = |z: f64| f.y(z);
    // Labels, with a leader back to their tick.
    let mut boxes: Vec<(f64, f64, f64, f64)> = Vec::new();
    for l in labels {
        let (colour, reach, gap, align) = if l.vertex {
            (VERTEX, 7.0, 4.0, Align::Left)
        } else {
            (PIVOT, -5.0, -4.0, Align::Right)
        };
        let x_end = x_line + reach;
        let x_text = x_end + gap;
        items.push(Item::art(
            Ink::line(colour, 0.12),
            Shape::polyline(
                &[
                    DVec2::new(x_end, y(l.z)),
                    DVec2::new(x_text - gap.signum(), y(l.at)),
                ],
                false,
            ),
        ));
        let at = DVec2::new(x_text, y(l.at) + LABEL * 0.35);
        let start = text::start(at, &l.text, Font::Regular, LABEL, align);
        let w = text::width(&l.text, Font::Regular, LABEL);
        boxes.push((
            start.x,
            start.x + w,
            at.y - 0.75 * LABEL,
            at.y + 0.2 * LABEL,
        ));
        items.push(text_item(at, LABEL, &l.text, Font::Regular, align, colour));
    }
    boxes
}

/// The registration marks, stopping short of the label boxes.
fn draw_marks(
    f: &Frame,
    c: &Columns,
    marks: &[(usize, f64, &str)],
    boxes: &[(f64, f64, f64, f64)],
    items: &mut Vec<Item>,
) {
    let x0 = f.x0;
    let y = |z: f64| f.y(z);
    // Registration marks: a line across the tile with a cross at each end.
    for &(m, z, which) in marks {
        let yy = y(z);
        let x_cross = x0 + c.cross;
        // The line stops short of the labels it would strike through.
        let mut gaps: Vec<(f64, f64)> = boxes
            .iter()
            .filter(|b| b.2 - 0.3 < yy && yy < b.3 + 0.3)
            .map(|b| (b.0 - 0.8, b.1 + 0.8))
            .collect();
        gaps.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut x = x0;
        for (a, b) in gaps.into_iter().chain([(x_cross, x_cross)]) {
            if a > x {
                items.push(Item::art(
                    Ink::line(BLACK, 0.15),
                    Shape::polyline(&[DVec2::new(x, yy), DVec2::new(a.min(x_cross), yy)], false),
                ));
            }
            x = x.max(b);
        }
        for x in [x0, x_cross] {
            items.push(Item::art(
                Ink::line(BLACK, 0.3),
                Shape::polyline(&[DVec2::new(x, yy - 3.0), DVec2::new(x, yy + 3.0)], false),
            ));
        }
        items.push(text_item(
            DVec2::new(x_cross + 2.0, yy + LABEL * 0.35),
            LABEL,
            &format!("mark {m}{which}"),
            Font::Bold,
            Align::Left,
            BLACK,
        ));
    }
}

fn label_text(names: &[String], more: usize) -> String {
    if more == 0 {
        names[0].clone()
    } else {
        format!("{} +{more}", names[0])
    }
}
