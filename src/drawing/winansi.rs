//! The upper half of WinAnsiEncoding (Windows code page 1252), the
//! encoding the PDF writers give the built-in Helvetica: each code's
//! character and its advance width in Helvetica and Helvetica-Bold
//! (thousandths of the font size, from Adobe's font metrics), so that
//! "Käfer-Brücke" is shown and measured as it is written rather than as
//! "K?fer-Br?cke". Codes 0x81, 0x8D, 0x8F, 0x90 and 0x9D have no character.

/// Code, character, width in Helvetica, width in Helvetica-Bold.
const UPPER: [(u8, char, u16, u16); 123] = [
    (0x80, '\u{20AC}', 556, 556),   // Euro
    (0x82, '\u{201A}', 222, 278),   // quotesinglbase
    (0x83, '\u{0192}', 556, 556),   // florin
    (0x84, '\u{201E}', 333, 500),   // quotedblbase
    (0x85, '\u{2026}', 1000, 1000), // ellipsis
    (0x86, '\u{2020}', 556, 556),   // dagger
    (0x87, '\u{2021}', 556, 556),   // daggerdbl
    (0x88, '\u{02C6}', 333, 333),   // circumflex
    (0x89, '\u{2030}', 1000, 1000), // perthousand
    (0x8A, '\u{0160}', 667, 667),   // Scaron
    (0x8B, '\u{2039}', 333, 333),   // guilsinglleft
    (0x8C, '\u{0152}', 1000, 1000), // OE
    (0x8E, '\u{017D}', 611, 611),   // Zcaron
    (0x91, '\u{2018}', 222, 278),   // quoteleft
    (0x92, '\u{2019}', 222, 278),   // quoteright
    (0x93, '\u{201C}', 333, 500),   // quotedblleft
    (0x94, '\u{201D}', 333, 500),   // quotedblright
    (0x95, '\u{2022}', 350, 350),   // bullet
    (0x96, '\u{2013}', 556, 556),   // endash
    (0x97, '\u{2014}', 1000, 1000), // emdash
    (0x98, '\u{02DC}', 333, 333),   // tilde
    (0x99, '\u{2122}', 1000, 1000), // trademark
    (0x9A, '\u{0161}', 500, 556),   // scaron
    (0x9B, '\u{203A}', 333, 333),   // guilsinglright
    (0x9C, '\u{0153}', 944, 944),   // oe
    (0x9E, '\u{017E}', 500, 500),   // zcaron
    (0x9F, '\u{0178}', 667, 667),   // Ydieresis
    (0xA0, '\u{00A0}', 278, 278),   // space
    (0xA1, '\u{00A1}', 333, 333),   // exclamdown
    (0xA2, '\u{00A2}', 556, 556),   // cent
    (0xA3, '\u{00A3}', 556, 556),   // sterling
    (0xA4, '\u{00A4}', 556, 556),   // currency
    (0xA5, '\u{00A5}', 556, 556),   // yen
    (0xA6, '\u{00A6}', 260, 280),   // brokenbar
    (0xA7, '\u{00A7}', 556, 556),   // section
    (0xA8, '\u{00A8}', 333, 333),   // dieresis
    (0xA9, '\u{00A9}', 737, 737),   // copyright
    (0xAA, '\u{00AA}', 370, 370),   // ordfeminine
    (0xAB, '\u{00AB}', 556, 556),   // guillemotleft
    (0xAC, '\u{00AC}', 584, 584),   // logicalnot
    (0xAD, '\u{00AD}', 333, 333),   // hyphen
    (0xAE, '\u{00AE}', 737, 737),   // registered
    (0xAF, '\u{00AF}', 333, 333),   // macron
    (0xB0, '\u{00B0}', 400, 400),   // degree
    (0xB1, '\u{00B1}', 584, 584),   // plusminus
    (0xB2, '\u{00B2}', 333, 333),   // twosuperior
    (0xB3, '\u{00B3}', 333, 333),   // threesuperior
    (0xB4, '\u{00B4}', 333, 333),   // acute
    (0xB5, '\u{00B5}', 556, 611),   // mu
    (0xB6, '\u{00B6}', 537, 556),   // paragraph
    (0xB7, '\u{00B7}', 278, 278),   // periodcentered
    (0xB8, '\u{00B8}', 333, 333),   // cedilla
    (0xB9, '\u{00B9}', 333, 333),   // onesuperior
    (0xBA, '\u{00BA}', 365, 365),   // ordmasculine
    (0xBB, '\u{00BB}', 556, 556),   // guillemotright
    (0xBC, '\u{00BC}', 834, 834),   // onequarter
    (0xBD, '\u{00BD}', 834, 834),   // onehalf
    (0xBE, '\u{00BE}', 834, 834),   // threequarters
    (0xBF, '\u{00BF}', 611, 611),   // questiondown
    (0xC0, '\u{00C0}', 667, 722),   // Agrave
    (0xC1, '\u{00C1}', 667, 722),   // Aacute
    (0xC2, '\u{00C2}', 667, 722),   // Acircumflex
    (0xC3, '\u{00C3}', 667, 722),   // Atilde
    (0xC4, '\u{00C4}', 667, 722),   // Adieresis
    (0xC5, '\u{00C5}', 667, 722),   // Aring
    (0xC6, '\u{00C6}', 1000, 1000), // AE
    (0xC7, '\u{00C7}', 722, 722),   // Ccedilla
    (0xC8, '\u{00C8}', 667, 667),   // Egrave
    (0xC9, '\u{00C9}', 667, 667),   // Eacute
    (0xCA, '\u{00CA}', 667, 667),   // Ecircumflex
    (0xCB, '\u{00CB}', 667, 667),   // Edieresis
    (0xCC, '\u{00CC}', 278, 278),   // Igrave
    (0xCD, '\u{00CD}', 278, 278),   // Iacute
    (0xCE, '\u{00CE}', 278, 278),   // Icircumflex
    (0xCF, '\u{00CF}', 278, 278),   // Idieresis
    (0xD0, '\u{00D0}', 722, 722),   // Eth
    (0xD1, '\u{00D1}', 722, 722),   // Ntilde
    (0xD2, '\u{00D2}', 778, 778),   // Ograve
    (0xD3, '\u{00D3}', 778, 778),   // Oacute
    (0xD4, '\u{00D4}', 778, 778),   // Ocircumflex
    (0xD5, '\u{00D5}', 778, 778),   // Otilde
    (0xD6, '\u{00D6}', 778, 778),   // Odieresis
    (0xD7, '\u{00D7}', 584, 584),   // multiply
    (0xD8, '\u{00D8}', 778, 778),   // Oslash
    (0xD9, '\u{00D9}', 722, 722),   // Ugrave
    (0xDA, '\u{00DA}', 722, 722),   // Uacute
    (0xDB, '\u{00DB}', 722, 722),   // Ucircumflex
    (0xDC, '\u{00DC}', 722, 722),   // Udieresis
    (0xDD, '\u{00DD}', 667, 667),   // Yacute
    (0xDE, '\u{00DE}', 667, 667),   // Thorn
    (0xDF, '\u{00DF}', 611, 611),   // germandbls
    (0xE0, '\u{00E0}', 556, 556),   // agrave
    (0xE1, '\u{00E1}', 556, 556),   // aacute
    (0xE2, '\u{00E2}', 556, 556),   // acircumflex
    (0xE3, '\u{00E3}', 556, 556),   // atilde
    (0xE4, '\u{00E4}', 556, 556),   // adieresis
    (0xE5, '\u{00E5}', 556, 556),   // aring
    (0xE6, '\u{00E6}', 889, 889),   // ae
    (0xE7, '\u{00E7}', 500, 556),   // ccedilla
    (0xE8, '\u{00E8}', 556, 556),   // egrave
    (0xE9, '\u{00E9}', 556, 556),   // eacute
    (0xEA, '\u{00EA}', 556, 556),   // ecircumflex
    (0xEB, '\u{00EB}', 556, 556),   // edieresis
    (0xEC, '\u{00EC}', 278, 278),   // igrave
    (0xED, '\u{00ED}', 278, 278),   // iacute
    (0xEE, '\u{00EE}', 278, 278),   // icircumflex
    (0xEF, '\u{00EF}', 278, 278),   // idieresis
    (0xF0, '\u{00F0}', 556, 611),   // eth
    (0xF1, '\u{00F1}', 556, 611),   // ntilde
    (0xF2, '\u{00F2}', 556, 611),   // ograve
    (0xF3, '\u{00F3}', 556, 611),   // oacute
    (0xF4, '\u{00F4}', 556, 611),   // ocircumflex
    (0xF5, '\u{00F5}', 556, 611),   // otilde
    (0xF6, '\u{00F6}', 556, 611),   // odieresis
    (0xF7, '\u{00F7}', 584, 584),   // divide
    (0xF8, '\u{00F8}', 611, 611),   // oslash
    (0xF9, '\u{00F9}', 556, 611),   // ugrave
    (0xFA, '\u{00FA}', 556, 611),   // uacute
    (0xFB, '\u{00FB}', 556, 611),   // ucircumflex
    (0xFC, '\u{00FC}', 556, 611),   // udieresis
    (0xFD, '\u{00FD}', 500, 556),   // yacute
    (0xFE, '\u{00FE}', 556, 611),   // thorn
    (0xFF, '\u{00FF}', 500, 556),   // ydieresis
];

/// The WinAnsi code of `c`, if the built-in fonts have its glyph.
fn code(c: char) -> Option<u8> {
    if (' '..='~').contains(&c) {
        return Some(c as u8);
    }
    UPPER.iter().find(|e| e.1 == c).map(|e| e.0)
}

/// The width of a character of the upper half (`None` for ASCII and
/// characters the encoding lacks), in thousandths of the font size.
pub(crate) fn upper_width(c: char, bold: bool) -> Option<u16> {
    UPPER
        .iter()
        .find(|e| e.1 == c)
        .map(|e| if bold { e.3 } else { e.2 })
}

/// `text` in WinAnsi bytes, `?` for a character the fonts lack.
pub(crate) fn encode(text: &str) -> Vec<u8> {
    text.chars().map(|c| code(c).unwrap_or(b'?')).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latin_letters_are_encoded_as_code_page_1252() {
        assert_eq!(encode("Käfer-Brücke"), b"K\xE4fer-Br\xFCcke");
        assert_eq!(encode("€ – ’"), b"\x80 \x96 \x92");
        assert_eq!(encode("円"), b"?");
        // Helvetica's ä is as wide as its a; Helvetica-Bold's Ä as its A.
        assert_eq!(upper_width('ä', false), Some(556));
        assert_eq!(upper_width('Ä', true), Some(722));
        assert_eq!(upper_width('a', false), None);
        // Every code once, every character once, none of them ASCII.
        let codes: std::collections::BTreeSet<u8> = UPPER.iter().map(|e| e.0).collect();
        assert_eq!(codes.len(), UPPER.len());
        let chars: std::collections::BTreeSet<char> = UPPER.iter().map(|e| e.1).collect();
        assert_eq!(chars.len(), UPPER.len());
        assert!(UPPER.iter().all(|e| e.0 >= 0x80 && !e.1.is_ascii()));
    }
}
