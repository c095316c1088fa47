//! Integration tests: the crate's modules working together, driven through the library and the
//! `contphy-eval` binary.

mod architecture;
mod cli;
mod exec;
mod pipeline;
mod support;
