//! Groups drawn alike: the strips of a big sheet are often the same drawing
//! moved (one part type engraved with its type, not its ID). The DXF and SVG
//! writers store such a drawing once (a BLOCK, a `<defs>` group) and place
//! it by reference, which is what CAD and SVG readers expect of repeats.
//!
//! A group's drawing is taken relative to its anchor, its first item's first
//! point rounded to the 0.1 um grid the writers print on; offsets are whole
//! grid steps, so anchor plus offset is exactly the point a flat file prints.

use super::number::units;
use crate::drawing::{Group, Item, Segment, Shape};
use glam::DVec2;
use std::hash::Hash;

/// A hash map for the writers' lookups of drawings and their texts (keys
/// of hundreds of integers or bytes), hashed by rustc-hash's FxHash
/// instead of std's SipHash, which is built against hostile keys: these
/// come from the build itself. Only looked up, never iterated, so no file
/// depends on the hash.
pub(crate) type KeyMap<K, V> = rustc_hash::FxHashMap<K, V>;

/// Which groups share a drawing with another group.
pub(crate) struct Repeats {
    /// Per group: the index of its shared drawing, or None (drawn alone).
    pub(crate) of_group: Vec<Option<usize>>,
    /// Per shared drawing: the first group drawn with it.
    pub(crate) first: Vec<usize>,
}

/// The shared drawings among groups keyed by their drawing relative to
/// their anchor (None: never shared); numbered in order of first use.
pub(crate) fn find<K: Hash + Eq>(keys: &[Option<K>]) -> Repeats {
    let mut count: KeyMap<&K, usize> = KeyMap::default();
    for key in keys.iter().flatten() {
        *count.entry(key).or_default() += 1;
    }
    let mut index: KeyMap<&K, usize> = KeyMap::default();
    let mut repeats = Repeats {
        of_group: Vec::with_capacity(keys.len()),
        first: Vec::new(),
    };
    for (g, key) in keys.iter().enumerate() {
        let shared = key.as_ref().filter(|k| count[k] > 1);
        repeats.of_group.push(shared.map(|key| {
            let next = index.len();
            let b = *index.entry(key).or_insert(next);
            if b == next {
                repeats.first.push(g);
            }
            b
        }));
    }
    repeats
}

/// `find` made cheap and exact: groups are first told apart by `keys` (equal
/// keys must mean equal drawings: a key holds every number its writer
/// prints, on the grid), and keys of equal texts (`text(g)`, written only
/// for the first group of each key) are one drawing, so the repeats are
/// those of the texts. A big sheet's 20,000 strips have a few keys: writing
/// every strip's text to compare them took a tenth of its build.
///
/// `coarse` is part of what the text shows, for each keyed group (equal
/// texts must have equal coarse keys: the points it prints, say, without
/// the inks): a key alone in its coarse class
/// prints a text no other key prints, so its text is written only if the
/// key is shared. The examples' strips all differ, and writing each text
/// once to compare and again to draw the strip was half of their writers.
/// Returns the repeats and each shared drawing's text.
pub(crate) fn find_exact<K: Hash + Eq, C: Hash + Eq>(
    keys: &[Option<K>],
    coarse: &[Option<C>],
    mut text: impl FnMut(usize) -> String,
) -> (Repeats, Vec<String>) {
    // The distinct keys of each coarse class.
    let mut keys_of: KeyMap<&C, KeyMap<&K, ()>> = KeyMap::default();
    for (key, c) in keys.iter().zip(coarse) {
        if let (Some(key), Some(c)) = (key, c) {
            keys_of.entry(c).or_default().insert(key, ());
        }
    }
    let alone = |g: usize| {
        let c = coarse[g].as_ref();
        c.is_some_and(|c| keys_of[c].len() == 1)
    };
    let mut of_key: KeyMap<&K, usize> = KeyMap::default();
    let mut of_text: KeyMap<String, usize> = KeyMap::default();
    // Per drawing: its text, where it was written.
    let mut texts: Vec<Option<String>> = Vec::new();
    let drawing: Vec<Option<usize>> = keys
        .iter()
        .enumerate()
        .map(|(g, key)| {
            let key = key.as_ref()?;
            if let Some(&d) = of_key.get(key) {
                return Some(d);
            }
            let next = texts.len();
            let d = if alone(g) {
                texts.push(None);
                next
            } else {
                let t = text(g);
                let d = *of_text.entry(t.clone()).or_insert(next);
                if d == next {
                    texts.push(Some(t));
                }
                d
            };
            of_key.insert(key, d);
            Some(d)
        })
        .collect();
    let repeats = find(&drawing);
    let shared = repeats
        .first
        .iter()
        .map(|&g| {
            let d = drawing[g].expect("a shared group has a key");
            texts[d].take().unwrap_or_else(|| text(g))
        })
        .collect();
    (repeats, shared)
}

/// Appends `head` and each of `points` (grid coordinates) to a coarse key
/// for `find_exact`.
pub(crate) fn push_points(
    k: &mut Vec<i64>,
    head: &[i64],
    points: impl IntoIterator<Item = [i64; 2]>,
) {
    k.extend_from_slice(head);
    for p in points {
        k.extend(p);
    }
}

/// Each group's `key` on the page grid relative to its anchor `at` (None
/// for a group without one): how the SVG and PNG writers compare drawings.
pub(crate) fn page_keys(groups: &[Group], at: &[Option<(i64, i64)>]) -> Vec<Option<Vec<i64>>> {
    groups
        .iter()
        .zip(at)
        .map(|(g, at)| {
            let (ax, ay) = (*at)?;
            Some(key(&g.items, &|p| [units(p.x) - ax, units(p.y) - ay]))
        })
        .collect()
}

/// A group's drawing as integers, exactly: each point through `grid` (the
/// writer's grid units relative to the anchor), other numbers by their
/// bits. Groups of equal keys draw the same up to a move.
pub(crate) fn key(items: &[Item], grid: &dyn Fn(DVec2) -> [i64; 2]) -> Vec<i64> {
    let mut k = Vec::with_capacity(8 * items.len());
    let colour =
        |c: Option<[u8; 3]>| c.map_or(-1, |[r, g, b]| i64::from_be_bytes([0, 0, 0, 0, 0, r, g, b]));
    for i in items {
        k.extend([
            i.layer as i64,
            colour(i.ink.stroke),
            colour(i.ink.fill),
            i.ink.width.to_bits() as i64,
        ]);
        match &i.shape {
            Shape::Circle { center, radius } => {
                k.push(0);
                k.extend(grid(*center));
                k.push(radius.to_bits() as i64);
            }
            Shape::Path {
                start,
                segments,
                closed,
            } => {
                k.extend([1, *closed as i64, segments.len() as i64]);
                k.extend(grid(*start));
                for s in segments {
                    match *s {
                        Segment::Line(p) => {
                            k.push(0);
                            k.extend(grid(p));
                        }
                        Segment::Arc {
                            to,
                            center,
                            clockwise,
                        } => {
                            k.push(1 + clockwise as i64);
                            k.extend(grid(to));
                            k.extend(grid(center));
                        }
                    }
                }
            }
            Shape::Text {
                at,
                size,
                text,
                font,
                align,
            } => {
                k.extend([2, size.to_bits() as i64, *font as i64, *align as i64]);
                k.extend(grid(*at));
                k.push(text.len() as i64);
                k.extend(text.bytes().map(i64::from));
            }
        }
    }
    k
}

/// A group's anchor (page mm, y down): its first item's first point;
/// None for an empty group.
pub(crate) fn first_point(g: &Group) -> Option<DVec2> {
    Some(match &g.items.first()?.shape {
        Shape::Circle { center, .. } => *center,
        Shape::Path { start, .. } => *start,
        Shape::Text { at, .. } => *at,
    })
}

/// `first_point` on the grid.
pub(crate) fn anchor(g: &Group) -> Option<(i64, i64)> {
    first_point(g).map(|p| (units(p.x), units(p.y)))
}

/// Page points to offsets from `at` (grid units) in whole grid steps, mm.
pub(crate) fn offset((ax, ay): (i64, i64)) -> impl Fn(DVec2) -> DVec2 {
    move |p: DVec2| {
        DVec2::new(
            (units(p.x) - ax) as f64 / 1e4,
            (units(p.y) - ay) as f64 / 1e4,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_drawings_used_twice_are_shared_in_order_of_first_use() {
        let k = |s: &str| Some(s.to_string());
        let r = find(&[k("a"), k("b"), None, k("c"), k("b"), k("a"), k("b")]);
        assert_eq!(
            r.of_group,
            [Some(0), Some(1), None, None, Some(1), Some(0), Some(1)]
        );
        assert_eq!(r.first, [0, 1]);
    }

    #[test]
    fn keys_of_equal_texts_are_one_drawing_and_each_key_is_written_once() {
        // Keys 1 and 2 print the same text: all their groups share it.
        let keys = [Some(1), Some(2), None, Some(1), Some(3), Some(2), Some(4)];
        let texts = ["", "x", "x", "y", "z"];
        let mut written = Vec::new();
        let coarse = [Some(0); 7];
        let (r, shared) = find_exact(&keys, &coarse, |g| {
            written.push(g);
            texts[keys[g].unwrap()].to_string()
        });
        assert_eq!(written, [0, 1, 4, 6]);
        assert_eq!(
            r.of_group,
            [Some(0), Some(0), None, Some(0), None, Some(0), None]
        );
        assert_eq!(r.first, [0]);
        assert_eq!(shared, ["x"]);
        let k = |s: &str| Some(s.to_string());
        let by_text = find(&[k("x"), k("x"), None, k("x"), k("y"), k("x"), k("z")]);
        assert_eq!(by_text.of_group, r.of_group);
    }

    #[test]
    fn a_key_alone_in_its_coarse_class_is_not_written_to_compare() {
        // Key 1 is the only key of class 10: its text is written once, for
        // its shared drawing; keys 2 and 3 print the same text.
        let keys = [Some(1), Some(2), Some(1), Some(3), Some(4)];
        let coarse = [Some(10), Some(20), Some(10), Some(20), Some(30)];
        let texts = ["", "x", "y", "y", "z"];
        let mut written = Vec::new();
        let (r, shared) = find_exact(&keys, &coarse, |g| {
            written.push(g);
            texts[keys[g].unwrap()].to_string()
        });
        assert_eq!(written, [1, 3, 0]);
        assert_eq!(r.of_group, [Some(0), Some(1), Some(0), Some(1), None]);
        assert_eq!(r.first, [0, 1]);
        assert_eq!(shared, ["x", "y"]);
    }

    #[test]
    fn offsets_are_whole_grid_steps() {
        let at = (units(785.69554), units(1090.0));
        let p = offset(at)(DVec2::new(799.83771, 1085.00004));
        assert_eq!((p.x * 1e4).round() as i64, 141_422);
        assert_eq!((p.y * 1e4).round() as i64, -50_000);
        assert_eq!(units(p.x) + at.0, units(799.83771));
    }
}
