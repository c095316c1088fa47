//! Placeholder for the `program` module; filled in by issue 2 work in progress.
