//! The printable assembly guide, as drawing-model pages: a cover, the bill
//! of materials with a 1:1 ruler, one step per row, the collapsed state as a
//! 1:1 inspection gauge, and a checklist. Everything a maker needs to build
//! the lattice on a table without a screen.

pub mod steps;

use crate::build::Build;
use crate::drawing::picture::{
    Camera, Fit, PIVOT, RodStyle, VERTEX, lattice_picture, pivots_and_vertices, rods,
};
use crate::drawing::{Align, Font, Group, Ink, Item, Page, Place, Shape, Symbol};
use crate::lattice::VertexKey;
use glam::DVec2;
pub use steps::{Step, steps};

const MARGIN: f64 = 15.0;
const BODY: f64 = 3.6;
const SMALL: f64 = 3.0;
const LINE: f64 = 5.0;
const BLACK: [u8; 3] = [0, 0, 0];
const GREY: [u8; 3] = [110, 110, 110];
const FAINT: [u8; 3] = [185, 185, 185];
const NEW: [u8; 3] = [214, 40, 40];

/// Builds pages top to bottom, starting a new page when one is full.
struct Writer {
    size: (f64, f64),
    title: String,
    pages: Vec<Page>,
    /// This page's finished groups, then the items of its open one.
    groups: Vec<Group>,
    items: Vec<Item>,
    y: f64,
    /// Drawn at the top of every continuation page.
    running_head: Option<String>,
}

impl Writer {
    fn new(size: (f64, f64), title: String) -> Self {
        Self {
            size,
            title,
            pages: Vec::new(),
            groups: Vec::new(),
            items: Vec::new(),
            y: MARGIN,
            running_head: None,
        }
    }

    fn width(&self) -> f64 {
        self.size.0 - 2.0 * MARGIN
    }

    fn bottom(&self) -> f64 {
        self.size.1 - MARGIN - 6.0
    }

    fn finish_page(&mut self) {
        if self.items.is_empty() && self.groups.is_empty() {
            return;
        }
        let number = self.pages.len() + 1;
        let footer = format!("{} - page {number}", self.title);
        let at = DVec2::new(self.size.0 / 2.0, self.size.1 - MARGIN / 2.0);
        self.items.push(text_item(
            at,
            SMALL,
            &footer,
            Font::Regular,
            Align::Center,
            GREY,
        ));
        self.close_group();
        self.pages.push(Page {
            width: self.size.0,
            height: self.size.1,
            title: format!("{} page {number}", self.title),
            metadata: Vec::new(),
            groups: std::mem::take(&mut self.groups),
        });
        self.y = MARGIN;
    }

    fn new_page(&mut self) {
        self.finish_page();
        self.y = MARGIN;
    }

    /// Room for `height` more mm, else continue on a new page.
    fn need(&mut self, height: f64) {
        if self.y + height > self.bottom() {
            self.new_page();
            if let Some(head) = self.running_head.clone() {
                self.text(&format!("{head} (continued)"), BODY, Font::Bold, GREY);
                self.y += 2.0;
            }
        }
    }

    fn text_at(&mut self, x: f64, text: &str, size: f64, font: Font, colour: [u8; 3]) {
        self.items.push(text_item(
            DVec2::new(x, self.y + size * 0.75),
            size,
            text,
            font,
            Align::Left,
            colour,
        ));
    }

    /// A line of text at the left margin; moves down.
    fn text(&mut self, text: &str, size: f64, font: Font, colour: [u8; 3]) {
        self.need(size * 1.4);
        self.text_at(MARGIN, text, size, font, colour);
        self.y += size * 1.4;
    }

    fn heading(&mut self, text: &str) {
        self.need(14.0);
        self.text(text, 7.0, Font::Bold, BLACK);
        self.y += 2.0;
    }

    /// A paragraph wrapped to the text width.
    fn paragraph(&mut self, text: &str, size: f64, colour: [u8; 3]) {
        let mut line = String::new();
        for word in text.split_whitespace() {
            let candidate = if line.is_empty() {
                word.to_string()
            } else {
                format!("{line} {word}")
            };
            if crate::drawing::text::width(&candidate, Font::Regular, size) > self.width()
                && !line.is_empty()
            {
                self.text(&line, size, Font::Regular, colour);
                line = word.to_string();
            } else {
                line = candidate;
            }
        }
        if !line.is_empty() {
            self.text(&line, size, Font::Regular, colour);
        }
        self.y += size * 0.4;
    }

    /// Table rows in fixed columns (x offsets from the margin).
    fn row(&mut self, columns: &[f64], cells: &[String], font: Font, colour: [u8; 3]) {
        self.need(LINE);
        for (x, cell) in columns.iter().zip(cells) {
            self.text_at(MARGIN + x, cell, SMALL, font, colour);
        }
        self.y += LINE * 0.85;
    }

    fn rule(&mut self) {
        let y = self.y;
        self.items.push(Item::art(
            Ink::line(FAINT, 0.2),
            Shape::polyline(
                &[DVec2::new(MARGIN, y), DVec2::new(self.size.0 - MARGIN, y)],
                false,
            ),
        ));
        self.y += 1.5;
    }

    fn push(&mut self, items: Vec<Item>) {
        self.items.extend(items);
    }

    /// The open items become a group of their own.
    fn close_group(&mut self) {
        if !self.items.is_empty() {
            let id = format!("page-{}-{}", self.pages.len() + 1, self.groups.len() + 1);
            self.groups
                .push(Group::new(id, std::mem::take(&mut self.items)));
        }
    }

    /// Draw shared symbols here, after what the page has so far.
    fn place(&mut self, places: Vec<Place>) {
        self.close_group();
        let id = format!("page-{}-{}", self.pages.len() + 1, self.groups.len() + 1);
        self.groups.push(Group {
            id,
            symbols: places,
            items: Vec::new(),
        });
    }
}

fn text_item(at: DVec2, size: f64, text: &str, font: Font, align: Align, colour: [u8; 3]) -> Item {
    Item::art(
        Ink::fill(colour),
        Shape::Text {
            at,
            size,
            text: text.to_string(),
            font,
            align,
        },
    )
}

fn key(k: VertexKey) -> String {
    format!("[{},{}]", k.row, k.col)
}

fn mm(x: f64) -> String {
    format!("{x:.1} mm")
}

/// How many spares to buy: a tenth more, at least two.
pub fn spares(n: usize) -> usize {
    n.div_ceil(10).max(2)
}

/// The guide's pages and the drawings they share.
#[derive(Clone, Debug, PartialEq)]
pub struct Guide {
    pub pages: Vec<Page>,
    /// The lattice's rows, drawn once each and placed on every step page
    /// that shows them (see `StepPictures`).
    pub symbols: Vec<Symbol>,
}

/// The guide for a build, on its paper (A4 or US Letter, portrait).
pub fn guide(b: &Build) -> Guide {
    let fab = &b.design.fabrication;
    let mut w = Writer::new(
        fab.paper.size(),
        format!("{} assembly guide", b.design.name),
    );
    let steps = steps(&b.lattice);
    cover(&mut w, b, &steps);
    materials(&mut w, b);
    let pictures = StepPictures::new(b, &steps, w.width());
    for step in &steps {
        step_pages(&mut w, b, step, steps.len(), &pictures);
    }
    gauge(&mut w, b);
    checklist(&mut w, b, &steps);
    w.finish_page();
    Guide {
        pages: w.pages,
        symbols: pictures.symbols,
    }
}

/// The height of a step page's picture of the lattice (mm).
const STEP_PICTURE: f64 = 95.0;

/// The step pages' pictures of the lattice, as shared symbols: step k shows
/// rows 0..k grey (faint), row k in colour on top, then the dots at the
/// pivots and vertices of rows 0..=k. Each row's grey rods and its dots are
/// one symbol each, drawn once; blocks of about sqrt(steps) consecutive
/// rows are symbols too, so that a page places at most about 2 sqrt(steps)
/// symbols and the whole guide grows with the cells, not rows x cells.
struct StepPictures {
    symbols: Vec<Symbol>,
    /// Symbol of each row's grey rods, and of its dots.
    faint: Vec<usize>,
    dots: Vec<usize>,
    /// Symbols of whole blocks of `block` rows: grey rods, dots.
    faint_blocks: Vec<usize>,
    dot_blocks: Vec<usize>,
    block: usize,
    /// Rod width of the grey rods (mm); the new row's is 1.3 times wider.
    width: f64,
}

impl StepPictures {
    fn new(b: &Build, steps: &[Step], text_width: f64) -> Self {
        let lattice = &b.assembled;
        // Symbols are drawn with the picture box's top-left corner at 0.
        let fit = Self::fit(b, DVec2::ZERO, text_width);
        let width = Self::rod_width(b, &fit);
        // Each vertex's dot belongs to the first step that shows it.
        let mut first = vec![usize::MAX; lattice.vertices.len()];
        let mut new_vertices: Vec<Vec<usize>> = vec![Vec::new(); steps.len()];
        for (k, step) in steps.iter().enumerate() {
            for &c in &step.cells {
                let cell = &lattice.cells[c];
                for v in [cell.ul, cell.ur, cell.ll, cell.lr] {
                    if first[v as usize] == usize::MAX {
                        first[v as usize] = k;
                        new_vertices[k].push(v as usize);
                    }
                }
            }
            new_vertices[k].sort_unstable();
        }
        let mut symbols = Vec::with_capacity(2 * steps.len() + 16);
        let (mut faint, mut dots) = (Vec::new(), Vec::new());
        for (step, vertices) in steps.iter().zip(&new_vertices) {
            let style = |_| {
                Some(RodStyle {
                    colour: FAINT,
                    width,
                })
            };
            faint.push(symbols.len());
            symbols.push(Symbol {
                uses: Vec::new(),
                items: rods(lattice, &fit, &step.cells, style),
            });
            dots.push(symbols.len());
            symbols.push(Symbol {
                uses: Vec::new(),
                items: pivots_and_vertices(lattice, &fit, &step.cells, vertices, width * 0.8),
            });
        }
        let block = (steps.len() as f64).sqrt().ceil().max(1.0) as usize;
        let (mut faint_blocks, mut dot_blocks) = (Vec::new(), Vec::new());
        for start in (0..steps.len()).step_by(block) {
            if start + block > steps.len() {
                break;
            }
            for (rows, blocks) in [(&faint, &mut faint_blocks), (&dots, &mut dot_blocks)] {
                blocks.push(symbols.len());
                symbols.push(Symbol {
                    uses: rows[start..start + block].to_vec(),
                    items: Vec::new(),
                });
            }
        }
        Self {
            symbols,
            faint,
            dots,
            faint_blocks,
            dot_blocks,
            block,
            width,
        }
    }

    fn fit(b: &Build, origin: DVec2, text_width: f64) -> Fit {
        Fit::new(
            &b.assembled,
            Camera::for_lattice(&b.assembled),
            origin,
            DVec2::new(text_width, STEP_PICTURE),
        )
    }

    fn rod_width(b: &Build, fit: &Fit) -> f64 {
        (0.6 * fit.scale() * b.design.fabrication.material.width).clamp(0.3, 1.4)
    }

    /// Symbols showing rows `0..end`, from `rows` and whole `blocks`.
    fn prefix(&self, rows: &[usize], blocks: &[usize], end: usize, at: DVec2) -> Vec<Place> {
        let whole = (end / self.block).min(blocks.len());
        blocks[..whole]
            .iter()
            .chain(&rows[whole * self.block..end])
            .map(|&symbol| Place { symbol, at })
            .collect()
    }
}

fn cover(w: &mut Writer, b: &Build, steps: &[Step]) {
    let fab = &b.design.fabrication;
    w.text(&b.design.name, 10.0, Font::Bold, BLACK);
    w.text("Scissor lattice - assembly guide", 5.0, Font::Regular, GREY);
    w.y += 4.0;
    let box_size = DVec2::new(w.width(), 120.0);
    let fit = Fit::new(
        &b.assembled,
        Camera::for_lattice(&b.assembled),
        DVec2::new(MARGIN, w.y),
        box_size,
    );
    let width = (0.6 * fit.scale() * fab.material.width).clamp(0.3, 1.6);
    w.push(lattice_picture(
        &b.assembled,
        &fit,
        |_| {
            Some(RodStyle {
                colour: [60, 60, 60],
                width,
            })
        },
        width * 0.9,
    ));
    w.y += box_size.y + 8.0;
    let (lo, hi) = b.assembled.extent();
    let size = hi - lo;
    let dims: Vec<String> = size.to_array()[..b.lattice.dim]
        .iter()
        .map(|x| format!("{x:.0}"))
        .collect();
    let vertex = b.parts.vertex_eyelets;
    let pivot = b.parts.pivot_eyelets;
    let helix = b.lattice.kind == crate::lattice::Kind::Helix;
    let facts = [
        format!("Deployed size: {} mm", dims.join(" x ")),
        if helix {
            format!(
                "Cells: {} on a helix, {} to a turn",
                b.lattice.cells.len(),
                b.lattice.width
            )
        } else {
            format!(
                "Cells: {} in {} rows of {}",
                b.lattice.cells.len(),
                b.lattice.rows(),
                b.lattice.width
            )
        },
        format!(
            "Strips: {} of {} {} mm, {} mm wide, cut from {} sheet{} of {} x {} mm",
            b.parts.strips.len(),
            fab.material.name,
            fab.material.thickness,
            fab.material.width,
            b.layout.sheets.len(),
            if b.layout.sheets.len() == 1 { "" } else { "s" },
            fab.sheet.width,
            fab.sheet.height
        ),
        format!(
            "Eyelets ({}): {} ({pivot} at scissor pivots, {vertex} at vertex pivots)",
            fab.eyelet.name,
            pivot + vertex
        ),
        format!(
            "Steps: {}, one for each {}, in the order the lattice was grown",
            steps.len(),
            if helix { "cell" } else { "row" }
        ),
    ];
    for f in &facts {
        w.text(f, BODY, Font::Regular, BLACK);
    }
    w.y += 3.0;
    w.text("Tools", 4.5, Font::Bold, BLACK);
    for t in [
        "A laser cutter, with cut.pdf or the files in sheets/ (SVG or DXF).".to_string(),
        format!(
            "An eyelet setter for {} eyelets and a small hammer or an eyelet press.",
            fab.eyelet.name
        ),
        "A flat table, and this guide printed at 100 % (actual size): its gauges are 1:1."
            .to_string(),
    ] {
        w.text(&format!("-  {t}"), BODY, Font::Regular, BLACK);
    }
    w.y += 3.0;
    w.paragraph(
        "Every strip carries its ID, e.g. R03-C05-A: cell row 3, column 5, rod A. The arrow < in front of it points \
         to the strip's upper end, the vertex of the earlier row. Strips of a cell cross at its scissor pivot with \
         rod A under rod B.",
        BODY,
        GREY,
    );
    w.new_page();
}

fn materials(w: &mut Writer, b: &Build) {
    let fab = &b.design.fabrication;
    w.heading("Bill of materials");
    w.running_head = Some("Bill of materials".into());
    let columns = [0.0, 30.0, 58.0, 110.0, 128.0];
    let header = [
        "Strip",
        "Tip to tip",
        "Hole pitch",
        "Sheet",
        "Position on the sheet",
    ]
    .map(String::from);
    w.row(&columns, &header, Font::Bold, BLACK);
    w.rule();
    let mut place = vec![None; b.parts.strips.len()];
    for (s, sheet) in b.layout.sheets.iter().enumerate() {
        for p in &sheet.placements {
            place[p.part] = Some((s + 1, *p));
        }
    }
    for (strip, place) in b.parts.strips.iter().zip(place) {
        let (sheet, p) = place.expect("every strip is placed");
        w.row(
            &columns,
            &[
                strip.id.clone(),
                mm(strip.length),
                format!("{:.1} + {:.1} mm", strip.legs[0], strip.legs[1]),
                sheet.to_string(),
                format!(
                    "x {:.0}, y {:.0} mm{}",
                    p.x,
                    p.y,
                    if p.rotated { ", upright" } else { "" }
                ),
            ],
            Font::Regular,
            BLACK,
        );
    }
    w.running_head = None;
    w.y += 4.0;
    w.need(60.0);
    w.text("Eyelets", 4.5, Font::Bold, BLACK);
    let mut by_stack = std::collections::BTreeMap::new();
    for j in crate::lattice::joints(&b.lattice)
        .iter()
        .filter(|j| j.needs_eyelet())
    {
        *by_stack.entry(j.ends.len()).or_insert(0usize) += 1;
    }
    let mut kinds = vec![(
        "scissor pivots, through 2 strips".to_string(),
        b.parts.pivot_eyelets,
    )];
    kinds.extend(
        by_stack
            .iter()
            .map(|(k, n)| (format!("vertex pivots, through {k} strips"), *n)),
    );
    for (kind, n) in &kinds {
        w.text(
            &format!("{n:>5}  {kind}  (+{} spares)", spares(*n)),
            BODY,
            Font::Regular,
            BLACK,
        );
    }
    let total: usize = kinds.iter().map(|k| k.1).sum();
    let spare: usize = kinds.iter().map(|k| spares(k.1)).sum();
    w.text(
        &format!(
            "{total:>5}  {} eyelets in all; buy {} with spares",
            fab.eyelet.name,
            total + spare
        ),
        BODY,
        Font::Bold,
        BLACK,
    );
    w.paragraph(
        "Stacks of 3 and 4 strips need eyelets with a longer barrel than the pivots' 2: check them on a test stack.",
        SMALL,
        GREY,
    );
    ruler(w);
}

/// A 1:1 ruler: print at 100 % and it must measure what it says.
fn ruler(w: &mut Writer) {
    let length = 150.0f64.min(w.width() - 10.0).floor();
    w.need(22.0);
    w.y += 3.0;
    w.text(
        &format!("Length gauge (1:1): this ruler must measure {length:.0} mm on paper"),
        BODY,
        Font::Bold,
        BLACK,
    );
    let y = w.y + 8.0;
    let x0 = MARGIN;
    let mut items = vec![Item::art(
        Ink::line(BLACK, 0.25),
        Shape::polyline(&[DVec2::new(x0, y), DVec2::new(x0 + length, y)], false),
    )];
    for k in 0..=(length as usize) {
        let tick = if k % 10 == 0 {
            5.0
        } else if k % 5 == 0 {
            3.5
        } else {
            2.0
        };
        let x = x0 + k as f64;
        items.push(Item::art(
            Ink::line(BLACK, 0.15),
            Shape::polyline(&[DVec2::new(x, y), DVec2::new(x, y - tick)], false),
        ));
        if k % 10 == 0 {
            items.push(text_item(
                DVec2::new(x, y + 3.5),
                2.5,
                &k.to_string(),
                Font::Regular,
                Align::Center,
                BLACK,
            ));
        }
    }
    w.push(items);
    w.y = y + 8.0;
}

fn step_pages(w: &mut Writer, b: &Build, step: &Step, count: usize, pictures: &StepPictures) {
    let strips = &b.parts.strips;
    w.new_page();
    // Step number and progress bar.
    w.text_at(
        MARGIN,
        &format!("Step {}", step.number),
        14.0,
        Font::Bold,
        BLACK,
    );
    let bar_x = MARGIN + 70.0;
    let bar_w = w.width() - 70.0;
    let fraction = step.number as f64 / count as f64;
    let y = w.y + 4.0;
    w.push(vec![
        Item::art(
            Ink {
                stroke: Some(GREY),
                width: 0.3,
                fill: None,
            },
            rect(bar_x, y, bar_w, 5.0),
        ),
        Item::art(Ink::fill(NEW), rect(bar_x, y, bar_w * fraction, 5.0)),
        text_item(
            DVec2::new(bar_x, y + 10.0),
            SMALL,
            &format!("step {} of {count}", step.number),
            Font::Regular,
            Align::Left,
            GREY,
        ),
    ]);
    w.y += 18.0;
    w.text(
        &format!(
            "{} {}: {}, {}, {}",
            if b.lattice.kind == crate::lattice::Kind::Helix {
                "Cell"
            } else {
                "Row"
            },
            step.row,
            plural(step.cells.len(), "cell"),
            plural(step.strips.len(), "strip"),
            plural(step.eyelets, "eyelet")
        ),
        BODY + 0.6,
        Font::Bold,
        BLACK,
    );
    // The lattice so far: earlier rows grey, this row in colour on top of
    // them, later rows not yet there; then the dots of the rows shown.
    let at = DVec2::new(MARGIN, w.y + 2.0);
    let k = step.number - 1;
    w.place(pictures.prefix(&pictures.faint, &pictures.faint_blocks, k, at));
    let fit = StepPictures::fit(b, at, w.width());
    let width = pictures.width;
    w.push(rods(&b.assembled, &fit, &step.cells, |_| {
        Some(RodStyle {
            colour: NEW,
            width: width * 1.3,
        })
    }));
    w.place(pictures.prefix(&pictures.dots, &pictures.dot_blocks, k + 1, at));
    w.y += STEP_PICTURE + 6.0;
    w.running_head = Some(format!("Step {}", step.number));

    w.text(
        "1. Pair the two strips of each cell at its scissor pivot, A under B, and set an eyelet:",
        BODY,
        Font::Bold,
        BLACK,
    );
    let pairs: Vec<String> = step
        .cells
        .iter()
        .map(|&c| format!("{} + {}", strips[2 * c].id, strips[2 * c + 1].id))
        .collect();
    columns(w, &pairs, 2);
    w.y += 2.0;
    if step.joints.is_empty() {
        w.text(
            "2. No vertex joint closes in this step.",
            BODY,
            Font::Bold,
            BLACK,
        );
    } else {
        w.text(
            "2. Close these vertex joints, strips stacked from the table up, one eyelet each:",
            BODY,
            Font::Bold,
            BLACK,
        );
        let lines: Vec<String> = step
            .joints
            .iter()
            .map(|j| {
                let stack: Vec<&str> = j.ends.iter().map(|e| strips[e.rod].id.as_str()).collect();
                format!(
                    "{}  {}",
                    key(b.lattice.vertex(j.vertex).key),
                    stack.join(" / ")
                )
            })
            .collect();
        columns(w, &lines, 1);
    }
    w.y += 2.0;
    w.text(
        &format!(
            "Eyelets in this step: {}. Set so far: {} of {}.",
            step.eyelets,
            step.total,
            b.parts.eyelets()
        ),
        BODY,
        Font::Bold,
        NEW,
    );
    w.running_head = None;
}

fn rect(x: f64, y: f64, w: f64, h: f64) -> Shape {
    Shape::polyline(
        &[
            DVec2::new(x, y),
            DVec2::new(x + w, y),
            DVec2::new(x + w, y + h),
            DVec2::new(x, y + h),
        ],
        true,
    )
}

/// Short lines in `n` columns across the text width.
fn columns(w: &mut Writer, lines: &[String], n: usize) {
    let col = w.width() / n as f64;
    for chunk in lines.chunks(n) {
        w.need(LINE);
        for (k, line) in chunk.iter().enumerate() {
            w.text_at(
                MARGIN + 4.0 + k as f64 * col,
                line,
                SMALL,
                Font::Regular,
                BLACK,
            );
        }
        w.y += LINE * 0.85;
    }
}

/// The collapsed state at 1:1 (MATH.md 3.2, 10.3): every hole of the folded
/// lattice on one line, at its collapsed coordinate z. A folded stack of
/// strips laid on the line must show a hole over every tick.
fn gauge(w: &mut Writer, b: &Build) {
    w.new_page();
    w.heading("Inspection gauge: the folded lattice (1:1)");
    let first = b
        .lattice
        .vertices
        .iter()
        .min_by(|a, b| a.z.total_cmp(&b.z))
        .map_or(String::new(), |v| key(v.key));
    w.paragraph(
        &format!(
            "Folded flat, every strip of the lattice lies on one line and every hole sits at a fixed distance along it. \
             Blue ticks are vertex pivots [row,column], orange ticks scissor pivots (row,column). Fold a finished part \
             of the lattice flat, lay it on the line with vertex {first} on 0, and check that the holes fall on the \
             ticks before setting the last eyelets. Print at 100 %: 10 mm on the scale is 10 mm on paper."
        ),
        SMALL,
        GREY,
    );
    let z0 = b
        .lattice
        .vertices
        .iter()
        .map(|v| v.z)
        .chain(b.lattice.cells.iter().map(|c| c.z_pivot))
        .fold(f64::INFINITY, f64::min);
    let mut marks: Vec<(f64, String, bool)> = b
        .lattice
        .vertices
        .iter()
        .map(|v| (v.z - z0, key(v.key), true))
        .collect();
    marks.extend(
        b.lattice
            .cells
            .iter()
            .map(|c| (c.z_pivot - z0, format!("({},{})", c.row, c.col), false)),
    );
    marks.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.2.cmp(&a.2)));
    // Holes closer than 0.05 mm share a tick.
    let mut ticks: Vec<(f64, Vec<String>, bool)> = Vec::new();
    for (z, label, vertex) in marks {
        match ticks.last_mut() {
            Some(t) if (z - t.0).abs() < 0.05 && t.2 == vertex => t.1.push(label),
            _ => ticks.push((z, vec![label], vertex)),
        }
    }
    let total = ticks.last().map_or(0.0, |t| t.0);
    let span = (w.width() - 10.0).floor();
    let lines = (total / span).floor() as usize + 1;
    for line in 0..lines {
        let (from, to) = (line as f64 * span, (line as f64 + 1.0) * span);
        w.need(34.0);
        let y = w.y + 14.0;
        let x0 = MARGIN + 5.0;
        let end = (total.min(to) - from).max(0.0);
        let mut items = vec![Item::art(
            Ink::line(BLACK, 0.25),
            Shape::polyline(&[DVec2::new(x0, y), DVec2::new(x0 + end, y)], false),
        )];
        let mut k = (from / 10.0).ceil() as usize;
        while (k as f64) * 10.0 <= total.min(to) + 1e-9 {
            let x = x0 + k as f64 * 10.0 - from;
            items.push(Item::art(
                Ink::line(GREY, 0.15),
                Shape::polyline(&[DVec2::new(x, y), DVec2::new(x, y + 2.0)], false),
            ));
            items.push(text_item(
                DVec2::new(x, y + 5.0),
                2.2,
                &format!("{}", k * 10),
                Font::Regular,
                Align::Center,
                GREY,
            ));
            k += 1;
        }
        let mut last_label = [f64::NEG_INFINITY; 2];
        for (z, labels, vertex) in ticks.iter().filter(|t| t.0 >= from - 1e-9 && t.0 < to) {
            let x = x0 + z - from;
            let (colour, reach) = if *vertex { (VERTEX, 7.0) } else { (PIVOT, 4.5) };
            items.push(Item::art(
                Ink::line(colour, 0.3),
                Shape::polyline(&[DVec2::new(x, y), DVec2::new(x, y - reach)], false),
            ));
            // Labels alternate between two heights and skip when crowded.
            let slot = *vertex as usize;
            let text = if labels.len() > 1 {
                format!("{} +{}", labels[0], labels.len() - 1)
            } else {
                labels[0].clone()
            };
            let size = 1.8;
            if x - last_label[slot] > crate::drawing::text::width(&text, Font::Regular, size) + 1.0
            {
                items.push(text_item(
                    DVec2::new(x, y - reach - 1.0),
                    size,
                    &text,
                    Font::Regular,
                    Align::Center,
                    colour,
                ));
                last_label[slot] = x;
            }
        }
        w.push(items);
        w.y = y + 12.0;
    }
}

fn checklist(w: &mut Writer, b: &Build, steps: &[Step]) {
    w.new_page();
    w.heading("Checklist");
    let pivot = b.parts.pivot_eyelets;
    let vertex = b.parts.vertex_eyelets;
    let items = [
        format!(
            "All {} strips cut, each with its ID and arrow legible.",
            b.parts.strips.len()
        ),
        format!("{pivot} scissor-pivot eyelets set, rod A under rod B in every cell."),
        format!("{vertex} vertex eyelets set, each stack in the order its step lists."),
        format!("All {} steps done; no strip left over.", steps.len()),
        "Folded flat, the holes lie on the inspection gauge's ticks.".to_string(),
        "Open the lattice slowly from one corner; stop at any joint that binds.".to_string(),
    ];
    for item in items {
        w.need(8.0);
        let y = w.y;
        w.push(vec![Item::art(
            Ink::line(BLACK, 0.3),
            rect(MARGIN, y, 4.0, 4.0),
        )]);
        w.text_at(MARGIN + 7.0, &item, BODY, Font::Regular, BLACK);
        w.y += 8.0;
    }
    w.y += 4.0;
    let note = if b.lattice.width == 1 {
        "This chain is a true mechanism: it opens and closes through every angle without bending a strip."
    } else {
        "A lattice of several rows generally reaches its deployed shape by bending its strips slightly on the way \
         (docs/verification.md, Deployment): that is expected, not a fault."
    };
    w.paragraph(note, BODY, GREY);
}

/// "1 cell", "3 cells".
fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}
