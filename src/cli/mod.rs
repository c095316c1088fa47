//! Placeholder for the `cli` module; filled in by issue 2 work in progress.
