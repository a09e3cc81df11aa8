//! Live plots of the history the simulation keeps: energy, momentum and the deepest contact
//! overlap against sim time.

use egui_plot::{Corner, Legend, Line, Plot, PlotPoints};

use crate::sim::HistorySample;

const PLOT_HEIGHT: f32 = 110.0;

/// Kinetic, potential and total energy (J) against sim time (s).
pub fn energy(ui: &mut egui::Ui, history: &[HistorySample]) {
    plot(
        ui,
        "energy",
        history,
        &[
            ("kinetic", |s| s.kinetic_energy),
            ("potential", |s| s.potential_energy),
            ("total", |s| s.kinetic_energy + s.potential_energy),
        ],
    );
}

/// The magnitudes of the total linear (kg·m/s) and angular (kg·m²/s) momentum against sim
/// time (s).
pub fn momentum(ui: &mut egui::Ui, history: &[HistorySample]) {
    plot(
        ui,
        "momentum",
        history,
        &[
            ("|p| linear", |s| s.linear_momentum),
            ("|L| angular", |s| s.angular_momentum),
        ],
    );
}

/// The deepest contact overlap (mm), from the step before each sample, against sim time (s).
pub fn penetration(ui: &mut egui::Ui, history: &[HistorySample]) {
    plot(
        ui,
        "penetration",
        history,
        &[("max overlap (mm)", |s| s.max_penetration * 1e3)],
    );
}

type Series = (&'static str, fn(&HistorySample) -> f64);

fn plot(ui: &mut egui::Ui, id: &str, history: &[HistorySample], series: &[Series]) {
    Plot::new(id)
        .height(PLOT_HEIGHT)
        .legend(
            Legend::default()
                .position(Corner::LeftTop)
                .background_alpha(0.5),
        )
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .show(ui, |plot_ui| {
            for (name, value) in series {
                let points: PlotPoints = history.iter().map(|s| [s.time, value(s)]).collect();
                plot_ui.line(Line::new(*name, points));
            }
        });
}
