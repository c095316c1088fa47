//! Placeholder for the `report` module; filled in by issue 2 work in progress.
