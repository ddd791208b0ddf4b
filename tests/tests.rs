//! One integration-test binary (fewer link steps on small machines).

mod cli;
mod cutfiles;
mod deploy;
mod errors;
mod fuzz;
mod gallery;
mod golden;
mod guide;
mod property;
mod thirdparty;
mod util;
mod workflow;
mod sim;
