//! Integration tests: the crate's modules working together, driven through the library and the
//! `contphy-eval` binary.

#![expect(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "integration tests fail by panicking, helpers included"
)]

mod api_spec;
mod architecture;
mod cli;
mod cloth;
mod exec;
mod fluid;
mod frames;
mod generate;
mod llm;
mod llm_run;
mod perception;
mod pipeline;
mod prompt;
mod shards;
mod support;
mod unchanged;
mod view;
