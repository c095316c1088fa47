//! Placeholder for the `sandbox` module; filled in by issue 2 work in progress.
