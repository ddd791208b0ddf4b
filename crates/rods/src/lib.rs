//! The inner loop of karigami's elastic simulation (karigami's
//! docs/physics.md): discrete elastic rods joined by eyelets, their energy
//! and its exact gradient and Hessian by second-order dual numbers, and
//! the modified Newton solver on a sparse Cholesky (`sparse`, `solver`).
//!
//! A crate of its own so that it can be compiled optimised in the test
//! profile (the dual-number arithmetic is about 30 times slower
//! unoptimised), like the picture crates.

pub mod adjoint;
pub mod dual;
pub mod frames;
pub mod model;
pub mod rng;
pub mod solver;
pub mod sparse;
