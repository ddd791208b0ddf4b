//! One integration-test binary (fewer link steps on small machines).

mod cli;
mod errors;
mod golden;
mod property;
mod util;
