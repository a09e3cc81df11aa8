//! GPU rendering.
