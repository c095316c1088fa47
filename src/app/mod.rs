//! Placeholder for the `app` module; filled in by issue 2 work in progress.
