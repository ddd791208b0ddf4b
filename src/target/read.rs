//! Reading a target file (docs/design.md, "Target files"): the format from
//! the name's extension, OBJ with `tobj`, STL (ASCII or binary) with
//! `stl_io`, a `[target]` table with `families`. Sizes are refused before
//! anything is parsed, from the file's length and the STL header's count,
//! so that a file of ten million triangles costs neither time nor memory.

use super::mesh::{Fault, Mesh, validated};
use super::{Expect, Target, families};
use crate::diagnostic::{Diagnostic, ErrorKind};
use glam::DVec3;

/// Triangles a target may have at most: ten times what a fine design
/// target needs (a 600 mm surface at 1 mm triangles is 0.7 million).
pub const MAX_TRIANGLES: usize = 1_000_000;
/// Bytes of a text target (OBJ, ASCII STL, TOML) at most: a million
/// triangles of OBJ written with normals and texture coordinates.
pub const MAX_TARGET_BYTES: u64 = 128 << 20;

/// Size of a binary STL's header and count, and of each triangle.
const STL_HEAD: u64 = 84;
const STL_TRIANGLE: u64 = 50;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Format {
    Obj,
    StlBinary,
    StlAscii,
    Toml,
}

fn format(file: &str, len: u64, head: &[u8]) -> Result<Format, Diagnostic> {
    let ext = std::path::Path::new(file)
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("obj") => Ok(Format::Obj),
        Some("toml") => Ok(Format::Toml),
        Some("stl") => {
            let binary = head.len() >= STL_HEAD as usize && {
                let n = u32::from_le_bytes([head[80], head[81], head[82], head[83]]) as u64;
                len == STL_HEAD + STL_TRIANGLE * n || !head.starts_with(b"solid")
            };
            Ok(if binary { Format::StlBinary } else { Format::StlAscii })
        }
        _ => Err(Diagnostic::new(
            ErrorKind::TargetFormat,
            format!("{file} is not a target file karigami reads"),
        )
        .hint("give a triangle mesh in mm (.obj, or .stl in ASCII or binary) or a .toml with a [target] table (docs/design.md)")),
    }
}

/// Refuse a target from its length and first 84 bytes (or fewer, for a
/// shorter file), before reading the rest: a binary STL whose header
/// counts more than `MAX_TRIANGLES`, whose length does not match its
/// count, or a text file over `MAX_TARGET_BYTES`.
pub fn refuse_early(file: &str, len: u64, head: &[u8]) -> Result<(), Diagnostic> {
    let too_large = |what: String| {
        Diagnostic::new(ErrorKind::TargetTooLarge, what).hint(format!(
            "simplify the mesh to at most {MAX_TRIANGLES} triangles (a modeller's 'decimate'); a design target needs far fewer"
        ))
    };
    match format(file, len, head)? {
        Format::StlBinary => {
            if len < STL_HEAD {
                return Err(Diagnostic::new(
                    ErrorKind::TargetFormat,
                    format!("the STL file is {len} bytes, shorter than a binary STL's 84-byte header, and is not ASCII STL (which starts with \"solid\")"),
                )
                .hint("export the mesh again as STL"));
            }
            let n = u32::from_le_bytes([head[80], head[81], head[82], head[83]]) as u64;
            if len != STL_HEAD + STL_TRIANGLE * n {
                return Err(Diagnostic::new(
                    ErrorKind::TargetFormat,
                    format!(
                        "the file is not a binary STL: its header counts {n} triangles, which take {} bytes, but it has {len}",
                        STL_HEAD + STL_TRIANGLE * n
                    ),
                )
                .hint("export the mesh again as STL (binary or ASCII); a truncated or renamed file cannot be read"));
            }
            if n > MAX_TRIANGLES as u64 {
                return Err(too_large(format!(
                    "the binary STL's header counts {n} triangles, more than the {MAX_TRIANGLES} karigami reads"
                )));
            }
        }
        _ if len > MAX_TARGET_BYTES => {
            return Err(too_large(format!(
                "the file is {len} bytes, more than the {MAX_TARGET_BYTES} karigami reads as a text target"
            )));
        }
        _ => {}
    }
    Ok(())
}

pub(crate) fn read(file: &str, bytes: &[u8], expect: Option<Expect>) -> Result<Target, Diagnostic> {
    refuse_early(file, bytes.len() as u64, &bytes[..bytes.len().min(84)])?;
    let format = format(file, bytes.len() as u64, bytes)?;
    if format == Format::Toml {
        return from_table(bytes, expect);
    }
    let text = std::str::from_utf8(bytes).ok();
    let (mesh, faces, what) = match format {
        Format::Obj => {
            let text = text.ok_or_else(|| not_text(file, "OBJ"))?;
            let (mesh, faces) = obj(text)?;
            (mesh, faces, "an OBJ mesh")
        }
        Format::StlBinary => (stl(bytes, format)?, Vec::new(), "a binary STL mesh"),
        _ => {
            let text = text.ok_or_else(|| not_text(file, "ASCII STL"))?;
            let mesh = stl(bytes, format).map_err(|d| locate_stl_error(text, d))?;
            (mesh, Vec::new(), "an ASCII STL mesh")
        }
    };
    let name = |t: usize| match faces.get(t) {
        Some(f) => format!("face {}", f + 1),
        None => format!("triangle {}", t + 1),
    };
    let (mesh, topology, _) =
        validated(&mesh, expect, &name).map_err(|f| locate(f, format, text, &faces))?;
    Ok(Target::new(mesh, what.to_string(), topology))
}

fn not_text(file: &str, what: &str) -> Diagnostic {
    Diagnostic::new(
        ErrorKind::TargetFormat,
        format!("{file} is not {what} text: it holds bytes that are not UTF-8"),
    )
    .hint("export the mesh again; a binary file named .obj is not a mesh karigami reads")
}

fn from_table(bytes: &[u8], expect: Option<Expect>) -> Result<Target, Diagnostic> {
    let source = std::str::from_utf8(bytes).map_err(|e| {
        Diagnostic::new(ErrorKind::TargetFormat, "the target file is not UTF-8 text")
            .at(e.valid_up_to()..e.valid_up_to() + 1)
            .hint("a target file is TOML text with a [target] table (docs/design.md)")
    })?;
    let parsed = families::parse(source)?;
    let name = parsed.family.name();
    let mesh = parsed.family.mesh(parsed.turn, parsed.at).ok_or_else(|| {
        Diagnostic::new(
            ErrorKind::TargetTooLarge,
            format!(
                "the {name} needs more than {} grid lines a side to stay within 0.1 % of its size",
                super::surfaces::MAX_LINES
            ),
        )
        .at(parsed.span.clone())
        .hint("a surface curved this tightly for its size is finer than any lattice; make the radius of curvature larger")
    })?;
    let (mesh, topology, _) = validated(&mesh, expect.or(parsed.expect), &|t| {
        format!("triangle {}", t + 1)
    })
    .map_err(|f| {
        // A topology the table itself asked for is refused at `expect`.
        let span = match (&parsed.expect_span, f.kind, expect) {
            (Some(at), ErrorKind::TargetTopology, None) => at.clone(),
            _ => parsed.span.clone(),
        };
        Diagnostic::new(f.kind, f.message).at(span).hint(f.hint)
    })?;
    Ok(Target::new(mesh, name.to_string(), topology))
}

/// The OBJ's triangles (polygons split into fans) and, for each, the
/// index of the face it came from.
fn obj(text: &str) -> Result<(Mesh, Vec<usize>), Diagnostic> {
    // Counted before parsing, so that a huge file is refused at once.
    let triangles: usize = face_lines(text).map(|(_, n)| n.saturating_sub(2)).sum();
    if triangles > MAX_TRIANGLES {
        return Err(Diagnostic::new(
            ErrorKind::TargetTooLarge,
            format!(
                "the OBJ has {triangles} triangles, more than the {MAX_TRIANGLES} karigami reads"
            ),
        )
        .hint("simplify the mesh (a modeller's 'decimate'); a design target needs far fewer"));
    }
    let options = tobj::LoadOptions {
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let (models, _) =
        tobj::load_obj_buf(&mut text.as_bytes(), &options, |_| Ok(Default::default()))
            .map_err(|e| obj_error(text, e))?;
    let mut mesh = Mesh::default();
    let mut faces = Vec::new();
    let mut face = 0;
    for model in &models {
        let m = &model.mesh;
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(
            m.positions
                .chunks_exact(3)
                .map(|p| DVec3::new(p[0], p[1], p[2])),
        );
        let arities: Vec<u32> = if m.face_arities.is_empty() {
            vec![3; m.indices.len() / 3]
        } else {
            m.face_arities.clone()
        };
        let mut at = 0usize;
        for n in arities {
            let corners = &m.indices[at..at + n as usize];
            for k in 1..corners.len().saturating_sub(1) {
                mesh.triangles
                    .push([corners[0], corners[k], corners[k + 1]].map(|i| base + i));
                faces.push(face);
            }
            at += n as usize;
            face += 1;
        }
    }
    Ok((mesh, faces))
}

/// The lines of an OBJ's faces, with the byte range of each and the number
/// of corners it lists.
fn face_lines(text: &str) -> impl Iterator<Item = (std::ops::Range<usize>, usize)> + '_ {
    lines(text).filter_map(|(range, line)| {
        let mut words = line.split_whitespace();
        (words.next() == Some("f")).then(|| (range, words.count()))
    })
}

/// Every line with its byte range (without the line break).
fn lines(text: &str) -> impl Iterator<Item = (std::ops::Range<usize>, &str)> {
    let mut start = 0;
    text.split_inclusive('\n').map(move |l| {
        let line = l.trim_end_matches(['\n', '\r']);
        let range = start..start + line.len();
        start += l.len();
        (range, line)
    })
}

/// A tobj error, at the first line of the kind it names that does not read.
fn obj_error(text: &str, e: tobj::LoadError) -> Diagnostic {
    let reads = |line: &str, key: &str| -> bool {
        let mut words = line.split_whitespace();
        if words.next() != Some(key) {
            return true;
        }
        match key {
            "v" => words.take(3).filter(|w| w.parse::<f64>().is_ok()).count() == 3,
            _ => words.all(|w| {
                w.split('/')
                    .next()
                    .is_some_and(|i| i.parse::<i64>().is_ok_and(|i| i != 0))
            }),
        }
    };
    let key = match e {
        tobj::LoadError::PositionParseError => Some("v"),
        tobj::LoadError::FaceParseError | tobj::LoadError::FaceVertexOutOfBounds => Some("f"),
        _ => None,
    };
    let place = key.and_then(|k| lines(text).find(|(_, l)| !reads(l, k)).map(|(r, _)| r));
    let d = Diagnostic::new(ErrorKind::TargetFormat, format!("the OBJ cannot be read: {e}"))
        .hint("each `v` line is x y z in mm and each `f` line lists the corners (counted from 1) of a face");
    match place.or_else(|| {
        lines(text)
            .find(|(_, l)| !l.trim().is_empty())
            .map(|(r, _)| r)
    }) {
        Some(r) => d.at(r),
        None => d,
    }
}

/// The STL's triangles, each corner its own (welded by `validated`).
fn stl(bytes: &[u8], format: Format) -> Result<Mesh, Diagnostic> {
    // stl_io takes a file starting "solid" for ASCII; a binary one whose
    // free header happens to start so is handed over with its header blank.
    let blank;
    let bytes = if format == Format::StlBinary && bytes.starts_with(b"solid") {
        let mut b = bytes.to_vec();
        b[..80].fill(0);
        blank = b;
        &blank[..]
    } else {
        bytes
    };
    let mut cursor = std::io::Cursor::new(bytes);
    let bad = |e: std::io::Error| {
        Diagnostic::new(
            ErrorKind::TargetFormat,
            format!("the STL cannot be read: {e}"),
        )
        .hint("export the mesh again as STL (binary or ASCII)")
    };
    let reader = stl_io::create_stl_reader(&mut cursor).map_err(bad)?;
    let mut mesh = Mesh::default();
    for (t, triangle) in reader.enumerate() {
        if t >= MAX_TRIANGLES {
            return Err(Diagnostic::new(
                ErrorKind::TargetTooLarge,
                format!("the STL has more than the {MAX_TRIANGLES} triangles karigami reads"),
            )
            .hint("simplify the mesh (a modeller's 'decimate'); a design target needs far fewer"));
        }
        let triangle = triangle.map_err(bad)?;
        let base = mesh.positions.len() as u32;
        for v in triangle.vertices {
            mesh.positions
                .push(DVec3::new(v[0].into(), v[1].into(), v[2].into()));
        }
        mesh.triangles.push([base, base + 1, base + 2]);
    }
    Ok(mesh)
}

/// An ASCII STL that stl_io refused, at the first `vertex` line that does
/// not hold three finite numbers, when there is one.
fn locate_stl_error(text: &str, d: Diagnostic) -> Diagnostic {
    let bad = lines(text).find_map(|(range, line)| {
        let mut words = line.split_whitespace();
        if words.next() != Some("vertex") {
            return None;
        }
        let numbers: Vec<Option<f64>> = words.map(|w| w.parse::<f64>().ok()).collect();
        let finite = numbers.len() == 3 && numbers.iter().all(|n| n.is_some_and(f64::is_finite));
        (!finite).then_some((range, numbers.iter().all(Option::is_some)))
    });
    match bad {
        Some((range, true)) => Diagnostic::new(ErrorKind::TargetNotFinite, "a corner of a triangle is not a finite point")
            .at(range)
            .hint("every coordinate must be an ordinary number; export the mesh again or remove the triangle"),
        Some((range, false)) => Diagnostic::new(ErrorKind::TargetFormat, "a `vertex` line does not hold three numbers")
            .at(range)
            .hint("each `vertex` line is x y z in mm"),
        None => d,
    }
}

/// A mesh fault placed in its file: the face's line of an OBJ, the
/// facet's line of an ASCII STL, the triangle's number of a binary STL
/// (in its message).
fn locate(f: Fault, format: Format, text: Option<&str>, faces: &[usize]) -> Diagnostic {
    let d = Diagnostic::new(f.kind, f.message).hint(f.hint);
    let Some(text) = text else { return d };
    let place = match (format, f.triangle) {
        (Format::Obj, _) if f.kind == ErrorKind::TargetNotFinite => lines(text)
            .find(|(_, l)| {
                let mut w = l.split_whitespace();
                w.next() == Some("v")
                    && w.take(3)
                        .any(|x| x.parse::<f64>().is_ok_and(|x| !x.is_finite()))
            })
            .map(|(r, _)| r),
        (Format::Obj, Some(t)) => face_lines(text)
            .filter(|(_, n)| *n >= 3)
            .nth(faces[t])
            .map(|(r, _)| r),
        (Format::StlAscii, Some(t)) => lines(text)
            .filter(|(_, l)| l.split_whitespace().next() == Some("facet"))
            .nth(t)
            .map(|(r, _)| r),
        _ => None,
    };
    d.at_opt(place)
}
