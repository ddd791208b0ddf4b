//! A single-stroke font for the engraving on strips and the test piece and
//! for the text of drawings: every glyph is a few open polylines, so labels
//! need no font files and cut as one pass.
//! Glyphs sit on a 4 x 6 grid (y up from the baseline); the advance is 5.

use glam::DVec2;

/// Grid units from the baseline to the cap height.
pub(crate) const CAP: f64 = 6.0;
/// Grid units from one glyph's origin to the next.
pub(crate) const ADVANCE: f64 = 5.0;

const OCTAGON: &str = "1,0 3,0 4,1 4,5 3,6 1,6 0,5 0,1 1,0";

/// Strokes of a glyph, as `x,y` points separated by spaces, strokes by `|`.
fn strokes(c: char) -> Option<&'static str> {
    Some(match c {
        '0' => "1,0 3,0 4,1 4,5 3,6 1,6 0,5 0,1 1,0|0.6,1.2 3.4,4.8",
        '1' => "1,5 2,6 2,0|1,0 3,0",
        '2' => "0,5 1,6 3,6 4,5 4,4 0,0 4,0",
        '3' => "0,6 4,6 2,3.5 3,3.5 4,2.5 4,1 3,0 1,0 0,1",
        '4' => "3,0 3,6 0,2 4,2",
        '5' => "4,6 0,6 0,3.5 3,3.5 4,2.5 4,1 3,0 0,0",
        '6' => "3,6 1,6 0,5 0,1 1,0 3,0 4,1 4,2.5 3,3.5 0,3.5",
        '7' => "0,6 4,6 1.5,0",
        '8' => "1,3.5 0,4.5 0,5 1,6 3,6 4,5 4,4.5 3,3.5 1,3.5 0,2.5 0,1 1,0 3,0 4,1 4,2.5 3,3.5",
        '9' => "1,0 3,0 4,1 4,5 3,6 1,6 0,5 0,3.5 1,2.5 4,2.5",
        'A' => "0,0 0,4 2,6 4,4 4,0|0,3 4,3",
        'B' => "0,0 0,6 3,6 4,5 4,4 3,3 0,3|3,3 4,2 4,1 3,0 0,0",
        'C' => "4,5 3,6 1,6 0,5 0,1 1,0 3,0 4,1",
        'D' => "0,0 0,6 2.5,6 4,4.5 4,1.5 2.5,0 0,0",
        'E' => "4,6 0,6 0,0 4,0|0,3 3,3",
        'F' => "4,6 0,6 0,0|0,3 3,3",
        'G' => "4,5 3,6 1,6 0,5 0,1 1,0 3,0 4,1 4,3 2,3",
        'H' => "0,0 0,6|4,0 4,6|0,3 4,3",
        'I' => "1,6 3,6|2,6 2,0|1,0 3,0",
        'J' => "4,6 4,1 3,0 1,0 0,1",
        'K' => "0,0 0,6|4,6 0,2|1.3,3.3 4,0",
        'L' => "0,6 0,0 4,0",
        'M' => "0,0 0,6 2,3 4,6 4,0",
        'N' => "0,0 0,6 4,0 4,6",
        'O' => OCTAGON,
        'P' => "0,0 0,6 3,6 4,5 4,4 3,3 0,3",
        'Q' => "1,0 3,0 4,1 4,5 3,6 1,6 0,5 0,1 1,0|2.5,1.5 4,0",
        'R' => "0,0 0,6 3,6 4,5 4,4 3,3 0,3|2,3 4,0",
        'S' => "4,5 3,6 1,6 0,5 0,4 1,3 3,3 4,2 4,1 3,0 1,0 0,1",
        'T' => "0,6 4,6|2,6 2,0",
        'U' => "0,6 0,1 1,0 3,0 4,1 4,6",
        'V' => "0,6 2,0 4,6",
        'W' => "0,6 1,0 2,4 3,0 4,6",
        'X' => "0,0 4,6|0,6 4,0",
        'Y' => "0,6 2,3 4,6|2,3 2,0",
        'Z' => "0,6 4,6 0,0 4,0",
        'm' => "0,0 0,4|0,3 1,4 1.5,4 2,3 2,0|2,3 2.5,4 3,4 4,3 4,0",
        '-' => "1,3 3,3",
        '<' => "3,5 0,3 3,1",
        '>' => "1,5 4,3 1,1",
        '.' => "1.6,0 2.4,0 2.4,0.8 1.6,0.8 1.6,0",
        ',' => "2.4,0.8 2.4,0 1.6,-1",
        ':' => "1.6,1 2.4,1 2.4,1.8 1.6,1.8 1.6,1|1.6,4 2.4,4 2.4,4.8 1.6,4.8 1.6,4",
        '/' => "0,0 4,6",
        '_' => "0,0 4,0",
        '(' => "3,6 2,5 2,1 3,0",
        ')' => "1,6 2,5 2,1 1,0",
        '+' => "2,1 2,5|0,3 4,3",
        '=' => "0,2 4,2|0,4 4,4",
        '#' => "1,0 1.5,6|2.5,0 3,6|0,2 4,2|0,4 4,4",
        '?' => "0,5 1,6 3,6 4,5 4,4 2,2.5 2,1.5|2,0 2,0.5",
        ' ' => "",
        _ => return None,
    })
}

/// Whether the `m` at `k` belongs to a word that is just `m` or `mm`.
fn is_unit(chars: &[char], k: usize) -> bool {
    let start = chars[..k]
        .iter()
        .rposition(|c| !c.is_alphabetic())
        .map_or(0, |i| i + 1);
    let end = chars[k..]
        .iter()
        .position(|c| !c.is_alphabetic())
        .map_or(chars.len(), |i| k + i);
    matches!(&chars[start..end], ['m'] | ['m', 'm'])
}

/// Strokes of `text` with its baseline origin at (0, 0), cap height `height`,
/// y up. Lower-case letters are drawn as capitals, except the unit `m` or
/// `mm` (a word of its own); a Latin letter with a mark is drawn as its
/// base letter (`folded`), and other characters the font lacks as `?`.
pub fn text(text: &str, height: f64) -> Vec<Vec<DVec2>> {
    let scale = height / CAP;
    let mut out = Vec::new();
    let chars: Vec<char> = folded(text).collect();
    for (k, &c) in chars.iter().enumerate() {
        let c = if c == 'm' && is_unit(&chars, k) {
            c
        } else {
            c.to_ascii_uppercase()
        };
        let glyph = strokes(c).unwrap_or_else(|| strokes('?').expect("? exists"));
        let x0 = k as f64 * ADVANCE;
        for stroke in glyph.split('|').filter(|s| !s.is_empty()) {
            let points = stroke
                .split(' ')
                .map(|p| {
                    let (x, y) = p.split_once(',').expect("x,y");
                    let (x, y): (f64, f64) =
                        (x.parse().expect("number"), y.parse().expect("number"));
                    DVec2::new((x0 + x) * scale, y * scale)
                })
                .collect();
            out.push(points);
        }
    }
    out
}

/// Width of `text` at cap height `height` (no trailing spacing).
pub(crate) fn width(text: &str, height: f64) -> f64 {
    let n = folded(text).count() as f64;
    if n == 0.0 {
        0.0
    } else {
        (n * ADVANCE - (ADVANCE - 4.0)) * height / CAP
    }
}

/// `text` as it fits in `room` mm at cap height `height`: whole when it
/// does, else cut and ended with "..." (a recipe's name may be 200
/// characters; a sheet's caption or a preview's title has one line).
pub(crate) fn fitted(text: &str, height: f64, room: f64) -> String {
    if width(text, height) <= room {
        return text.to_string();
    }
    let chars: Vec<char> = text.chars().collect();
    (0..chars.len())
        .rev()
        .map(|n| chars[..n].iter().collect::<String>() + "...")
        .find(|cut| width(cut, height) <= room)
        .unwrap_or_default()
}

/// `text` with each Latin-1 letter that carries a mark (and the Latin
/// ligatures) as the letters the stroke font has: a name engraved as
/// KAFER-BRUCKE reads where K?FER-BR?CKE does not. (The guide's PDF
/// text keeps the marks: its font has them.)
fn folded(text: &str) -> impl Iterator<Item = char> + '_ {
    text.chars().flat_map(|c| {
        let (kept, base) = match base_letters(c) {
            Some(base) => (None, base),
            None => (Some(c), ""),
        };
        kept.into_iter().chain(base.chars())
    })
}

/// The letters a Latin letter with a mark (or a ligature) is written
/// with when the marks cannot be drawn.
fn base_letters(c: char) -> Option<&'static str> {
    Some(match c {
        'À'..='Å' | 'à'..='å' => "a",
        'Æ' | 'æ' => "ae",
        'Ç' | 'ç' => "c",
        'È'..='Ë' | 'è'..='ë' => "e",
        'Ì'..='Ï' | 'ì'..='ï' => "i",
        'Ð' | 'ð' => "d",
        'Ñ' | 'ñ' => "n",
        'Ò'..='Ö' | 'Ø' | 'ò'..='ö' | 'ø' => "o",
        'Œ' | 'œ' => "oe",
        'Ù'..='Ü' | 'ù'..='ü' => "u",
        'Ý' | 'ý' | 'ÿ' | 'Ÿ' => "y",
        'Þ' | 'þ' => "th",
        'ß' => "ss",
        'Š' | 'š' => "s",
        'Ž' | 'ž' => "z",
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_glyph_parses_and_stays_in_its_box() {
        let all = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZm-<>.,:/_()+=#? ";
        for (k, c) in all.chars().enumerate() {
            for stroke in text(&c.to_string(), CAP) {
                assert!(stroke.len() >= 2, "{c}: a stroke needs two points");
                for p in stroke {
                    assert!(
                        (-0.01..=4.01).contains(&p.x) && (-1.01..=6.01).contains(&p.y),
                        "{c} (#{k}) at {p}"
                    );
                }
            }
        }
    }

    #[test]
    fn width_matches_the_strokes() {
        let strokes = text("R03-C05-A", 3.0);
        let max_x = strokes.iter().flatten().map(|p| p.x).fold(0.0, f64::max);
        assert!(max_x <= width("R03-C05-A", 3.0) + 1e-12);
        assert!((width("R03-C05-A", 3.0) - (9.0 * 5.0 - 1.0) * 0.5).abs() < 1e-12);
    }

    #[test]
    fn only_the_unit_keeps_a_small_m() {
        assert_eq!(text("mirror-arm", 6.0), text("MIRROR-ARM", 6.0));
        assert_ne!(text("12 mm", 6.0), text("12 MM", 6.0));
        assert_ne!(text("3.5m", 6.0), text("3.5M", 6.0));
    }

    #[test]
    fn unknown_characters_become_question_marks() {
        assert_eq!(text("円", 6.0), text("?", 6.0));
    }

    #[test]
    fn a_long_text_is_cut_to_its_room() {
        assert_eq!(fitted("SHORT", 2.5, 100.0), "SHORT");
        let long = "N".repeat(199);
        let cut = fitted(&long, 2.5, 100.0);
        assert!(cut.ends_with("...") && width(&cut, 2.5) <= 100.0, "{cut}");
        let one_more = format!("{}N...", &cut[..cut.len() - 3]);
        assert!(width(&one_more, 2.5) > 100.0);
        assert_eq!(fitted(&long, 2.5, 0.1), "");
    }

    #[test]
    fn latin_letters_with_marks_are_drawn_as_their_base_letters() {
        assert_eq!(text("Käfer-Brücke", 6.0), text("KAFER-BRUCKE", 6.0));
        assert_eq!(text("Straße Æ", 6.0), text("STRASSE AE", 6.0));
        assert_eq!(width("Straße", 6.0), width("STRASSE", 6.0));
        assert_eq!(text("é円", 6.0), text("E?", 6.0));
    }
}
