//! The reports of a check and a build (not `lattice::Report`, the
//! verification they describe): human-readable text (report.txt, the
//! terminal summary) in `text.rs`, the `--json` reports in `json.rs`.

mod json;
mod text;

pub use json::{build_check_json, build_json, check_json};
pub use text::build_text;
pub use text::{check_text, summary};
