//! Writing the files users keep (saved worlds, snapshots, recordings, images) so that a
//! failed write never costs the file that was there: the output goes to a temporary file
//! beside it, which replaces the old one only once it is whole on disk.

use std::fs::File;
use std::io::{BufWriter, Error, ErrorKind, Write};
use std::path::{Path, PathBuf};

/// Writes `text` to `path` through a temporary file in the same folder, renamed over `path`
/// once written and synced. On any error the temporary file is removed and `path` is left
/// as it was.
pub fn write_atomically(path: &Path, text: &str) -> Result<(), Error> {
    write_atomically_with(path, |file| file.write_all(text.as_bytes()))
}

/// As `write_atomically`, for output made as it is written (images, animations): `write`
/// fills the temporary file, and its error leaves `path` as it was.
pub fn write_atomically_with<E: From<Error>>(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<(), E>,
) -> Result<(), E> {
    let temporary = temporary_beside(path)?;
    let written = write_synced(&temporary, write)
        .and_then(|()| std::fs::rename(&temporary, path).map_err(E::from));
    if written.is_err() {
        // Best effort: the error that matters is the write's.
        let _ = std::fs::remove_file(&temporary);
    }
    written
}

/// `.NAME.tmp` beside `path`.
fn temporary_beside(path: &Path) -> Result<PathBuf, Error> {
    let name = path
        .file_name()
        .ok_or_else(|| Error::new(ErrorKind::InvalidInput, "the path names no file"))?;
    let mut temporary_name = std::ffi::OsString::from(".");
    temporary_name.push(name);
    temporary_name.push(".tmp");
    Ok(path.with_file_name(temporary_name))
}

fn write_synced<E: From<Error>>(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<(), E>,
) -> Result<(), E> {
    let mut file = BufWriter::new(File::create(path)?);
    write(&mut file)?;
    file.into_inner().map_err(|e| e.into_error())?.sync_all()?;
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A folder of the test process's own under the system's temporary one, made if missing;
    /// `name` tells the tests apart (they share the process).
    pub(crate) fn scratch_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("rigid-output-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// Asserts that `dir` holds one entry, the file a write made: no temporary was left.
    pub(crate) fn assert_only_one_file(dir: &std::path::Path) {
        let left: Vec<_> = std::fs::read_dir(dir).unwrap().collect();
        assert_eq!(left.len(), 1, "a temporary file was left: {left:?}");
    }

    #[test]
    fn a_write_replaces_the_file_and_leaves_no_temporary() {
        let dir = scratch_dir("replace");
        let path = dir.join("world.ron");
        std::fs::write(&path, "old").unwrap();
        write_atomically(&path, "new").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        assert_only_one_file(&dir);
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// A write that cannot complete (here the target is a folder, so the rename fails after
    /// the text was written) leaves what was at the path and no temporary file.
    #[test]
    fn a_failed_write_keeps_what_was_there() {
        let dir = scratch_dir("failed");
        let path = dir.join("taken");
        std::fs::create_dir(&path).unwrap();
        std::fs::write(path.join("inside"), "kept").unwrap();
        assert!(write_atomically(&path, "new").is_err());
        assert_eq!(
            std::fs::read_to_string(path.join("inside")).unwrap(),
            "kept"
        );
        assert!(!dir.join(".taken.tmp").exists());
        std::fs::remove_dir_all(dir).unwrap();
    }
}
