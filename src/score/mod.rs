//! Placeholder for the `score` module; filled in by issue 2 work in progress.
