//! One integration-test binary (fewer link steps on small machines).

mod errors;
mod cli;
mod golden;
mod property;
mod util;
