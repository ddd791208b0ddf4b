//! Errors that point: a message, where it happened (a span of the recipe
//! and/or a lattice site), and what to change. Rendered like rustc/cargo.

use std::fmt::Write as _;
use std::ops::Range;

/// Exit status of a run that found a design invalid or a check failed.
pub const EXIT_INVALID: i32 = 1;
/// Exit status of a usage error: a flag, command or name that is not known.
pub const EXIT_USAGE: i32 = 2;
/// Exit status of a file that could not be read or written.
pub const EXIT_IO: i32 = 3;

/// Write the `ErrorKind` enum once: each kind, whose own name is the name
/// shown to users, and the exit status it ends a run with.
macro_rules! error_kinds {
    ($($(#[$doc:meta])* $kind:ident => $exit:ident,)*) => {
        /// Every error karigami reports, each its own kind. The kind decides
        /// the name in `error[NAME]` and in JSON, and the exit status.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum ErrorKind {
            $($(#[$doc])* $kind,)*
        }

        impl ErrorKind {
            /// Every kind, in the order they are declared.
            pub const ALL: &'static [ErrorKind] = &[$(ErrorKind::$kind,)*];

            /// The name users see and search for (MATH.md 9 for growth).
            pub fn name(self) -> &'static str {
                match self {
                    $(Self::$kind => stringify!($kind),)*
                }
            }

            /// The exit status of a run stopped by this error.
            pub fn exit_code(self) -> i32 {
                match self {
                    $(Self::$kind => $exit,)*
                }
            }
        }
    };
}

error_kinds! {
    // Files and the command line.
    /// A file could not be read or written.
    Io => EXIT_IO,
    /// A command line that cannot be run: an unknown template, a folder
    /// with no recipes, a name that is not usable.
    Usage => EXIT_USAGE,
    /// The recipe is not TOML, or a value has the wrong type.
    Toml => EXIT_INVALID,

    // Growth (MATH.md 9).
    SeedTooShort => EXIT_INVALID,
    SeedEdgeNotSpacelike => EXIT_INVALID,
    StartOutOfRange => EXIT_INVALID,
    BadDirection => EXIT_INVALID,
    InadmissibleDirection => EXIT_INVALID,
    DoubleEdgeNotSpacelike => EXIT_INVALID,
    NonPositiveLeg => EXIT_INVALID,
    MatchNeedsLength => EXIT_INVALID,
    DegenerateCell => EXIT_INVALID,
    InvertedCell => EXIT_INVALID,
    /// More cells, rows, edges or guide steps than karigami makes.
    TooLarge => EXIT_INVALID,
    NumericalBreakdown => EXIT_INVALID,
    LoopKappaSumNonzero => EXIT_INVALID,
    LoopClosureFree => EXIT_INVALID,
    NoLoopClosure => EXIT_INVALID,
    LoopClosureResidual => EXIT_INVALID,
    HelixSeedNotNull => EXIT_INVALID,
    FrontNotCompatible => EXIT_INVALID,

    // The recipe's values.
    ControlCharacter => EXIT_INVALID,
    StringTooLong => EXIT_INVALID,
    NestedTooDeep => EXIT_INVALID,
    NotFinite => EXIT_INVALID,
    NumberTooLarge => EXIT_INVALID,
    OutOfRange => EXIT_INVALID,
    EmptyName => EXIT_INVALID,
    UnknownSeed => EXIT_INVALID,
    FittedRowsGiven => EXIT_INVALID,
    WrongCoordinates => EXIT_INVALID,
    NoSeedPoints => EXIT_INVALID,
    SeedGivenTwice => EXIT_INVALID,
    LineDimensionsDiffer => EXIT_INVALID,
    NonPositiveRadius => EXIT_INVALID,
    PolylineDimensionsDiffer => EXIT_INVALID,
    PlanarSeedOffPlane => EXIT_INVALID,
    UnknownPlane => EXIT_INVALID,
    HelixTakesNoRows => EXIT_INVALID,
    HelixNeedsCells => EXIT_INVALID,
    SeedDimensionsDiffer => EXIT_INVALID,
    NoKappa => EXIT_INVALID,
    KappaCount => EXIT_INVALID,
    CellsWithoutHelix => EXIT_INVALID,
    RowSettingInGrow => EXIT_INVALID,
    RowsOutsideGrow => EXIT_INVALID,
    RowGivenTwice => EXIT_INVALID,
    RowBeyondLattice => EXIT_INVALID,
    NoRows => EXIT_INVALID,
    NoLegDirection => EXIT_INVALID,
    DirectionAndAngle => EXIT_INVALID,
    DirectionDimension => EXIT_INVALID,
    AngleNotFinite => EXIT_INVALID,
    TiltNeeds3d => EXIT_INVALID,
    TargetDimension => EXIT_INVALID,
    EmptyFront => EXIT_INVALID,
    FrontAnglesNotFinite => EXIT_INVALID,

    // Fitted lattices ([lattice.fit]).
    FitNeeds => EXIT_INVALID,
    FitNotPositive => EXIT_INVALID,
    FitAxes => EXIT_INVALID,
    FitProfilePoint => EXIT_INVALID,
    FitTubeTooLarge => EXIT_INVALID,
    FitStepOutOfRange => EXIT_INVALID,
    UnknownFitSurface => EXIT_INVALID,
    FitDimension => EXIT_INVALID,
    FitProfileRows => EXIT_INVALID,
    FitUnused => EXIT_INVALID,
    FitValuesPerRow => EXIT_INVALID,
    FitStepsNotPositive => EXIT_INVALID,

    // Fabrication settings, from the recipe.
    LengthOutOfRange => EXIT_INVALID,
    UnknownEyelet => EXIT_INVALID,
    UnknownLabel => EXIT_INVALID,
    SheetAutoWithSize => EXIT_INVALID,
    UnknownSheet => EXIT_INVALID,
    UnknownPaper => EXIT_INVALID,
    UnknownColours => EXIT_INVALID,
    UnknownGrouping => EXIT_INVALID,
    TabsWiderThanStrip => EXIT_INVALID,
    HoleWiderThanStrip => EXIT_INVALID,
    HoleTooCloseToEnd => EXIT_INVALID,
    SheetTooLarge => EXIT_INVALID,
    SheetTooSmall => EXIT_INVALID,

    // Fabrication settings, from the command line's flags.
    FlagOutOfRange => EXIT_USAGE,
    UnknownEyeletFlag => EXIT_USAGE,
    UnknownLabelFlag => EXIT_USAGE,
    UnknownSheetFlag => EXIT_USAGE,
    UnknownPaperFlag => EXIT_USAGE,
    UnknownColoursFlag => EXIT_USAGE,
    TabsWiderThanStripFlag => EXIT_USAGE,

    // Simulation and optimisation settings.
    SimulationOutOfRange => EXIT_INVALID,
    UnknownVertexJoint => EXIT_INVALID,
    NegativeClearance => EXIT_INVALID,
    UnknownStacking => EXIT_INVALID,
    StackingNeedsEvenLoop => EXIT_INVALID,
    UnknownVary => EXIT_INVALID,
    UnknownOptimiseMethod => EXIT_INVALID,
    EmptyVary => EXIT_INVALID,
    NonPositiveStep => EXIT_INVALID,
    OptimiseNegative => EXIT_INVALID,
    UnknownCurvaturePattern => EXIT_INVALID,
    NoOptimiseTable => EXIT_INVALID,
    NothingToVary => EXIT_INVALID,
    /// The optimiser's library stopped with an error.
    Optimiser => EXIT_INVALID,
    OptimiseFailed => EXIT_INVALID,
    /// `karigami tune` did not reach the cells asked for.
    TuneNotReached => EXIT_INVALID,
    ConstraintNotMet => EXIT_INVALID,

    // Checks of the grown lattice and its strips.
    VerificationFailed => EXIT_INVALID,
    LegShorterThanFlange => EXIT_INVALID,
    StripLongerThanSheet => EXIT_INVALID,
    StripClash => EXIT_INVALID,
    Overstrain => EXIT_INVALID,
    /// Some recipes of a batch failed (each was reported on its own).
    BatchFailed => EXIT_INVALID,
    /// `karigami simulate` found no equilibrium.
    SimulationFailed => EXIT_INVALID,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// What went wrong; decides the name shown and the exit status.
    pub kind: ErrorKind,
    pub message: String,
    /// Byte range in the recipe.
    pub span: Option<Range<usize>>,
    /// Lattice site, e.g. "row 3, column 2".
    pub site: Option<String>,
    pub hint: Option<String>,
}

impl Diagnostic {
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        Self {
            kind,
            message: message.into(),
            span: None,
            site: None,
            hint: None,
        }
    }

    pub fn at(mut self, span: Range<usize>) -> Self {
        self.span = Some(span);
        self
    }

    pub fn at_opt(mut self, span: Option<Range<usize>>) -> Self {
        self.span = span;
        self
    }

    pub fn site(mut self, site: impl Into<String>) -> Self {
        self.site = Some(site.into());
        self
    }

    pub fn hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }

    /// 1-based line and column of the start of the span.
    pub fn line_col(&self, source: &str) -> Option<(usize, usize)> {
        self.span.as_ref().map(|s| line_col(source, s.start))
    }

    /// The diagnostic with the file name and, when there is a span, the
    /// offending line with the text underlined.
    pub fn render(&self, file: &str, source: &str) -> String {
        let mut out = format!("error[{}]: {}\n", self.kind.name(), self.message);
        match self.line_col(source) {
            Some((line, col)) => {
                let _ = write!(out, "  --> {file}:{line}:{col}");
            }
            None => {
                let _ = write!(out, "  --> {file}");
            }
        }
        if let Some(site) = &self.site {
            let _ = write!(out, " (lattice {site})");
        }
        out.push('\n');
        if let Some(span) = &self.span {
            out.push_str(&snippet(source, span.clone()));
        }
        if let Some(hint) = &self.hint {
            let _ = writeln!(out, "   = help: {hint}");
        }
        out
    }
}

fn line_col(source: &str, offset: usize) -> (usize, usize) {
    let offset = floor_char_boundary(source, offset.min(source.len()));
    let before = &source[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    // A byte-order mark is not a column editors count.
    let text = source[line_start..offset].trim_start_matches('\u{FEFF}');
    (line, text.chars().count() + 1)
}

/// Columns a character takes in a terminal: 2 for East Asian wide and
/// full-width characters (CJK, Hangul, full-width forms, most emoji), 0
/// for a byte-order mark and combining marks, else 1. A short table
/// rather than a crate: carets only need the common scripts right.
fn columns(c: char) -> usize {
    let u = u32::from(c);
    let wide = matches!(u,
        0x1100..=0x115F | 0x2E80..=0x303E | 0x3041..=0x33FF | 0x3400..=0x4DBF
        | 0x4E00..=0x9FFF | 0xA000..=0xA4CF | 0xAC00..=0xD7A3 | 0xF900..=0xFAFF
        | 0xFE30..=0xFE4F | 0xFF00..=0xFF60 | 0xFFE0..=0xFFE6 | 0x1F300..=0x1F64F
        | 0x1F900..=0x1F9FF | 0x20000..=0x3FFFD);
    if wide {
        2
    } else if c == '\u{FEFF}' || (0x0300..=0x036F).contains(&u) {
        0
    } else {
        1
    }
}

fn display_width(s: impl IntoIterator<Item = char>) -> usize {
    s.into_iter().map(columns).sum()
}

fn floor_char_boundary(s: &str, mut i: usize) -> usize {
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// The first line of the span with carets under the spanned text. A long
/// line (a one-line list of points) is cut to a window round the span.
fn snippet(source: &str, span: Range<usize>) -> String {
    const CONTEXT: usize = 40;
    let start = floor_char_boundary(source, span.start.min(source.len()));
    let (line_no, col) = line_col(source, start);
    let line_start = source[..start].rfind('\n').map_or(0, |i| i + 1);
    let line_end = source[line_start..]
        .find('\n')
        .map_or(source.len(), |i| line_start + i);
    let text = source[line_start..line_end].trim_end_matches('\r');
    let end = floor_char_boundary(source, span.end.clamp(start, line_end.max(start)));
    let width = source[start..end].chars().count().max(1);
    let chars: Vec<char> = text.chars().collect();
    // Characters of the line shown: [from, to).
    let from = (col - 1).saturating_sub(CONTEXT);
    let to = (col - 1 + width.min(2 * CONTEXT) + CONTEXT).min(chars.len());
    let mut shown: String = chars[from.min(chars.len())..to].iter().collect();
    let mut offset = col - 1 - from;
    if from > 0 {
        shown.insert_str(0, "...");
        offset += 3;
    }
    if to < chars.len() {
        shown.push_str("...");
    }
    // Carets in terminal columns: wide characters take two.
    let lead: usize = display_width(shown.chars().take(offset));
    let under: usize =
        display_width(shown.chars().skip(offset).take(width.min(2 * CONTEXT))).max(1);
    let gutter = line_no.to_string().len();
    let pad = " ".repeat(gutter);
    format!(
        "{pad} |\n{line_no} | {shown}\n{pad} | {}{}\n",
        " ".repeat(lead),
        "^".repeat(under)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_file_line_column_and_underline() {
        let src = "a = 1\nkappa = [2.0, -30.0]\n";
        let start = src.find("-30.0").unwrap();
        let d = Diagnostic::new(ErrorKind::SeedEdgeNotSpacelike, "too big")
            .at(start..start + 5)
            .site("seed edge 1")
            .hint("lower it");
        let text = d.render("d.toml", src);
        assert!(
            text.contains("--> d.toml:2:15 (lattice seed edge 1)"),
            "{text}"
        );
        assert!(
            text.contains("2 | kappa = [2.0, -30.0]\n  |               ^^^^^"),
            "{text}"
        );
        assert!(text.contains("= help: lower it"));
    }

    #[test]
    fn long_lines_are_cut_round_the_span() {
        let src = format!(
            "points = [{}[9.0, 9.0]{}]\n",
            "[1.0, 2.0], ".repeat(30),
            ", [3.0, 4.0]".repeat(30)
        );
        let start = src.find("[9.0").unwrap();
        let d = Diagnostic::new(ErrorKind::Usage, "y").at(start..start + 10);
        let text = d.render("f", &src);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[3].len() < 110, "{text}");
        assert!(
            lines[3].starts_with("1 | ...") && lines[3].ends_with("..."),
            "{text}"
        );
        assert!(lines[3].contains("[1.0, 2.0], [9.0, 9.0], [3.0"), "{text}");
        let caret = lines[4].find('^').unwrap();
        assert_eq!(&lines[3][caret..caret + 10], "[9.0, 9.0]", "{text}");
    }

    #[test]
    fn a_byte_order_mark_is_not_a_column_and_wide_text_gets_wide_carets() {
        let src = "\u{FEFF}name = 5\n";
        let d = Diagnostic::new(ErrorKind::Usage, "y").at(src.find('5').unwrap()..src.len() - 1);
        assert_eq!(d.line_col(src), Some((1, 8)));
        let src = "seed = \"円円\"\n";
        let d = Diagnostic::new(ErrorKind::Usage, "y").at(7..src.len() - 1);
        let text = d.render("f", src);
        assert!(
            text.contains("| seed = \"円円\"\n  |        ^^^^^^\n"),
            "{text}"
        );
    }

    #[test]
    fn every_kind_has_its_own_name_and_an_exit_status() {
        let mut names = std::collections::HashSet::new();
        for &k in ErrorKind::ALL {
            let name = k.name();
            // The name is the kind's, so no two kinds share one.
            assert_eq!(format!("{k:?}"), name);
            assert!(names.insert(name), "{name} twice");
            assert!([EXIT_INVALID, EXIT_USAGE, EXIT_IO].contains(&k.exit_code()));
        }
        assert_eq!(ErrorKind::Io.exit_code(), EXIT_IO);
        assert_eq!(ErrorKind::UnknownSheetFlag.exit_code(), EXIT_USAGE);
        assert_eq!(ErrorKind::UnknownSheet.exit_code(), EXIT_INVALID);
        assert_eq!(ErrorKind::UnknownSheet.name(), "UnknownSheet");
    }

    #[test]
    fn spans_past_the_end_do_not_panic() {
        let d = Diagnostic::new(ErrorKind::Usage, "y").at(100..200);
        let text = d.render("f", "short");
        assert!(text.contains("f:1:6"), "{text}");
    }
}
