//! From sheet to finished piece (issue 13): every strip can be told apart
//! once cut (its engraving read back from the drawn sheets), the test piece,
//! colour presets and the LightBurn projects.

use crate::cli::recipes;
use glam::DVec2;
use karigami::{
    Build, Group, Item, Layer, Overrides, Page, Segment, Shape, build, parse_with,
    testing::{TEST_PIECE_ID, font},
};
use std::collections::BTreeMap;

/// The example's build up to its simulation, shared with the other tests
/// (tests/util.rs): cut files, sheets and layouts do not read the
/// simulated shape.
fn build_example(path: &std::path::Path, o: &Overrides) -> &'static Build {
    crate::util::unsimulated_with(path.to_str().unwrap(), o)
}

/// A path's points (arcs by their end points).
fn points(shape: &Shape) -> Vec<DVec2> {
    match shape {
        Shape::Path {
            start, segments, ..
        } => std::iter::once(*start)
            .chain(segments.iter().map(|s| match *s {
                Segment::Line(p) | Segment::Arc { to: p, .. } => p,
            }))
            .collect(),
        _ => vec![],
    }
}

/// What a strip's drawn engraving says, read in the strip's own frame
/// (x along from the start hole, y across): the text whose single-stroke
/// glyphs it is, or the number of dots of the dot code.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Read {
    Text(String),
    Dots(usize),
}

/// The strip frame of a drawn strip: origin at its first hole, unit axis.
fn frame(g: &Group) -> (DVec2, DVec2) {
    let holes: Vec<DVec2> = g
        .items
        .iter()
        .filter_map(|i| match i.shape {
            Shape::Circle { center, .. } if i.layer == Layer::Holes => Some(center),
            _ => None,
        })
        .collect();
    let axis = (holes[holes.len() - 1] - holes[0]).normalize();
    (holes[0], axis)
}

fn labels(g: &Group) -> Vec<Vec<DVec2>> {
    let (o, axis) = frame(g);
    let across = DVec2::new(-axis.y, axis.x);
    g.items
        .iter()
        .filter(|i: &&Item| i.layer == Layer::Labels)
        .map(|i| {
            points(&i.shape)
                .into_iter()
                .map(|p| DVec2::new((p - o).dot(axis), (p - o).dot(across)))
                .collect()
        })
        .collect()
}

/// Whether `strokes` are exactly the glyphs of `text` at some height and
/// position (y down in the strip frame, as engraved).
fn says(strokes: &[Vec<DVec2>], text: &str) -> bool {
    let glyphs = font::text(text, 1.0);
    if glyphs.len() != strokes.len() {
        return false;
    }
    let min = |v: &[Vec<DVec2>]| {
        v.iter()
            .flatten()
            .fold(DVec2::splat(f64::INFINITY), |a, &p| a.min(p))
    };
    let max = |v: &[Vec<DVec2>]| {
        v.iter()
            .flatten()
            .fold(DVec2::splat(f64::NEG_INFINITY), |a, &p| a.max(p))
    };
    // Glyphs are y up; engraving is y down: flip, then fit scale and offset.
    let glyphs: Vec<Vec<DVec2>> = glyphs
        .into_iter()
        .map(|s| s.into_iter().map(|p| DVec2::new(p.x, -p.y)).collect())
        .collect();
    let (g0, g1, s0, s1) = (min(&glyphs), max(&glyphs), min(strokes), max(strokes));
    let scale = (s1.x - s0.x) / (g1.x - g0.x);
    if !(scale > 0.0) {
        return false;
    }
    glyphs.iter().zip(strokes).all(|(g, s)| {
        g.len() == s.len()
            && g.iter()
                .zip(s)
                .all(|(&a, &b)| (s0 + (a - g0) * scale).distance(b) < 1e-6)
    })
}

/// The dots of a dot code: small closed squares not part of a glyph.
fn dots(strokes: &[Vec<DVec2>]) -> (usize, Vec<Vec<DVec2>>) {
    let mut rest = Vec::new();
    let mut n = 0;
    for s in strokes {
        let side = s.iter().map(|p| p.distance(s[0])).fold(0.0, f64::max);
        if s.len() == 5 && s[0].distance(s[4]) < 1e-9 && side <= karigami::testing::DOT * 1.5 {
            n += 1;
        } else {
            rest.push(s.clone());
        }
    }
    (n, rest)
}

fn read(g: &Group, candidates: &[String]) -> Option<Read> {
    let strokes = labels(g);
    if let Some(t) = candidates.iter().find(|t| says(&strokes, t)) {
        return Some(Read::Text(t.clone()));
    }
    let (n, rest) = dots(&strokes);
    (n > 0 && (rest.is_empty() || says(&rest, "<"))).then_some(Read::Dots(n))
}

/// Hole pitches and outline spine length of a drawn strip, measured.
fn measure(g: &Group) -> [f64; 3] {
    let holes: Vec<DVec2> = g
        .items
        .iter()
        .filter_map(|i| match i.shape {
            Shape::Circle { center, .. } if i.layer == Layer::Holes => Some(center),
            _ => None,
        })
        .collect();
    let (o, axis) = frame(g);
    let outline = g.items.iter().find(|i| i.layer == Layer::Outlines).unwrap();
    let along: Vec<f64> = points(&outline.shape)
        .iter()
        .map(|p| (*p - o).dot(axis))
        .collect();
    let spine = along.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        - along.iter().copied().fold(f64::INFINITY, f64::min);
    [
        holes[0].distance(holes[1]),
        holes[1].distance(holes[2]),
        spine,
    ]
}

#[test]
fn every_strip_of_every_example_can_be_told_apart_once_cut() {
    let mut summary = Vec::new();
    for path in recipes("examples") {
        let b = build_example(&path, &Overrides::default());
        let tol = b.design.fabrication.part_tolerance;
        let parts = &b.parts;
        let index: BTreeMap<&str, usize> = parts
            .strips
            .iter()
            .enumerate()
            .map(|(i, s)| (s.id.as_str(), i))
            .collect();
        // Engraving read back from the drawn sheets -> the strips that carry it.
        let mut by_engraving: BTreeMap<Read, Vec<(String, [f64; 3])>> = BTreeMap::new();
        let (mut ids, mut types, mut dotted) = (0, 0, 0);
        for page in &b.pages {
            for g in page
                .groups
                .iter()
                .filter(|g| index.contains_key(g.id.as_str()))
            {
                let s = &parts.strips[index[g.id.as_str()]];
                let t = &parts.types[s.part_type];
                let code = if t.symmetric {
                    t.code.clone()
                } else {
                    format!("<{}", t.code)
                };
                let said = read(g, &[format!("<{}", s.id), code.clone()]).unwrap_or_else(|| {
                    panic!(
                        "{}: {} carries no ID, type or dot code",
                        path.display(),
                        s.id
                    )
                });
                match &said {
                    Read::Text(t) if *t == format!("<{}", s.id) => ids += 1,
                    Read::Text(t) => {
                        assert_eq!(*t, code);
                        types += 1;
                    }
                    Read::Dots(n) => {
                        assert_eq!(Some(*n), t.dots, "{}", s.id);
                        dotted += 1;
                    }
                }
                by_engraving
                    .entry(said)
                    .or_default()
                    .push((s.id.clone(), measure(g)));
            }
        }
        assert_eq!(
            ids + types + dotted,
            parts.strips.len(),
            "{}",
            path.display()
        );
        // Strips that read the same are interchangeable, measured on the sheet.
        for (said, strips) in &by_engraving {
            if strips.len() == 1 {
                continue;
            }
            for (a, ma) in strips {
                for (b, mb) in strips {
                    for k in 0..3 {
                        assert!(
                            (ma[k] - mb[k]).abs() <= tol + 1e-6,
                            "{}: {a} and {b} both read {said:?} but differ by {} mm",
                            path.display(),
                            (ma[k] - mb[k]).abs()
                        );
                    }
                }
            }
        }
        summary.push(format!(
            "{}: {} strips, {} types: {ids} ID, {types} type code, {dotted} dot code",
            path.file_stem().unwrap().to_string_lossy(),
            parts.strips.len(),
            parts.types.len()
        ));
    }
    eprintln!("{}", summary.join("\n"));
}

#[test]
fn the_test_piece_is_on_sheet_one_unless_left_out() {
    let path = crate::cli::repo().join("examples/flat-sheet.toml");
    let b = build_example(&path, &Overrides::default());
    let fab = &b.design.fabrication;
    let piece = karigami::testing::test_piece(fab).unwrap();
    let page = &b.pages[0];
    let g = page
        .groups
        .iter()
        .find(|g| g.id == TEST_PIECE_ID)
        .expect("a test piece");
    // Its holes: the stepped diameters, nominal among them.
    let diameters: Vec<f64> = g
        .items
        .iter()
        .filter_map(|i| match i.shape {
            Shape::Circle { radius, .. } => Some(2.0 * radius),
            _ => None,
        })
        .collect();
    assert_eq!(diameters.len(), piece.holes.len());
    assert!(diameters.len() >= 3);
    assert!(diameters.iter().any(|d| (d - fab.eyelet.hole).abs() < 1e-9));
    for w in diameters.windows(2) {
        assert!((w[1] - w[0] - 0.1).abs() < 1e-9, "{diameters:?}");
    }
    // 100 mm tip to tip: the outline's extent along its axis.
    let (o, axis) = frame(g);
    let outline = g.items.iter().find(|i| i.layer == Layer::Outlines).unwrap();
    let along: Vec<f64> = points(&outline.shape)
        .iter()
        .map(|p| (*p - o).dot(axis))
        .collect();
    let spine = along.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        - along.iter().copied().fold(f64::INFINITY, f64::min);
    assert!((spine + fab.material.width - 100.0).abs() < 1e-9, "{spine}");
    // Every hole labelled with its diameter, and the length.
    let strokes = labels(g);
    let glyphs: usize = piece.labels.iter().map(|t| font::text(t, 1.0).len()).sum();
    assert_eq!(strokes.len(), glyphs);
    assert_eq!(piece.labels.len(), piece.holes.len() + 1);
    // Nested like a part: inside the margins and clear of every strip.
    let spec = &b.layout.sheet;
    let bbox = |g: &Group| {
        let pts: Vec<DVec2> = g
            .items
            .iter()
            .filter(|i| i.layer.is_cut())
            .flat_map(|i| match i.shape {
                Shape::Circle { center, radius } => {
                    vec![center - DVec2::splat(radius), center + DVec2::splat(radius)]
                }
                _ => points(&i.shape),
            })
            .collect();
        let lo = pts
            .iter()
            .fold(DVec2::splat(f64::INFINITY), |a, &p| a.min(p));
        let hi = pts
            .iter()
            .fold(DVec2::splat(f64::NEG_INFINITY), |a, &p| a.max(p));
        (lo - DVec2::splat(fab.material.width / 2.0) * 0.0, hi)
    };
    let (lo, hi) = bbox(g);
    // Arcs bulge beyond their end points by at most half the width.
    let half = fab.material.width / 2.0;
    assert!(lo.x >= spec.margin - half && lo.y >= spec.margin - half);
    assert!(hi.x <= spec.width - spec.margin + half && hi.y <= spec.height - spec.margin + half);
    let p = b.layout.sheets[0].test_piece.unwrap();
    let len = b.layout.test_piece.unwrap();
    let rect = |x: f64, y: f64, rotated: bool, l: f64| {
        let (w, h) = if rotated {
            (b.layout.part_width, l)
        } else {
            (l, b.layout.part_width)
        };
        (x, y, x + w, y + h)
    };
    let t = rect(p.x, p.y, p.rotated, len);
    for q in &b.layout.sheets[0].placements {
        let r = rect(q.x, q.y, q.rotated, b.layout.lengths[q.part]);
        let apart = (r.0 - t.2).max(t.0 - r.2).max(r.1 - t.3).max(t.1 - r.3);
        assert!(
            apart >= spec.gap - 1e-9,
            "test piece {apart} mm from strip {}",
            q.part
        );
    }
    // Left out on request.
    let o = Overrides {
        test_piece: Some(false),
        ..Overrides::default()
    };
    let b = build_example(&path, &o);
    assert!(
        b.pages
            .iter()
            .all(|p| p.groups.iter().all(|g| g.id != TEST_PIECE_ID))
    );
    assert!(b.layout.test_piece.is_none());
}

/// An SVG with every colour replaced by one token and the metadata dropped.
fn without_colours(svg: &[u8]) -> String {
    let s = String::from_utf8(svg.to_vec()).unwrap();
    let start = s.find("<metadata>").unwrap();
    let end = s.find("</metadata>").unwrap();
    let s = format!("{}{}", &s[..start], &s[end..]);
    let mut out = String::new();
    let mut rest = s.as_str();
    while let Some(i) = rest.find('#') {
        out.push_str(&rest[..i]);
        out.push_str("#colour");
        rest = &rest[i + 7..];
    }
    out + rest
}

#[test]
fn colour_presets_change_only_colours() {
    let path = crate::cli::repo().join("examples/disk.toml");
    let a = build_example(&path, &Overrides::default());
    let o = Overrides {
        colours: Some("boxes".into()),
        ..Overrides::default()
    };
    let b = build_example(&path, &o);
    let svgs = |b: &Build| -> Vec<(String, Vec<u8>)> {
        karigami::files(b)
            .into_iter()
            .filter(|f| f.0.ends_with(".svg"))
            .collect()
    };
    let (sa, sb) = (svgs(a), svgs(b));
    assert_eq!(sa.len(), sb.len());
    for ((name, x), (_, y)) in sa.iter().zip(&sb) {
        assert_ne!(x, y, "{name}: the preset changed nothing");
        assert_eq!(without_colours(x), without_colours(y), "{name}");
    }
    // The box-generator convention: outer cut black, inner cut blue,
    // annotation red.
    let colour = |page: &Page, layer: Layer| {
        page.groups
            .iter()
            .flat_map(|g| &g.items)
            .find(|i| i.layer == layer)
            .unwrap()
            .ink
            .stroke
            .unwrap()
    };
    assert_eq!(colour(&b.pages[0], Layer::Outlines), [0, 0, 0]);
    assert_eq!(colour(&b.pages[0], Layer::Holes), [0, 0, 255]);
    assert_eq!(colour(&b.pages[0], Layer::Reference), [255, 0, 0]);
    assert_eq!(colour(&a.pages[0], Layer::Outlines), [255, 0, 0]);
    // An unknown preset is refused by name.
    let text = std::fs::read_to_string(&path).unwrap();
    let bad = Overrides {
        colours: Some("rainbow".into()),
        ..Overrides::default()
    };
    let e = karigami::parse_with(&text, "x", &bad).unwrap_err();
    assert!(
        e.message.contains("rainbow") && e.hint.as_deref().unwrap_or("").contains("boxes"),
        "{e:?}"
    );
}

/// A LightBurn project read back: layers and shapes.
#[derive(Default, Debug)]
struct Lbrn {
    /// index -> (name, priority, output)
    layers: BTreeMap<usize, (String, usize, bool)>,
    /// (layer, centre, radius) of each ellipse
    circles: Vec<(usize, DVec2, f64)>,
    /// (layer, vertices) of each path
    paths: Vec<(usize, Vec<DVec2>, String)>,
    /// Group shapes (the test piece).
    groups: usize,
}

fn numbers_after(s: &str, key: char) -> Vec<f64> {
    // "V1 2c0x3c0y4V5 6" -> the two numbers after each `key`.
    s.split(key)
        .skip(1)
        .flat_map(|chunk| {
            let chunk = chunk.split('c').next().unwrap();
            chunk
                .split_whitespace()
                .map(|t| t.parse::<f64>().unwrap())
                .collect::<Vec<_>>()
        })
        .collect()
}

fn read_lbrn(xml: &str) -> Lbrn {
    use svg::node::element::tag::Type;
    use svg::parser::Event;
    let mut out = Lbrn::default();
    let mut setting: Option<(usize, String, usize, bool)> = None;
    let mut shape: Option<(String, usize, f64)> = None;
    let mut text_of: Option<&'static str> = None;
    let mut verts = String::new();
    let mut prims = String::new();
    let mut xform = String::new();
    // LightBurn's shared geometry: a VertID/PrimID's list is written with
    // its first shape only.
    let mut ids: Option<(String, String)> = None;
    let mut vert_lists: BTreeMap<String, String> = BTreeMap::new();
    let mut prim_lists: BTreeMap<String, String> = BTreeMap::new();
    for e in svg::read(xml).expect("the project parses") {
        match e {
            Event::Tag("LightBurnProject", _, _) => {}
            Event::Tag("CutSetting", Type::Start, _) => setting = Some((0, String::new(), 0, true)),
            Event::Tag("CutSetting", Type::End, _) => {
                let (i, n, p, o) = setting.take().unwrap();
                out.layers.insert(i, (n, p, o));
            }
            Event::Tag(name @ ("index" | "name" | "priority" | "doOutput"), _, a) => {
                let v = a.get("Value").unwrap().to_string();
                let s = setting.as_mut().expect("inside a cut setting");
                match name {
                    "index" => s.0 = v.parse().unwrap(),
                    "name" => s.1 = v,
                    "priority" => s.2 = v.parse().unwrap(),
                    _ => s.3 = v == "1",
                }
            }
            Event::Tag("Shape", Type::Start, a) if *a.get("Type").unwrap() == "Group" => {
                out.groups += 1;
            }
            Event::Tag("Shape", Type::Start, a) => {
                let r = a.get("Rx").map_or(0.0, |v| v.to_string().parse().unwrap());
                if let Some(ry) = a.get("Ry") {
                    assert_eq!(ry.to_string().parse::<f64>().unwrap(), r, "true circles");
                }
                shape = Some((
                    a.get("Type").unwrap().to_string(),
                    a.get("CutIndex").unwrap().to_string().parse().unwrap(),
                    r,
                ));
                ids = a
                    .get("VertID")
                    .map(|v| (v.to_string(), a.get("PrimID").unwrap().to_string()));
                verts.clear();
                prims.clear();
                xform.clear();
            }
            Event::Tag("Shape", Type::End, _) => {
                // The end of a group (its children are already read).
                let Some((kind, cut, r)) = shape.take() else {
                    continue;
                };
                let x: Vec<f64> = xform
                    .split_whitespace()
                    .map(|t| t.parse().unwrap())
                    .collect();
                assert_eq!(&x[..4], &[1.0, 0.0, 0.0, 1.0]);
                if kind == "Ellipse" {
                    out.circles.push((cut, DVec2::new(x[4], x[5]), r));
                } else {
                    assert_eq!(kind, "Path");
                    if let Some((v, p)) = ids.take() {
                        // A list is defined once: by the first shape naming its ID.
                        for (list, id, table) in [
                            (&mut verts, v, &mut vert_lists),
                            (&mut prims, p, &mut prim_lists),
                        ] {
                            if list.is_empty() {
                                list.push_str(table.get(&id).expect("an ID defined before use"));
                            } else {
                                assert!(table.insert(id, list.clone()).is_none(), "defined once");
                            }
                        }
                    }
                    let n = numbers_after(&verts, 'V');
                    let v = n
                        .chunks(2)
                        .map(|c| DVec2::new(c[0] + x[4], c[1] + x[5]))
                        .collect();
                    out.paths.push((cut, v, prims.clone()));
                }
            }
            Event::Tag("XForm", Type::Start, _) => text_of = Some("x"),
            Event::Tag("VertList", Type::Start, _) => text_of = Some("v"),
            Event::Tag("PrimList", Type::Start, _) => text_of = Some("p"),
            Event::Tag(_, Type::End, _) => text_of = None,
            Event::Text(t) => match text_of {
                Some("x") => xform.push_str(t),
                Some("v") => verts.push_str(t),
                Some("p") => prims.push_str(t),
                _ => {}
            },
            _ => {}
        }
    }
    out
}

#[test]
fn lightburn_projects_hold_every_hole_and_outline_with_layers_set_up() {
    for name in ["flat-sheet", "disk"] {
        for colours in ["karigami", "boxes"] {
            let path = crate::cli::repo().join(format!("examples/{name}.toml"));
            let o = Overrides {
                colours: Some(colours.into()),
                ..Overrides::default()
            };
            let b = build_example(&path, &o);
            let files = karigami::files(b);
            for (i, page) in b.pages.iter().enumerate() {
                let file = format!("sheets/sheet-{:02}.lbrn2", i + 1);
                let bytes = &files
                    .iter()
                    .find(|f| f.0 == file)
                    .expect("a project per sheet")
                    .1;
                let lb = read_lbrn(std::str::from_utf8(bytes).unwrap());
                let h = page.height;
                let flip = |p: DVec2| DVec2::new(p.x, h - p.y);
                // Layers: labels, holes, outlines in that order; the reference not output.
                let layer_of = |prefix: &str| {
                    lb.layers
                        .iter()
                        .find(|(_, v)| v.0.starts_with(prefix))
                        .map(|(&i, v)| (i, v.1, v.2))
                        .unwrap()
                };
                let (li, lp, lo) = layer_of("labels");
                let (hi, hp, ho) = layer_of("holes");
                let (oi, op, oo) = layer_of("outlines");
                let (ri, _, ro) = layer_of("reference");
                assert!(lp < hp && hp < op, "holes before outlines, labels first");
                assert!(lo && ho && oo && !ro, "only the reference is not output");
                // LightBurn's palette: the layer index is its colour.
                let expected = if colours == "boxes" {
                    [3, 1, 0, 2]
                } else {
                    [0, 1, 2, 3]
                };
                assert_eq!([li, hi, oi, ri], expected, "{colours}");
                // Every hole: same centre and radius.
                let holes: Vec<(DVec2, f64)> = page
                    .groups
                    .iter()
                    .flat_map(|g| &g.items)
                    .filter_map(|i| match i.shape {
                        Shape::Circle { center, radius } if i.layer == Layer::Holes => {
                            Some((flip(center), radius))
                        }
                        _ => None,
                    })
                    .collect();
                // Every hole is a LightBurn circle: an Ellipse on the holes' layer.
                let circles: Vec<(usize, DVec2, f64)> =
                    lb.circles.iter().filter(|c| c.0 == hi).copied().collect();
                assert!(lb.paths.iter().all(|p| p.0 != hi), "no holes as paths");
                assert_eq!(circles.len(), holes.len(), "{name} {file}");
                for ((c, r), (_, lc, lr)) in holes.iter().zip(&circles) {
                    assert!(
                        c.distance(*lc) < 1e-4 && (r - lr).abs() < 1e-4,
                        "{file}: hole at {c}"
                    );
                }
                // Every outline: its corner points among the path's vertices,
                // closed, lines and Beziers.
                let outlines: Vec<Vec<DVec2>> = page
                    .groups
                    .iter()
                    .flat_map(|g| &g.items)
                    .filter(|i| i.layer == Layer::Outlines)
                    .map(|i| points(&i.shape).into_iter().map(flip).collect())
                    .collect();
                let paths: Vec<_> = lb.paths.iter().filter(|p| p.0 == oi).collect();
                assert_eq!(paths.len(), outlines.len(), "{name} {file}");
                for (pts, (_, verts, prims)) in outlines.iter().zip(&paths) {
                    for p in pts {
                        assert!(
                            verts.iter().any(|v| v.distance(*p) < 1e-4),
                            "{file}: outline point {p} lost"
                        );
                    }
                    assert!(prims.contains('B') && prims.contains('L'), "{prims}");
                    assert!(prims.ends_with(" 0"), "closed: {prims}");
                }
                // The test piece, on sheet 1 only, is one group.
                let pieces = page.groups.iter().filter(|g| g.id == TEST_PIECE_ID).count();
                assert_eq!(lb.groups, pieces, "{file}");
                assert_eq!(pieces, usize::from(i == 0), "{file}");
                // A part's label strokes (ID, arrow) are one path.
                let labels = page
                    .groups
                    .iter()
                    .filter(|g| g.items.iter().any(|i| i.layer == Layer::Labels))
                    .count();
                assert_eq!(lb.paths.iter().filter(|p| p.0 == li).count(), labels);
            }
        }
    }
}

#[test]
fn lightburn_projects_are_well_formed_xml() {
    // A third-party XML parser (Python's expat), when available.
    let dir = crate::cli::scratch("lbrn2-xml");
    let path = crate::cli::repo().join("examples/flat-sheet.toml");
    let b = build_example(&path, &Overrides::default());
    let (name, bytes) = karigami::files(b)
        .into_iter()
        .find(|f| f.0.ends_with(".lbrn2"))
        .unwrap();
    let file = dir.join(name.rsplit('/').next().unwrap());
    std::fs::write(&file, bytes).unwrap();
    let Some(out) = crate::thirdparty::run(
        "python3",
        &[
            "-c",
            "import sys, xml.etree.ElementTree as E; r = E.parse(sys.argv[1]).getroot(); \
             assert r.tag == 'LightBurnProject'; \
             print(sum(1 for s in r.iter('Shape') if s.get('Type') != 'Group'))",
            file.to_str().unwrap(),
        ],
    ) else {
        return;
    };
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let shapes: usize = String::from_utf8_lossy(&out.stdout).trim().parse().unwrap();
    // A shape per item, but a run of a part's labels is one path.
    let mut expected = 0;
    for g in &b.pages[0].groups {
        let mut run = None;
        for i in g.items.iter().filter(|i| i.layer != Layer::Art) {
            let circle = matches!(i.shape, Shape::Circle { .. });
            let joins = i.layer == Layer::Labels && !circle;
            let this = joins.then_some((i.layer, circle));
            if this.is_none() || this != run {
                expected += 1;
            }
            run = this;
        }
    }
    assert_eq!(shapes, expected);
}

#[test]
fn a_helix_that_degenerates_points_at_its_cell_count() {
    let template = karigami::template::find("helix").unwrap();
    let text = karigami::template::instantiate(template, "hx").replace("cells = 12", "cells = 60");
    let design = karigami::parse(&text, "hx").unwrap();
    let e = design.grow().unwrap_err();
    assert_eq!(e.kind.name(), "DoubleEdgeNotSpacelike", "{e:?}");
    let span = e.span.clone().expect("a place in the recipe");
    assert_eq!(&text[span], "60", "{}", e.render("hx.toml", &text));
}

#[test]
fn random_designs_leave_no_strip_unidentifiable() {
    use crate::property::random_lattice;
    let mut rng = crate::util::Rng::new(13);
    let mut built = 0;
    for case in 0..40 {
        let Ok((_, d)) = random_lattice(&mut rng, 2 + case % 2) else {
            continue;
        };
        let text = crate::cutfiles::recipe(&d, 40.0, "");
        let Ok(b) = build(karigami::parse(&text, "random").unwrap()) else {
            continue;
        };
        built += 1;
        let parts = &b.parts;
        let index: BTreeMap<&str, usize> = parts
            .strips
            .iter()
            .enumerate()
            .map(|(i, s)| (s.id.as_str(), i))
            .collect();
        for g in b.pages.iter().flat_map(|p| &p.groups) {
            let Some(&i) = index.get(g.id.as_str()) else {
                continue;
            };
            let s = &parts.strips[i];
            let t = &parts.types[s.part_type];
            let code = if t.symmetric {
                t.code.clone()
            } else {
                format!("<{}", t.code)
            };
            let said = read(g, &[format!("<{}", s.id), code]);
            assert!(
                said.is_some(),
                "case {case}: {} carries nothing readable\n{text}",
                s.id
            );
            if let Some(Read::Dots(n)) = said {
                assert_eq!(Some(n), t.dots);
            }
        }
        // Every type is interchangeable: pitches and length within the tolerance.
        let tol = b.design.fabrication.part_tolerance;
        for t in &parts.types {
            for &a in &t.strips {
                for &c in &t.strips {
                    let (x, y) = (&parts.strips[a], &parts.strips[c]);
                    assert!((x.legs[0] - y.legs[0]).abs() <= tol);
                    assert!((x.legs[1] - y.legs[1]).abs() <= tol);
                    assert!((x.length - y.length).abs() <= tol);
                }
            }
        }
    }
    assert!(built >= 10, "only {built} random designs built");
}

// Sheet advice, cutting by assembly step and holding tabs (issue 13, items 8 and 9).

#[test]
fn check_takes_the_build_flags_and_sheet_auto_picks_the_smallest_preset() {
    use crate::cli::{karigami, repo, scratch};
    use serde_json::Value;
    let dir = scratch("maker-sheet-advice");
    let flat = repo().join("examples/flat-sheet.toml");
    let f = flat.to_str().unwrap();
    // The recipe's 600 x 400 sheet holds the flat sheet at 28 %; A3 holds
    // it on one sheet at 51 % (measured: 0.2674 and 0.5145).
    let out = karigami(&["check", f], &dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("utilisation 26.7%")
            && text.contains(
                "sheet advice: the smallest preset that holds the job is a3 (420 x 297 mm), 1 sheet at 51.5% utilisation"
            ),
        "{text}"
    );
    let out = karigami(&["check", f, "--sheet", "auto", "--json"], &dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let b = &v[0]["build"];
    assert_eq!(b["sheet"]["name"], "a3");
    assert_eq!(b["sheets"], 1);
    assert_eq!(b["sheet_auto"], true);
    let u = b["utilisation"].as_f64().unwrap();
    assert!((u - 0.5145).abs() < 5e-4, "{u}");
    // The pick is the smallest: no preset needs fewer sheets, and every
    // other one-sheet preset is larger than A3.
    let options = b["sheet_options"].as_array().unwrap();
    assert_eq!(options.len(), karigami::SHEET_PRESETS.len());
    let area = |o: &Value| o["width_mm"].as_f64().unwrap() * o["height_mm"].as_f64().unwrap();
    for o in options {
        let n = o["sheets"].as_u64().unwrap();
        assert!(n >= 1);
        if o["name"] != "a3" {
            assert!(n > 1 || area(o) > 420.0 * 297.0, "{o}");
        }
    }
    let a4 = options.iter().find(|o| o["name"] == "a4").unwrap();
    assert_eq!(a4["sheets"], 2);
    let default = options.iter().find(|o| o["name"] == "600x400").unwrap();
    assert!((default["utilisation"].as_f64().unwrap() - 0.2674).abs() < 5e-4);
    assert_eq!(b["sheet_advice"]["name"], "a3");
    // Every fabrication flag of build is a flag of check.
    let out = karigami(
        &[
            "check",
            f,
            "--sheet",
            "a3",
            "--eyelet",
            "5/32in",
            "--strip-width",
            "11",
            "--kerf",
            "0.2",
            "--compensate-kerf",
            "--label",
            "compact",
            "--paper",
            "letter",
            "--no-test-piece",
            "--colours",
            "boxes",
            "--group-by-step",
            "--tabs",
            "0.5",
            "--json",
        ],
        &dir,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let b = &v[0]["build"];
    assert_eq!(b["sheet"]["name"], "a3");
    assert_eq!(b["group_by_step"], true);
    assert_eq!(b["tabs_mm"], 0.5);
    // Part types in check --json: code, count, length, pitches, engraving.
    let types = b["part_types"].as_array().unwrap();
    let strips: u64 = types.iter().map(|t| t["count"].as_u64().unwrap()).sum();
    assert_eq!(strips, b["strips"].as_u64().unwrap());
    for t in types {
        let e = &t["engraved"];
        let engraved: u64 = ["id", "type_code", "dot_code", "arrow_only"]
            .iter()
            .map(|k| e[k].as_u64().unwrap())
            .sum();
        assert_eq!(engraved, t["count"].as_u64().unwrap(), "{t}");
        let p = t["pitches_mm"].as_array().unwrap();
        assert!(t["length_mm"].as_f64().unwrap() > p[0].as_f64().unwrap() + p[1].as_f64().unwrap());
    }
}

#[test]
fn a_recipe_can_ask_for_the_smallest_sheet() {
    let text =
        std::fs::read_to_string(crate::cli::repo().join("examples/flat-sheet.toml")).unwrap();
    let auto = build(
        parse_with(
            &format!("{text}\n[sheet]\npreset = \"auto\"\n"),
            "x",
            &Overrides::default(),
        )
        .unwrap(),
    )
    .unwrap();
    let a3 = build_example(
        &crate::cli::repo().join("examples/flat-sheet.toml"),
        &Overrides {
            sheet: Some("a3".into()),
            ..Overrides::default()
        },
    );
    assert_eq!(auto.design.fabrication.sheet, a3.design.fabrication.sheet);
    assert_eq!(auto.layout, a3.layout);
    // A size beside "auto" is a contradiction, pointed at.
    let err = parse_with(
        &format!("{text}\n[sheet]\npreset = \"auto\"\nwidth = 500\n"),
        "x",
        &Overrides::default(),
    )
    .unwrap_err();
    assert!(err.message.contains("auto"), "{}", err.message);
    assert!(
        err.line_col(&format!(
            "{text}\n[sheet]\npreset = \"auto\"\nwidth = 500\n"
        ))
        .is_some()
    );
}

#[test]
fn cutting_by_step_keeps_each_steps_strips_together_in_step_order() {
    for (name, sheet) in [
        ("torus", "a3"),
        ("flat-sheet", "a4"),
        ("disk", "600x400"),
        // A helix, one cell a step (the gallery's bowl before its redesign).
        ("helix-bowl", "a3"),
    ] {
        let recipe = match name {
            "helix-bowl" => "fixtures/designs/helix-bowl.toml".to_string(),
            _ => format!("examples/{name}.toml"),
        };
        let b = build_example(
            &crate::cli::repo().join(recipe),
            &Overrides {
                sheet: Some(sheet.into()),
                group_by_step: Some(true),
                ..Overrides::default()
            },
        );
        let step = |part: usize| b.lattice.step_of(b.parts.strips[part].rod / 2);
        // Every lane's steps in order along it, sheet by sheet, lane by lane.
        let mut lanes: Vec<Vec<usize>> = Vec::new();
        for (i, s) in b.layout.sheets.iter().enumerate() {
            // A lane is a row of parts at one offset across it.
            let mut on: BTreeMap<i64, Vec<(i64, usize)>> = BTreeMap::new();
            let key = |v: f64| (v * 1000.0).round() as i64;
            for p in &s.placements {
                let (across, along) = if p.rotated { (p.x, p.y) } else { (p.y, p.x) };
                on.entry(key(across))
                    .or_default()
                    .push((key(along), step(p.part)));
            }
            if let Some(t) = s.test_piece {
                assert_eq!(i, 0);
                let (across, along) = if t.rotated { (t.x, t.y) } else { (t.y, t.x) };
                // First on its sheet: no strip before it.
                assert!(on.iter().all(|(&k, v)| k > key(across)
                    || (k == key(across) && v.iter().all(|&(a, _)| a > key(along)))));
            }
            for mut lane in on.into_values() {
                lane.sort();
                lanes.push(lane.into_iter().map(|(_, s)| s).collect());
            }
        }
        let order: Vec<usize> = lanes.iter().flatten().copied().collect();
        assert_eq!(order.len(), b.parts.strips.len());
        assert!(
            order.windows(2).all(|w| w[0] <= w[1]),
            "{name}: steps out of order {order:?}"
        );
        assert_eq!(order.last().copied(), Some(b.lattice.steps() - 1));
        // A lane shared by steps holds every step after its first whole.
        for (i, lane) in lanes.iter().enumerate() {
            for &s in lane.iter().skip_while(|&&s| s == lane[0]) {
                let elsewhere = lanes
                    .iter()
                    .enumerate()
                    .any(|(j, l)| j != i && l.contains(&s));
                assert!(!elsewhere, "{name}: step {s} split across lanes it shares");
            }
        }
        // Row steps (many strips) never share a lane.
        if name != "helix-bowl" {
            assert!(lanes.iter().all(|l| l.iter().all(|&s| s == l[0])), "{name}");
        }
        // The drawn sheets hold the same strips as the layout.
        for (page, s) in b.pages.iter().zip(&b.layout.sheets) {
            for p in &s.placements {
                let id = &b.parts.strips[p.part].id;
                assert!(page.groups.iter().any(|g| &g.id == id));
            }
        }
    }
}

/// Run a tests/tools script on a file; None when Python or its module is missing.
fn python_tool(script: &str, file: &std::path::Path) -> Option<serde_json::Value> {
    let script = crate::cli::repo().join("tests/tools").join(script);
    let out = crate::thirdparty::run(
        "python3",
        &[script.to_str().unwrap(), file.to_str().unwrap()],
    )?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            std::env::var_os("KARIGAMI_REQUIRE_TOOLS").is_none()
                && err.contains("ModuleNotFoundError"),
            "{err}"
        );
        eprintln!("note: {} needs a Python module: {err}", script.display());
        return None;
    }
    Some(serde_json::from_slice(&out.stdout).unwrap())
}

#[test]
fn holding_tabs_are_gaps_of_the_tab_width_in_every_outline_of_every_file() {
    use karigami::{Outline, testing::tabs::centres};
    use std::f64::consts::PI;
    let tab = 0.5;
    for compensate in [false, true] {
        let b = build_example(
            &crate::cli::repo().join("examples/flat-sheet.toml"),
            &Overrides {
                sheet: Some("a3".into()),
                tabs: Some(tab),
                compensate_kerf: Some(compensate),
                ..Overrides::default()
            },
        );
        let fab = &b.design.fabrication;
        // From the drawing model: per outline, the perimeter of the full
        // stadium less what is drawn is the tab count times the tab width.
        let mut expected: BTreeMap<String, (usize, f64)> = BTreeMap::new();
        for g in b
            .pages
            .iter()
            .flat_map(|p| &p.groups)
            .filter(|g| g.id != "reference")
        {
            let length = if g.id == TEST_PIECE_ID {
                karigami::testing::test_piece::LENGTH
            } else {
                b.parts.strips.iter().find(|s| s.id == g.id).unwrap().length
            };
            let o = Outline::of(length, fab);
            let r = o.width / 2.0;
            let (top, bottom) = centres(-o.grow + r, length + o.grow - r, tab);
            let tabs = top.len() + bottom.len();
            assert!(tabs >= 2, "{}", g.id);
            let pieces: Vec<&Item> = g
                .items
                .iter()
                .filter(|i| i.layer == Layer::Outlines)
                .collect();
            assert_eq!(pieces.len(), tabs, "{}: one piece between two tabs", g.id);
            assert!(
                pieces
                    .iter()
                    .all(|i| matches!(i.shape, Shape::Path { closed: false, .. }))
            );
            let drawn: f64 = pieces.iter().map(|i| i.shape.length()).sum();
            let perimeter = 2.0 * (o.length - o.width) + PI * o.width;
            let uncut = perimeter - drawn;
            assert!(
                (uncut - tabs as f64 * tab).abs() < 0.01,
                "{}: {uncut} mm uncut for {tabs} tabs",
                g.id
            );
            expected.insert(g.id.clone(), (tabs, perimeter));
        }
        if compensate {
            continue;
        }
        let dir = crate::cli::scratch("maker-tabs");
        let page = &b.pages[0];
        let svg = dir.join("sheet.svg");
        std::fs::write(&svg, karigami::formats::svg::write(page)).unwrap();
        // Read back with svgelements: the same pieces and gaps.
        if let Some(v) = python_tool("outline_pieces.py", &svg) {
            let groups = v["groups"].as_object().unwrap();
            assert_eq!(groups.len(), expected.len());
            for (id, (tabs, perimeter)) in &expected {
                let [n, len] = [&groups[id][0], &groups[id][1]];
                assert_eq!(n.as_u64().unwrap() as usize, *tabs, "{id}");
                let uncut = perimeter - len.as_f64().unwrap();
                assert!(
                    (uncut - *tabs as f64 * tab).abs() < 0.01,
                    "{id}: svgelements reads {uncut} mm uncut"
                );
            }
        }
        // DXF (ezdxf): open polylines only, the same total gap.
        let dxf = dir.join("sheet.dxf");
        std::fs::write(&dxf, karigami::formats::dxf::write(page)).unwrap();
        if let Some(v) = python_tool("outline_pieces.py", &dxf) {
            let tabs: usize = expected.values().map(|e| e.0).sum();
            let perimeters: f64 = expected.values().map(|e| e.1).sum();
            assert_eq!(v["count"].as_u64().unwrap() as usize, tabs);
            assert_eq!(v["closed"], 0);
            let uncut = perimeters - v["length"].as_f64().unwrap();
            assert!(
                (uncut - tabs as f64 * tab).abs() < 0.01 * tabs as f64,
                "{uncut}"
            );
        }
        // LightBurn: one open path per piece on the outlines layer.
        let lbrn = read_lbrn(&String::from_utf8(karigami::formats::lbrn2::write(page)).unwrap());
        let outlines = *lbrn
            .layers
            .iter()
            .find(|(_, l)| l.0.starts_with("outlines"))
            .unwrap()
            .0;
        let paths = lbrn.paths.iter().filter(|p| p.0 == outlines).count();
        assert_eq!(paths, expected.values().map(|e| e.0).sum::<usize>());
    }
    // Without tabs, each outline stays one closed path.
    let b = build_example(
        &crate::cli::repo().join("examples/flat-sheet.toml"),
        &Overrides::default(),
    );
    for g in b.pages[0].groups.iter().filter(|g| g.id != "reference") {
        let pieces: Vec<&Item> = g
            .items
            .iter()
            .filter(|i| i.layer == Layer::Outlines)
            .collect();
        assert!(matches!(
            pieces[..],
            [Item {
                shape: Shape::Path { closed: true, .. },
                ..
            }]
        ));
    }
}

#[test]
fn dxf_layer_colours_follow_the_colour_preset() {
    // (colour preset, ACI of holes, outlines, labels, reference)
    for (preset, aci) in [("karigami", [5, 1, 7, 3]), ("boxes", [5, 7, 3, 1])] {
        let b = build_example(
            &crate::cli::repo().join("examples/flat-sheet.toml"),
            &Overrides {
                colours: Some(preset.into()),
                ..Overrides::default()
            },
        );
        let dxf = String::from_utf8(karigami::formats::dxf::write(&b.pages[0])).unwrap();
        let pairs: Vec<&str> = dxf.lines().map(str::trim).collect();
        for (layer, want) in Layer::ALL.iter().zip(aci) {
            let want = want.to_string();
            // The LAYER table entry: name (2), flags (70), colour (62).
            let table = pairs
                .windows(6)
                .find(|w| w[0] == "2" && w[1] == layer.name() && w[2] == "70" && w[4] == "62")
                .unwrap_or_else(|| panic!("{preset}: no layer {}", layer.name()));
            assert_eq!(table[5], want, "{preset}: layer {}", layer.name());
            // Every entity on the layer: layer (8), colour (62).
            let entities: Vec<&&str> = pairs
                .windows(4)
                .filter(|w| w[0] == "8" && w[1] == layer.name() && w[2] == "62")
                .map(|w| &w[3])
                .collect();
            assert!(!entities.is_empty());
            assert!(
                entities.iter().all(|c| **c == want),
                "{preset}: {}",
                layer.name()
            );
        }
    }
}

#[test]
fn tab_and_grouping_settings_are_checked() {
    let text =
        std::fs::read_to_string(crate::cli::repo().join("examples/flat-sheet.toml")).unwrap();
    for (extra, says) in [
        ("[laser]\ntabs = 12\n", "wider than the 10 mm strips"),
        ("[laser]\ntabs = -1\n", "laser.tabs"),
        ("[sheet]\ngroup = \"rows\"\n", "unknown sheet grouping"),
    ] {
        let source = format!("{text}\n{extra}");
        let err = parse_with(&source, "x", &Overrides::default()).unwrap_err();
        assert!(err.message.contains(says), "{extra}: {}", err.message);
        let (line, _) = err.line_col(&source).expect("located");
        assert_eq!(
            source.lines().nth(line - 1).unwrap(),
            extra.lines().nth(1).unwrap()
        );
    }
    let err = parse_with(
        &text,
        "x",
        &Overrides {
            tabs: Some(f64::NAN),
            ..Overrides::default()
        },
    )
    .unwrap_err();
    assert!(err.message.contains("--tabs"), "{}", err.message);
}

#[test]
fn sheets_cut_by_step_with_tabs_are_the_same_on_every_run() {
    let o = Overrides {
        sheet: Some("auto".into()),
        group_by_step: Some(true),
        tabs: Some(0.5),
        ..Overrides::default()
    };
    let path = crate::cli::repo().join("fixtures/designs/helix-bowl.toml");
    let fresh = crate::util::unsimulated(path.to_str().unwrap(), &o);
    let (a, b) = (build_example(&path, &o), fresh.build());
    // The helix bowl (the gallery's bowl before its redesign) grouped by
    // step needs the 600 x 400 sheet.
    assert_eq!(a.design.fabrication.sheet.name, "600x400");
    for (p, q) in a.pages.iter().zip(&b.pages) {
        assert_eq!(
            karigami::formats::svg::write(p),
            karigami::formats::svg::write(q)
        );
        assert_eq!(
            karigami::formats::dxf::write(p),
            karigami::formats::dxf::write(q)
        );
        assert_eq!(
            karigami::formats::lbrn2::write(p),
            karigami::formats::lbrn2::write(q)
        );
    }
}

/// Issue 13 item 11: the PDFs carry no date (neither the wall clock, which
/// would break byte-identical output, nor a made-up one such as 1970) and no
/// PDF/X version key; poppler reads them without any date.
#[test]
fn pdfs_carry_no_dates_and_no_pdfx_key() {
    let b = build_example(
        &crate::cli::repo().join("examples/flat-sheet.toml"),
        &Overrides::default(),
    );
    let files = karigami::files(b);
    let dir = crate::cli::scratch("pdf-metadata");
    for name in ["assembly.pdf", "cut.pdf"] {
        let bytes = &files.iter().find(|f| f.0 == name).expect(name).1;
        let raw = String::from_utf8_lossy(bytes);
        for key in ["/CreationDate", "/ModDate", "GTS_PDFX", "D:1970"] {
            assert!(!raw.contains(key), "{name} has {key}");
        }
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        if let Some(o) = crate::thirdparty::run("pdfinfo", &[path.to_str().unwrap()]) {
            let info = String::from_utf8_lossy(&o.stdout);
            assert!(info.contains("Pages:"), "{name}: {info}");
            assert!(
                !info.contains("CreationDate") && !info.contains("ModDate"),
                "{name}: {info}"
            );
        }
    }
}
