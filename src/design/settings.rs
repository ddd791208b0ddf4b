//! The simulation's settings as a recipe gives them (`[simulation]`, read
//! in `simulation.rs`): the strip material, the opening to deploy to, what
//! deployment holds, the mesh and the joint model. Plain numbers and
//! choices: the simulation (`sim`) reads them; the recipe needs nothing of
//! it.

/// The memory a simulation may take unless the command line says otherwise
/// (`--memory`): 2 GiB.
pub const DEFAULT_MEMORY: u64 = 2 << 30;

/// The strip material. Defaults: ABS (docs/physics.md, "ABS and the
/// recipe's `[simulation]` table").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Young's modulus (MPa = N/mm^2).
    pub youngs: f64,
    /// Poisson's ratio (enters the shear modulus only).
    pub poisson: f64,
    /// Largest corner-fibre strain a strip may take (fraction).
    pub eps_allow: f64,
}

impl Material {
    /// ABS: E = 2200 MPa, Poisson's ratio 0.35, allowable strain 1.5 %.
    pub const ABS: Material = Material {
        youngs: 2200.0,
        poisson: 0.35,
        eps_allow: 0.015,
    };

    /// The shear modulus (MPa).
    pub fn shear(&self) -> f64 {
        self.youngs / (2.0 * (1.0 + self.poisson))
    }
}

/// The `[simulation]` settings of a recipe.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// The strip material.
    pub material: Material,
    /// Opening to deploy to (radians), of the held measure; None: the design's.
    pub theta: Option<f64>,
    /// What deployment holds: the mean opening of all cells, or cell 0's.
    pub actuation: Actuation,
    /// Longest interior edge (mm).
    pub h_max: f64,
    /// How rod ends at a shared vertex are joined.
    pub vertex_joint: VertexJoint,
    /// Strips strained beyond eps_allow are accepted by `build`.
    pub accept_overstrain: bool,
    /// A loop lattice's rotational symmetry: the number of identical
    /// copies of its cells around the loop (1: none). Under the mean hold,
    /// every cell then opens as much as its copies (docs/physics.md,
    /// "Deployment").
    pub symmetry: u32,
    /// The most memory the simulation may take (bytes): a mesh estimated
    /// above it is refused before it is made (`sim::estimate`).
    pub memory: u64,
    /// Vertices held at their design positions (`[simulation] supports`),
    /// each as its key `[row, column]` (row 0 on a helix): pins to a
    /// table or base. Empty: the lattice stands free, cell 0's pivot
    /// anchored. Checked against the grown lattice by `Design::grow`: at
    /// least three, not all on one line.
    pub supports: Vec<[u32; 2]>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            material: Material::ABS,
            theta: None,
            actuation: Actuation::Mean,
            h_max: 10.0,
            vertex_joint: VertexJoint::Eyelet,
            accept_overstrain: false,
            symmetry: 1,
            memory: DEFAULT_MEMORY,
            supports: Vec::new(),
        }
    }
}

/// The measure a maker holds while the rest of the lattice finds its
/// equilibrium (docs/physics.md, "Deployment").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Actuation {
    /// The mean opening of all cells: every cell may open more or less.
    Mean,
    /// The opening of the first cell (R00-C00), the others free.
    FirstCell,
}

impl Actuation {
    /// How reports name the held opening.
    pub fn describe(self) -> &'static str {
        match self {
            Actuation::Mean => "mean opening of all cells",
            Actuation::FirstCell => "opening of the first cell",
        }
    }
}

/// How rod ends at a shared vertex are joined (docs/physics.md, "Eyelets").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexJoint {
    /// Centre lines meet and faces stay stacked; each strip turns freely
    /// about the eyelet's axis.
    Eyelet,
    /// Position only (the ideal linkage's spherical joint).
    Ball,
}

impl VertexJoint {
    /// The recipe's name for it (`[simulation] vertex_joint`): `eyelet` or `ball`.
    pub fn name(self) -> &'static str {
        match self {
            VertexJoint::Eyelet => "eyelet",
            VertexJoint::Ball => "ball",
        }
    }
}
