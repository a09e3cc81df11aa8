//! Record and replay. The simulation logs every command it applies with the tick (fixed steps
//! taken since it started) at which it was applied. Stepping is deterministic, so applying
//! the same commands at the same ticks to the same scene reproduces the run bit for bit,
//! whatever the wall clock, frame rate or machine load were while it was recorded.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::sim::command::Command;

/// A command and the tick before which it was applied.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordedCommand {
    /// Fixed steps the run had taken when the command was applied, counted from its start
    /// across resets and scene loads.
    pub tick: u64,
    /// What was applied.
    pub command: Command,
}

/// A run as a scene and the commands applied to it; `ticks` is how long it ran.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Recording {
    /// The scene the run started with: a built-in name or a scene file path.
    pub scene: String,
    /// Fixed steps the run took; no command may have a later tick.
    pub ticks: u64,
    /// In tick order; commands of the same tick in the order they were applied.
    pub commands: Vec<RecordedCommand>,
}

impl Recording {
    /// The recording as the RON text `save` writes.
    pub fn to_ron(&self) -> String {
        let config = ron::ser::PrettyConfig::new().depth_limit(2);
        ron::ser::to_string_pretty(self, config).expect("a recording is plain data")
    }

    /// Parses a recording; `file` names it in errors. Commands must be in tick order.
    pub fn from_ron(text: &str, file: &str) -> Result<Recording, String> {
        let recording: Recording = ron::from_str(text).map_err(|e| format!("{file}: {e}"))?;
        let in_order = recording
            .commands
            .windows(2)
            .all(|w| w[0].tick <= w[1].tick);
        if !in_order {
            return Err(format!("{file}: commands are not in tick order"));
        }
        if let Some(late) = recording.commands.iter().find(|c| c.tick > recording.ticks) {
            return Err(format!(
                "{file}: a command at tick {} comes after the end (tick {})",
                late.tick, recording.ticks
            ));
        }
        Ok(recording)
    }

    /// Writes the recording to `path`, leaving the old file whole if the write fails; the
    /// error names the path.
    pub fn save(&self, path: &Path) -> Result<(), String> {
        crate::output_file::write_atomically(path, &self.to_ron())
            .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Reads and checks a recording file (see `from_ron`); errors name the file.
    pub fn load(path: &Path) -> Result<Recording, String> {
        let file = path.display().to_string();
        let text = crate::input_file::read_text(path).map_err(|e| format!("{file}: {e}"))?;
        Recording::from_ron(&text, &file)
    }
}
