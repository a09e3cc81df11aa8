//! The window: the egui control panel with plots, mouse picking and pushing, and the event
//! loop that ties the simulation thread and the renderer together.
//!
//! Reading order: `app` (event loop and frame) → `panel` → `plots`; `picking` → `drag`,
//! `inspector` and `aim`.

pub mod aim;
pub mod app;
pub mod display;
pub mod drag;
pub mod inspector;
pub mod panel;
pub mod picking;
pub mod plots;
pub mod touch;
