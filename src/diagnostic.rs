//! Errors that point: a message, where it happened (a span of the recipe
//! and/or a lattice site), and what to change. Rendered like rustc/cargo.

use std::fmt::Write as _;
use std::ops::Range;

/// Exit status of a run that found a design invalid or a check failed.
pub(crate) const EXIT_INVALID: i32 = 1;
/// Exit status of a usage error: a flag, command or name that is not known.
pub(crate) const EXIT_USAGE: i32 = 2;
/// Exit status of a file that could not be read or written.
pub(crate) const EXIT_IO: i32 = 3;
/// Exit status of a refused `--out` (not a build folder, a file, a link,
/// holding an input, locked by another run): the same as `EXIT_IO`, as the
/// docs/commands.md promises, because the folder's state, not the command line, is
/// what has to change.
pub(crate) const EXIT_OUT_REFUSED: i32 = 3;
/// Exit status of a run stopped at its `--time-limit` (docs/commands.md,
/// "Time limits"): nothing half-done was written.
pub(crate) const EXIT_TIME: i32 = 4;

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
            #[cfg(test)]
            pub(crate) const ALL: &'static [ErrorKind] = &[$(ErrorKind::$kind,)*];

            /// The name users see and search for (docs/math.md 9 for growth).
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
    /// A folder given as recipes holds no `.toml` file.
    NoRecipes => EXIT_USAGE,
    /// Two recipes of a batch would build into the same subfolder.
    SameSubfolder => EXIT_USAGE,

    // A refused `--out` (docs/commands.md: exit status 3). A refusal writes nothing.
    /// `--out` names no folder (`.`, `/`, `..`).
    OutNotAFolderName => EXIT_OUT_REFUSED,
    /// A folder `--out` would be created in is a file.
    OutUnderAFile => EXIT_OUT_REFUSED,
    /// `--out` is a file.
    OutIsAFile => EXIT_OUT_REFUSED,
    /// `--out` is a symbolic link.
    OutIsALink => EXIT_OUT_REFUSED,
    /// `--out` holds an input of the run.
    OutHoldsInput => EXIT_OUT_REFUSED,
    /// `--out` is the current folder or holds it.
    OutHoldsCurrentFolder => EXIT_OUT_REFUSED,
    /// `--out` exists and is not a karigami build folder (no `--force`).
    NotABuildFolder => EXIT_OUT_REFUSED,
    /// `--out` is a build folder holding files the build did not write (no
    /// `--force`).
    BuildFolderHasOtherFiles => EXIT_OUT_REFUSED,
    /// Another karigami run is writing `--out` right now.
    OutLocked => EXIT_OUT_REFUSED,

    // Growth (docs/math.md 9).
    /// The seed has too few points to grow (docs/math.md 9).
    SeedTooShort => EXIT_INVALID,
    /// A seed or rebuilt front edge is no longer than its |kappa|: `|kappa| >= |t|`.
    SeedEdgeNotSpacelike => EXIT_INVALID,
    /// A row's `start` site is not a cell of the row.
    StartOutOfRange => EXIT_INVALID,
    /// A row's leg direction cannot be used: zero length, or angles with no
    /// reference (a front edge along z, a tilt in 2-D).
    BadDirection => EXIT_INVALID,
    /// A leg direction (or loop target) falls outside the cell's admissible
    /// cone: the pivot would be at or beyond infinity.
    InadmissibleDirection => EXIT_INVALID,
    /// A transfer has no admissible corner: the distance across two front
    /// edges is no longer than |sum| of their kappa.
    DoubleEdgeNotSpacelike => EXIT_INVALID,
    /// A leg comes out (or is given) zero or negative.
    NonPositiveLeg => EXIT_INVALID,
    /// Both end legs of a one-cell-wide row are `match`; one needs a length.
    MatchNeedsLength => EXIT_INVALID,
    /// A cell's opening angle is too close to 0 or pi.
    DegenerateCell => EXIT_INVALID,
    /// 2-D: a cell turned over relative to the lattice's first cell.
    InvertedCell => EXIT_INVALID,
    /// More cells, rows, edges or guide steps than karigami makes.
    TooLarge => EXIT_INVALID,
    /// The construction produced a non-finite number.
    NumericalBreakdown => EXIT_INVALID,
    /// A loop seed's kappa do not sum to 0, so it cannot collapse.
    LoopKappaSumNonzero => EXIT_INVALID,
    /// A symmetric loop row closes for every direction and was given none.
    LoopClosureFree => EXIT_INVALID,
    /// No admissible leg direction closes a loop row, or the one given (by
    /// direction or `candidate`) does not.
    NoLoopClosure => EXIT_INVALID,
    /// A loop row closes only to more than `CLOSURE_TOL`.
    LoopClosureResidual => EXIT_INVALID,
    /// A helix seed breaks its condition `|y_N - y_1| = z_N - z_1`.
    HelixSeedNotNull => EXIT_INVALID,
    /// A row's `front` moves cannot rebuild its front.
    FrontNotCompatible => EXIT_INVALID,

    // The recipe's values.
    /// A recipe string holds a control character.
    ControlCharacter => EXIT_INVALID,
    /// A recipe string is longer than karigami accepts.
    StringTooLong => EXIT_INVALID,
    /// Arrays and tables are nested deeper than karigami accepts.
    NestedTooDeep => EXIT_INVALID,
    /// A number is NaN or infinite.
    NotFinite => EXIT_INVALID,
    /// A number is larger in magnitude than any size karigami accepts.
    NumberTooLarge => EXIT_INVALID,
    /// A number lies outside its allowed range.
    OutOfRange => EXIT_INVALID,
    /// The design's `name` is empty.
    EmptyName => EXIT_INVALID,
    /// `lattice.seed` is not sheet, loop or helix.
    UnknownSeed => EXIT_INVALID,
    /// A fitted lattice (`[lattice.fit]`) also writes rows out.
    FittedRowsGiven => EXIT_INVALID,
    /// A point or vector has neither 2 nor 3 coordinates.
    WrongCoordinates => EXIT_INVALID,
    /// The lattice gives no seed points.
    NoSeedPoints => EXIT_INVALID,
    /// The seed points are given by more than one of `points` and the seed tables.
    SeedGivenTwice => EXIT_INVALID,
    /// `line.from` and `line.to` have different numbers of coordinates.
    LineDimensionsDiffer => EXIT_INVALID,
    /// An arc or circle seed's radius is not positive.
    NonPositiveRadius => EXIT_INVALID,
    /// Polyline points have different numbers of coordinates.
    PolylineDimensionsDiffer => EXIT_INVALID,
    /// A seed table of a 2-D lattice names a plane other than xy.
    PlanarSeedOffPlane => EXIT_INVALID,
    /// A seed table names an unknown plane.
    UnknownPlane => EXIT_INVALID,
    /// A helix is given rows, which its seed already determines.
    HelixTakesNoRows => EXIT_INVALID,
    /// A helix does not say how many cells to grow (`cells`).
    HelixNeedsCells => EXIT_INVALID,
    /// Seed points have different numbers of coordinates.
    SeedDimensionsDiffer => EXIT_INVALID,
    /// The seed has no `kappa`.
    NoKappa => EXIT_INVALID,
    /// `kappa` has a count of values other than one per seed edge.
    KappaCount => EXIT_INVALID,
    /// `cells` is given for a seed that is not a helix.
    CellsWithoutHelix => EXIT_INVALID,
    /// A setting of one row is written in `[lattice.grow]`.
    RowSettingInGrow => EXIT_INVALID,
    /// `rows` is written outside `[lattice.grow]`.
    RowsOutsideGrow => EXIT_INVALID,
    /// Two `[[lattice.rows]]` entries describe the same row.
    RowGivenTwice => EXIT_INVALID,
    /// A `[[lattice.rows]]` entry names a row before an earlier entry's.
    RowsOutOfOrder => EXIT_INVALID,
    /// A `[[lattice.rows]]` entry reaches past the lattice's last row.
    RowBeyondLattice => EXIT_INVALID,
    /// The design grows no rows.
    NoRows => EXIT_INVALID,
    /// A row has no leg direction (`angle` or `direction`).
    NoLegDirection => EXIT_INVALID,
    /// A row gives both `direction` and `angle`.
    DirectionAndAngle => EXIT_INVALID,
    /// A `direction` has more or fewer coordinates than the lattice's dimension.
    DirectionDimension => EXIT_INVALID,
    /// A row's angle is not a finite number.
    AngleNotFinite => EXIT_INVALID,
    /// A tilt angle is given in a 2-D lattice.
    TiltNeeds3d => EXIT_INVALID,
    /// A loop row's `target` has more or fewer coordinates than the lattice's
    /// dimension.
    TargetDimension => EXIT_INVALID,
    /// A row's `front = { }` holds no move.
    EmptyFront => EXIT_INVALID,
    /// A front move's angles are not finite.
    FrontAnglesNotFinite => EXIT_INVALID,
    /// A front's saddle is not one or two finite amplitudes (`c` or `[c, d]`).
    FrontSaddleAmplitudes => EXIT_INVALID,

    // Fitted lattices ([lattice.fit]).
    /// A fit surface lacks a value it needs.
    FitNeeds => EXIT_INVALID,
    /// A fit size that must be positive is not.
    FitNotPositive => EXIT_INVALID,
    /// `fit.axes` is not three positive semi-axes.
    FitAxes => EXIT_INVALID,
    /// A fit profile point is not `[r, z]` with `r > 0`.
    FitProfilePoint => EXIT_INVALID,
    /// A torus fit's `tube` is not smaller than its `radius`.
    FitTubeTooLarge => EXIT_INVALID,
    /// `fit.step` is not between 0 and 90 degrees.
    FitStepOutOfRange => EXIT_INVALID,
    /// `fit.surface` names an unknown target.
    UnknownFitSurface => EXIT_INVALID,
    /// The fit surface grows a lattice of another dimension or seed kind
    /// than the recipe's.
    FitDimension => EXIT_INVALID,
    /// A fit profile's point count does not match `fit.rows`.
    FitProfileRows => EXIT_INVALID,
    /// `fit.angles` or `fit.steps` is given for a target that does not use it.
    FitUnused => EXIT_INVALID,
    /// `fit.angles` or `fit.steps` does not have one value per row.
    FitValuesPerRow => EXIT_INVALID,
    /// `fit.steps` holds a length that is not positive.
    FitStepsNotPositive => EXIT_INVALID,

    // Targets (docs/design.md, "Validation").
    /// A target file is not one karigami reads: another extension, not
    /// text where text is needed, or not OBJ or STL inside.
    TargetFormat => EXIT_INVALID,
    /// A target has no triangles.
    TargetEmpty => EXIT_INVALID,
    /// A target has more triangles or bytes than karigami reads.
    TargetTooLarge => EXIT_INVALID,
    /// A corner of a target's triangle is NaN or infinite.
    TargetNotFinite => EXIT_INVALID,
    /// A target's triangle has zero area.
    TargetDegenerate => EXIT_INVALID,
    /// An edge of a target joins more than two triangles, or two surfaces
    /// touch at one corner.
    TargetNonManifold => EXIT_INVALID,
    /// A target is more than one piece.
    TargetPieces => EXIT_INVALID,
    /// A target's size suggests it is not in millimetres.
    TargetUnits => EXIT_INVALID,
    /// A target has another topology than the one asked for.
    TargetTopology => EXIT_INVALID,
    /// `[target] family` names an unknown family.
    UnknownTargetFamily => EXIT_INVALID,
    /// A `[target]` family lacks a parameter it needs.
    TargetNeeds => EXIT_INVALID,
    /// A `[target]` table gives a parameter its family does not use.
    TargetUnused => EXIT_INVALID,
    /// A `[target]` parameter lies outside its range.
    TargetParameter => EXIT_INVALID,
    /// A target bends tighter than the strips do at their allowable strain
    /// (docs/design.md, "Curvature the strips reach").
    TargetTooCurved => EXIT_INVALID,
    /// The best design `karigami design` found misses the goal
    /// (docs/design.md, "The goal"): refused, not written.
    GoalMissed => EXIT_INVALID,

    // Fabrication settings, from the recipe.
    /// A fabrication length (mm) lies outside its allowed range.
    LengthOutOfRange => EXIT_INVALID,
    /// `[eyelet] preset` names an unknown eyelet.
    UnknownEyelet => EXIT_INVALID,
    /// `[strip] label` names an unknown label style.
    UnknownLabel => EXIT_INVALID,
    /// `[material] preset` names unknown stock.
    UnknownMaterial => EXIT_INVALID,
    /// `[material] thickness` is outside its preset's range.
    ThicknessOutsidePreset => EXIT_INVALID,
    /// `[laser] machine` names an unknown laser.
    UnknownMachine => EXIT_INVALID,
    /// `[machine] preset` names an unknown machine.
    UnknownMachinePreset => EXIT_INVALID,
    /// `[machine] preset` and `[laser] machine` name different machines,
    /// or `[machine] min_hole` is given for a laser.
    MachineConflict => EXIT_INVALID,
    /// On a cutting plotter the sheet is a mat: `[sheet]` names another
    /// sheet or gives a size.
    SheetNotAMat => EXIT_INVALID,
    /// The eyelet holes are smaller than a cutting plotter's blade cuts
    /// cleanly.
    HoleTooSmallForBlade => EXIT_INVALID,
    /// `[sheet]` is `preset = "auto"` and also given a size.
    SheetAutoWithSize => EXIT_INVALID,
    /// `[sheet] preset` names an unknown sheet.
    UnknownSheet => EXIT_INVALID,
    /// The guide's paper is neither A4 nor Letter.
    UnknownPaper => EXIT_INVALID,
    /// The recipe names an unknown colour preset.
    UnknownColours => EXIT_INVALID,
    /// The recipe names an unknown sheet grouping.
    UnknownGrouping => EXIT_INVALID,
    /// `laser.tabs` is wider than the strips.
    TabsWiderThanStrip => EXIT_INVALID,
    /// The eyelet hole leaves less than `MIN_WALL` of material each side of
    /// the strip.
    HoleWiderThanStrip => EXIT_INVALID,
    /// The eyelet's flange is no wider than its hole.
    FlangeNotWiderThanHole => EXIT_INVALID,
    /// Kerf compensation would cut a hole (an eyelet hole or a test piece
    /// step) to nothing: the recipe's kerf, eyelet or `compensate`.
    KerfClosesHole => EXIT_INVALID,
    /// `strip.end_margin` puts the end holes closer to the tips than the
    /// rounded end allows.
    HoleTooCloseToEnd => EXIT_INVALID,
    /// The sheet is larger than karigami lays out.
    SheetTooLarge => EXIT_INVALID,
    /// The sheet's usable area is narrower than one strip.
    SheetTooSmall => EXIT_INVALID,

    // Fabrication settings, from the command line's flags.
    /// A fabrication flag's length (mm) lies outside its allowed range.
    FlagOutOfRange => EXIT_USAGE,
    /// `--eyelet` names an unknown eyelet.
    UnknownEyeletFlag => EXIT_USAGE,
    /// `--label` names an unknown label style.
    UnknownLabelFlag => EXIT_USAGE,
    /// `--sheet` is neither a preset, `auto`, nor `WxH` in mm.
    UnknownSheetFlag => EXIT_USAGE,
    /// `--machine` names an unknown machine.
    UnknownMachinePresetFlag => EXIT_USAGE,
    /// `--sheet` names a sheet that is not a mat of the cutting plotter.
    SheetNotAMatFlag => EXIT_USAGE,
    /// `--paper` is neither a4 nor letter.
    UnknownPaperFlag => EXIT_USAGE,
    /// `--colours` names an unknown colour preset.
    UnknownColoursFlag => EXIT_USAGE,
    /// `--tabs` is wider than the strips.
    TabsWiderThanStripFlag => EXIT_USAGE,
    /// `--kerf` with compensation would cut a hole to nothing.
    KerfClosesHoleFlag => EXIT_USAGE,

    // Simulation and optimisation settings.
    /// A `[simulation]` value lies outside its allowed range.
    SimulationOutOfRange => EXIT_INVALID,
    /// The simulation's mesh would take more memory than allowed.
    SimulationTooLarge => EXIT_INVALID,
    /// Work estimated from the input (a simulation, `--explore`'s starts,
    /// tune's designs) would take longer than allowed (docs/commands.md,
    /// "Time limits"): refused before it starts.
    WorkTooLong => EXIT_INVALID,
    /// The run stopped at its `--time-limit`, having written nothing.
    TimeLimit => EXIT_TIME,
    /// `[simulation] vertex_joint` is neither eyelet nor ball.
    UnknownVertexJoint => EXIT_INVALID,
    /// A `[simulation] supports` entry is not a vertex name the lattice
    /// can have (`[row, column]`, `[index]` on a helix).
    SupportNotAVertexName => EXIT_INVALID,
    /// A `[simulation] supports` entry names no vertex of the grown lattice.
    UnknownSupport => EXIT_INVALID,
    /// A vertex is named twice in `[simulation] supports`.
    DuplicateSupport => EXIT_INVALID,
    /// `[simulation] supports` names one or two vertices, or only vertices
    /// on one line: the pins do not fix the lattice's rigid motion.
    SupportsTooFew => EXIT_INVALID,
    /// `clash.clearance` is negative.
    NegativeClearance => EXIT_INVALID,
    /// `[clash] stacking` is not one of the known words ("rows", "columns").
    UnknownStacking => EXIT_INVALID,
    /// `[clash] stacking = "columns"` on a lattice that is not a loop with an
    /// even number of columns, where neighbouring columns cannot alternate.
    StackingNeedsEvenLoop => EXIT_INVALID,
    /// `optimise.vary` names something the optimiser cannot vary.
    UnknownVary => EXIT_INVALID,
    /// `optimise.method` names an unknown method.
    UnknownOptimiseMethod => EXIT_INVALID,
    /// `optimise.vary` is empty.
    EmptyVary => EXIT_INVALID,
    /// `optimise.step` is not positive.
    NonPositiveStep => EXIT_INVALID,
    /// A value of `[optimise]` that must not be negative (a weight) is.
    OptimiseNegative => EXIT_INVALID,
    /// The optimiser's curvature objective names an unknown pattern.
    UnknownCurvaturePattern => EXIT_INVALID,
    /// `optimise.target.shape` is neither "design" nor "simulated".
    UnknownTargetShape => EXIT_INVALID,
    /// `target.shape = "simulated"` without a curvature objective to measure.
    TargetShapeUnused => EXIT_INVALID,
    /// `karigami optimise` was run on a recipe with no `[optimise]` table.
    NoOptimiseTable => EXIT_INVALID,
    /// The recipe holds none of the numbers `optimise.vary` names.
    NothingToVary => EXIT_INVALID,
    /// No design the optimiser tried grows every row.
    OptimiseFailed => EXIT_INVALID,
    /// `karigami tune` did not reach the cells asked for.
    TuneNotReached => EXIT_INVALID,
    /// No design the optimiser found meets a `require` constraint.
    ConstraintNotMet => EXIT_INVALID,

    // Checks of the grown lattice and its strips.
    /// The grown lattice fails an invariant of docs/math.md 8 beyond the tolerance.
    VerificationFailed => EXIT_INVALID,
    /// Two holes of a strip are closer than the eyelet flange: the eyelets
    /// would overlap.
    LegShorterThanFlange => EXIT_INVALID,
    /// A strip does not fit the sheet's usable area.
    StripLongerThanSheet => EXIT_INVALID,
    /// Two strips of one stacking layer overlap in the assembled lattice.
    StripClash => EXIT_INVALID,
    /// A strip is strained beyond the material's allowable in the simulated
    /// deployed shape.
    Overstrain => EXIT_INVALID,
    /// Some recipes of a batch failed (each was reported on its own).
    BatchFailed => EXIT_INVALID,
    /// `karigami simulate` found no equilibrium.
    SimulationFailed => EXIT_INVALID,
}

/// An error that points: what went wrong, where (recipe text and/or lattice
/// site) and what to change; rendered like rustc's messages.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// What went wrong; decides the name shown and the exit status.
    pub kind: ErrorKind,
    /// What went wrong, in plain words.
    pub message: String,
    /// Byte range in the recipe.
    pub span: Option<Range<usize>>,
    /// Lattice site, e.g. "row 3, column 2".
    pub site: Option<String>,
    /// What to change to fix it.
    pub hint: Option<String>,
}

impl Diagnostic {
    pub(crate) fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        Self {
            kind,
            message: message.into(),
            span: None,
            site: None,
            hint: None,
        }
    }

    pub(crate) fn at(mut self, span: Range<usize>) -> Self {
        self.span = Some(span);
        self
    }

    pub(crate) fn at_opt(mut self, span: Option<Range<usize>>) -> Self {
        self.span = span;
        self
    }

    pub(crate) fn site(mut self, site: impl Into<String>) -> Self {
        self.site = Some(site.into());
        self
    }

    pub(crate) fn hint(mut self, hint: impl Into<String>) -> Self {
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
            // `=` under the snippet's bar, whose column grows with the line
            // number's digits (as rustc does); three spaces without one.
            let gutter = self
                .line_col(source)
                .map_or(2, |(line, _)| line.to_string().len());
            let _ = writeln!(out, "{} = help: {hint}", " ".repeat(gutter));
        }
        out
    }
}

/// A number for a message, readable whatever its size: to 14 significant
/// digits (a computed bound such as 2 + 3.97 is 5.970000000000001 in
/// binary; the message says 5.97, while a value a user wrote just below a
/// bound, 0.09999999999999, is not rounded onto it), as the shortest text
/// from 1e-4 up to 1e6, else in e-notation, so `1e-300` is not printed
/// with 300 digits.
pub fn shown(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let x: f64 = format!("{x:.13e}").parse().unwrap_or(x);
    if x == 0.0 || (1e-4..1e6).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
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
    fn help_sits_under_the_bar_for_every_line_number_width() {
        for line in [1usize, 9, 10, 99, 100, 12345] {
            let src = format!("{}x = 1\n", "\n".repeat(line - 1));
            let start = src.find('x').unwrap();
            let d = Diagnostic::new(ErrorKind::OutOfRange, "y")
                .at(start..start + 1)
                .hint("h");
            let text = d.render("f", &src);
            let lines: Vec<&str> = text.lines().collect();
            let bar = lines[2].find('|').unwrap();
            assert_eq!(bar, line.to_string().len() + 1, "{text}");
            let help = lines.last().unwrap();
            assert_eq!(help.find('='), Some(bar), "{text}");
            assert!(help.ends_with("= help: h"), "{text}");
        }
        // Without a snippet, three spaces as before.
        let d = Diagnostic::new(ErrorKind::OutOfRange, "y").hint("h");
        assert!(d.render("f", "").ends_with("\n   = help: h\n"));
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
            assert!(
                [
                    EXIT_INVALID,
                    EXIT_USAGE,
                    EXIT_IO,
                    EXIT_OUT_REFUSED,
                    EXIT_TIME
                ]
                .contains(&k.exit_code())
            );
        }
        assert_eq!(ErrorKind::Io.exit_code(), EXIT_IO);
        assert_eq!(ErrorKind::UnknownSheetFlag.exit_code(), EXIT_USAGE);
        assert_eq!(ErrorKind::UnknownSheet.exit_code(), EXIT_INVALID);
        assert_eq!(ErrorKind::UnknownSheet.name(), "UnknownSheet");
    }

    #[test]
    fn numbers_in_messages_stay_short() {
        assert_eq!(shown(1e-300), "1e-300");
        assert_eq!(shown(-2.5e-7), "-2.5e-7");
        assert_eq!(shown(3e12), "3e12");
        assert_eq!(shown(0.15), "0.15");
        assert_eq!(shown(-0.0001), "-0.0001");
        assert_eq!(shown(999999.5), "999999.5");
        assert_eq!(shown(0.0), "0");
        assert_eq!(shown(2.0 + 3.97), "5.97");
        assert_eq!(shown(609.6 - 2.0 * 302.7), "4.2");
        assert_eq!(shown(0.09999999999999), "0.09999999999999");
        assert_eq!(shown(f64::NAN), "NaN");
        assert_eq!(shown(-f64::INFINITY), "-inf");
    }

    #[test]
    fn spans_past_the_end_do_not_panic() {
        let d = Diagnostic::new(ErrorKind::Usage, "y").at(100..200);
        let text = d.render("f", "short");
        assert!(text.contains("f:1:6"), "{text}");
    }
}
