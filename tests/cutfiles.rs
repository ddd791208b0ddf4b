//! Cut files re-measured from what was written: random designs go through the
//! whole pipeline as TOML recipes, and the SVG sheets (read with the svg
//! crate's parser) must hold every strip with its holes at the lattice's leg
//! lengths, no two parts closer than the gap, all inside the margins.

use crate::property::{RandomDesign, random_lattice};
use crate::util::Rng;
use glam::DVec2;
use karigami::{Direction, Leg};
use serde_json::Value;
use std::collections::HashMap;
use svg::node::element::tag::Type;
use svg::parser::Event;

/// A random admissible design as a recipe in mm (unit lattices scaled up).
pub(crate) fn recipe(d: &RandomDesign, scale: f64, extra: &str) -> String {
    let coords = |v: glam::DVec3| {
        let c: Vec<String> = v.to_array()[..d.dim]
            .iter()
            .map(|x| format!("{:?}", x * scale))
            .collect();
        format!("[{}]", c.join(", "))
    };
    let mut t = String::from("[lattice]\nseed = \"sheet\"\n");
    let pts: Vec<String> = d.points.iter().map(|&p| coords(p)).collect();
    t += &format!("points = [{}]\n", pts.join(", "));
    let k: Vec<String> = d.kappa.iter().map(|k| format!("{:?}", k * scale)).collect();
    t += &format!("kappa = [{}]\n", k.join(", "));
    for r in &d.rows {
        let Some(Direction::Vector(v)) = r.direction else {
            panic!("random rows use vectors")
        };
        let leg = |l: Leg| match l {
            Leg::Match => "\"match\"".to_string(),
            Leg::Length(x) => format!("{:?}", x * scale),
        };
        let dir: Vec<String> = v.to_array()[..d.dim]
            .iter()
            .map(|x| format!("{x:?}"))
            .collect();
        t += &format!(
            "[[lattice.rows]]\nstart = {}\ndirection = [{}]\nleft_leg = {}\nright_leg = {}\n",
            r.start,
            dir.join(", "),
            leg(r.left_leg),
            leg(r.right_leg)
        );
    }
    t + extra
}

/// What an SVG sheet holds, per strip group.
#[derive(Default, Debug)]
pub(crate) struct SvgStrip {
    pub holes: Vec<(DVec2, f64)>,
    /// The two semicircle centres of the outline and its radius.
    pub spine: Option<(DVec2, DVec2, f64)>,
}

pub(crate) struct SvgSheet {
    pub width_mm: f64,
    pub height_mm: f64,
    pub view_box: Vec<f64>,
    pub strips: HashMap<String, SvgStrip>,
}

fn numbers(s: &str) -> Vec<f64> {
    s.split(|c: char| c.is_whitespace() || c == ',' || c.is_ascii_alphabetic() && c != 'e')
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().unwrap())
        .collect()
}

/// The points a path passes through, absolute, after each of its commands
/// (`M`, `L`, `A` absolute; `h`, `v`, `l`, `a` relative; `z`), and the radius
/// of its last arc.
fn path_points(d: &str) -> (Vec<DVec2>, f64) {
    let mut commands: Vec<(char, Vec<f64>)> = Vec::new();
    for (i, c) in d
        .char_indices()
        .filter(|(_, c)| c.is_ascii_alphabetic() && *c != 'e')
    {
        let rest = &d[i + 1..];
        let end = rest
            .find(|c: char| c.is_ascii_alphabetic() && c != 'e')
            .unwrap_or(rest.len());
        commands.push((c, numbers(&rest[..end])));
    }
    let (mut at, mut points, mut radius) = (DVec2::ZERO, Vec::new(), 0.0);
    for (c, n) in commands {
        at = match c {
            'M' | 'L' => DVec2::new(n[0], n[1]),
            'A' => DVec2::new(n[5], n[6]),
            'h' => at + DVec2::new(n[0], 0.0),
            'v' => at + DVec2::new(0.0, n[0]),
            'l' => at + DVec2::new(n[0], n[1]),
            'a' => at + DVec2::new(n[5], n[6]),
            'z' | 'Z' => continue,
            other => panic!("unexpected path command {other}"),
        };
        if c.eq_ignore_ascii_case(&'a') {
            radius = n[0];
        }
        points.push(at);
    }
    (points, radius)
}

/// The outline path (start, line, semicircle, line, semicircle): its spine.
fn spine(d: &str) -> (DVec2, DVec2, f64) {
    let (p, r) = path_points(d);
    let (m, l1, a1, l2) = (p[0], p[1], p[2], p[3]);
    ((l1 + a1) / 2.0, (m + l2) / 2.0, r)
}

pub(crate) fn read_svg(text: &str) -> SvgSheet {
    let mut sheet = SvgSheet {
        width_mm: 0.0,
        height_mm: 0.0,
        view_box: vec![],
        strips: HashMap::new(),
    };
    let mut group: Option<String> = None;
    // Drawings written once in <defs> and placed by a <use> in each strip's
    // group (src/write/svg.rs), read relative to the place they are used at.
    let mut defs: HashMap<String, SvgStrip> = HashMap::new();
    let mut in_defs = false;
    for event in svg::read(text).expect("the SVG parses") {
        if let Event::Tag(name, kind, attrs) = event {
            let get = |k: &str| attrs.get(k).map(|v| v.to_string());
            match (name, kind) {
                ("svg", Type::Start) => {
                    sheet.width_mm = get("width")
                        .unwrap()
                        .trim_end_matches("mm")
                        .parse()
                        .unwrap();
                    sheet.height_mm = get("height")
                        .unwrap()
                        .trim_end_matches("mm")
                        .parse()
                        .unwrap();
                    sheet.view_box = numbers(&get("viewBox").unwrap());
                }
                ("defs", Type::Start) => in_defs = true,
                ("defs", Type::End) => in_defs = false,
                ("g", Type::Start) => group = get("id"),
                ("g", Type::End) => group = None,
                ("circle", _) => {
                    let g = group.clone().expect("circles belong to a strip");
                    let c = DVec2::new(
                        get("cx").unwrap().parse().unwrap(),
                        get("cy").unwrap().parse().unwrap(),
                    );
                    let r: f64 = get("r").unwrap().parse().unwrap();
                    let into = if in_defs {
                        &mut defs
                    } else {
                        &mut sheet.strips
                    };
                    into.entry(g).or_default().holes.push((c, r));
                }
                ("path", _) if get("class").as_deref() == Some("outlines") => {
                    let g = group.clone().expect("outlines belong to a strip");
                    let into = if in_defs {
                        &mut defs
                    } else {
                        &mut sheet.strips
                    };
                    into.entry(g).or_default().spine = Some(spine(&get("d").unwrap()));
                }
                ("use", _) => {
                    let g = group.clone().expect("a <use> belongs to a strip");
                    let href = get("xlink:href").expect("a <use> names its drawing");
                    let drawing = &defs[href.trim_start_matches('#')];
                    let at = DVec2::new(
                        get("x").unwrap().parse().unwrap(),
                        get("y").unwrap().parse().unwrap(),
                    );
                    let strip = sheet.strips.entry(g).or_default();
                    strip
                        .holes
                        .extend(drawing.holes.iter().map(|&(c, r)| (c + at, r)));
                    strip.spine = drawing.spine.map(|(a, b, r)| (a + at, b + at, r));
                }
                _ => {}
            }
        }
    }
    sheet
}

fn segment_distance(a0: DVec2, a1: DVec2, b0: DVec2, b1: DVec2) -> f64 {
    let point_seg = |p: DVec2, s0: DVec2, s1: DVec2| {
        let d = s1 - s0;
        let t = if d.length_squared() > 0.0 {
            ((p - s0).dot(d) / d.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        p.distance(s0 + t * d)
    };
    // Parallel or not, for non-crossing segments the minimum is at an endpoint.
    let crossing = {
        let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
        cross(a0, a1, b0) * cross(a0, a1, b1) < 0.0 && cross(b0, b1, a0) * cross(b0, b1, a1) < 0.0
    };
    if crossing {
        return 0.0;
    }
    point_seg(a0, b0, b1)
        .min(point_seg(a1, b0, b1))
        .min(point_seg(b0, a0, a1))
        .min(point_seg(b1, a0, a1))
}

/// Each rod's two legs, by id, derived from lattice.json's cells as
/// docs/lattice-json.md says: rod A of cell c (id 2c) runs UL-pivot-LR,
/// rod B (id 2c + 1) UR-pivot-LL, UL and UR from `top` where a row rebuilt.
pub(crate) fn rod_legs(lattice: &Value) -> Vec<[f64; 2]> {
    let vertices = lattice["vertices"].as_array().unwrap();
    let xyz = crate::util::floats;
    let dist = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let mut legs = Vec::new();
    for cell in lattice["cells"].as_array().unwrap() {
        let corner = |k: usize| {
            if k < 2 && !cell["top"].is_null() {
                return xyz(&cell["top"][k]);
            }
            xyz(&vertices[cell["vertices"][k].as_u64().unwrap() as usize]["pos"])
        };
        let p = xyz(&cell["pivot"]);
        let [ul, ur, ll, lr] = [0, 1, 2, 3].map(|k| dist(&p, &corner(k)));
        legs.push([ul, lr]);
        legs.push([ur, ll]);
    }
    legs
}

/// Check every written sheet of a build against its lattice.json and parts.csv.
pub(crate) fn check_files(files: &[(String, Vec<u8>)], margin: f64, gap: f64) {
    let file = |name: &str| {
        &files
            .iter()
            .find(|f| f.0 == name)
            .unwrap_or_else(|| panic!("{name} written"))
            .1
    };
    let lattice: Value = serde_json::from_slice(file("lattice.json")).unwrap();
    let rods = rod_legs(&lattice);
    let csv = String::from_utf8(file("parts.csv").clone()).unwrap();
    let rod_of: HashMap<&str, usize> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[0], f[1].parse().unwrap())
        })
        .collect();
    assert_eq!(rod_of.len(), rods.len(), "one strip per rod");
    let mut seen = 0;
    for (name, bytes) in files.iter().filter(|f| f.0.ends_with(".svg")) {
        let sheet = read_svg(std::str::from_utf8(bytes).unwrap());
        assert_eq!(
            sheet.view_box,
            [0.0, 0.0, sheet.width_mm, sheet.height_mm],
            "{name}: one user unit = 1 mm"
        );
        let strips: Vec<(&String, &SvgStrip)> = sheet.strips.iter().collect();
        for (id, s) in &strips {
            if id.as_str() == karigami::testing::TEST_PIECE_ID {
                // The test piece: on the first sheet, within the margins and
                // clear of every strip like a part (checked below).
                assert!(
                    name.ends_with("sheet-01.svg"),
                    "{name}: test piece off sheet 1"
                );
                assert!(!s.holes.is_empty(), "{name}: test piece without holes");
                let (a, b, r) = s.spine.expect("a test piece outline");
                for p in [a, b] {
                    assert!(
                        p.x - r >= margin - 1e-6
                            && p.x + r <= sheet.width_mm - margin + 1e-6
                            && p.y - r >= margin - 1e-6
                            && p.y + r <= sheet.height_mm - margin + 1e-6,
                        "{name}: test piece outside the margins"
                    );
                }
                continue;
            }
            seen += 1;
            let legs = rods[rod_of[id.as_str()]];
            assert_eq!(s.holes.len(), 3, "{id}: three holes");
            for (k, leg) in legs.iter().enumerate() {
                let measured = s.holes[k].0.distance(s.holes[k + 1].0);
                assert!(
                    (measured - leg).abs() < 0.01,
                    "{name} {id}: holes {k}-{} are {measured} apart, leg is {leg}",
                    k + 1
                );
            }
            let (a, b, r) = s.spine.expect("an outline");
            for p in [a, b] {
                assert!(
                    p.x - r >= margin - 1e-6 && p.x + r <= sheet.width_mm - margin + 1e-6,
                    "{name} {id}: outside the margin in x"
                );
                assert!(
                    p.y - r >= margin - 1e-6 && p.y + r <= sheet.height_mm - margin + 1e-6,
                    "{name} {id}: outside the margin in y"
                );
            }
        }
        for i in 0..strips.len() {
            for j in i + 1..strips.len() {
                let (a0, a1, r) = strips[i].1.spine.unwrap();
                let (b0, b1, _) = strips[j].1.spine.unwrap();
                let d = segment_distance(a0, a1, b0, b1);
                assert!(
                    d >= 2.0 * r + gap - 1e-3,
                    "{name}: {} and {} are {:.4} mm apart",
                    strips[i].0,
                    strips[j].0,
                    d - 2.0 * r
                );
            }
        }
    }
    assert_eq!(seen, rods.len(), "every strip is on a sheet");
}

#[test]
fn random_designs_give_true_cut_files() {
    let mut rng = Rng::new(11);
    let mut built = 0;
    let sheets = ["600x400", "a4", "glowforge"];
    for case in 0..60 {
        let dim = 2 + case % 2;
        let Ok((_, d)) = random_lattice(&mut rng, dim) else {
            continue;
        };
        let sheet = sheets[case % 3];
        // Random cells may overlap their neighbours; the files are still checked.
        let text = recipe(
            &d,
            40.0,
            &format!("[sheet]\npreset = \"{sheet}\"\n[clash]\nallow = true\n"),
        );
        let design = karigami::parse(&text, "random")
            .unwrap_or_else(|e| panic!("{}", e.render("random", &text)));
        // Up to the simulation: the cut files and lattice.json are what is
        // checked, and they do not read the simulated shape.
        match karigami::build_unsimulated(design, &mut |_| {}) {
            Ok(u) => {
                let b = u.build();
                built += 1;
                check_files(
                    &karigami::files(b),
                    b.design.fabrication.sheet.margin,
                    b.design.fabrication.sheet.gap,
                );
            }
            // Random cells can be too small for the eyelets or too long for
            // the sheet; those are refused by name, never mis-drawn.
            Err(e) => assert!(
                ["LegShorterThanFlange", "StripLongerThanSheet"].contains(&e.kind.name()),
                "{e:?}"
            ),
        }
    }
    assert!(built >= 20, "only {built} random designs built");
}

#[test]
fn building_twice_in_one_process_gives_identical_bytes() {
    // printpdf's document IDs come from a process-wide counter; ours must not.
    let o = karigami::Overrides::default();
    let once = karigami::files(crate::util::example("flat-sheet"));
    let twice = karigami::files(&crate::util::build_example("flat-sheet", &o));
    assert_eq!(once, twice);
}

#[test]
fn every_example_fits_the_area_bound() {
    for path in crate::cli::recipes("examples") {
        let b = crate::util::unsimulated_with(path.to_str().unwrap(), &Default::default());
        assert_eq!(
            b.layout.sheets.len(),
            b.bounds().area.max(1),
            "{}",
            path.display()
        );
    }
}
