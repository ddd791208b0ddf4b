//! Groups drawn alike: the strips of a big sheet are often the same drawing
//! moved (one part type engraved with its type, not its ID). The DXF and SVG
//! writers store such a drawing once (a BLOCK, a `<defs>` group) and place
//! it by reference, which is what CAD and SVG readers expect of repeats.
//!
//! A group's drawing is taken relative to its anchor, its first item's first
//! point rounded to the 0.1 um grid the writers print on; offsets are whole
//! grid steps, so anchor plus offset is exactly the point a flat file prints.

use super::number::units;
use crate::drawing::{Group, Shape};
use glam::DVec2;
use std::collections::HashMap;
use std::hash::Hash;

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
    let mut count: HashMap<&K, usize> = HashMap::new();
    for key in keys.iter().flatten() {
        *count.entry(key).or_default() += 1;
    }
    let mut index: HashMap<&K, usize> = HashMap::new();
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

/// A group's anchor on the grid (page mm, y down): its first item's first
/// point; None for an empty group.
pub(crate) fn anchor(g: &Group) -> Option<(i64, i64)> {
    let p = match &g.items.first()?.shape {
        Shape::Circle { center, .. } => *center,
        Shape::Path { start, .. } => *start,
        Shape::Text { at, .. } => *at,
    };
    Some((units(p.x), units(p.y)))
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
    fn offsets_are_whole_grid_steps() {
        let at = (units(785.69554), units(1090.0));
        let p = offset(at)(DVec2::new(799.83771, 1085.00004));
        assert_eq!((p.x * 1e4).round() as i64, 141_422);
        assert_eq!((p.y * 1e4).round() as i64, -50_000);
        assert_eq!(units(p.x) + at.0, units(799.83771));
    }
}
