//! karigami: grow scissor lattices from TOML recipes, verify them, and turn
//! them into fabrication files. Data flows one way:
//! design -> lattice -> parts -> layout -> drawing -> bytes.
//! Everything here is pure; only the binary touches files and the terminal.

pub mod assembly;
pub mod build;
pub mod design;
pub mod diagnostic;
pub mod drawing;
pub mod fabrication;
pub mod font;
pub mod guide;
pub mod hash;
pub mod lattice;
pub mod layout;
pub mod legs;
pub mod output;
pub mod parts;
pub mod report;
pub mod rng;
pub mod sim;
pub mod solve;
pub mod templates;
pub mod words;
pub mod write;
