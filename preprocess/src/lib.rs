//! Offline pass (skeleton).
