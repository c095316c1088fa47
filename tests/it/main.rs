//! Integration tests: the crate's modules working together, driven through the library and the
//! `contphy-eval` binary.

#![expect(
    clippy::unwrap_used,
    clippy::expect_used,
    reason = "integration tests fail by panicking, helpers included"
)]

mod architecture;
mod cli;
mod exec;
mod pipeline;
mod shards;
mod support;
