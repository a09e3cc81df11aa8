//! What the viewer saves and loads: the world's snapshot plus what only the viewer knows
//! about it (the scene it came from, which bodies the scene hides, its material names).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::physics::WorldSnapshot;

/// A saved world file (RON), as `Command::SaveWorld` writes it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SavedWorld {
    /// The built-in scene name or scene file path the world came from: loading takes the
    /// camera from it when it still builds, and `Reset` afterwards rebuilds it.
    pub scene: String,
    /// The fixed step the world was running at, s.
    pub dt: f64,
    /// By body index; bodies past the end are drawn.
    pub hidden: Vec<bool>,
    /// By body index, the scene's material names (absent in worlds saved before they were).
    #[serde(default)]
    pub materials: Vec<String>,
    /// The engine's whole state: time, settings, forces and bodies (see `WorldSnapshot`).
    pub world: WorldSnapshot,
}

impl SavedWorld {
    /// Writes the file to `path`, leaving the old file whole if the write fails; the error
    /// names the path.
    pub fn save(&self, path: &Path) -> Result<(), String> {
        let config = ron::ser::PrettyConfig::new().depth_limit(4);
        let text = ron::ser::to_string_pretty(self, config).expect("a saved world is plain data");
        crate::output_file::write_atomically(path, &text)
            .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Reads and checks a saved world (see `WorldSnapshot::check`).
    pub fn load(path: &Path) -> Result<SavedWorld, String> {
        let file = path.display().to_string();
        let text = crate::input_file::read_text(path).map_err(|e| format!("{file}: {e}"))?;
        let saved: SavedWorld = ron::from_str(&text).map_err(|e| format!("{file}: {e}"))?;
        saved.world.check(&file).map_err(|e| e.to_string())?;
        if !(saved.dt.is_finite() && saved.dt > 0.0) {
            return Err(format!("{file}: dt must be positive, got {}", saved.dt));
        }
        Ok(saved)
    }
}
