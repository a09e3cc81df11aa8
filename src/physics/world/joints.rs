//! The world's joints: adding, removing and reading them, and what they tie together (the
//! islands they link, the pairs whose collision they switch off).

use std::collections::HashSet;

use super::World;
use crate::physics::collision::broad_phase::BodyPair;
use crate::physics::dynamics::body::BodyId;
use crate::physics::joints::desc::{JointDesc, JointDrives, JointError, JointId, JointKind};
use crate::physics::joints::joint::Joint;

/// What the joints tie together: grown joint by joint as joints are added, derived from the
/// joint list again when one is removed.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct JointLinks {
    /// The slots of each joint's bodies, for the islands: joined bodies sleep and wake
    /// together.
    links: Vec<(u32, u32)>,
    /// Slots of joined bodies that do not collide (`JointDesc::collide_connected` off), lower
    /// first.
    unjoined: HashSet<(u32, u32)>,
}

impl JointLinks {
    pub(super) fn of(joints: &[Option<Joint>]) -> JointLinks {
        let mut links = JointLinks::default();
        for joint in joints.iter().flatten() {
            links.add(joint);
        }
        links
    }

    /// Takes in one more joint: adding joints one by one costs each the same, where deriving
    /// the links again made building a scene of n joints cost n².
    fn add(&mut self, joint: &Joint) {
        let (a, b) = (joint.body_a.index() as u32, joint.body_b.index() as u32);
        self.links.push((a, b));
        if !joint.collide_connected {
            self.unjoined.insert((a.min(b), a.max(b)));
        }
    }

    pub(super) fn links(&self) -> &[(u32, u32)] {
        &self.links
    }

    /// Takes out of the broad phase's pairs those of joined bodies that do not collide.
    pub(super) fn drop_unjoined_pairs(&self, pairs: &mut Vec<BodyPair>) {
        if !self.unjoined.is_empty() {
            let slots = |p: &BodyPair| (p.a.index() as u32, p.b.index() as u32);
            pairs.retain(|p| !self.unjoined.contains(&slots(p)));
        }
    }
}

impl World {
    /// Joins two bodies as they are now (anchors and axes in world coordinates). Refused, with
    /// the world unchanged, for a body that does not exist or no longer takes part, the same
    /// body twice, two bodies neither of which is dynamic, and what `JointDesc::validate`
    /// refuses.
    pub fn add_joint(&mut self, desc: JointDesc) -> Result<JointId, JointError> {
        desc.validate()?;
        for id in [desc.body_a, desc.body_b] {
            match self.get_body(id) {
                None => return Err(JointError::NoSuchBody(id.0)),
                Some(body) if !body.motion.takes_part() => {
                    return Err(JointError::BodyGone(id.0));
                }
                Some(_) => {}
            }
        }
        let (a, b) = (
            &self.bodies[desc.body_a.index()],
            &self.bodies[desc.body_b.index()],
        );
        if !a.is_dynamic() && !b.is_dynamic() {
            return Err(JointError::NoDynamicBody);
        }
        let joint = Joint::new(&desc, a, b);
        let id = JointId(self.joints.len() as u32);
        self.joint_links.add(&joint);
        self.joints.push(Some(joint));
        self.wake_joined(&[desc.body_a, desc.body_b]);
        Ok(id)
    }

    /// Removes a joint; its bodies wake.
    pub fn remove_joint(&mut self, id: JointId) -> Result<(), JointError> {
        let slot = self.joints.get_mut(id.0 as usize);
        let Some(joint) = slot.and_then(Option::take) else {
            return Err(JointError::NoSuchJoint(id.0));
        };
        self.joints_changed(&[joint.body_a, joint.body_b]);
        Ok(())
    }

    /// Changes what drives joint `id` (its motor, servo and spring) while the world runs;
    /// its bodies wake. Refused, with the joint unchanged, for what `JointDesc::validate`
    /// refuses of them, and for a spring on a rod (a distance joint made with neither limits
    /// nor a spring, which its length holds rigidly: `Joint::limits`).
    pub fn set_joint_drives(&mut self, id: JointId, drives: JointDrives) -> Result<(), JointError> {
        let Some(joint) = self.joints.get_mut(id.0 as usize).and_then(Option::as_mut) else {
            return Err(JointError::NoSuchJoint(id.0));
        };
        drives.check(joint.kind)?;
        let rod =
            joint.kind == JointKind::Distance && joint.limits.is_some_and(|(lo, hi)| lo == hi);
        if rod && drives.spring.is_some() {
            return Err(JointError::Unsupported("spring on a rod"));
        }
        (joint.motor, joint.servo, joint.spring) = (drives.motor, drives.servo, drives.spring);
        let bodies = [joint.body_a, joint.body_b];
        self.wake_joined(&bodies);
        Ok(())
    }

    /// The joint `id` (with the reaction of the last step), or None if there is no such
    /// joint or it was removed.
    pub fn joint(&self, id: JointId) -> Option<&Joint> {
        self.joints.get(id.0 as usize)?.as_ref()
    }

    /// Every joint that is still there, with its id.
    pub fn joints(&self) -> impl Iterator<Item = (JointId, &Joint)> {
        (self.joints.iter().enumerate())
            .filter_map(|(k, j)| j.as_ref().map(|j| (JointId(k as u32), j)))
    }

    /// The joints that broke in the last step (their reaction exceeded their
    /// `JointDesc::breaking` load): they are out of the world, and their ids refused.
    pub fn broken_joints(&self) -> &[JointId] {
        &self.broken_joints
    }

    /// Takes out the joints whose reaction in this step exceeded their breaking load.
    pub(super) fn break_overloaded_joints(&mut self) {
        self.broken_joints.clear();
        let mut bodies = Vec::new();
        for (k, slot) in self.joints.iter_mut().enumerate() {
            if slot.is_some_and(|j| j.overloaded()) {
                let joint = slot.take().expect("checked");
                bodies.extend([joint.body_a, joint.body_b]);
                self.broken_joints.push(JointId(k as u32));
            }
        }
        if !bodies.is_empty() {
            self.joints_changed(&bodies);
        }
    }

    /// How many joints the world holds.
    pub fn joint_count(&self) -> usize {
        self.joint_links.links.len()
    }

    /// Removes the joints of body `index` (the body is being removed).
    pub(super) fn remove_joints_of(&mut self, index: usize) {
        let mut bodies = Vec::new();
        for slot in &mut self.joints {
            if slot.is_some_and(|j| j.holds(index)) {
                let joint = slot.take().expect("checked");
                bodies.extend([joint.body_a, joint.body_b]);
            }
        }
        if !bodies.is_empty() {
            self.joints_changed(&bodies);
        }
    }

    /// The links are derived again, and the joined bodies woken and looked at again.
    fn joints_changed(&mut self, bodies: &[BodyId]) {
        self.joint_links = JointLinks::of(&self.joints);
        self.wake_joined(bodies);
    }

    /// Bodies whose joints changed wake and are looked at again.
    fn wake_joined(&mut self, bodies: &[BodyId]) {
        for id in bodies {
            let body = &mut self.bodies[id.index()];
            if body.sleeping {
                body.wake();
            }
            self.awake_set.touch(id.index());
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::JointLinks;
    use crate::physics::dynamics::body::BodyDesc;
    use crate::physics::geometry::shape::Shape;
    use crate::physics::joints::desc::JointDesc;
    use crate::physics::world::World;

    /// The links grown joint by joint are the ones derived from the whole list, through
    /// adds and removals.
    #[test]
    fn links_grown_joint_by_joint_are_the_links_of_the_list() {
        let mut world = World::default();
        let ids: Vec<_> = (0..6)
            .map(|k| {
                let desc = BodyDesc::dynamic(Shape::sphere(0.25)).at(DVec3::X * k as f64);
                world.add_body(desc).expect("a valid ball")
            })
            .collect();
        let mut joints = Vec::new();
        for (k, pair) in ids.windows(2).enumerate() {
            let desc = JointDesc::ball(pair[0], pair[1], DVec3::X * (k as f64 + 0.5));
            joints.push(
                world
                    .add_joint(desc.colliding(k % 2 == 0))
                    .expect("a valid joint"),
            );
            assert_eq!(world.joint_links, JointLinks::of(&world.joints));
        }
        assert_eq!(
            world.joint_links.unjoined.len(),
            2,
            "joints 1 and 3 do not collide"
        );
        world.remove_joint(joints[1]).expect("joint 1 exists");
        assert_eq!(world.joint_links, JointLinks::of(&world.joints));
        assert_eq!(world.joint_count(), 4);
        let desc = JointDesc::distance(ids[0], ids[5], DVec3::ZERO, DVec3::X * 5.0);
        world.add_joint(desc).expect("a valid joint");
        assert_eq!(world.joint_links, JointLinks::of(&world.joints));
    }
}
