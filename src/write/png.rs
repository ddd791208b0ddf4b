//! PNG pictures of pages (tiny-skia): the same drawing model as the cut
//! files and the guide, rasterised on white. Hairlines are widened to a
//! visible minimum; text is drawn with the single-stroke font.

use super::repeats;
use crate::drawing::{Group, Item, Page, Segment, Shape, arc_to_cubics, text, walk};
use glam::DVec2;
use std::collections::HashMap;
use tiny_skia::{
    Color, FillRule, LineCap, LineJoin, Paint, Path, PathBuilder, Pixmap, PremultipliedColorU8,
    Stroke, Transform,
};

/// Render `page` at `px_per_mm`, strokes at least `min_stroke_px` wide.
///
/// A drawing that several groups share up to a move (the strips of a big
/// sheet: one part type, engraved with its type) is rasterised once per
/// sub-pixel phase into a tile and the tile is laid on the page for each
/// copy: anti-aliased hairlines cost per pixel of stroke, and a 100 x 100
/// sheet has 20,000 strips. A copy lands at most 1/(2 PHASES) px from where
/// drawing it would put it (see `tiles_draw_as_the_strips_would`).
pub fn write(page: &Page, px_per_mm: f64, min_stroke_px: f64) -> Vec<u8> {
    encode(&render(page, px_per_mm, min_stroke_px, true))
}

/// Sub-pixel phases a tile is drawn at, in each direction.
const PHASES: f64 = 16.0;

/// The page as a pixmap; `tiled`: shared drawings laid as tiles.
fn render(page: &Page, px_per_mm: f64, min_stroke_px: f64, tiled: bool) -> Pixmap {
    let w = (page.width * px_per_mm).round().max(1.0) as u32;
    let h = (page.height * px_per_mm).round().max(1.0) as u32;
    let mut pixmap = Pixmap::new(w, h).expect("a page of positive size");
    pixmap.fill(Color::WHITE);
    let transform = Transform::from_scale(px_per_mm as f32, px_per_mm as f32);
    let min_width = min_stroke_px / px_per_mm;
    let anchors: Vec<Option<(i64, i64)>> = page.groups.iter().map(repeats::anchor).collect();
    let mut keys = repeats::page_keys(&page.groups, &anchors);
    if !tiled {
        keys.fill(None);
    }
    let shared = repeats::find(&keys);
    let mut tiles: HashMap<(usize, i64, i64), Tile> = HashMap::new();
    for (g, (b, at)) in page.groups.iter().zip(shared.of_group.iter().zip(&anchors)) {
        if let (Some(b), Some((x, y))) = (b, at) {
            let (x, fx) = phase(*x, px_per_mm);
            let (y, fy) = phase(*y, px_per_mm);
            let first = shared.first[*b];
            let tile = tiles.entry((*b, fx, fy)).or_insert_with(|| {
                let at = anchors[first].expect("a shared drawing has an anchor");
                Tile::new(&page.groups[first], at, px_per_mm, min_width, (fx, fy))
            });
            tile.lay(&mut pixmap, (x, y));
            continue;
        }
        for p in g.items.iter().filter_map(|i| painted(i, min_width)) {
            paint(&mut pixmap, &p, transform);
        }
    }
    pixmap
}

/// A grid coordinate (0.1 um units) on the page in pixels: the whole
/// pixel and the phase within it, in 1/PHASES px.
fn phase(units: i64, px_per_mm: f64) -> (i64, i64) {
    let px = units as f64 / 1e4 * px_per_mm;
    let whole = px.floor();
    let q = ((px - whole) * PHASES).round() as i64;
    (whole as i64 + q / PHASES as i64, q % PHASES as i64)
}

/// A shared drawing rasterised at one phase: its inked pixels, relative
/// to the whole pixel of its anchor.
struct Tile {
    origin: (i64, i64),
    pixels: Vec<(u32, u32, PremultipliedColorU8)>,
}

impl Tile {
    /// `g`'s items relative to its anchor `at`, drawn with the anchor at
    /// (`fx`, `fy`) / PHASES px.
    fn new(
        g: &Group,
        at: (i64, i64),
        px_per_mm: f64,
        min_width: f64,
        (fx, fy): (i64, i64),
    ) -> Tile {
        let shift = repeats::offset(at);
        let painted: Vec<Painted> = g
            .items
            .iter()
            .filter_map(|i| {
                let moved = Item {
                    shape: i.shape.moved(&shift),
                    ..i.clone()
                };
                painted(&moved, min_width)
            })
            .collect();
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for p in &painted {
            let b = p.path.bounds();
            let pad = if p.stroke.is_some() {
                p.width / 2.0
            } else {
                0.0
            };
            lo = lo.min(DVec2::new(b.left() as f64, b.top() as f64) - pad);
            hi = hi.max(DVec2::new(b.right() as f64, b.bottom() as f64) + pad);
        }
        let empty = Tile {
            origin: (0, 0),
            pixels: Vec::new(),
        };
        if !lo.is_finite() {
            return empty;
        }
        // Two pixels of room: anti-aliasing reaches one beyond the edge.
        let f = DVec2::new(fx as f64, fy as f64) / PHASES;
        let lo = (lo * px_per_mm + f).floor() - 2.0;
        let hi = (hi * px_per_mm + f).ceil() + 2.0;
        let size = hi - lo;
        let Some(mut pixmap) = Pixmap::new(size.x as u32, size.y as u32) else {
            return empty;
        };
        let s = px_per_mm as f32;
        let transform =
            Transform::from_row(s, 0.0, 0.0, s, (f.x - lo.x) as f32, (f.y - lo.y) as f32);
        for p in &painted {
            paint(&mut pixmap, p, transform);
        }
        let w = pixmap.width();
        let pixels = pixmap
            .pixels()
            .iter()
            .enumerate()
            .filter(|(_, c)| c.alpha() > 0)
            .map(|(i, c)| (i as u32 % w, i as u32 / w, *c))
            .collect();
        Tile {
            origin: (lo.x as i64, lo.y as i64),
            pixels,
        }
    }

    /// Lay the tile over `pixmap` with its anchor in pixel `at` (source
    /// over, as drawing it there would blend).
    fn lay(&self, pixmap: &mut Pixmap, at: (i64, i64)) {
        let (w, h) = (pixmap.width() as i64, pixmap.height() as i64);
        let (ox, oy) = (at.0 + self.origin.0, at.1 + self.origin.1);
        let page = pixmap.pixels_mut();
        for &(dx, dy, src) in &self.pixels {
            let (x, y) = (ox + dx as i64, oy + dy as i64);
            if x < 0 || y < 0 || x >= w || y >= h {
                continue;
            }
            let dst = &mut page[(y * w + x) as usize];
            let keep = 255 - src.alpha() as u32;
            let over = |s: u8, d: u8| s + div255(d as u32 * keep);
            *dst = PremultipliedColorU8::from_rgba(
                over(src.red(), dst.red()),
                over(src.green(), dst.green()),
                over(src.blue(), dst.blue()),
                over(src.alpha(), dst.alpha()),
            )
            .expect("source over keeps colour within alpha");
        }
    }
}

/// `v / 255` rounded, for `v` up to 255 * 255.
fn div255(v: u32) -> u8 {
    ((v + 128 + ((v + 128) >> 8)) >> 8) as u8
}

/// An item as a path (page mm) and how to paint it.
struct Painted {
    path: Path,
    fill: Option<[u8; 3]>,
    stroke: Option<[u8; 3]>,
    /// Stroke width (mm), at least the minimum.
    width: f64,
}

fn painted(item: &Item, min_width: f64) -> Option<Painted> {
    let ink = item.ink;
    let (path, fill, stroke, width) = match &item.shape {
        Shape::Text { size, .. } => {
            let mut pb = PathBuilder::new();
            for s in text::strokes(&item.shape) {
                pb.move_to(s[0].x as f32, s[0].y as f32);
                for p in &s[1..] {
                    pb.line_to(p.x as f32, p.y as f32);
                }
            }
            (
                pb.finish(),
                None,
                ink.fill.or(ink.stroke),
                (0.09 * size).max(min_width),
            )
        }
        Shape::Circle { center, radius } => (
            PathBuilder::from_circle(center.x as f32, center.y as f32, *radius as f32),
            ink.fill,
            ink.stroke,
            ink.width.max(min_width),
        ),
        Shape::Path {
            start,
            segments,
            closed,
        } => {
            let mut pb = PathBuilder::new();
            pb.move_to(start.x as f32, start.y as f32);
            for (from, s) in walk(*start, segments) {
                match s {
                    Segment::Line(p) => pb.line_to(p.x as f32, p.y as f32),
                    Segment::Arc {
                        to,
                        center,
                        clockwise,
                    } => {
                        for [c1, c2, end] in arc_to_cubics(from, to, center, clockwise) {
                            pb.cubic_to(
                                c1.x as f32,
                                c1.y as f32,
                                c2.x as f32,
                                c2.y as f32,
                                end.x as f32,
                                end.y as f32,
                            );
                        }
                    }
                }
            }
            if *closed {
                pb.close();
            }
            (pb.finish(), ink.fill, ink.stroke, ink.width.max(min_width))
        }
    };
    Some(Painted {
        path: path?,
        fill,
        stroke,
        width,
    })
}

fn paint(pixmap: &mut Pixmap, p: &Painted, transform: Transform) {
    let paint = |[r, g, b]: [u8; 3]| {
        let mut p = Paint::default();
        p.set_color_rgba8(r, g, b, 255);
        p.anti_alias = true;
        p
    };
    if let Some(c) = p.fill {
        pixmap.fill_path(&p.path, &paint(c), FillRule::Winding, transform, None);
    }
    if let Some(c) = p.stroke {
        let stroke = Stroke {
            width: p.width as f32,
            line_cap: LineCap::Round,
            line_join: LineJoin::Round,
            ..Stroke::default()
        };
        pixmap.stroke_path(&p.path, &paint(c), &stroke, transform, None);
    }
}

/// PNG bytes of a pixmap, deflated at level 1 with adaptive filtering.
/// tiny-skia's encode_png (png's Balanced) took a fifth of a 100 x 100
/// build. Re-encoding that build's 4000 x 2667 px sheet: Balanced 5.3 s
/// and 4.4 MB, level 1 0.77 s and 5.6 MB, png's Fast 0.48 s but 9.8 MB
/// (its 1280 x 960 preview: 0.32, 0.40 and 1.9 MB).
///
/// A picture of at most 256 colours is written as an indexed-colour PNG,
/// one byte or less a pixel instead of three. A cut sheet has more: its
/// four layer colours blended with white at every anti-aliasing level; with
/// each channel rounded to 16 levels (at most 8/255 off, which the eye does
/// not see on a hairline's edge) they are a few dozen, and the 100 x 100
/// sheet's pictures take a fraction of their RGB bytes. Pictures that have
/// more colours even so (shaded previews) stay RGB and exact.
fn encode(pixmap: &Pixmap) -> Vec<u8> {
    // Pages are painted on white, so every pixel is opaque: RGB, a quarter
    // less to filter, deflate and store than RGBA.
    let opaque = pixmap.pixels().iter().all(|p| p.alpha() == u8::MAX);
    if opaque && let Some((palette, depth, raw)) = indexed(pixmap) {
        return indexed_png(pixmap, depth, palette, &raw);
    }
    let raw: Vec<u8> = if opaque {
        pixmap
            .pixels()
            .iter()
            .flat_map(|p| [p.red(), p.green(), p.blue()])
            .collect()
    } else {
        pixmap
            .pixels()
            .iter()
            .flat_map(|p| {
                let c = p.demultiply();
                [c.red(), c.green(), c.blue(), c.alpha()]
            })
            .collect()
    };
    let colour = if opaque {
        png::ColorType::Rgb
    } else {
        png::ColorType::Rgba
    };
    deflate(pixmap, colour, png::BitDepth::Eight, None, &raw)
}

/// A channel rounded to the nearest of 16 levels (multiples of 17).
fn sixteen_levels(c: u8) -> u8 {
    ((c as u16 + 8) / 17 * 17) as u8
}

/// The palette (RGB triples, sorted, so that the bytes depend only on the
/// pixels), the smallest bit depth that indexes it and the packed rows of
/// an opaque pixmap: its exact colours if there are at most 256, else its
/// colours with each channel at `sixteen_levels`; None when those are more
/// than 256 too.
///
/// One pass over the pixels numbers the colours in order of first sight
/// (a small hash table: most pixels repeat the one before and skip it),
/// one byte a pixel (w h bytes: more than a 2^24-bit set of colours on
/// pictures over 2 Mpixel, but written once); the numbers are then mapped
/// to the sorted palette's and packed. (That bitset, 2 MiB zeroed a picture,
/// cost a second pass over the pixels.) The pass numbers exact colours
/// until the 257th, then renumbers the pixels before it by their colours'
/// levels (a table of 256) and goes on in levels: a cut sheet's picture
/// has more than 256 exact colours, and a second pass over it in levels
/// cost a third of the palette's time.
fn indexed(pixmap: &Pixmap) -> Option<(Vec<u8>, png::BitDepth, Vec<u8>)> {
    let exact = |c: u32| c;
    let levels = |c: u32| {
        let [_, r, g, b] = c.to_be_bytes();
        u32::from_be_bytes([0, sixteen_levels(r), sixteen_levels(g), sixteen_levels(b)])
    };
    let (w, h) = (pixmap.width() as usize, pixmap.height() as usize);
    let pixels = pixmap.pixels();
    let mut colours = Colours::default();
    let mut numbers = vec![0u8; w * h];
    if let Err(at) = number_colours(pixels, &mut numbers, &mut colours, exact) {
        // The 257th colour: the pixels before it in levels, and on.
        let mut by_level = Colours::default();
        let mut renumber = [0u8; 256];
        for (c, i) in colours.found() {
            renumber[i as usize] = by_level.number(levels(c))?;
        }
        for n in &mut numbers[..at] {
            *n = renumber[*n as usize];
        }
        colours = by_level;
        number_colours(&pixels[at..], &mut numbers[at..], &mut colours, levels).ok()?;
    }
    let mut sorted: Vec<(u32, u8)> = colours.found();
    sorted.sort_unstable();
    let mut rank = [0u8; 256];
    let mut palette = Vec::with_capacity(3 * sorted.len());
    for (r, &(c, first)) in sorted.iter().enumerate() {
        rank[first as usize] = r as u8;
        palette.extend_from_slice(&c.to_be_bytes()[1..]);
    }
    let (depth, bits) = match sorted.len() {
        0..=2 => (png::BitDepth::One, 1),
        3..=4 => (png::BitDepth::Two, 2),
        5..=16 => (png::BitDepth::Four, 4),
        _ => (png::BitDepth::Eight, 8),
    };
    if bits == 8 {
        numbers.iter_mut().for_each(|i| *i = rank[*i as usize]);
        return Some((palette, depth, numbers));
    }
    let row_bytes = (w * bits).div_ceil(8);
    let mut raw = vec![0u8; row_bytes * h];
    for (row, out) in numbers
        .chunks_exact(w.max(1))
        .zip(raw.chunks_exact_mut(row_bytes.max(1)))
    {
        for (x, &i) in row.iter().enumerate() {
            let bit = x * bits;
            // Pixels fill each byte from its most significant bits.
            out[bit / 8] |= rank[i as usize] << (8 - bits - bit % 8);
        }
    }
    Some((palette, depth, raw))
}

/// Each pixel's colour (0x00RRGGBB, through `level`) numbered in
/// `colours`, into `numbers`; Err(the first pixel past 256 colours).
fn number_colours(
    pixels: &[PremultipliedColorU8],
    numbers: &mut [u8],
    colours: &mut Colours,
    level: impl Fn(u32) -> u32,
) -> Result<(), usize> {
    let mut last: Option<(PremultipliedColorU8, u8)> = None;
    for (at, (p, out)) in pixels.iter().zip(numbers).enumerate() {
        *out = match last {
            // Most pixels repeat the one before (white between strips).
            Some((q, i)) if q == *p => i,
            _ => {
                let c = u32::from_be_bytes([0, p.red(), p.green(), p.blue()]);
                let i = colours.number(level(c)).ok_or(at)?;
                last = Some((*p, i));
                i
            }
        };
    }
    Ok(())
}

/// Up to 256 colours (0x00RRGGBB) numbered in order of first sight, in an
/// open-addressed table four times that size.
struct Colours {
    keys: [u32; 1024],
    numbers: [u8; 1024],
    count: usize,
}

impl Default for Colours {
    fn default() -> Self {
        Self {
            keys: [u32::MAX; 1024],
            numbers: [0; 1024],
            count: 0,
        }
    }
}

impl Colours {
    /// `c`'s number, numbering it if new; None past 256 colours.
    fn number(&mut self, c: u32) -> Option<u8> {
        let mut slot = (c.wrapping_mul(0x9E37_79B1) >> 22) as usize;
        loop {
            match self.keys[slot] {
                k if k == c => return Some(self.numbers[slot]),
                u32::MAX => break,
                _ => slot = (slot + 1) % self.keys.len(),
            }
        }
        if self.count == 256 {
            return None;
        }
        self.keys[slot] = c;
        self.numbers[slot] = self.count as u8;
        self.count += 1;
        Some(self.numbers[slot])
    }

    /// Every colour with its number.
    fn found(&self) -> Vec<(u32, u8)> {
        self.keys
            .iter()
            .zip(&self.numbers)
            .filter(|(k, _)| **k != u32::MAX)
            .map(|(&k, &n)| (k, n))
            .collect()
    }
}

/// The indexed-colour PNG of `raw` rows: the bytes `deflate` writes, made
/// without flate2's writer, which zeroed its 32 kB output buffer before
/// each of png's two writes a row (1.2 G of the examples' 8.7 G
/// instructions, in memset). The rows are unfiltered (see `deflate`), and
/// the compressor is handed what png hands flate2, call by call (deflate's
/// blocks depend on how its input comes: one call for the whole picture
/// gave other bytes): `indexed_pictures_are_the_bytes_png_writes`.
fn indexed_png(pixmap: &Pixmap, depth: png::BitDepth, palette: Vec<u8>, raw: &[u8]) -> Vec<u8> {
    let row = raw.len() / (pixmap.height() as usize).max(1);
    let zlib = zlib_level_1(raw.chunks_exact(row.max(1)));
    let mut bytes = Vec::with_capacity(zlib.len() + palette.len() + 128);
    let mut encoder = png::Encoder::new(&mut bytes, pixmap.width(), pixmap.height());
    encoder.set_color(png::ColorType::Indexed);
    encoder.set_depth(depth);
    encoder.set_palette(palette);
    encoder.validate_sequence(false);
    let mut writer = encoder
        .write_header()
        .expect("PNG header of an in-memory pixmap");
    // One IDAT chunk, as png writes up to 2 GiB.
    writer
        .write_chunk(png::chunk::IDAT, &zlib)
        .expect("PNG data of an in-memory pixmap");
    writer.finish().expect("PNG end of an in-memory pixmap");
    bytes
}

/// Unfiltered `rows` as the zlib stream png writes at level 1 through
/// flate2 (miniz_oxide set up as `Compression::new(1)` sets it up): each
/// row's filter byte (0) and its bytes handed over as two writes, into a
/// 32 kB output buffer, then finished.
fn zlib_level_1<'a>(rows: impl Iterator<Item = &'a [u8]>) -> Vec<u8> {
    use miniz_oxide::deflate::core::CompressorOxide;
    use miniz_oxide::deflate::stream::deflate;
    use miniz_oxide::{DataFormat, MZFlush, MZStatus};
    let mut compressor = Box::<CompressorOxide>::default();
    compressor.set_format_and_level(DataFormat::Zlib, 1);
    let mut buffer = vec![0u8; 32 * 1024];
    let mut out = Vec::new();
    for row in rows {
        for mut input in [&[0u8][..], row] {
            while !input.is_empty() {
                let r = deflate(&mut compressor, input, &mut buffer, MZFlush::None);
                r.status.expect("deflate of an in-memory buffer");
                out.extend_from_slice(&buffer[..r.bytes_written]);
                input = &input[r.bytes_consumed..];
            }
        }
    }
    loop {
        let r = deflate(&mut compressor, &[], &mut buffer, MZFlush::Finish);
        out.extend_from_slice(&buffer[..r.bytes_written]);
        let status = r.status.expect("deflate of an in-memory buffer");
        if status == MZStatus::StreamEnd || r.bytes_written == 0 {
            return out;
        }
    }
}

/// The PNG of `raw` rows in the given colour type and depth.
fn deflate(
    pixmap: &Pixmap,
    colour: png::ColorType,
    depth: png::BitDepth,
    palette: Option<Vec<u8>>,
    raw: &[u8],
) -> Vec<u8> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, pixmap.width(), pixmap.height());
    encoder.set_color(colour);
    encoder.set_depth(depth);
    if let Some(palette) = palette {
        encoder.set_palette(palette);
    }
    encoder.set_deflate_compression(png::DeflateCompression::Level(1));
    // Filters predict smooth colour; palette indices are not (the PNG
    // specification advises none for them).
    encoder.set_filter(if colour == png::ColorType::Indexed {
        png::Filter::NoFilter
    } else {
        png::Filter::Adaptive
    });
    let mut writer = encoder
        .write_header()
        .expect("PNG header of an in-memory pixmap");
    writer
        .write_image_data(raw)
        .expect("PNG encoding of an in-memory pixmap");
    writer.finish().expect("PNG end of an in-memory pixmap");
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn indexed_pictures_are_the_bytes_png_writes() {
        // Strips of two layer colours, in many deflate blocks; a picture of
        // one colour (one bit a pixel).
        let page = |width: f64, groups: Vec<Group>| Page {
            width,
            height: 80.0,
            title: "t".into(),
            metadata: Vec::new(),
            laser: None,
            groups,
        };
        let strips = (0..12)
            .map(|i| {
                let mut g = strip(
                    DVec2::new(5.0 + 7.0 * i as f64, 10.0 + 5.0 * i as f64),
                    i % 2 == 0,
                );
                if i % 3 == 0 {
                    for item in &mut g.items {
                        item.layer = crate::drawing::Layer::Reference;
                    }
                }
                g
            })
            .collect();
        let (strips, blank) = (page(120.0, strips), page(30.0, Vec::new()));
        let mut depths = Vec::new();
        for (page, px_per_mm) in [(&strips, 10.0), (&strips, 3.0), (&blank, 5.0)] {
            let pixmap = render(page, px_per_mm, 1.0, true);
            let (palette, depth, raw) = indexed(&pixmap).expect("few colours");
            depths.push(depth);
            let png = deflate(
                &pixmap,
                png::ColorType::Indexed,
                depth,
                Some(palette.clone()),
                &raw,
            );
            assert_eq!(indexed_png(&pixmap, depth, palette, &raw), png);
        }
        assert_eq!(depths[2], png::BitDepth::One);
    }

    /// Largest channel difference, and the number of pixels off by more
    /// than 12 levels, between a page drawn with tiles and item by item.
    fn tiled_against_direct(page: &Page, px_per_mm: f64) -> (u8, usize) {
        let tiled = render(page, px_per_mm, 1.0, true);
        let direct = render(page, px_per_mm, 1.0, false);
        let mut most = 0;
        let mut over_12 = 0;
        for (a, b) in tiled.pixels().iter().zip(direct.pixels()) {
            let d = [
                a.red().abs_diff(b.red()),
                a.green().abs_diff(b.green()),
                a.blue().abs_diff(b.blue()),
            ];
            let d = d.into_iter().max().unwrap_or(0);
            most = most.max(d);
            over_12 += usize::from(d > 12);
        }
        (most, over_12)
    }

    /// A strip as the cut sheets draw it: a stadium outline from `at`
    /// along x, three holes and (`label`) its type engraved.
    fn strip(at: DVec2, label: bool) -> Group {
        let p = |x: f64, y: f64| at + DVec2::new(x, y);
        let outline = Shape::Path {
            start: p(0.0, -3.0),
            segments: vec![
                Segment::Line(p(32.0, -3.0)),
                Segment::Arc {
                    to: p(32.0, 3.0),
                    center: p(32.0, 0.0),
                    clockwise: true,
                },
                Segment::Line(p(0.0, 3.0)),
                Segment::Arc {
                    to: p(0.0, -3.0),
                    center: p(0.0, 0.0),
                    clockwise: true,
                },
            ],
            closed: true,
        };
        let mut items: Vec<Item> = [0.0, 16.0, 32.0]
            .map(|x| {
                let hole = Shape::Circle {
                    center: p(x, 0.0),
                    radius: 1.1,
                };
                Item::on(crate::drawing::Layer::Holes, hole)
            })
            .into();
        items.push(Item::on(crate::drawing::Layer::Outlines, outline));
        let label_text = Shape::Text {
            at: p(8.0, 1.0),
            size: 2.5,
            text: "A".into(),
            font: crate::drawing::Font::Regular,
            align: crate::drawing::Align::Center,
        };
        if label {
            items.push(Item::on(crate::drawing::Layer::Labels, label_text));
        }
        Group::new("strip", items)
    }

    #[test]
    fn tiles_draw_as_the_strips_would() {
        // 2,000 strips of one drawing at every sub-pixel offset, at the
        // resolution of a 3000 mm sheet's picture (4/3 px/mm). A tile is
        // 1/32 px at most from where the strip is, which moves an
        // anti-aliased edge by a few levels: 23 at most here, 0.4 % of the
        // inked pixels more than 12 (the encoder itself rounds by up to 8).
        let page = |label: bool| Page {
            width: 1600.0,
            height: 450.0,
            title: "strips".into(),
            metadata: Vec::new(),
            laser: None,
            groups: (0..2000)
                .map(|i| {
                    let (col, row) = ((i % 40) as f64, (i / 40) as f64);
                    // Irrational steps: every phase, no two strips alike.
                    let at = DVec2::new(5.0 + 39.0 * col + 0.618_034 * row, 5.0 + 8.0 * row);
                    strip(at + DVec2::new(0.0, 0.414_214 * col / 40.0), label)
                })
                .collect(),
        };
        let inked = |page: &Page| {
            render(page, 4.0 / 3.0, 1.0, false)
                .pixels()
                .iter()
                .filter(|c| c.red() < 255 || c.green() < 255 || c.blue() < 255)
                .count()
        };
        let plain = page(false);
        let (most, over_12) = tiled_against_direct(&plain, 4.0 / 3.0);
        let n = inked(&plain);
        eprintln!("unlabelled: {most} levels, {over_12} of {n}");
        assert!(n > 100_000, "{n} inked pixels");
        assert!(most <= 24, "{most} levels");
        assert!(over_12 * 200 < n, "{over_12} of {n} pixels");
        // Engraved text 3 px high: tiny-skia's hairlines of strokes shorter
        // than a pixel shade such a glyph's few pixels differently for
        // shifts as small as 1/512 px (measured), so a letter's pixels may
        // differ by more (111 levels here; 1.3 % of the pixels more than 12).
        let labelled = page(true);
        let (most, over_12) = tiled_against_direct(&labelled, 4.0 / 3.0);
        let n = inked(&labelled);
        eprintln!("labelled: {most} levels, {over_12} of {n}");
        assert!(over_12 * 50 < n, "{over_12} of {n} pixels");
    }

    #[test]
    fn opaque_pictures_keep_every_pixel_indexed_or_rgb() {
        let mut pixmap = Pixmap::new(7, 5).unwrap();
        pixmap.fill(Color::WHITE);
        pixmap.pixels_mut()[8] = tiny_skia::ColorU8::from_rgba(10, 200, 30, 255).premultiply();
        let bytes = encode(&pixmap);
        // Colour type (IHDR byte 25): 3 = indexed; two colours, one bit.
        assert_eq!((bytes[24], bytes[25]), (1, 3));
        let back = Pixmap::decode_png(&bytes).unwrap();
        assert_eq!(back.data(), pixmap.data());
        // 17 colours: a byte a pixel.
        for i in 0..16 {
            pixmap.pixels_mut()[10 + i] =
                tiny_skia::ColorU8::from_rgba(i as u8, 0, 255, 255).premultiply();
        }
        let bytes = encode(&pixmap);
        assert_eq!((bytes[24], bytes[25]), (8, 3));
        assert_eq!(Pixmap::decode_png(&bytes).unwrap().data(), pixmap.data());
        // More than 256 colours that round to few: indexed, within 8/255.
        let mut blends = Pixmap::new(256, 4).unwrap();
        for (i, p) in blends.pixels_mut().iter_mut().enumerate() {
            let v = (i % 256) as u8;
            let c = [[v, v, 255], [255, v, v], [v, 255, v], [v, v, v]][i / 256];
            *p = tiny_skia::ColorU8::from_rgba(c[0], c[1], c[2], 255).premultiply();
        }
        let bytes = encode(&blends);
        assert_eq!(bytes[25], 3);
        let back = Pixmap::decode_png(&bytes).unwrap();
        for (a, b) in back.data().iter().zip(blends.data()) {
            assert!(a.abs_diff(*b) <= 8, "{a} for {b}");
        }
        assert_eq!(sixteen_levels(0), 0);
        assert_eq!(sixteen_levels(255), 255);
        assert_eq!(sixteen_levels(8), 0);
        assert_eq!(sixteen_levels(9), 17);
        // More than 256 colours even rounded: RGB (2), exact.
        let mut many = Pixmap::new(300, 1).unwrap();
        for (i, p) in many.pixels_mut().iter_mut().enumerate() {
            let (r, g) = ((i % 16) as u8 * 17, (i / 16 % 16) as u8 * 17);
            let b = if i < 256 { 0 } else { 255 };
            *p = tiny_skia::ColorU8::from_rgba(r, g, b, 255).premultiply();
        }
        let bytes = encode(&many);
        assert_eq!(bytes[25], 2);
        assert_eq!(Pixmap::decode_png(&bytes).unwrap().data(), many.data());
        // A transparent pixel keeps the alpha channel (6 = RGBA).
        pixmap.pixels_mut()[3] = tiny_skia::ColorU8::from_rgba(0, 0, 0, 0).premultiply();
        let bytes = encode(&pixmap);
        assert_eq!(bytes[25], 6);
        assert_eq!(Pixmap::decode_png(&bytes).unwrap().data(), pixmap.data());
    }
}
