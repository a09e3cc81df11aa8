//! Bodies and their motion without contacts: the report's state, environmental forces,
//! time integration, and the islands that fall asleep together.

pub(crate) mod awake_set;
pub mod body;
pub(crate) mod containment;
pub mod forces;
pub mod integrate;
pub(crate) mod islands;
pub(crate) mod slots;
pub(crate) mod union_find;
