//! The page flow of a printed document (the assembly guide): text, tables
//! and pictures laid top to bottom, a new page started when one is full,
//! with a running head on continuation pages and a footer on each page.
//! Drawing-model layout, so it sits with the model; what the pages say is
//! the guide's.

use super::{Align, Font, Group, Ink, Item, Page, Place, Shape};
use glam::DVec2;

/// The page margin (mm).
pub(crate) const MARGIN: f64 = 15.0;
/// Text sizes (mm): body, small print; and the height of a table row.
pub(crate) const BODY: f64 = 3.6;
pub(crate) const SMALL: f64 = 3.0;
pub(crate) const LINE: f64 = 5.0;
pub(crate) const BLACK: [u8; 3] = [0, 0, 0];
pub(crate) const GREY: [u8; 3] = [110, 110, 110];
pub(crate) const FAINT: [u8; 3] = [185, 185, 185];

/// Builds pages top to bottom, starting a new page when one is full.
pub(crate) struct PageFlow {
    size: (f64, f64),
    title: String,
    pub(crate) pages: Vec<Page>,
    /// This page's finished groups, then the items of its open one.
    groups: Vec<Group>,
    pub(crate) items: Vec<Item>,
    pub(crate) y: f64,
    /// Drawn at the top of every continuation page.
    pub(crate) running_head: Option<String>,
    /// The id of the groups closed while it is set (e.g. "step-3-text"),
    /// so tests and readers find a step's words and picture labels.
    pub(crate) group_id: Option<String>,
}

impl PageFlow {
    pub(crate) fn new(size: (f64, f64), title: String) -> Self {
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

    pub(crate) fn width(&self) -> f64 {
        self.size.0 - 2.0 * MARGIN
    }

    pub(crate) fn bottom(&self) -> f64 {
        self.size.1 - MARGIN - 6.0
    }

    pub(crate) fn finish_page(&mut self) {
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
            laser: None,
            groups: std::mem::take(&mut self.groups),
        });
        self.y = MARGIN;
    }

    pub(crate) fn new_page(&mut self) {
        self.finish_page();
        self.y = MARGIN;
    }

    /// Room for `height` more mm, else continue on a new page.
    pub(crate) fn need(&mut self, height: f64) {
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

    pub(crate) fn text_at(&mut self, x: f64, text: &str, size: f64, font: Font, colour: [u8; 3]) {
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
    pub(crate) fn text(&mut self, text: &str, size: f64, font: Font, colour: [u8; 3]) {
        self.need(size * 1.4);
        self.text_at(MARGIN, text, size, font, colour);
        self.y += size * 1.4;
    }

    pub(crate) fn heading(&mut self, text: &str) {
        self.need(14.0);
        self.text(text, 7.0, Font::Bold, BLACK);
        self.y += 2.0;
    }

    /// A paragraph wrapped to the text width.
    pub(crate) fn paragraph(&mut self, text: &str, size: f64, colour: [u8; 3]) {
        for line in self.wrap(text, size) {
            self.text(&line, size, Font::Regular, colour);
        }
        self.y += size * 0.4;
    }

    /// The lines of a paragraph wrapped to the text width.
    pub(crate) fn wrap(&self, text: &str, size: f64) -> Vec<String> {
        wrap(text, Font::Regular, size, self.width())
    }

    /// How far `paragraph` moves down, when it does not break the page.
    pub(crate) fn paragraph_height(&self, text: &str, size: f64) -> f64 {
        self.wrap(text, size).len() as f64 * size * 1.4 + size * 0.4
    }

    /// Table rows in fixed columns (x offsets from the margin).
    pub(crate) fn row(&mut self, columns: &[f64], cells: &[String], font: Font, colour: [u8; 3]) {
        self.need(LINE);
        for (x, cell) in columns.iter().zip(cells) {
            self.text_at(MARGIN + x, cell, SMALL, font, colour);
        }
        self.y += LINE * 0.85;
    }

    pub(crate) fn rule(&mut self) {
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

    pub(crate) fn push(&mut self, items: Vec<Item>) {
        self.items.extend(items);
    }

    /// The open items become a group of their own.
    pub(crate) fn close_group(&mut self) {
        if !self.items.is_empty() {
            let id = self.group_id.clone().unwrap_or_else(|| {
                format!("page-{}-{}", self.pages.len() + 1, self.groups.len() + 1)
            });
            self.groups
                .push(Group::new(id, std::mem::take(&mut self.items)));
        }
    }

    /// Draw shared symbols here, after what the page has so far.
    pub(crate) fn place(&mut self, places: Vec<Place>) {
        self.close_group();
        let id = format!("page-{}-{}", self.pages.len() + 1, self.groups.len() + 1);
        self.groups.push(Group {
            id,
            symbols: places,
            items: Vec::new(),
        });
    }
}

pub(crate) fn text_item(
    at: DVec2,
    size: f64,
    text: &str,
    font: Font,
    align: Align,
    colour: [u8; 3],
) -> Item {
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

/// Lines of at most `width` mm.
pub(crate) fn wrap(text: &str, font: Font, size: f64, width: f64) -> Vec<String> {
    let mut out = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        let candidate = if line.is_empty() {
            word.to_string()
        } else {
            format!("{line} {word}")
        };
        if super::text::width(&candidate, font, size) > width && !line.is_empty() {
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
