//! Contact solvers. `soft`: substepped soft constraints (the default pipeline). `classic`:
//! the report's time-ordered impulses, with `toi` finding the times of impact. Both share
//! the impulse geometry; the soft solver's packed arithmetic (`lanes`), its dense view of the
//! bodies (`solver_bodies`) and the colouring that spreads it over threads (`contact_colors`)
//! are its own.

pub mod classic;
pub mod contact_colors;
pub(crate) mod impulse;
pub(crate) mod lanes;
pub mod soft;
pub(crate) mod solver_bodies;
pub mod toi;
