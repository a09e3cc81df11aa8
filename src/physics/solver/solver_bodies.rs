//! The soft solver's view of the bodies: the momenta and poses of the awake bodies in one
//! dense array, gathered from the bodies before a pass over the contacts and written back
//! after it. Contacts then address two small neighbouring records by slot instead of two
//! large bodies by index, and need no "does it move" test on every impulse.
//!
//! Slot 0 stands for every body that does not move in this step (static, asleep): zero
//! momenta and inverse mass, never written.
//!
//! A kinematic body has a slot of its own: contacts and joints must see its velocity, and
//! nothing they do may change it. Its slot holds its velocities times `KINEMATIC_SCALE` as
//! momenta, with the inverse mass (and inverse inertia, `spin_of_momentum`) 1/`KINEMATIC_SCALE`:
//! a power of two, so the velocities read back exactly. The impulses the contacts give it
//! change that velocity by less than 10⁻¹⁹ of themselves within a substep; they are dropped
//! when the substep starts again from the body's own velocity, and are never written back.
//! The effective masses of its contacts and joints take its inverse mass as zero.
//!
//! The slots are padded with copies of slot 0 to a power of two, so that a pass can keep
//! every slot it is handed within them with one mask (`SharedBodies::get`) instead of a
//! bounds check and its panic path, about six per contact point in every pass
//! (BENCHMARKS.md, "Solver slots").

use std::marker::PhantomData;

use glam::{DMat3, DVec3};

use crate::physics::dynamics::body::{Motion, RigidBody};
use crate::physics::solver::lanes::{F64x4, LaneVector, Lanes};

/// The part of a body that a pass over the contacts reads and changes, as lanes (see
/// `lanes`): matrices by columns. What every pass reads comes first.
#[derive(Clone, Copy, Debug)]
pub struct SolverBody {
    pub linear_momentum: F64x4,
    pub angular_momentum: F64x4,
    pub inv_mass: f64,
    /// The linear momentum by which this substep's deep contacts push the body out
    /// (`soft::push_out`): **integrate positions** moves the body by it, at
    /// most `max_push_out` fast, and its velocity keeps none of it. In the padding after
    /// `inv_mass`, beside what the contacts read anyway.
    pub push_out: DVec3,
    pub position: F64x4,
    pub orientation: [F64x4; 3],
    /// The linear and angular impulse the body's contacts give it at the next warm start.
    pub warm_start: [F64x4; 2],
    /// The momenta before this substep's warm start: what the contacts have added since is
    /// the next substep's warm start (`store_warm_start`).
    pub before_contacts: [F64x4; 2],
    /// The linear and angular impulse the body's joints give it at the next warm start,
    /// along their directions where the last relax pass left the bodies (`joints::solve`).
    pub joints_warm_start: [F64x4; 2],
}

// The push-out fills the padding after `inv_mass`: the record is no larger for it.
const _: () = assert!(std::mem::size_of::<SolverBody>() == 13 * 32);

impl SolverBody {
    /// The velocity of the push-out (see `push_out`).
    #[inline(always)]
    pub fn push_out_velocity(&self) -> DVec3 {
        self.push_out * self.inv_mass
    }

    /// Moves the body by this substep's push-out, `h` long and at most `max_speed` fast,
    /// and clears it.
    #[inline(always)]
    fn move_out(&mut self, body: &mut RigidBody, max_speed: f64, h: f64) {
        let velocity = self.push_out_velocity();
        self.push_out = DVec3::ZERO;
        if body.is_kinematic() {
            return; // its path is scripted
        }
        let speed = velocity.length();
        body.position += velocity * (h * (max_speed / speed).min(1.0));
    }

    /// Writes the momenta the contacts changed back to the body.
    #[inline(always)]
    fn write_momenta(&self, body: &mut RigidBody) {
        if body.is_kinematic() {
            return; // its scaled velocities are the solver's alone
        }
        body.linear_momentum = self.linear_momentum.to_vec3();
        body.angular_momentum = self.angular_momentum.to_vec3();
    }
}

/// A body whose spin a soft step limits (`SolverBodies::limit_spins`): its slot, and the
/// angular momentum, kg·m²/s, below which it cannot spin faster than the limit.
#[derive(Clone, Copy, Debug)]
pub struct SpinGuard {
    pub slot: u32,
    pub momentum: f64,
}

/// What a kinematic body's slot scales its velocities by (see the module comment).
pub const KINEMATIC_SCALE: f64 = 18_446_744_073_709_551_616.0; // 2^64

/// The slot that every body which does not move shares.
pub const FIXED_SLOT: u32 = 0;

const FIXED: SolverBody = SolverBody {
    linear_momentum: F64x4::ZERO,
    angular_momentum: F64x4::ZERO,
    inv_mass: 0.0,
    position: F64x4::ZERO,
    orientation: [F64x4::ZERO; 3],
    warm_start: [F64x4::ZERO; 2],
    before_contacts: [F64x4::ZERO; 2],
    joints_warm_start: [F64x4::ZERO; 2],
    push_out: DVec3::ZERO,
};

/// Slots of the awake bodies, kept between steps so that no step allocates.
#[derive(Clone, Debug, Default)]
pub struct SolverBodies {
    /// Slot k ≥ 1 holds awake body `awake[k − 1]`; then padding (see the module comment).
    pub slots: Vec<SolverBody>,
    awake: Vec<u32>,
    /// The slot of each body index, `FIXED_SLOT` for bodies without one. Only the entries of
    /// the awake bodies are ever set, and they are cleared again by `release`, so idle
    /// bodies cost nothing here.
    slot_of: Vec<u32>,
}

impl SolverBodies {
    /// Gives each of the `awake` bodies (indices into `bodies`) a slot and gathers it.
    pub fn assign(&mut self, bodies: &[RigidBody], awake: &[u32]) {
        if self.slot_of.len() < bodies.len() {
            self.slot_of.resize(bodies.len(), FIXED_SLOT);
        }
        self.awake.clear();
        self.awake.extend_from_slice(awake);
        self.slots.clear();
        self.slots.push(FIXED);
        for (k, &index) in awake.iter().enumerate() {
            self.slot_of[index as usize] = k as u32 + 1;
            self.slots.push(gathered(&bodies[index as usize]));
        }
        self.slots
            .resize(self.slots.len().next_power_of_two(), FIXED);
    }

    /// The slots in use: the fixed one and one per awake body.
    pub fn count(&self) -> usize {
        self.awake.len() + 1
    }

    /// Forgets the slots of this step.
    pub fn release(&mut self) {
        for &index in &self.awake {
            self.slot_of[index as usize] = FIXED_SLOT;
        }
    }

    pub fn slot_of(&self, index: usize) -> u32 {
        self.slot_of[index]
    }

    /// Adds a contact's impulse on each of its bodies to their next warm start; nothing to
    /// `FIXED_SLOT`, which is never written.
    #[inline(always)]
    pub fn add_warm_start<L: Lanes>(&mut self, l: L, pushes: [Push<L::Vector>; 2]) {
        for push in pushes {
            if push.slot != FIXED_SLOT {
                let body = &mut self.slots[push.slot as usize];
                body.warm_start[0] = (l.load(body.warm_start[0]) + push.linear).store();
                body.warm_start[1] = (l.load(body.warm_start[1]) + push.angular).store();
            }
        }
    }

    /// Starts a substep (**integrate velocities**, **warm start**): `integrate` changes the
    /// momenta of each awake body (the forces; it gets the body's place in `awake`), then the
    /// slot reads them and applies the warm start, the joints' share and then the
    /// contacts', remembering the momenta before the contacts' share. One loop over the
    /// bodies, not three.
    #[inline(always)]
    pub fn integrate_velocities_and_warm_start(
        &mut self,
        bodies: &mut [RigidBody],
        mut integrate: impl FnMut(usize, &mut RigidBody),
    ) {
        for (k, (slot, &index)) in self.slots[1..].iter_mut().zip(&self.awake).enumerate() {
            let body = &mut bodies[index as usize];
            if body.is_kinematic() {
                *slot = gathered(body);
                continue;
            }
            integrate(k, body);
            // The joints' share first: it is not the contacts' (see `before_contacts`).
            let [joint_linear, joint_angular] = slot.joints_warm_start;
            slot.before_contacts = [
                F64x4::from_vec3(body.linear_momentum) + joint_linear,
                F64x4::from_vec3(body.angular_momentum) + joint_angular,
            ];
            slot.joints_warm_start = [F64x4::ZERO; 2];
            let [linear, angular] = slot.warm_start;
            slot.linear_momentum = slot.before_contacts[0] + linear;
            slot.angular_momentum = slot.before_contacts[1] + angular;
        }
    }

    /// Slows each guarded body whose angular momentum passes its guard and that spins
    /// faster than `max_spin`, rad/s, to that speed. The change is kept out of the warm
    /// start, which holds only what the contacts gave.
    pub fn limit_spins(&mut self, bodies: &[RigidBody], guards: &[SpinGuard], max_spin: f64) {
        for guard in guards {
            let slot = &mut self.slots[guard.slot as usize];
            let momentum = slot.angular_momentum.to_vec3();
            if momentum.length_squared() <= guard.momentum * guard.momentum {
                continue;
            }
            let body = &bodies[self.awake[guard.slot as usize - 1] as usize];
            let spin = (body.inv_inertia_world * momentum).length();
            if spin > max_spin {
                let removed = momentum * (1.0 - max_spin / spin);
                slot.angular_momentum = F64x4::from_vec3(momentum - removed);
                let before = slot.before_contacts[1].to_vec3();
                slot.before_contacts[1] = F64x4::from_vec3(before - removed);
            }
        }
    }

    /// **Integrate positions**: writes the momenta back to each awake body, lets `integrate`
    /// move it, moves it by its push-out (at most `max_push_out` fast over the substep `h`),
    /// and reads its new pose: one loop over the bodies.
    #[inline(always)]
    pub fn integrate_positions(
        &mut self,
        bodies: &mut [RigidBody],
        (max_push_out, h): (f64, f64),
        mut integrate: impl FnMut(&mut RigidBody),
    ) {
        for (slot, &index) in self.slots[1..].iter_mut().zip(&self.awake) {
            let body = &mut bodies[index as usize];
            slot.write_momenta(body);
            integrate(body);
            if slot.push_out != DVec3::ZERO {
                slot.move_out(body, max_push_out, h);
            }
            slot.position = F64x4::from_vec3(body.position);
            slot.orientation = columns(&body.orientation);
        }
    }

    /// Ends a substep (**store impulses**): writes the momenta back to the bodies and, when another substep
    /// follows, takes what the contacts gave each body as its warm start. Every contact's
    /// final impulse is its warm start plus what the passes added, and the momenta changed
    /// by nothing else since `integrate_velocities_and_warm_start`: so the change in momenta is the sum of
    /// the final impulses, found per body rather than per contact (which cost two more body
    /// updates per contact point in every relax pass).
    pub fn store_warm_start(&mut self, bodies: &mut [RigidBody], warm_start_next: bool) {
        for (slot, &index) in self.slots[1..].iter_mut().zip(&self.awake) {
            if warm_start_next {
                let [linear, angular] = slot.before_contacts;
                slot.warm_start = [
                    slot.linear_momentum - linear,
                    slot.angular_momentum - angular,
                ];
            }
            let body = &mut bodies[index as usize];
            slot.write_momenta(body);
        }
    }

    /// Writes the momenta the contacts changed back to the bodies.
    pub fn write_back(&self, bodies: &mut [RigidBody]) {
        for (slot, &index) in self.slots[1..].iter().zip(&self.awake) {
            let body = &mut bodies[index as usize];
            slot.write_momenta(body);
        }
    }
}

impl SolverBodies {
    /// What turns a body's slot's angular momentum into its spin: I⁻¹ in world axes at
    /// step start for a dynamic body, 1/`KINEMATIC_SCALE` for a kinematic one (see the
    /// module comment); zero for one that does not move.
    #[inline(always)]
    pub fn spin_of_momentum(body: &RigidBody) -> DMat3 {
        match body.motion {
            Motion::Dynamic => body.inv_inertia_world,
            Motion::Kinematic => DMat3::from_diagonal(DVec3::splat(1.0 / KINEMATIC_SCALE)),
            _ => DMat3::ZERO,
        }
    }
}

fn gathered(body: &RigidBody) -> SolverBody {
    if body.is_kinematic() {
        return SolverBody {
            linear_momentum: F64x4::from_vec3(body.kinematic_velocity * KINEMATIC_SCALE),
            angular_momentum: F64x4::from_vec3(body.kinematic_spin * KINEMATIC_SCALE),
            inv_mass: 1.0 / KINEMATIC_SCALE,
            ..gathered_at_rest(body)
        };
    }
    gathered_at_rest(body)
}

fn gathered_at_rest(body: &RigidBody) -> SolverBody {
    SolverBody {
        linear_momentum: F64x4::from_vec3(body.linear_momentum),
        angular_momentum: F64x4::from_vec3(body.angular_momentum),
        inv_mass: body.inv_mass,
        position: F64x4::from_vec3(body.position),
        orientation: columns(&body.orientation),
        warm_start: [F64x4::ZERO; 2],
        before_contacts: [F64x4::ZERO; 2],
        joints_warm_start: [F64x4::ZERO; 2],
        push_out: DVec3::ZERO,
    }
}

fn columns(matrix: &DMat3) -> [F64x4; 3] {
    [0, 1, 2].map(|k| F64x4::from_vec3(matrix.col(k)))
}

/// The solver bodies, open to the contacts of one colour on several threads at once.
///
/// Contacts of one colour share no moving body (`contact_colors`), so while a colour is
/// solved each slot but `FIXED_SLOT` is read and written by one thread only, and
/// `FIXED_SLOT` is only read. That is the whole safety argument for the raw pointer below:
/// no slot is ever reachable from two threads while one of them writes it.
#[derive(Clone, Copy)]
pub struct SharedBodies<'a> {
    slots: *mut SolverBody,
    /// The number of slots less one; the number is a power of two.
    mask: usize,
    _borrow: PhantomData<&'a mut [SolverBody]>,
}

// SAFETY: see the type's comment; the colouring keeps threads on disjoint slots.
unsafe impl Send for SharedBodies<'_> {}
unsafe impl Sync for SharedBodies<'_> {}

impl<'a> SharedBodies<'a> {
    /// `slots` as `SolverBodies` pads them: a power of two of them.
    ///
    /// # Safety
    ///
    /// While the result (or a copy) is used from several threads at once, no two of them may
    /// reach the same moving slot: each thread's contacts address slots no other thread's
    /// contacts address, as the contacts of one colour do. `FIXED_SLOT` is only read.
    pub unsafe fn new(slots: &'a mut [SolverBody]) -> Self {
        assert!(slots.len().is_power_of_two(), "{} slots", slots.len());
        SharedBodies {
            slots: slots.as_mut_ptr(),
            mask: slots.len() - 1,
            _borrow: PhantomData,
        }
    }

    /// The slot `slot` within the slots (every slot a contact holds is: `SolverBodies`
    /// hands them out).
    #[inline(always)]
    fn within(&self, slot: u32) -> usize {
        let index = slot as usize & self.mask;
        debug_assert_eq!(index, slot as usize, "slot {slot} out of range");
        index
    }

    #[inline(always)]
    pub fn get(&self, slot: u32) -> &SolverBody {
        // SAFETY: `within` is at most the mask, so in range; no other thread writes this
        // slot (see the type's comment), and this thread does not write it while the
        // reference lives (`add` takes no borrow).
        unsafe { &*self.slots.add(self.within(slot)) }
    }

    /// A moving body's slot; None for `FIXED_SLOT`, which is never written.
    #[inline(always)]
    #[allow(clippy::mut_from_ref)] // the colouring makes this slot this thread's alone
    fn moving(&self, slot: u32) -> Option<&mut SolverBody> {
        if slot == FIXED_SLOT {
            return None;
        }
        // SAFETY: in range (`within`), and only this thread reaches this slot in this colour;
        // the reference is used for one update and dropped before the slot is reached again.
        Some(unsafe { &mut *self.slots.add(self.within(slot)) })
    }

    /// Adds an impulse to a moving body's momenta; does nothing for `FIXED_SLOT`.
    #[inline(always)]
    pub fn add<L: Lanes>(&self, l: L, push: Push<L::Vector>) {
        if let Some(body) = self.moving(push.slot) {
            body.linear_momentum = (l.load(body.linear_momentum) + push.linear).store();
            body.angular_momentum = (l.load(body.angular_momentum) + push.angular).store();
        }
    }

    /// Adds an impulse to a moving body's push-out (`SolverBody::push_out`; see `add`).
    #[inline(always)]
    pub fn add_push_out(&self, slot: u32, impulse: DVec3) {
        if let Some(body) = self.moving(slot) {
            body.push_out += impulse;
        }
    }
}

/// An impulse on one body at a contact: its linear part and its moment about the centre of
/// mass.
#[derive(Clone, Copy, Debug)]
pub struct Push<V> {
    pub slot: u32,
    pub linear: V,
    pub angular: V,
}
