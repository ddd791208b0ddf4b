//! Writers: each turns a model into bytes. No writer touches the filesystem.

pub mod deployed;
pub mod dxf;
pub mod lattice_json;
pub mod lbrn2;
mod number;
pub mod obj;
pub mod part_types_csv;
pub mod parts_csv;
pub mod pdf;
pub mod png;
pub mod svg;
pub mod viewer;
