//! Drawings that repeat, up to a move (the strips of one part type on the
//! cut sheets), found and replaced by places of one shared symbol.

use crate::drawing::{Item, Page, Place, Symbol};
use crate::write::repeats::KeyMap;
use crate::write::repeats::first_point;
use glam::DVec2;

/// A group's drawing relative to its anchor `a`, as numbers (coordinates
/// on the 0.1 um grid, finer than the 0.01 pt the PDF prints; other numbers
/// by their bits): two groups with the same key draw the same thing, moved.
/// Numbers rather than text: building the text was 7 % of a 100 x 100 build.
fn key(items: &[Item], a: DVec2) -> Vec<i64> {
    crate::write::repeats::key(items, &|v| {
        let d = v - a;
        [(d.x * 1e4).round() as i64, (d.y * 1e4).round() as i64]
    })
}

/// A group's anchor and key.
type Keyed = (DVec2, Vec<i64>);

/// The pages with every group whose drawing occurs more than once (up to
/// a move) replaced by a place of one shared symbol: a Form XObject
/// written once. A 100 x 100 sheet build has 20,000 strips of one or two
/// drawings; each copy then costs one short `cm ... Do` line.
pub(super) fn share_repeats(pages: &[Page]) -> (Vec<Page>, Vec<Symbol>) {
    // Each group that could be shared: its anchor and key.
    let keys: Vec<Vec<Option<Keyed>>> = pages
        .iter()
        .map(|page| {
            page.groups
                .iter()
                .map(|g| {
                    let a = first_point(g).filter(|_| g.symbols.is_empty())?;
                    Some((a, key(&g.items, a)))
                })
                .collect()
        })
        .collect();
    let mut count: KeyMap<&[i64], usize> = KeyMap::default();
    for (_, k) in keys.iter().flatten().flatten() {
        *count.entry(k).or_default() += 1;
    }
    let mut index: KeyMap<&[i64], usize> = KeyMap::default();
    let mut symbols: Vec<Symbol> = Vec::new();
    let mut out = Vec::with_capacity(pages.len());
    for (page, keys) in pages.iter().zip(&keys) {
        let mut page = page.clone();
        for (g, k) in page.groups.iter_mut().zip(keys) {
            let Some((at, k)) = k else {
                continue;
            };
            if count[k.as_slice()] < 2 {
                continue;
            }
            let symbol = *index.entry(k).or_insert_with(|| {
                let items = g
                    .items
                    .iter()
                    .map(|i| Item {
                        shape: i.shape.moved(&|p| p - *at),
                        ..i.clone()
                    })
                    .collect();
                symbols.push(Symbol {
                    uses: Vec::new(),
                    items,
                });
                symbols.len() - 1
            });
            g.symbols = vec![Place { symbol, at: *at }];
            g.items.clear();
        }
        out.push(page);
    }
    (out, symbols)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::{Group, Layer, Shape};
    use crate::write::pdf::write;

    /// A strip-like group (a hole and a closed outline) anchored at `at`.
    fn strip(id: &str, at: DVec2, hole: f64) -> Group {
        let c = |x: f64, y: f64| at + DVec2::new(x, y);
        Group::new(
            id,
            vec![
                Item::on(
                    Layer::Holes,
                    Shape::Circle {
                        center: c(0.0, 0.0),
                        radius: hole,
                    },
                ),
                Item::on(
                    Layer::Outlines,
                    Shape::polyline(&[c(-5.0, -5.0), c(30.0, -5.0), c(30.0, 5.0)], true),
                ),
            ],
        )
    }

    #[test]
    fn repeated_drawings_become_one_symbol_placed_where_each_copy_was() {
        let page = |groups| Page {
            width: 200.0,
            height: 100.0,
            title: "t".into(),
            metadata: Vec::new(),
            laser: None,
            groups,
        };
        let a = DVec2::new(10.0, 20.0);
        let b = DVec2::new(60.123_45, 70.0);
        let pages = vec![
            page(vec![strip("A", a, 1.6), strip("odd", a, 2.0)]),
            page(vec![strip("B", b, 1.6)]),
        ];
        let (shared, symbols) = share_repeats(&pages);
        assert_eq!(symbols.len(), 1, "one drawing repeats");
        // The symbol is the drawing relative to its anchor (the hole).
        assert_eq!(
            symbols[0].items,
            strip("A", DVec2::ZERO, 1.6).items,
            "the symbol draws the strip at the origin"
        );
        let places: Vec<(String, Vec<Place>, usize)> = shared
            .iter()
            .flat_map(|p| &p.groups)
            .map(|g| (g.id.clone(), g.symbols.clone(), g.items.len()))
            .collect();
        assert_eq!(places[0], ("A".into(), vec![Place { symbol: 0, at: a }], 0));
        // A drawing that occurs once stays inline.
        assert_eq!(places[1], ("odd".into(), vec![], 2));
        assert_eq!(places[2], ("B".into(), vec![Place { symbol: 0, at: b }], 0));
        // And the PDF places it twice, with one Form XObject.
        let bytes = write("t", &pages);
        let text = String::from_utf8_lossy(&bytes);
        assert_eq!(text.matches("/Subtype /Form").count(), 1);
    }
}
