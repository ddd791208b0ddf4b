//! PNG pictures of pages (tiny-skia): the same drawing model as the cut
//! files and the guide, rasterised on white. Hairlines are widened to a
//! visible minimum; text is drawn with the single-stroke font.

use crate::drawing::{Page, Segment, Shape, arc_to_cubics, text, walk};
use tiny_skia::{
    Color, FillRule, LineCap, LineJoin, Paint, PathBuilder, Pixmap, Stroke, Transform,
};

/// Render `page` at `px_per_mm`, strokes at least `min_stroke_px` wide.
pub fn write(page: &Page, px_per_mm: f64, min_stroke_px: f64) -> Vec<u8> {
    let w = (page.width * px_per_mm).round().max(1.0) as u32;
    let h = (page.height * px_per_mm).round().max(1.0) as u32;
    let mut pixmap = Pixmap::new(w, h).expect("a page of positive size");
    pixmap.fill(Color::WHITE);
    let transform = Transform::from_scale(px_per_mm as f32, px_per_mm as f32);
    let min_width = min_stroke_px / px_per_mm;
    for item in page.groups.iter().flat_map(|g| &g.items) {
        let ink = item.ink;
        let (paths, filled, stroke_colour, width) = match &item.shape {
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
                    false,
                    ink.fill.or(ink.stroke),
                    (0.09 * size).max(min_width),
                )
            }
            Shape::Circle { center, radius } => (
                PathBuilder::from_circle(center.x as f32, center.y as f32, *radius as f32),
                ink.fill.is_some(),
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
                (
                    pb.finish(),
                    ink.fill.is_some(),
                    ink.stroke,
                    ink.width.max(min_width),
                )
            }
        };
        let Some(path) = paths else { continue };
        let paint = |[r, g, b]: [u8; 3]| {
            let mut p = Paint::default();
            p.set_color_rgba8(r, g, b, 255);
            p.anti_alias = true;
            p
        };
        if filled {
            if let Some(c) = ink.fill {
                pixmap.fill_path(&path, &paint(c), FillRule::Winding, transform, None);
            }
        }
        if let Some(c) = stroke_colour {
            let stroke = Stroke {
                width: width as f32,
                line_cap: LineCap::Round,
                line_join: LineJoin::Round,
                ..Stroke::default()
            };
            pixmap.stroke_path(&path, &paint(c), &stroke, transform, None);
        }
    }
    encode(&pixmap)
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
    if opaque {
        let found = indexed(pixmap, |c| c).or_else(|| indexed(pixmap, sixteen_levels));
        if let Some((palette, depth, raw)) = found {
            return deflate(pixmap, png::ColorType::Indexed, depth, Some(palette), &raw);
        }
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
/// an opaque pixmap, each channel mapped by `level`; None when that leaves
/// more than 256 colours.
fn indexed(pixmap: &Pixmap, level: fn(u8) -> u8) -> Option<(Vec<u8>, png::BitDepth, Vec<u8>)> {
    let rgb = |p: &tiny_skia::PremultipliedColorU8| {
        u32::from_be_bytes([0, level(p.red()), level(p.green()), level(p.blue())])
    };
    let mut colours: Vec<u32> = Vec::new();
    let mut last = None;
    for c in pixmap.pixels().iter().map(rgb) {
        if last != Some(c) {
            last = Some(c);
            if let Err(at) = colours.binary_search(&c) {
                if colours.len() == 256 {
                    return None;
                }
                colours.insert(at, c);
            }
        }
    }
    let (depth, bits) = match colours.len() {
        0..=2 => (png::BitDepth::One, 1),
        3..=4 => (png::BitDepth::Two, 2),
        5..=16 => (png::BitDepth::Four, 4),
        _ => (png::BitDepth::Eight, 8),
    };
    let (w, h) = (pixmap.width() as usize, pixmap.height() as usize);
    let row_bytes = (w * bits).div_ceil(8);
    let mut raw = vec![0u8; row_bytes * h];
    let mut last = (u32::MAX, 0u8);
    for (row, out) in pixmap
        .pixels()
        .chunks_exact(w.max(1))
        .zip(raw.chunks_exact_mut(row_bytes.max(1)))
    {
        for (x, p) in row.iter().enumerate() {
            let c = rgb(p);
            if c != last.0 {
                let index = colours.binary_search(&c).expect("a colour of the palette");
                last = (c, index as u8);
            }
            let bit = x * bits;
            // Pixels fill each byte from its most significant bits.
            out[bit / 8] |= last.1 << (8 - bits - bit % 8);
        }
    }
    let palette = colours
        .iter()
        .flat_map(|c| c.to_be_bytes()[1..].to_vec())
        .collect();
    Some((palette, depth, raw))
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
