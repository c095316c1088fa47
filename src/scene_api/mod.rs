//! Placeholder for the `scene_api` module; filled in by issue 2 work in progress.
