//! Writers: each turns a model into bytes. No writer touches the filesystem.

pub(crate) mod deployed;
pub mod dxf;
pub(crate) mod lattice_json;
pub mod lbrn2;
mod number;
pub(crate) mod obj;
pub(crate) mod part_types_csv;
pub(crate) mod parts_csv;
pub(crate) mod path_png;
pub(crate) mod pdf;
pub mod png;
mod repeats;
pub mod svg;
pub mod viewer;
