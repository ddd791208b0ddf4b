//! One integration-test binary (fewer link steps on small machines).

mod cli;
mod cutfiles;
mod deploy;
mod design;
mod errors;
mod finding;
mod fuzz;
mod gallery;
mod golden;
mod goldens;
mod guide;
mod layers;
mod maker;
mod property;
mod rebuild;
mod report_once;
mod safety;
mod shape;
mod sim;
mod targets;
mod thirdparty;
mod util;
mod viewer;
mod workflow;
