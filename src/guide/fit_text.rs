//! Text the user wrote (the design's name) fitted to the page: wrapped to
//! a few lines, a word longer than a line broken, and what is left over
//! cut with "...", so a 200-character name stays on the cover and in the
//! footer instead of running off the paper.

use crate::drawing::Font;
use crate::drawing::flow::wrap;
use crate::drawing::text::width;

const MORE: &str = "...";

/// `text` in at most `max_lines` lines of at most `room` mm at `size`:
/// wrapped at spaces, a word too long for a line broken between
/// characters, and the last line cut with "..." when text is left over.
pub(super) fn lines(text: &str, font: Font, size: f64, room: f64, max_lines: usize) -> Vec<String> {
    // A text that fits is left as written (its spaces too).
    if width(text, font, size) <= room {
        return vec![text.to_string()];
    }
    let mut out: Vec<String> = Vec::new();
    // Wrapped at spaces, a line is too wide only when it is one long word:
    // that one is broken between characters.
    for wrapped in wrap(text, font, size, room) {
        let mut line = String::new();
        for c in wrapped.chars() {
            line.push(c);
            if width(&line, font, size) > room && line.chars().count() > 1 {
                line.pop();
                out.push(std::mem::replace(&mut line, c.to_string()));
            }
        }
        out.push(line);
    }
    if out.len() > max_lines.max(1) {
        let rest = out.split_off(max_lines.max(1) - 1).join(" ");
        out.push(shortened(&rest, font, size, room));
    }
    out
}

/// `text` on one line of at most `room` mm: as it is when it fits, else
/// cut after as many characters as leave room for "...".
pub(super) fn shortened(text: &str, font: Font, size: f64, room: f64) -> String {
    if width(text, font, size) <= room {
        return text.to_string();
    }
    let mut cut = String::new();
    for c in text.chars() {
        cut.push(c);
        if width(&format!("{cut}{MORE}"), font, size) > room {
            cut.pop();
            break;
        }
    }
    format!("{}{MORE}", cut.trim_end())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_names_wrap_break_and_shorten_within_the_room() {
        let room = 60.0;
        let name = "Käfer-Brücke";
        assert_eq!(lines(name, Font::Bold, 5.0, room, 3), vec![name]);
        assert_eq!(lines("a  b", Font::Bold, 5.0, room, 3), vec!["a  b"]);
        // One word of 199 characters: broken into full lines, the third cut.
        let long = "x".repeat(199);
        let got = lines(&long, Font::Bold, 5.0, room, 3);
        assert_eq!(got.len(), 3, "{got:?}");
        assert!(
            got.iter().all(|l| width(l, Font::Bold, 5.0) <= room),
            "{got:?}"
        );
        assert!(got[2].ends_with("..."), "{got:?}");
        assert!(got[0].len() > 20, "{got:?}");
        // Words wrap at spaces.
        let words = "a scissor lattice named at some length for the cover";
        let got = lines(words, Font::Regular, 5.0, room, 3);
        assert!(got.len() > 1 && got.join(" ") == words, "{got:?}");
        let cut = shortened(&long, Font::Regular, 3.0, room);
        assert!(cut.ends_with("...") && width(&cut, Font::Regular, 3.0) <= room);
        assert_eq!(shortened(name, Font::Regular, 3.0, room), name);
    }
}
