//! The recipe as written: serde types that keep the TOML spans, so every
//! later check can point at the text it is about. Validation lives in
//! `design::mod`; nothing here interprets the numbers.

use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use std::fmt;
use toml::Spanned;

pub(crate) type Num = Spanned<f64>;
pub(crate) type Coords = Spanned<Vec<Num>>;
/// A vertex name as written: `[row, column]` (`[index]` on a helix).
pub(crate) type VertexName = Spanned<Vec<Spanned<i64>>>;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawDesign {
    pub(crate) name: Option<Spanned<String>>,
    pub(crate) lattice: Spanned<RawLattice>,
    pub(crate) material: Option<Spanned<RawMaterial>>,
    pub(crate) eyelet: Option<Spanned<RawEyelet>>,
    pub(crate) strip: Option<Spanned<RawStrip>>,
    pub(crate) laser: Option<Spanned<RawLaser>>,
    pub(crate) machine: Option<Spanned<RawMachine>>,
    pub(crate) sheet: Option<Spanned<RawSheet>>,
    pub(crate) guide: Option<Spanned<RawGuide>>,
    pub(crate) clash: Option<Spanned<RawClash>>,
    pub(crate) optimise: Option<Spanned<RawOptimise>>,
    pub(crate) simulation: Option<Spanned<RawSimulation>>,
    pub(crate) target: Option<Spanned<RawTargetRecord>>,
}

/// `[target]`: the target a design was made for (`karigami design`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTargetRecord {
    pub(crate) file: Spanned<String>,
    pub(crate) hash: Option<Spanned<String>>,
}

/// `[guide]`: the printed assembly guide.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawGuide {
    pub(crate) paper: Option<Spanned<String>>,
}

/// `[material]`: the strip stock.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMaterial {
    /// A stock preset ("pp", "petg", ...; docs/fabrication.md).
    pub(crate) preset: Option<Spanned<String>>,
    pub(crate) name: Option<Spanned<String>>,
    pub(crate) thickness: Option<Num>,
    pub(crate) width: Option<Num>,
}

/// `[eyelet]`: a preset and/or explicit diameters.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawEyelet {
    pub(crate) preset: Option<Spanned<String>>,
    pub(crate) hole: Option<Num>,
    pub(crate) flange: Option<Num>,
}

/// `[strip]`: end margin and engraving.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawStrip {
    pub(crate) end_margin: Option<Num>,
    pub(crate) label: Option<Spanned<String>>,
    /// Strips agreeing within this (mm) are one part type.
    pub(crate) part_tolerance: Option<Num>,
}

/// `[laser]`: kerf and whether the geometry is compensated for it.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLaser {
    pub(crate) kerf: Option<Num>,
    pub(crate) compensate: Option<Spanned<bool>>,
    /// Colour preset of the cut files: "karigami" or "boxes".
    pub(crate) colours: Option<Spanned<String>>,
    /// Width of the holding tabs in mm (0 or absent: none).
    pub(crate) tabs: Option<Num>,
    /// The laser the settings are for: "co2" or "diode".
    pub(crate) machine: Option<Spanned<String>>,
    /// SVG without `<use>`, DXF without blocks.
    pub(crate) flat: Option<Spanned<bool>>,
}

/// `[machine]`: the machine the job is cut on.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMachine {
    /// "laser-co2", "laser-diode", "cricut" or "silhouette".
    pub(crate) preset: Option<Spanned<String>>,
    /// A cutting plotter's smallest hole (mm), replacing the preset's.
    pub(crate) min_hole: Option<Num>,
}

/// `[sheet]`: the bed or stock sheet.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSheet {
    pub(crate) preset: Option<Spanned<String>>,
    pub(crate) width: Option<Num>,
    pub(crate) height: Option<Num>,
    pub(crate) margin: Option<Num>,
    pub(crate) gap: Option<Num>,
    /// Whether the first sheet carries the test piece (default true).
    pub(crate) test_piece: Option<Spanned<bool>>,
    /// "step": each assembly step's strips in lanes of their own; "none".
    pub(crate) group: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLattice {
    pub(crate) seed: Spanned<String>,
    pub(crate) points: Option<Spanned<Vec<Coords>>>,
    pub(crate) line: Option<Spanned<RawLine>>,
    pub(crate) arc: Option<Spanned<RawArc>>,
    pub(crate) polyline: Option<Spanned<RawPolyline>>,
    pub(crate) circle: Option<Spanned<RawCircle>>,
    pub(crate) kappa: Option<Spanned<RawKappa>>,
    /// Helix seeds: how many cells to grow.
    pub(crate) cells: Option<Spanned<i64>>,
    /// Target fitting instead of explicit rows.
    pub(crate) fit: Option<Spanned<RawFit>>,
    pub(crate) grow: Option<Spanned<RawRow>>,
    pub(crate) rows: Option<Vec<Spanned<RawRow>>>,
}

/// `cells` evenly spaced edges from `from` to `to`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLine {
    pub(crate) from: Coords,
    pub(crate) to: Coords,
    pub(crate) cells: Spanned<i64>,
}

/// `cells` equal edges on a circular arc, angles in degrees.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawArc {
    pub(crate) center: Coords,
    pub(crate) radius: Num,
    pub(crate) from: Num,
    pub(crate) to: Num,
    pub(crate) cells: Spanned<i64>,
    pub(crate) plane: Option<Spanned<String>>,
}

/// `points` evenly spaced points round a full circle (loop seeds).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCircle {
    pub(crate) center: Coords,
    pub(crate) radius: Num,
    pub(crate) points: Spanned<i64>,
    pub(crate) plane: Option<Spanned<String>>,
    /// Angle of the first point, degrees (default 0).
    pub(crate) start: Option<Num>,
}

/// `[lattice.fit]`: grow rows that approximate a target surface.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawFit {
    /// "disk", "ellipsoid" or "revolution".
    pub(crate) surface: Spanned<String>,
    pub(crate) rows: Spanned<i64>,
    /// disk: its radius; revolution: not used.
    pub(crate) radius: Option<Num>,
    /// ellipsoid semi-axes [a, b, c] (the half with z <= 0 is fitted).
    pub(crate) axes: Option<Coords>,
    /// revolution: the profile curve as [r, z] points, in growth order.
    pub(crate) profile: Option<Spanned<Vec<Coords>>>,
    /// disk and ellipsoid: candidate leg directions tried per row.
    pub(crate) samples: Option<Spanned<i64>>,
    /// torus: the tube's radius (`radius` is the centre circle's)...
    pub(crate) tube: Option<Num>,
    /// ...and the tube angle each row adds (degrees).
    pub(crate) step: Option<Num>,
    /// Open fits: each row's leg angle (degrees) instead of a search.
    pub(crate) angles: Option<Spanned<Vec<Num>>>,
    /// Ellipsoid loops: each ring's step down the meridian (mm) instead of
    /// one front edge.
    pub(crate) steps: Option<Spanned<Vec<Num>>>,
}

/// A polyline whose segments are each split into `cells_per_segment` edges.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawPolyline {
    pub(crate) points: Spanned<Vec<Coords>>,
    pub(crate) cells_per_segment: Option<Spanned<i64>>,
}

/// One row (in `[[lattice.rows]]`) or the default row (`[lattice.grow]`).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRow {
    /// `[[lattice.rows]]` only: the 0-based row this entry describes.
    pub(crate) row: Option<Spanned<i64>>,
    /// `[[lattice.rows]]` only: how many consecutive rows it describes.
    pub(crate) repeat: Option<Spanned<i64>>,
    /// `[lattice.grow]` only: how many rows the lattice has.
    pub(crate) rows: Option<Spanned<i64>>,
    pub(crate) start: Option<Spanned<i64>>,
    pub(crate) direction: Option<Coords>,
    pub(crate) angle: Option<Spanned<RawAngle>>,
    pub(crate) left_leg: Option<Spanned<RawLeg>>,
    pub(crate) right_leg: Option<Spanned<RawLeg>>,
    /// Loops: where the row's new vertex x[i+1][1] goes.
    pub(crate) target: Option<Coords>,
    /// Loops: which closing direction, 1 or 2.
    pub(crate) candidate: Option<Spanned<i64>>,
    /// Intrinsic growth: how to rebuild the front before this row.
    pub(crate) front: Option<Spanned<RawFront>>,
}

/// `front = { ... }`: the generators of docs/math.md 7. Angles in degrees.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawFront {
    pub(crate) turn: Option<Spanned<RawAngles>>,
    pub(crate) bend: Option<Spanned<RawAngles>>,
    pub(crate) twist: Option<Spanned<RawAngles>>,
    pub(crate) pivot: Option<Vec<Spanned<RawPivot>>>,
    pub(crate) crank: Option<Vec<Spanned<RawCrank>>>,
    /// Crank every odd vertex about its two neighbours, alternately by
    /// +angle and -angle: identical up-down sub-units along the front.
    pub(crate) zigzag: Option<Num>,
    /// Lay the whole front on the saddle z' = r^2 (c cos 2t + d cos 6t):
    /// `c`, or `[c, d]` (1/mm).
    pub(crate) saddle: Option<Spanned<RawAmplitudes>>,
}

impl RawFront {
    /// `front = { }`: no generator given.
    pub(crate) fn is_empty(&self) -> bool {
        self.turn.is_none()
            && self.bend.is_none()
            && self.twist.is_none()
            && self.pivot.is_none()
            && self.crank.is_none()
            && self.zigzag.is_none()
            && self.saddle.is_none()
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawPivot {
    pub(crate) at: Spanned<i64>,
    pub(crate) angle: Num,
    pub(crate) axis: Option<Coords>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCrank {
    pub(crate) from: Spanned<i64>,
    pub(crate) to: Spanned<i64>,
    pub(crate) angle: Num,
}

/// One angle for every vertex, or a list.
#[derive(Debug)]
pub(crate) struct RawAngles(pub Vec<f64>);

impl<'de> Deserialize<'de> for RawAngles {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        number_or_array(d, "an angle in degrees, or an array of angles").map(RawAngles)
    }
}

/// A saddle's amplitudes (1/mm): `c`, or `[c, d]`; how many is checked
/// where the row is known (`design::rows`).
#[derive(Debug)]
pub(crate) struct RawAmplitudes(pub Vec<f64>);

impl<'de> Deserialize<'de> for RawAmplitudes {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        number_or_array(d, "an amplitude in 1/mm (c), or an array of two ([c, d])")
            .map(RawAmplitudes)
    }
}

/// One number, as a list of one, or an array of numbers; `expecting`
/// says what in the recipe's words when it is neither.
fn number_or_array<'de, D: Deserializer<'de>>(
    d: D,
    expecting: &'static str,
) -> Result<Vec<f64>, D::Error> {
    struct V(&'static str);
    impl<'de> Visitor<'de> for V {
        type Value = Vec<f64>;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str(self.0)
        }
        fn visit_f64<E: de::Error>(self, v: f64) -> Result<Vec<f64>, E> {
            Ok(vec![v])
        }
        fn visit_i64<E: de::Error>(self, v: i64) -> Result<Vec<f64>, E> {
            Ok(vec![v as f64])
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<f64>, A::Error> {
            let mut out = Vec::new();
            while let Some(a) = seq.next_element::<f64>()? {
                out.push(a);
            }
            Ok(out)
        }
    }
    d.deserialize_any(V(expecting))
}

/// `kappa = 0.5` (every seed edge) or `kappa = [..]` (one per edge).
#[derive(Debug)]
pub(crate) enum RawKappa {
    Uniform(f64),
    PerEdge(Vec<Num>),
}

/// `angle = 30` or, in 3-D, `angle = [30, 10]` (angle, tilt).
#[derive(Debug, Clone, Copy)]
pub(crate) struct RawAngle {
    pub(crate) angle: f64,
    pub(crate) tilt: Option<f64>,
}

#[derive(Debug, Clone, Copy)]
pub(crate) enum RawLeg {
    Length(f64),
    Match,
}

impl<'de> Deserialize<'de> for RawKappa {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = RawKappa;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number (the same kappa for every seed edge) or an array of numbers, one per seed edge")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<RawKappa, E> {
                Ok(RawKappa::Uniform(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<RawKappa, E> {
                Ok(RawKappa::Uniform(v as f64))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<RawKappa, A::Error> {
                let mut out = Vec::new();
                while let Some(k) = seq.next_element::<Num>()? {
                    out.push(k);
                }
                Ok(RawKappa::PerEdge(out))
            }
        }
        d.deserialize_any(V)
    }
}

impl<'de> Deserialize<'de> for RawAngle {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = RawAngle;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an angle in degrees, or [angle, tilt] in degrees for 3-D")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<RawAngle, E> {
                Ok(RawAngle {
                    angle: v,
                    tilt: None,
                })
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<RawAngle, E> {
                self.visit_f64(v as f64)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<RawAngle, A::Error> {
                let angle = seq
                    .next_element::<f64>()?
                    .ok_or_else(|| de::Error::invalid_length(0, &self))?;
                let tilt = seq
                    .next_element::<f64>()?
                    .ok_or_else(|| de::Error::invalid_length(1, &self))?;
                if seq.next_element::<f64>()?.is_some() {
                    return Err(de::Error::invalid_length(3, &self));
                }
                Ok(RawAngle {
                    angle,
                    tilt: Some(tilt),
                })
            }
        }
        d.deserialize_any(V)
    }
}

impl<'de> Deserialize<'de> for RawLeg {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = RawLeg;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a leg length in mm or \"match\"")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<RawLeg, E> {
                Ok(RawLeg::Length(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<RawLeg, E> {
                Ok(RawLeg::Length(v as f64))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<RawLeg, E> {
                if v == "match" {
                    Ok(RawLeg::Match)
                } else {
                    Err(de::Error::invalid_value(de::Unexpected::Str(v), &self))
                }
            }
        }
        d.deserialize_any(V)
    }
}

/// Largest size of any number in a recipe: lengths are in mm, and a
/// kilometre is beyond anything karigami makes; larger numbers would only
/// overflow to infinity in later arithmetic.
pub(crate) const MAX_NUMBER: f64 = 1e6;
/// Longest string in a recipe, in characters (names, presets, keywords).
pub(crate) const MAX_STRING: usize = 200;
/// Deepest nesting of arrays and tables.
pub(crate) const MAX_DEPTH: usize = 8;

/// Bounds every value of the recipe, wherever it is, before any field is
/// read: numbers finite and within `MAX_NUMBER`, strings within
/// `MAX_STRING` characters and free of control characters (they would
/// break the DXF and SVG files a name reaches), nesting within
/// `MAX_DEPTH`. A recipe TOML cannot parse is left to the typed parse,
/// which says why.
pub(crate) fn check_values(source: &str) -> Result<(), crate::diagnostic::Diagnostic> {
    use toml::de::{DeTable, DeValue};
    let Ok(table) = DeTable::parse(source) else {
        return Ok(());
    };
    fn key_error(
        key: &Spanned<std::borrow::Cow<'_, str>>,
    ) -> Option<crate::diagnostic::Diagnostic> {
        text_error(key.get_ref(), "a key", key.span())
    }
    fn text_error(
        s: &str,
        what: &str,
        span: std::ops::Range<usize>,
    ) -> Option<crate::diagnostic::Diagnostic> {
        use crate::diagnostic::{Diagnostic, ErrorKind};
        if let Some(c) = s.chars().find(|c| c.is_control()) {
            return Some(
                Diagnostic::new(
                    ErrorKind::ControlCharacter,
                    format!("{what} holds the control character U+{:04X}", u32::from(c)),
                )
                .at(span)
                .hint("remove it: names and settings are one line of printable text"),
            );
        }
        let n = s.chars().count();
        (n > MAX_STRING).then(|| {
            Diagnostic::new(
                ErrorKind::StringTooLong,
                format!("{what} is {n} characters long; karigami accepts at most {MAX_STRING}"),
            )
            .at(span)
            .hint("shorten it")
        })
    }
    fn walk(v: &Spanned<DeValue<'_>>, depth: usize) -> Option<crate::diagnostic::Diagnostic> {
        use crate::diagnostic::{Diagnostic, ErrorKind};
        if depth > MAX_DEPTH {
            return Some(
                Diagnostic::new(
                    ErrorKind::NestedTooDeep,
                    format!("arrays and tables are nested more than {MAX_DEPTH} deep"),
                )
                .at(v.span())
                .hint("no recipe field nests that deep; check the brackets"),
            );
        }
        match v.get_ref() {
            DeValue::String(s) => text_error(s, "this string", v.span()),
            DeValue::Float(f) => {
                let x: f64 = f.as_str().replace('_', "").parse().unwrap_or(f64::NAN);
                if !x.is_finite() {
                    Some(
                        Diagnostic::new(
                            ErrorKind::NotFinite,
                            format!("{} is not a finite number", f.as_str()),
                        )
                        .at(v.span())
                        .hint("give a number"),
                    )
                } else if x.abs() > MAX_NUMBER {
                    Some(
                        Diagnostic::new(
                            ErrorKind::NumberTooLarge,
                            format!(
                                "{} is larger than any size karigami accepts (at most {MAX_NUMBER:e} in magnitude; lengths are in mm)",
                                f.as_str()
                            ),
                        )
                        .at(v.span())
                        .hint("check the value and its unit: lengths are in millimetres"),
                    )
                } else {
                    None
                }
            }
            DeValue::Array(a) => a.into_iter().find_map(|x| walk(x, depth + 1)),
            DeValue::Table(t) => t
                .iter()
                .find_map(|(k, x)| key_error(k).or_else(|| walk(x, depth + 1))),
            _ => None,
        }
    }
    let root = table.get_ref();
    match root
        .iter()
        .find_map(|(k, x)| key_error(k).or_else(|| walk(x, 1)))
    {
        Some(d) => Err(d),
        None => Ok(()),
    }
}

// `[clash]` and `[optimise]` (read by design/optimise.rs).

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawClash {
    pub(crate) clearance: Option<Num>,
    pub(crate) allow: Option<Spanned<bool>>,
    pub(crate) stacking: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOptimise {
    pub(crate) vary: Spanned<Vec<Spanned<String>>>,
    pub(crate) method: Option<Spanned<String>>,
    pub(crate) budget: Option<Spanned<i64>>,
    pub(crate) seed: Option<Spanned<i64>>,
    pub(crate) step: Option<Num>,
    pub(crate) objective: Option<Spanned<RawWeights>>,
    pub(crate) target: Option<Spanned<RawTarget>>,
    pub(crate) require: Option<Spanned<RawRequire>>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawWeights {
    pub(crate) surface: Option<Num>,
    pub(crate) boundary: Option<Num>,
    pub(crate) coverage: Option<Num>,
    pub(crate) regularity: Option<Num>,
    pub(crate) legs: Option<Num>,
    pub(crate) clashes: Option<Num>,
    pub(crate) curvature: Option<Num>,
    pub(crate) rings: Option<Num>,
    pub(crate) bending: Option<Num>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTarget {
    pub(crate) defect: Option<Num>,
    pub(crate) pattern: Option<Spanned<String>>,
    pub(crate) shape: Option<Spanned<String>>,
}

/// Hard constraints, each a bound on one measure.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRequire {
    pub(crate) max_distance: Option<Num>,
    pub(crate) max_boundary_distance: Option<Num>,
    pub(crate) min_coverage: Option<Num>,
    pub(crate) max_area_ratio: Option<Num>,
    pub(crate) min_positive: Option<Num>,
    pub(crate) min_negative: Option<Num>,
    pub(crate) max_mean_defect: Option<Num>,
    pub(crate) min_mean_defect: Option<Num>,
    pub(crate) max_k_spread: Option<Num>,
    pub(crate) max_front_gap: Option<Num>,
    pub(crate) max_turn_spread: Option<Num>,
    pub(crate) max_clashes: Option<Num>,
    /// Share of interior vertices with a defect of at least +3 deg / at most -3 deg.
    pub(crate) min_bumps: Option<Num>,
    /// Shortest leg (mm): at least the eyelet flange plus the walls.
    pub(crate) min_leg: Option<Num>,
    pub(crate) min_dimples: Option<Num>,
}

/// `[simulation]`: the elastic simulation's material, opening, joints and
/// mesh (validated in `simulation.rs`).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSimulation {
    /// Young's modulus (MPa).
    pub(crate) youngs_modulus: Option<Spanned<f64>>,
    pub(crate) poisson_ratio: Option<Spanned<f64>>,
    /// Allowable corner-fibre strain, in percent.
    pub(crate) allowable_strain: Option<Spanned<f64>>,
    /// Build even when a strip is strained beyond the allowable.
    pub(crate) accept_overstrain: Option<Spanned<bool>>,
    /// Opening of the reference cell (degrees).
    pub(crate) theta: Option<Spanned<f64>>,
    /// "eyelet" or "ball".
    pub(crate) vertex_joint: Option<Spanned<String>>,
    /// "mean" (mean opening of all cells) or "first-cell".
    pub(crate) actuation: Option<Spanned<String>>,
    /// Longest rod edge (mm).
    pub(crate) edge_length: Option<Spanned<f64>>,
    /// Identical copies of a loop lattice's cells around the loop.
    pub(crate) symmetry: Option<Spanned<i64>>,
    /// Vertices held at their design positions, each named as messages
    /// name it: `[row, column]` (`[index]` on a helix).
    pub(crate) supports: Option<Spanned<Vec<VertexName>>>,
}
