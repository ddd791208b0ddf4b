//! The printable assembly guide, as drawing-model pages: a cover, the bill
//! of materials with a 1:1 ruler, one step per row, the collapsed state as a
//! 1:1 inspection gauge, and a checklist. Everything a maker needs to build
//! the lattice on a table without a screen.

mod gauge;
mod labels;
pub(crate) mod stacking;
pub mod steps;

use crate::build::Build;
use crate::drawing::picture::{
    Camera, Fit, RodStyle, VERTEX, crossing_rods, lattice_picture, pivots_and_vertices, rods,
};
use crate::drawing::{Align, Font, Group, Ink, Item, Page, Place, Shape, Symbol};
use crate::lattice::VertexKey;
pub use gauge::{GAUGE_OVERLAP, gauge_tiles};
use glam::DVec2;
use labels::{Label, Placer};
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
    /// The id of the groups closed while it is set (e.g. "step-3-text"),
    /// so tests and readers find a step's words and picture labels.
    group_id: Option<String>,
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
            group_id: None,
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
        // The footer belongs to no step: close the open group first.
        self.close_group();
        let id = self.group_id.take();
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
        self.group_id = id;
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
                let id = self.group_id.take();
                self.text(&format!("{head} (continued)"), BODY, Font::Bold, GREY);
                self.close_group();
                self.group_id = id;
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
        for line in self.wrap(text, size) {
            self.text(&line, size, Font::Regular, colour);
        }
        self.y += size * 0.4;
    }

    /// The lines of a paragraph wrapped to the text width.
    fn wrap(&self, text: &str, size: f64) -> Vec<String> {
        wrap(text, Font::Regular, size, self.width())
    }

    /// How far `paragraph` moves down, when it does not break the page.
    fn paragraph_height(&self, text: &str, size: f64) -> f64 {
        self.wrap(text, size).len() as f64 * size * 1.4 + size * 0.4
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
            let id = self.group_id.clone().unwrap_or_else(|| {
                format!("page-{}-{}", self.pages.len() + 1, self.groups.len() + 1)
            });
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
pub(crate) fn spares(n: usize) -> usize {
    n.div_ceil(10).max(2)
}

/// The guide's pages and the drawings they share.
#[derive(Clone, Debug, PartialEq)]
pub struct Guide {
    /// The guide's pages, in reading order.
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
    let side = stacking::side(&b.lattice);
    cover(&mut w, b, &steps, &side);
    materials(&mut w, b);
    test_piece_block(&mut w, b);
    let layout = StepLayout::new(b, &steps, w.width());
    let pictures = StepPictures::new(b, &steps, layout.overview());
    for step in &steps {
        step_block(&mut w, b, step, steps.len(), &pictures, &layout, &side);
    }
    // The checklist before the gauge: the gauge's pages are cut up.
    checklist(&mut w, b, &steps);
    gauge::gauge(&mut w, b);
    w.finish_page();
    Guide {
        pages: w.pages,
        symbols: pictures.symbols,
    }
}

/// The height of a step page's picture of the lattice (mm).
const STEP_PICTURE: f64 = 84.0;

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
    fn new(b: &Build, steps: &[Step], size: DVec2) -> Self {
        let lattice = &b.assembled;
        // Symbols are drawn with the picture box's top-left corner at 0.
        let fit = Self::fit(b, DVec2::ZERO, size);
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

    fn fit(b: &Build, origin: DVec2, size: DVec2) -> Fit {
        Fit::new(&b.assembled, step_camera(b), origin, size)
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

fn cover(w: &mut Writer, b: &Build, steps: &[Step], side: &stacking::Side) {
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
        &format!("Stacking side: {}. {}", side.name, side.explain),
        BODY,
        BLACK,
    );
    if let Some(bumps) = bumps(b) {
        w.paragraph(&bumps, BODY, BLACK);
    }
    w.paragraph(
        "Strips are picked by part type: strips of one type are the same part. A strip is engraved with its ID \
         (R03-C05-A: row 3, column 5, rod A) where it fits, else its type code or a dot code (see the bill of \
         materials). The arrow < points to the strip's upper end, the one joined to the row above. In every \
         cell rod A runs from its upper left corner to its lower right one and rod B crosses over it. Each step's \
         picture shows the work so far in grey and the new strips in red, labelled with their types, the joints \
         to close with their keys, and the columns in grey.",
        BODY,
        GREY,
    );
    w.new_page();
}

/// What is engraved on the strips of a type, e.g. "ID 12, code 3, 4 dots 2".
fn engraved(b: &Build, t: &crate::parts::PartType) -> String {
    use crate::parts::Marking;
    let mut counts: Vec<(String, usize)> = Vec::new();
    for &s in &t.strips {
        let what = match b.parts.strips[s].marking {
            Marking::Id | Marking::Compact => "ID".to_string(),
            Marking::Type => "code".to_string(),
            Marking::Dots(n) => format!("{n} dot{}", if n == 1 { "" } else { "s" }),
            Marking::Arrow => "arrow only".to_string(),
        };
        match counts.iter_mut().find(|c| c.0 == what) {
            Some(c) => c.1 += 1,
            None => counts.push((what, 1)),
        }
    }
    if counts.len() == 1 {
        return counts.remove(0).0;
    }
    counts
        .iter()
        .map(|(what, n)| format!("{what} {n}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Eyelets by grip (the thickness of the stack they hold): (strips in the
/// stack, scissor pivots, vertex joints).
pub fn eyelets_by_grip(b: &Build) -> Vec<(usize, usize, usize)> {
    let mut by: std::collections::BTreeMap<usize, (usize, usize)> = Default::default();
    by.entry(2).or_default().0 += b.parts.pivot_eyelets;
    for j in crate::lattice::joints(&b.lattice)
        .iter()
        .filter(|j| j.needs_eyelet())
    {
        by.entry(j.ends.len()).or_default().1 += 1;
    }
    by.into_iter()
        .filter(|(_, (p, v))| p + v > 0)
        .map(|(k, (p, v))| (k, p, v))
        .collect()
}

fn materials(w: &mut Writer, b: &Build) {
    let fab = &b.design.fabrication;
    let t = fab.material.thickness;
    w.heading("Bill of materials");
    w.running_head = Some("Bill of materials".into());
    w.paragraph(
        &format!(
            "{} strips of {} part types. Strips of one type are the same part (length and hole pitches \
             within {} mm): any of them fits wherever the guide asks for that type.",
            b.parts.strips.len(),
            b.parts.types.len(),
            fab.part_tolerance
        ),
        SMALL,
        GREY,
    );
    w.y += 1.0;
    // Two tables side by side when there are many types.
    let halves = if b.parts.types.len() > 16 { 2 } else { 1 };
    let half = w.width() / halves as f64;
    // Pitches may read "123.4+123.4 both": room for it before Engraved.
    let columns = [0.0, 9.0, 27.0, 41.0, 67.0];
    let header = ["Type", "Strips", "Length", "Pitches", "Engraved"].map(String::from);
    let mut cells: Vec<String> = Vec::new();
    let mut header_cells = Vec::new();
    let mut header_columns = Vec::new();
    for h in 0..halves {
        header_columns.extend(columns.map(|x| x + h as f64 * half));
        header_cells.extend(header.clone());
    }
    w.row(&header_columns, &header_cells, Font::Bold, BLACK);
    w.text(
        "Lengths tip to tip and hole pitches (start to pivot + pivot to end) in mm; \"both\": either end first.",
        SMALL,
        Font::Regular,
        GREY,
    );
    w.rule();
    for chunk in b.parts.types.chunks(halves) {
        let mut row_columns = Vec::new();
        cells.clear();
        for (h, ty) in chunk.iter().enumerate() {
            row_columns.extend(columns.map(|x| x + h as f64 * half));
            let strips = if ty.strips.len() == 1 {
                b.parts.strips[ty.strips[0]].id.clone()
            } else {
                ty.strips.len().to_string()
            };
            cells.extend([
                ty.code.clone(),
                strips,
                format!("{:.1}", ty.length),
                format!(
                    "{:.1}+{:.1}{}",
                    ty.legs[0],
                    ty.legs[1],
                    if ty.symmetric { " both" } else { "" }
                ),
                engraved(b, ty),
            ]);
        }
        w.row(&row_columns, &cells, Font::Regular, BLACK);
    }
    w.y += 2.0;
    let dots: Vec<String> = b
        .parts
        .types
        .iter()
        .filter_map(|t| t.dots.map(|n| format!("{n} = {}", t.code)))
        .collect();
    let mut how = String::from(
        "How to tell strips apart: a strip carries its ID (R03-C05-A: row 3, column 5, rod A) where it fits, \
         else its type code; the arrow < points to its upper end, the one joined to the row above. ",
    );
    if b.design.fabrication.label == crate::fabrication::LabelStyle::Compact {
        how.push_str(
            "This job engraves IDs in compact form: 3.5A is row 3, column 5, rod A (R03-C05-A). ",
        );
    }
    if !dots.is_empty() {
        how.push_str(&format!(
            "Strips too short for text carry a dot code: a row of engraved dots, counted to read the type ({}). ",
            dots.join(", ")
        ));
    }
    how.push_str("parts-types.csv lists every strip with its type and sheet position.");
    w.paragraph(&how, SMALL, GREY);
    if b.parts.types.iter().any(|t| t.strips.len() > 1) {
        w.text("Strips of each type", 4.0, Font::Bold, BLACK);
        let lists: Vec<String> = b
            .parts
            .types
            .iter()
            .filter(|t| t.strips.len() > 1)
            .map(|ty| {
                let ids: Vec<&str> = ty
                    .strips
                    .iter()
                    .map(|&s| b.parts.strips[s].id.as_str())
                    .collect();
                format!("{}: {}.", ty.code, ids.join(" "))
            })
            .collect();
        w.paragraph(&lists.join("  "), SMALL, BLACK);
    }
    w.running_head = None;
    w.y += 3.0;
    w.need(50.0);
    w.text("Eyelets, by grip", 4.5, Font::Bold, BLACK);
    w.paragraph(
        &format!(
            "The grip is the thickness of the stack an eyelet holds: strips x {t} mm. Use eyelets whose barrel \
             is a little longer than the grip. Every eyelet is a pivot: set it loose enough that the strips \
             still turn (roll the flange over, do not flatten the stack)."
        ),
        SMALL,
        GREY,
    );
    let columns = [0.0, 30.0, 55.0, 110.0];
    let header = ["Grip", "Eyelets", "Where", "Buy (with spares)"].map(String::from);
    w.row(&columns, &header, Font::Bold, BLACK);
    w.rule();
    let mut total = 0;
    let mut buy = 0;
    for (k, pivots, joints) in eyelets_by_grip(b) {
        let n = pivots + joints;
        let mut at = Vec::new();
        if pivots > 0 {
            at.push(format!("{pivots} scissor pivots"));
        }
        if joints > 0 {
            at.push(format!("{joints} joints"));
        }
        w.row(
            &columns,
            &[
                format!("{} ({k} strips)", mm(k as f64 * t)),
                n.to_string(),
                at.join(", "),
                (n + spares(n)).to_string(),
            ],
            Font::Regular,
            BLACK,
        );
        total += n;
        buy += n + spares(n);
    }
    w.text(
        &format!(
            "{total} {} eyelets in all; buy {buy} with spares",
            fab.eyelet.name
        ),
        BODY,
        Font::Bold,
        BLACK,
    );
    ruler(w);
}

/// Before step 1: the test piece on sheet 1 checks scale, kerf and eyelet fit.
fn test_piece_block(w: &mut Writer, b: &Build) {
    let fab = &b.design.fabrication;
    w.need(40.0);
    w.y += 2.0;
    w.text(
        "Before step 1: cut and test the test piece",
        5.0,
        Font::Bold,
        BLACK,
    );
    let text = match crate::parts::test_piece(fab) {
        Some(piece) => {
            let diameters: Vec<String> = piece.holes.iter().map(|h| format!("{:.1}", h.1)).collect();
            let kerf = if fab.compensate_kerf {
                "It is cut with kerf compensation on, so it must measure 100.0 mm tip to tip: if it does not, \
                 your kerf setting is off by the difference."
                    .to_string()
            } else {
                format!(
                    "It is cut without kerf compensation, so it measures 100 mm minus your laser's kerf: \
                     100.0 - measured = kerf (the recipe assumes {} mm).",
                    fab.kerf
                )
            };
            format!(
                "Cut sheet 1's test piece first (the 100 mm strip with the stepped holes) and check it before \
                 cutting the rest. Scale: measure it tip to tip. {kerf} Eyelet fit: set an eyelet in each hole \
                 ({} mm, labelled on the strip); the right hole is the smallest one the eyelet's barrel enters \
                 without forcing and still turns in. If that is not the {:.1} mm hole, set [eyelet] hole to its \
                 diameter in the recipe (docs/recipe.md) and build again.",
                diameters.join(", "),
                fab.eyelet.hole
            )
        }
        None => "The test piece is left out (--no-test-piece, or it does not fit the sheet): cut one strip first, \
                 measure it against the bill of materials and try an eyelet in its holes before cutting the rest."
            .to_string(),
    };
    w.paragraph(&text, SMALL, BLACK);
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

/// Room above and below a step picture for labels set off the lattice (mm).
const LABEL_ROOM: f64 = 2.5;

/// How this guide lays out its steps: the picture beside the text for steps
/// of up to 3 cells (several steps a page), above it for wider rows.
struct StepLayout {
    side: bool,
    /// Rows of more than a few cells: the whole-lattice picture is small and
    /// unlabelled, and zoomed pictures of the row follow, a few cells each.
    detail: bool,
    /// The picture's box (mm).
    size: DVec2,
    /// Beside the text, the whole lattice takes the box's left part and a
    /// zoomed picture of the step starts this far (mm) from its left.
    zoom_x: f64,
}

impl StepLayout {
    /// The box of the whole-lattice picture.
    fn overview(&self) -> DVec2 {
        if self.side {
            DVec2::new(self.zoom_x - 3.0, self.size.y)
        } else {
            self.size
        }
    }
}

impl StepLayout {
    fn new(b: &Build, steps: &[Step], text_width: f64) -> Self {
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

/// Step pictures of a lattice built flat look square on at it.
fn step_camera(b: &Build) -> Camera {
    if stacking::built_flat(&b.lattice) {
        Camera::face_on(&b.assembled)
    } else {
        Camera::for_lattice(&b.assembled)
    }
}

/// How a bent-facet lattice takes its shape, with its bumps and dimples
/// counted (interior vertices with an angle defect of at least +3 degrees,
/// or at most -3), or None for a lattice whose shape the geometry fixes.
fn bumps(b: &Build) -> Option<String> {
    if b.lattice.extrinsic() || b.lattice.dim == 2 {
        return None;
    }
    let c = b.lattice.curvature();
    let bumps = c.iter().filter(|v| v.defect.to_degrees() >= 3.0).count();
    let dimples = c.iter().filter(|v| v.defect.to_degrees() <= -3.0).count();
    Some(format!(
        "Bent facets: rows of this lattice grew on rebuilt fronts, so where two rows join, the strips must bend. \
         Assemble every joint with the strips straight; as you open the lattice the strips bend at the row joins \
         and the relief forms by itself: {bumps} of its {} inner vertices become bumps (angle defect +3 deg or \
         more) and {dimples} dimples (-3 deg or less), as preview.png and deployed.obj show. Open it slowly and \
         evenly; how far the bumps rise depends on the strips' stiffness (docs/physics.md).",
        c.len()
    ))
}

/// Cells in one zoomed picture of a wide row, and its height (mm).
const DETAIL_CELLS: usize = 8;
const DETAIL_HEIGHT: f64 = 42.0;

/// Zoomed pictures of a wide step, `DETAIL_CELLS` cells each: the row above
/// in grey and this row in colour, labelled like a whole-lattice picture.
/// Each joint is labelled in the first picture that shows it.
fn details(w: &mut Writer, b: &Build, step: &Step, named: &[usize]) {
    let l = &b.assembled;
    // On a 3-D loop a picture shows at most a quarter of the ring, so that
    // it is seen square on.
    let most = if l.dim == 3 && l.kind == crate::lattice::Kind::Loop {
        l.width.div_ceil(4).clamp(1, DETAIL_CELLS)
    } else {
        DETAIL_CELLS
    };
    let chunks = step.cells.len().div_ceil(most);
    let per = step.cells.len().div_ceil(chunks.max(1));
    let mut done = vec![false; step.joints.len()];
    for cells in step.cells.chunks(per.max(1)) {
        let cols: Vec<u32> = cells.iter().map(|&c| l.cells[c].col).collect();
        let above: Vec<usize> = (0..l.cells.len())
            .filter(|&c| {
                let cell = &l.cells[c];
                step.row > 0 && cell.row + 1 == step.row && cols.contains(&cell.col)
            })
            .filter(|_| l.kind != crate::lattice::Kind::Helix)
            .collect();
        let points = cells.iter().chain(&above).flat_map(|&c| {
            let cell = &l.cells[c];
            [cell.ul, cell.ur, cell.ll, cell.lr]
                .map(|v| l.vertex(v).pos)
                .into_iter()
                .chain([cell.pivot])
        });
        let camera = detail_camera(b, cells).unwrap_or_else(|| step_camera(b));
        let height = DETAIL_HEIGHT + 2.0 * LABEL_ROOM;
        w.need(height + 2.0);
        let top = w.y;
        let at = DVec2::new(MARGIN, top + LABEL_ROOM);
        let fit = Fit::around(points, camera, at, DVec2::new(w.width(), DETAIL_HEIGHT));
        let width = (0.6 * fit.scale() * b.design.fabrication.material.width).clamp(0.4, 2.0);
        let mut items = rods(l, &fit, &above, |_| {
            Some(RodStyle {
                colour: FAINT,
                width,
            })
        });
        items.extend(crossing_rods(l, &fit, cells, |_| {
            Some(RodStyle {
                colour: NEW,
                width: width * 1.3,
            })
        }));
        let mut vertices: Vec<usize> = cells
            .iter()
            .chain(&above)
            .flat_map(|&c| {
                let cell = &l.cells[c];
                [cell.ul, cell.ur, cell.ll, cell.lr].map(|v| v as usize)
            })
            .collect();
        vertices.sort_unstable();
        vertices.dedup();
        let all: Vec<usize> = cells.iter().chain(&above).copied().collect();
        items.extend(pivots_and_vertices(l, &fit, &all, &vertices, width * 0.8));
        let mut joints = Vec::new();
        for (k, j) in step.joints.iter().enumerate() {
            if !done[k] && vertices.contains(&(j.vertex as usize)) {
                done[k] = true;
                joints.push(j);
            }
        }
        let mut placer = Placer::new(
            DVec2::new(MARGIN - 1.0, top),
            DVec2::new(MARGIN + w.width() + 1.0, top + height),
        );
        let shown = Shown {
            cells,
            joints,
            first_row: step.row.saturating_sub(1),
            vertices: Some(&vertices),
        };
        items.extend(step_labels(b, step, &fit, &mut placer, named, &shown));
        items.extend(placer.items);
        w.push(items);
        w.group_id = Some(format!("step-{}-labels", step.number));
        w.close_group();
        w.group_id = None;
        w.y = top + height + 2.0;
    }
}

/// A camera square on to a stretch of a loop's row, from outside, the row
/// above at the top; None for other lattices (their step camera serves).
fn detail_camera(b: &Build, cells: &[usize]) -> Option<Camera> {
    let l = &b.assembled;
    if l.dim != 3 || l.kind == crate::lattice::Kind::Sheet {
        return None;
    }
    let (mut normal, mut up, mut centre) =
        (glam::DVec3::ZERO, glam::DVec3::ZERO, glam::DVec3::ZERO);
    for &c in cells {
        let [ul, ur, ll, lr] = l.corners(&l.cells[c]);
        normal += (ur - ul).cross(ll - ul).normalize_or_zero();
        up += (ul + ur - ll - lr).normalize_or_zero();
        centre += l.cells[c].pivot;
    }
    centre /= cells.len().max(1) as f64;
    let middle =
        l.vertices.iter().map(|v| v.pos).sum::<glam::DVec3>() / l.vertices.len().max(1) as f64;
    // Outward: away from the lattice's centre.
    let outward = if normal.dot(centre - middle) < 0.0 {
        -normal
    } else {
        normal
    };
    Camera::looking(-outward, up)
}

/// A joint as the guide names it: `[row,col]`, or `[k]` on a helix.
fn joint_key(l: &crate::lattice::Lattice, vertex: u32) -> String {
    let k = l.vertex(vertex).key;
    if l.kind == crate::lattice::Kind::Helix {
        format!("[{}]", k.col)
    } else {
        key(k)
    }
}

/// "2 x type C, 2 x type D": a step's strips counted by part type.
fn take_list(b: &Build, strips: &[usize]) -> String {
    let mut counts: std::collections::BTreeMap<usize, usize> = Default::default();
    for &s in strips {
        *counts.entry(b.parts.strips[s].part_type).or_default() += 1;
    }
    counts
        .iter()
        .map(|(&t, n)| format!("{n} x type {}", b.parts.types[t].code))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The step's words: (text, bold, colour), each wrapped later.
fn step_text(
    b: &Build,
    step: &Step,
    side: &stacking::Side,
    order: Option<&[stacking::Role]>,
) -> Vec<(String, bool, [u8; 3])> {
    let l = &b.lattice;
    let strips = &b.parts.strips;
    let t = b.design.fabrication.material.thickness;
    let helix = l.kind == crate::lattice::Kind::Helix;
    let what = if helix { "cell" } else { "row" };
    let mut lines = vec![(format!("Take {}.", take_list(b, &step.strips)), true, BLACK)];
    let place = match stacking::place(l, step) {
        stacking::Place::First => format!("This is the first {what}: lay it out as pictured."),
        stacking::Place::Over => format!("This {what} goes on top of the work."),
        stacking::Place::Under => format!(
            "This {what} goes UNDER the work: slide its strips under the strips already there."
        ),
        stacking::Place::Between => format!(
            "This {what}'s strips go between strips of the work: follow each joint's order."
        ),
    };
    lines.push((
        format!(
            "Stacking side {}: first strip {}, last {}. {place}",
            side.name, side.first, side.last
        ),
        false,
        BLACK,
    ));
    if bumps(b).is_some() && step.number > 1 {
        lines.push((
            format!(
                "Bent facets: where this {what} joins the work its strips will bend as the lattice opens; join them straight now."
            ),
            false,
            GREY,
        ));
    }
    let mut pivots = format!(
        "1. Pivots (orange): rod A, then rod B over it (as drawn); {}, grip {}, loose enough to turn.",
        plural(step.cells.len(), "eyelet"),
        mm(2.0 * t)
    );
    if !helix {
        let pairs: Vec<String> = step
            .cells
            .iter()
            .map(|&c| {
                let code = |s: usize| b.parts.types[strips[s].part_type].code.as_str();
                format!("{}: {}+{}", l.cells[c].col, code(2 * c), code(2 * c + 1))
            })
            .collect();
        pivots.push_str(&format!(" Rod A + rod B by column: {}.", pairs.join(", ")));
    } else if let [c] = step.cells[..] {
        let code = |s: usize| b.parts.types[strips[s].part_type].code.as_str();
        pivots.push_str(&format!(
            " Rod A is type {}, rod B type {}.",
            code(2 * c),
            code(2 * c + 1)
        ));
    }
    lines.push((pivots, false, BLACK));
    if step.joints.is_empty() {
        lines.push(("2. No joint closes in this step.".into(), false, BLACK));
    } else if let Some(order) = order {
        let roles: Vec<String> = order.iter().map(|r| r.name(helix)).collect();
        let mut by_grip: std::collections::BTreeMap<usize, Vec<String>> = Default::default();
        for j in &step.joints {
            by_grip
                .entry(j.ends.len())
                .or_default()
                .push(joint_key(l, j.vertex));
        }
        let grips: Vec<String> = by_grip
            .iter()
            .rev()
            .map(|(k, keys)| format!("{k} strips, grip {}: {}", mm(*k as f64 * t), keys.join(" ")))
            .collect();
        lines.push((
            format!(
                "2. Joints (blue): stack {} (fewer at an edge); one eyelet each. {}.",
                roles.join(", then "),
                grips.join("; ")
            ),
            false,
            BLACK,
        ));
    } else {
        lines.push((
            "2. Joints (blue), stacked first to last as listed:".into(),
            false,
            BLACK,
        ));
        for j in &step.joints {
            let stack: Vec<&str> = j.ends.iter().map(|e| strips[e.rod].id.as_str()).collect();
            lines.push((
                format!(
                    "{}  {}  (grip {})",
                    joint_key(l, j.vertex),
                    stack.join(" / "),
                    mm(j.ends.len() as f64 * t)
                ),
                false,
                BLACK,
            ));
        }
    }
    lines.push((
        format!(
            "Eyelets: {} now, {} of {} so far.",
            step.eyelets,
            step.total,
            b.parts.eyelets()
        ),
        true,
        NEW,
    ));
    lines
}

/// Lines of at most `width` mm.
fn wrap(text: &str, font: Font, size: f64, width: f64) -> Vec<String> {
    let mut out = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        let candidate = if line.is_empty() {
            word.to_string()
        } else {
            format!("{line} {word}")
        };
        if crate::drawing::text::width(&candidate, font, size) > width && !line.is_empty() {
            out.push(std::mem::replace(&mut line, word.to_string()));
        } else {
            line = candidate;
        }
    }
    if !line.is_empty() {
        out.push(line);
    }
    out
}

/// The labels of a step's picture: joint keys, the new strips' types (or
/// IDs where the text names strips), column numbers, and a loop's seam.
/// What one picture of a step shows and labels: the step's cells and
/// joints in it, and the first row its seam line starts at.
struct Shown<'a> {
    cells: &'a [usize],
    joints: Vec<&'a crate::lattice::Joint>,
    first_row: u32,
    /// The vertices in the picture, sorted (None: all).
    vertices: Option<&'a [usize]>,
}

fn step_labels(
    b: &Build,
    step: &Step,
    fit: &Fit,
    placer: &mut Placer,
    named: &[usize],
    shown: &Shown,
) -> Vec<Item> {
    let l = &b.assembled;
    let strips = &b.parts.strips;
    let mut extra = Vec::new();
    // A loop's seam: the column where the ring closes, on every row shown.
    if l.kind == crate::lattice::Kind::Loop {
        let seam: Vec<DVec2> = l
            .vertices
            .iter()
            .enumerate()
            .filter(|(i, v)| {
                v.key.col == 0
                    && v.key.row >= shown.first_row
                    && v.key.row <= step.row + 1
                    && shown.vertices.is_none_or(|vs| vs.binary_search(i).is_ok())
            })
            .map(|(_, v)| fit.map(v.pos))
            .collect();
        if seam.len() >= 2 {
            extra.push(Item::art(
                Ink::line(BLACK, 0.5),
                Shape::polyline(&seam, false),
            ));
        }
    }
    for j in &shown.joints {
        placer.place(&Label {
            anchor: fit.map(l.vertex(j.vertex).pos),
            text: joint_key(&b.lattice, j.vertex),
            colour: VERTEX,
            bold: false,
            toward: DVec2::Y,
        });
    }
    // Where a strip is named: the middle of its leg next to `vertex`.
    let leg_middle = |rod: usize, start: bool| {
        let r = l.cell_rods(rod / 2)[rod % 2];
        let [a, p, e] = r.hole_pos;
        fit.map((if start { a } else { e } + p) / 2.0)
    };
    let mut labelled = std::collections::BTreeSet::new();
    for &s in named {
        if !labelled.insert(s) {
            continue;
        }
        let new = step.strips.contains(&s);
        let end = step
            .joints
            .iter()
            .flat_map(|j| &j.ends)
            .find(|e| e.rod == s)
            .map_or(crate::lattice::RodEnd::Start, |e| e.end);
        let code = &b.parts.types[strips[s].part_type].code;
        placer.place(&Label {
            anchor: leg_middle(s, end == crate::lattice::RodEnd::Start),
            text: if new {
                format!("{} ({code})", strips[s].id)
            } else {
                strips[s].id.clone()
            },
            colour: if new { NEW } else { GREY },
            bold: new,
            toward: DVec2::new(if s % 2 == 0 { -1.0 } else { 1.0 }, -0.3),
        });
    }
    for &c in shown.cells {
        for s in [2 * c, 2 * c + 1] {
            if labelled.contains(&s) {
                continue;
            }
            let m = leg_middle(s, true);
            let other = leg_middle(s ^ 1, true);
            placer.place(&Label {
                anchor: m,
                text: b.parts.types[strips[s].part_type].code.clone(),
                colour: NEW,
                bold: true,
                toward: m - other,
            });
        }
    }
    if l.kind != crate::lattice::Kind::Helix {
        for &c in shown.cells {
            let cell = &l.cells[c];
            let top = (fit.map(l.vertex(cell.ul).pos)
                + fit.map(l.vertex(cell.ur).pos)
                + fit.map(cell.pivot))
                / 3.0;
            placer.place(&Label {
                anchor: top,
                text: cell.col.to_string(),
                colour: GREY,
                bold: false,
                toward: DVec2::NEG_Y,
            });
        }
    }
    if l.kind == crate::lattice::Kind::Loop {
        if let Some(v) = l.vertices.iter().find(|v| {
            v.key.col == 0
                && v.key.row == step.row
                && shown.cells.iter().any(|&c| l.cells[c].col == 0)
        }) {
            placer.place(&Label {
                anchor: fit.map(v.pos),
                text: "seam".into(),
                colour: BLACK,
                bold: true,
                toward: DVec2::NEG_X,
            });
        }
    }
    extra
}

#[allow(clippy::too_many_arguments)]
fn step_block(
    w: &mut Writer,
    b: &Build,
    step: &Step,
    count: usize,
    pictures: &StepPictures,
    layout: &StepLayout,
    side: &stacking::Side,
) {
    let helix = b.lattice.kind == crate::lattice::Kind::Helix;
    let order = stacking::common_order(&b.lattice, step);
    let lines = step_text(b, step, side, order.as_deref());
    let text_x = if layout.side {
        MARGIN + layout.size.x + 5.0
    } else {
        MARGIN
    };
    let text_w = MARGIN + w.width() - text_x;
    let line_h = SMALL * 1.35;
    let wrapped: Vec<(String, bool, [u8; 3])> = lines
        .iter()
        .flat_map(|(t, bold, c)| {
            let font = if *bold { Font::Bold } else { Font::Regular };
            wrap(t, font, SMALL, text_w)
                .into_iter()
                .map(move |x| (x, *bold, *c))
        })
        .collect();
    let title_h = 6.0;
    let text_h = title_h + wrapped.len() as f64 * line_h;
    let pic_h = layout.size.y + 2.0 * LABEL_ROOM;
    let room = w.bottom() - MARGIN;
    let beside = layout.side && pic_h.max(text_h) <= room;
    let block = if beside {
        pic_h.max(text_h)
    } else {
        title_h + pic_h + (text_h - title_h).min(30.0)
    };
    w.need(block + 3.0);
    w.close_group();
    let title_y = w.y;
    // The picture: beside the text, or under the title.
    let top = if beside { w.y } else { w.y + title_h };
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
    let named: Vec<usize> = if order.is_none() {
        step.joints
            .iter()
            .flat_map(|j| j.ends.iter().map(|e| e.rod))
            .collect()
    } else {
        Vec::new()
    };
    if layout.side {
        // The whole lattice is small beside the text: the step's cells and
        // the cells they join are drawn again, zoomed, right of it, and
        // labelled there.
        let l = &b.assembled;
        let mut corner = vec![false; l.vertices.len()];
        for &c in &step.cells {
            let cell = &l.cells[c];
            for v in [cell.ul, cell.ur, cell.ll, cell.lr] {
                corner[v as usize] = true;
            }
        }
        let k0 = step.number - 1;
        let around: Vec<usize> = (0..l.cells.len())
            .filter(|&c| {
                let cell = &l.cells[c];
                l.step_of(c) < k0
                    && [cell.ul, cell.ur, cell.ll, cell.lr]
                        .iter()
                        .any(|&v| corner[v as usize])
            })
            .collect();
        let all: Vec<usize> = step.cells.iter().chain(&around).copied().collect();
        let mut vertices: Vec<usize> = all
            .iter()
            .flat_map(|&c| {
                let cell = &l.cells[c];
                [cell.ul, cell.ur, cell.ll, cell.lr].map(|v| v as usize)
            })
            .collect();
        vertices.sort_unstable();
        vertices.dedup();
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
        items.extend(step_labels(b, step, &zfit, &mut placer, &named, &shown));
        items.extend(placer.items);
        w.push(items);
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

fn checklist(w: &mut Writer, b: &Build, steps: &[Step]) {
    w.need(90.0);
    w.y += 4.0;
    w.heading("Checklist");
    let pivot = b.parts.pivot_eyelets;
    let vertex = b.parts.vertex_eyelets;
    let items = [
        format!(
            "All {} strips cut, each with its engraving legible (ID, type code or dot code, as the bill of materials lists).",
            b.parts.strips.len()
        ),
        format!("{pivot} scissor-pivot eyelets set, rod A under rod B in every cell."),
        format!("{vertex} vertex eyelets set, each stack in the order its step lists."),
        "Every eyelet lets its strips turn: none is crimped tight.".to_string(),
        format!("All {} steps done; no strip left over.", steps.len()),
        "Folded flat, the holes lie on the ticks of the inspection gauge (at the end of the guide)."
            .to_string(),
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
