//! Writers: each turns a model into bytes. No writer touches the filesystem.

pub mod lattice_json;
