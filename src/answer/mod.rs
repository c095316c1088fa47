//! Placeholder for the `answer` module; filled in by issue 2 work in progress.
