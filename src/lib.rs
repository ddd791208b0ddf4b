//! karigami: grow scissor lattices from TOML recipes, verify them, and turn
//! them into fabrication files. Data flows one way:
//! design -> lattice -> parts -> layout -> drawing -> bytes.
//! Everything here is pure; only the binary touches files and the terminal.

pub mod design;
pub mod diagnostic;
pub mod geometry;
pub mod lattice;
pub mod report;
pub mod write;
