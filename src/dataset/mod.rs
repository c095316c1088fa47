//! Dataset loading.
