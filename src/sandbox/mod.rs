//! The sandbox (work in progress on this branch: scene bindings only).

mod scene_host;
