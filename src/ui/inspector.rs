//! The inspector: what the viewer shows beside the cursor about the body under it (or the
//! one being dragged): its name, mass, speed, spin, sleep and contacts.

use crate::sim::snapshot::{BodyState, Snapshot};

/// The lines shown for body `index` of `snapshot`, or None for a body it does not hold.
pub fn inspection(snapshot: &Snapshot, index: usize) -> Option<String> {
    let body = snapshot.bodies.get(index)?;
    let name = match snapshot.names.get(index) {
        Some(name) if !name.is_empty() => name.clone(),
        _ => format!("body {index}"),
    };
    let speeds = format!(
        "{:.3} m/s, {:.3} rad/s",
        body.velocity.length(),
        body.angular_velocity.length()
    );
    let motion = if body.is_dynamic {
        let state = if body.sleeping { "asleep" } else { "awake" };
        format!("{:.3} kg, {state}\n{speeds}", body.mass)
    } else if body.is_kinematic {
        // Moved by its script, whatever pushes on it: its mass is not a number to read.
        format!("kinematic\n{speeds}")
    } else {
        "static".to_string()
    };
    Some(format!("{name}\n{motion}\n{}", contacts(body)))
}

/// The contacts line: a sleeping body's contacts leave the solver until it wakes, so it
/// has none to count.
fn contacts(body: &BodyState) -> String {
    if body.sleeping {
        return "contacts not solved while asleep".to_string();
    }
    let bodies = if body.touching == 1 { "body" } else { "bodies" };
    let points = if body.contact_points == 1 {
        "point"
    } else {
        "points"
    };
    format!(
        "touching {} {bodies} ({} contact {points})",
        body.touching, body.contact_points
    )
}

/// Draws `text` in a small frame just below and right of `cursor` (egui points).
pub fn show(ctx: &egui::Context, cursor: egui::Pos2, text: &str) {
    egui::Area::new(egui::Id::unique("inspector"))
        .order(egui::Order::Tooltip)
        .interactable(false)
        .fixed_pos(cursor + egui::vec2(16.0, 16.0))
        .show(ctx, |ui| {
            egui::Frame::popup(ui.style()).show(ui, |ui| ui.label(text));
        });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::simulation::Simulation;

    /// In the stack of ten boxes on a floor, before it falls asleep (a sleeping pair's
    /// manifold leaves the solver, and then shows no contacts): a middle box touches the box
    /// below and the one above, the top box only the one below, and the floor the bottom
    /// box; each resting face holds four contact points.
    #[test]
    fn the_inspector_names_a_stacked_box_and_its_two_neighbours() {
        let mut sim = Simulation::new("stack").unwrap();
        for _ in 0..30 {
            sim.step();
        }
        let snapshot = sim.snapshot(web_time::Instant::now());
        let index = |name: &str| {
            (snapshot.names.iter())
                .position(|n| n == name)
                .unwrap_or_else(|| panic!("no body {name} in {:?}", snapshot.names))
        };
        let middle = inspection(&snapshot, index("box_4")).unwrap();
        assert!(middle.starts_with("box_4\n600.000 kg, awake\n"), "{middle}");
        assert!(
            middle.contains("touching 2 bodies (8 contact points)"),
            "{middle}"
        );
        let top = inspection(&snapshot, index("box_9")).unwrap();
        assert!(top.contains("touching 1 body (4 contact points)"), "{top}");
        let floor = inspection(&snapshot, index("floor")).unwrap();
        assert!(floor.contains("static\ntouching 1 body"), "{floor}");
        assert_eq!(inspection(&snapshot, snapshot.bodies.len()), None);
    }

    /// A windmill is kinematic, not static: the inspector says so and shows the rate its
    /// script turns it at, 3 rad/s (`scenes/windmills.ron`).
    #[test]
    fn the_inspector_shows_a_windmill_turning() {
        let mut sim = Simulation::new("windmills").unwrap();
        sim.step();
        let snapshot = sim.snapshot(web_time::Instant::now());
        let index = (snapshot.names.iter())
            .position(|n| n == "left_windmill")
            .expect("a left windmill");
        let windmill = inspection(&snapshot, index).unwrap();
        assert!(
            windmill.starts_with("left_windmill\nkinematic\n0.000 m/s, 3.000 rad/s\n"),
            "{windmill}"
        );
    }
}
