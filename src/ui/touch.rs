//! Touch input, for phones and tablets (the browser gives touches, not mouse events): one
//! finger does what the left mouse button does (pushes the body under it, or orbits), two
//! fingers pinch to zoom and move together to pan. A third finger is ignored.

use glam::Vec2;
use smallvec::SmallVec;
use winit::event::TouchPhase;

/// What the touches ask of the viewer, in the mouse's terms where there is one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Gesture {
    /// The pointer is here now (as a mouse moving).
    Point(Vec2),
    /// The left button goes down at the pointer.
    Press,
    /// The left button comes up.
    Release,
    /// Zoom by this many wheel steps (`Camera::zoom`).
    Zoom(f32),
    /// Pan by this many pixels (`Camera::pan`).
    Pan(Vec2),
}

/// The fingers down on the view.
#[derive(Debug, Default)]
pub struct Touches {
    /// Up to two fingers: their ids and positions, pixels.
    fingers: SmallVec<[(u64, Vec2); 2]>,
    /// Set once a second finger lands, until every finger is lifted: a finger left over
    /// from a pinch neither pushes nor orbits.
    pinched: bool,
}

impl Touches {
    /// The gestures a touch event makes. `over_panel`: it started on the panel, which
    /// handles it (only its end is followed, in case it is one of ours).
    pub fn on_touch(
        &mut self,
        id: u64,
        phase: TouchPhase,
        position: Vec2,
        over_panel: bool,
    ) -> SmallVec<[Gesture; 2]> {
        let mut gestures = SmallVec::new();
        let finger = self.fingers.iter().position(|&(f, _)| f == id);
        match (phase, finger) {
            (TouchPhase::Started, None) if !over_panel => self.land(id, position, &mut gestures),
            (TouchPhase::Moved, Some(k)) => self.slide(k, position, &mut gestures),
            (TouchPhase::Ended | TouchPhase::Cancelled, Some(k)) => {
                self.fingers.remove(k);
                if self.fingers.is_empty() {
                    if !self.pinched {
                        gestures.push(Gesture::Release);
                    }
                    self.pinched = false;
                }
            }
            _ => {}
        }
        gestures
    }

    fn land(&mut self, id: u64, position: Vec2, gestures: &mut SmallVec<[Gesture; 2]>) {
        match self.fingers.len() {
            0 => {
                self.fingers.push((id, position));
                gestures.extend([Gesture::Point(position), Gesture::Press]);
            }
            1 => {
                // The first finger's push or orbit ends where the pinch begins.
                self.fingers.push((id, position));
                if !self.pinched {
                    gestures.push(Gesture::Release);
                }
                self.pinched = true;
            }
            _ => {}
        }
    }

    fn slide(&mut self, k: usize, position: Vec2, gestures: &mut SmallVec<[Gesture; 2]>) {
        let moved_from = std::mem::replace(&mut self.fingers[k].1, position);
        match (self.fingers.as_slice(), self.pinched) {
            ([_], false) => gestures.push(Gesture::Point(position)),
            (&[(_, a1), (_, b1)], _) => {
                let [a0, b0] = if k == 0 {
                    [moved_from, b1]
                } else {
                    [a1, moved_from]
                };
                let (spread_before, spread) = (a0.distance(b0), a1.distance(b1));
                if spread_before > 0.0 && spread > 0.0 {
                    // Fingers twice as far apart show the scene twice as large.
                    let steps = (spread / spread_before).ln() / (1.0f32 / 0.9).ln();
                    gestures.push(Gesture::Zoom(steps));
                }
                gestures.push(Gesture::Pan((a1 + b1) / 2.0 - (a0 + b0) / 2.0));
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::OrbitCamera;

    fn touch(touches: &mut Touches, id: u64, phase: TouchPhase, x: f32, y: f32) -> Vec<Gesture> {
        touches
            .on_touch(id, phase, Vec2::new(x, y), false)
            .into_vec()
    }

    /// One finger is the left mouse button: down where it lands, moving, up.
    #[test]
    fn one_finger_presses_moves_and_releases() {
        let mut touches = Touches::default();
        let start = touch(&mut touches, 7, TouchPhase::Started, 10.0, 20.0);
        assert_eq!(
            start,
            [Gesture::Point(Vec2::new(10.0, 20.0)), Gesture::Press]
        );
        let moved = touch(&mut touches, 7, TouchPhase::Moved, 15.0, 18.0);
        assert_eq!(moved, [Gesture::Point(Vec2::new(15.0, 18.0))]);
        assert_eq!(
            touch(&mut touches, 7, TouchPhase::Ended, 15.0, 18.0),
            [Gesture::Release]
        );
        // A touch this viewer never took up does nothing.
        assert!(touch(&mut touches, 8, TouchPhase::Moved, 1.0, 1.0).is_empty());
    }

    /// Two fingers spreading from 100 to 200 px apart halve the camera's distance (the
    /// scene looks twice as large), and their midpoint's slide pans; the finger left after
    /// the pinch neither pushes nor orbits, and a third finger is ignored.
    #[test]
    fn a_pinch_zooms_by_the_ratio_of_the_spreads_and_pans_with_the_midpoint() {
        let mut touches = Touches::default();
        let mut gestures = touch(&mut touches, 1, TouchPhase::Started, 100.0, 100.0);
        gestures.extend(touch(&mut touches, 2, TouchPhase::Started, 200.0, 100.0));
        assert_eq!(gestures.last(), Some(&Gesture::Release));
        assert!(touch(&mut touches, 3, TouchPhase::Started, 0.0, 0.0).is_empty());
        let mut camera = OrbitCamera {
            target: glam::Vec3::ZERO,
            distance: 10.0,
            yaw: 0.0,
            pitch: 0.3,
        };
        let distance = camera.distance;
        let mut panned = Vec2::ZERO;
        // In ten moves of each finger, 50 px outward each: 100 to 200 px apart.
        for k in 1..=10 {
            let out = 5.0 * k as f32;
            for (id, x) in [(1, 100.0 - out), (2, 200.0 + out)] {
                for gesture in touch(&mut touches, id, TouchPhase::Moved, x, 100.0 + k as f32) {
                    match gesture {
                        Gesture::Zoom(steps) => camera.zoom(steps),
                        Gesture::Pan(delta) => panned += delta,
                        other => panic!("{other:?} during a pinch"),
                    }
                }
            }
        }
        let ratio = camera.distance / distance;
        assert!((ratio - 0.5).abs() < 1e-5, "distance × {ratio}");
        assert!(
            (panned - Vec2::new(0.0, 10.0)).length() < 1e-4,
            "panned {panned}"
        );
        assert!(touch(&mut touches, 1, TouchPhase::Ended, 50.0, 110.0).is_empty());
        assert!(touch(&mut touches, 2, TouchPhase::Moved, 260.0, 110.0).is_empty());
        assert!(touch(&mut touches, 2, TouchPhase::Ended, 260.0, 110.0).is_empty());
        // All lifted: the next finger is a press again.
        let again = touch(&mut touches, 4, TouchPhase::Started, 5.0, 5.0);
        assert_eq!(again, [Gesture::Point(Vec2::new(5.0, 5.0)), Gesture::Press]);
    }

    /// A touch that starts on the panel is the panel's.
    #[test]
    fn a_touch_on_the_panel_is_left_to_it() {
        let mut touches = Touches::default();
        let on_panel = touches.on_touch(1, TouchPhase::Started, Vec2::ONE, true);
        assert!(on_panel.is_empty());
        assert!(touch(&mut touches, 1, TouchPhase::Moved, 9.0, 9.0).is_empty());
        assert!(touch(&mut touches, 1, TouchPhase::Ended, 9.0, 9.0).is_empty());
    }
}
