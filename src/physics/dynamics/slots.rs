//! Generational ids: each body slot has a generation, raised when its body is removed, and
//! removed slots are handed out again, lowest first. A world that adds and removes bodies
//! forever keeps as many slots as it ever held at once, and the id of a removed body never
//! names the body that took its slot.

use crate::physics::dynamics::body::{BodyId, Motion, RigidBody};

#[derive(Clone, Debug, Default)]
pub struct Slots {
    /// Per slot: the generation its current id carries.
    generations: Vec<u32>,
    /// Removed slots that may be reused, in descending order so that `pop` gives the lowest
    /// (the same slot whatever order they were freed in: a restored world reuses as the
    /// original does).
    free: Vec<u32>,
}

impl Slots {
    /// The slots of restored `bodies` at `generations` (empty for a snapshot written before
    /// generations: its removed bodies get generation 1, so their old ids stay refused).
    pub fn restored(generations: Vec<u32>, bodies: &[RigidBody]) -> Self {
        let removed = |i: usize| bodies[i].motion == Motion::Removed;
        let generations = if generations.is_empty() {
            (0..bodies.len()).map(|i| removed(i) as u32).collect()
        } else {
            generations
        };
        let free = (0..bodies.len())
            .rev()
            .filter(|&i| removed(i) && generations[i] < BodyId::MAX_GENERATION)
            .map(|i| i as u32)
            .collect();
        Slots { generations, free }
    }

    pub fn generations(&self) -> &[u32] {
        &self.generations
    }

    /// A removed slot to reuse, if there is one, with the id its new body gets.
    pub fn reuse(&mut self) -> Option<BodyId> {
        let index = self.free.pop()? as usize;
        Some(self.current(index))
    }

    /// The id of a new slot at the end.
    pub fn push(&mut self) -> BodyId {
        self.generations.push(0);
        BodyId::new(self.generations.len() - 1, 0)
    }

    /// Slot `index` lost its body: its old id is refused from now on, and the slot is
    /// reused unless its generations are spent.
    pub fn release(&mut self, index: usize) {
        self.generations[index] += 1;
        if self.generations[index] < BodyId::MAX_GENERATION {
            let at = self.free.partition_point(|&f| f as usize > index);
            self.free.insert(at, index as u32);
        }
    }

    /// The id slot `index` answers to now.
    pub fn current(&self, index: usize) -> BodyId {
        BodyId::new(index, self.generations[index])
    }

    /// Whether `id` names the body in its slot now (not a removed one, nor another world's).
    pub fn is_current(&self, id: BodyId) -> bool {
        self.generations.get(id.index()) == Some(&id.generation())
    }
}
