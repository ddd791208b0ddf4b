//! Growth errors (docs/math.md 9): what failed, the design parameter it is
//! about, and where (row and column), with the helpers that build them.

use super::*;

/// The design parameter a growth error is about, so the recipe layer can
/// point at the text that sets it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Param {
    /// The seed points (`points`, or a seed table such as `[lattice.line]`).
    SeedPoints,
    /// The kappa of one seed edge.
    SeedKappa(usize),
    /// The front a row grows on: the seed for row 0, else the previous row.
    Front,
    /// A row's `start` site.
    Start,
    /// A row's leg direction (`angle` or `direction`).
    Direction,
    /// A row's free leg at the left end (`left_leg`).
    LeftLeg,
    /// A row's free leg at the right end (`right_leg`).
    RightLeg,
    /// A loop row's `target` point for its vertex `x[i+1][1]`.
    Target,
    /// A loop row's closing direction `candidate`.
    Candidate,
    /// A row's `front` moves (intrinsic growth).
    FrontMoves,
    /// A helix's cell count.
    Cells,
}

/// A design that cannot be grown, with the place it fails.
#[derive(Clone, Debug, PartialEq)]
pub struct GrowthError {
    /// What failed (a growth kind of docs/math.md 9); decides the name shown and the
    /// exit status.
    pub kind: ErrorKind,
    pub(crate) param: Param,
    /// The row being grown (`None` for a problem of the seed itself).
    pub(crate) row: Option<usize>,
    /// The column (cell, or seed edge) where it fails, when there is one.
    pub(crate) col: Option<usize>,
    pub(crate) message: String,
    pub(crate) hint: String,
}

impl GrowthError {
    pub(crate) fn new(
        kind: ErrorKind,
        param: Param,
        row: Option<usize>,
        col: Option<usize>,
        message: impl Into<String>,
        hint: impl Into<String>,
    ) -> Self {
        Self {
            kind,
            param,
            row,
            col,
            message: message.into(),
            hint: hint.into(),
        }
    }

    /// An error of the design as a whole (its seed, its size), at no lattice site.
    pub(crate) fn of_design(
        kind: ErrorKind,
        param: Param,
        message: impl Into<String>,
        hint: impl Into<String>,
    ) -> Self {
        Self::new(kind, param, None, None, message, hint)
    }

    /// "row 3, column 2" style location in lattice terms.
    pub(crate) fn site(&self) -> String {
        match (self.row, self.col) {
            (Some(r), Some(c)) => format!("row {r}, column {c}"),
            (Some(r), None) => format!("row {r}"),
            (None, Some(c)) => format!("seed edge {c}"),
            (None, None) => "seed".to_string(),
        }
    }
}

impl fmt::Display for GrowthError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} at {}: {}",
            self.kind.name(),
            self.site(),
            self.message
        )
    }
}

impl std::error::Error for GrowthError {}

/// A refused transfer across the double edge from front vertex `a` to `b`.
pub(super) fn transfer_error(
    refusal: Refusal,
    x: &[Point],
    a: usize,
    b: usize,
    i: usize,
    j: usize,
) -> GrowthError {
    match refusal {
        Refusal::NotSpacelike => GrowthError::new(
            ErrorKind::DoubleEdgeNotSpacelike,
            Param::Front,
            Some(i),
            Some(j),
            format!(
                "the front is too folded at cell {j}: front vertices {a} and {b} are {} apart, not more than |kappa| summed between them ({})",
                fmt_len(x[a].pos.distance(x[b].pos)),
                fmt_len((x[a].z - x[b].z).abs()),
            ),
            "unfold the front here: change the seed points or kappa (row 0), or the previous row's direction or legs",
        ),
        Refusal::MissesCone => propagated_cone(i, j),
    }
}

pub(super) fn propagated_cone(i: usize, j: usize) -> GrowthError {
    GrowthError::new(
        ErrorKind::InadmissibleDirection,
        Param::Direction,
        Some(i),
        Some(j),
        "the leg direction carried over from the neighbouring cell falls outside this cell's admissible cone (the pivot would be at infinity)",
        "this row's start direction is admissible at its start site but not across the row: choose a direction nearer the cone axis",
    )
}

#[inline]
pub(super) fn check_leg(leg: f64, name: &str, i: usize, j: usize) -> Result<(), GrowthError> {
    if positive_finite(leg) {
        return Ok(());
    }
    Err(leg_error(leg, name, i, j))
}

/// `check_leg`'s refusal, out of the growth loop's way.
#[cold]
#[inline(never)]
pub(super) fn leg_error(leg: f64, name: &str, i: usize, j: usize) -> GrowthError {
    if !leg.is_finite() {
        return breakdown(i, j);
    }
    GrowthError::new(
        ErrorKind::NonPositiveLeg,
        Param::Direction,
        Some(i),
        Some(j),
        format!(
            "leg {name} would be {} (the pivot lies beyond the corner)",
            fmt_len(leg)
        ),
        "choose a direction nearer the cone axis for this row",
    )
}

pub(super) fn check_boundary_leg(
    leg: f64,
    param: Param,
    i: usize,
    j: usize,
) -> Result<(), GrowthError> {
    if positive_finite(leg) {
        return Ok(());
    }
    let name = if param == Param::LeftLeg {
        "left_leg (L2)"
    } else {
        "right_leg (L3)"
    };
    Err(GrowthError::new(
        ErrorKind::NonPositiveLeg,
        param,
        Some(i),
        Some(j),
        format!("{name} is {} but must be a positive length", fmt_len(leg)),
        format!(
            "give {} a positive length in mm, or \"match\"",
            name.split(' ').next().unwrap_or(name)
        ),
    ))
}

pub(super) fn breakdown(i: usize, j: usize) -> GrowthError {
    GrowthError::new(
        ErrorKind::NumericalBreakdown,
        Param::Direction,
        Some(i),
        Some(j),
        "the construction produced a non-finite number",
        "the design is too close to degenerate here: change this row's direction or legs",
    )
}
