//! Record and replay. The simulation logs every command it applies with the tick (fixed steps
//! taken since it started) at which it was applied. Stepping is deterministic, so applying
//! the same commands at the same ticks to the same scene reproduces the run bit for bit,
//! whatever the wall clock, frame rate or machine load were while it was recorded.

use std::path::Path;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::sim::command::Command;

/// Most ticks a recording may run: 48 days of a session at a 1/240 s step. A replay has no
/// other end, and `ticks` of 10¹² once replayed for ever.
pub const MAX_RECORDING_TICKS: u64 = 1_000_000_000;

/// Whether a replay may run the commands that read or write files they name (`SaveWorld`,
/// `SaveRecording`, `LoadWorld`, `LoadScene` of a file): a recording can come from anyone,
/// and replaying it must not overwrite or read the user's files unless asked to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileCommands {
    /// Refuse a recording that holds any (the default of the command-line tools).
    Refuse,
    /// Run them as recorded (`--allow-file-commands`).
    Allow,
}

/// Why a recording cannot be read or replayed; `file` names it as the caller did.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum RecordingError {
    /// The file cannot be read or does not parse.
    #[error("{file}: {message}")]
    Unreadable {
        /// The recording's name.
        file: String,
        /// The reader's or parser's error.
        message: String,
    },
    /// Commands out of tick order, or one after the recording's end.
    #[error("{file}: {message}")]
    Ticks {
        /// The recording's name.
        file: String,
        /// Which order is broken.
        message: String,
    },
    /// A command holds a value the simulation cannot run with (see `Command::check`).
    #[error("{file}: command {index} ({command}, tick {tick}): {message}")]
    BadCommand {
        /// The recording's name.
        file: String,
        /// Its position in `commands`, from 0.
        index: usize,
        /// The command's variant.
        command: &'static str,
        /// The tick it was recorded at.
        tick: u64,
        /// What is wrong with its value.
        message: String,
    },
    /// A command that reads or writes a file, in a replay that did not allow them.
    #[error(
        "{file}: command {index} ({command}, tick {tick}) would access the file '{target}'; \
         replaying never touches files unless allowed (--allow-file-commands)"
    )]
    FileCommand {
        /// The recording's name.
        file: String,
        /// Its position in `commands`, from 0.
        index: usize,
        /// The command's variant.
        command: &'static str,
        /// The tick it was recorded at.
        tick: u64,
        /// The path it names.
        target: String,
    },
    /// `ticks` is more than `MAX_RECORDING_TICKS`.
    #[error(
        "{file}: field 'ticks': {ticks}, more than MAX_RECORDING_TICKS ({MAX_RECORDING_TICKS})"
    )]
    TooLong {
        /// The recording's name.
        file: String,
        /// The ticks it asks for.
        ticks: u64,
    },
    /// The scene the recording starts from cannot be built.
    #[error("{file}: {message}")]
    Scene {
        /// The recording's name.
        file: String,
        /// The scene's error.
        message: String,
    },
}

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

    /// Parses a recording; `file` names it in errors. Commands must be in tick order and
    /// hold values the simulation can run with (see `check`); whether its file commands may
    /// run is decided when it is replayed.
    pub fn from_ron(text: &str, file: &str) -> Result<Recording, RecordingError> {
        let recording: Recording = ron::from_str(text).map_err(|e| RecordingError::Unreadable {
            file: file.to_string(),
            message: e.to_string(),
        })?;
        recording.check(file, FileCommands::Allow)?;
        Ok(recording)
    }

    /// At most `MAX_RECORDING_TICKS` ticks, commands in tick order, none after `ticks`,
    /// every value runnable, and, unless `files` allows them, no command that reads or
    /// writes a file.
    pub fn check(&self, file: &str, files: FileCommands) -> Result<(), RecordingError> {
        if self.ticks > MAX_RECORDING_TICKS {
            return Err(RecordingError::TooLong {
                file: file.to_string(),
                ticks: self.ticks,
            });
        }
        let ticks = |message: String| RecordingError::Ticks {
            file: file.to_string(),
            message,
        };
        if !self.commands.windows(2).all(|w| w[0].tick <= w[1].tick) {
            return Err(ticks("commands are not in tick order".into()));
        }
        if let Some(late) = self.commands.iter().find(|c| c.tick > self.ticks) {
            return Err(ticks(format!(
                "a command at tick {} comes after the end (tick {})",
                late.tick, self.ticks
            )));
        }
        for (index, recorded) in self.commands.iter().enumerate() {
            let command = &recorded.command;
            command
                .check()
                .map_err(|message| RecordingError::BadCommand {
                    file: file.to_string(),
                    index,
                    command: command.name(),
                    tick: recorded.tick,
                    message,
                })?;
            if let (FileCommands::Refuse, Some(target)) = (files, command.file_named()) {
                return Err(RecordingError::FileCommand {
                    file: file.to_string(),
                    index,
                    command: command.name(),
                    tick: recorded.tick,
                    target,
                });
            }
        }
        Ok(())
    }

    /// Writes the recording to `path`, leaving the old file whole if the write fails; the
    /// error names the path.
    pub fn save(&self, path: &Path) -> Result<(), String> {
        crate::output_file::write_atomically(path, &self.to_ron())
            .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Reads and checks a recording file (see `from_ron`); errors name the file.
    pub fn load(path: &Path) -> Result<Recording, RecordingError> {
        let file = path.display().to_string();
        let text = crate::input_file::read_text(path).map_err(|e| RecordingError::Unreadable {
            file: file.clone(),
            message: e.to_string(),
        })?;
        Recording::from_ron(&text, &file)
    }
}
