//! Reading the text files users hand in (scenes, saved worlds, recordings): only regular
//! files of sane size, so that a path to a device or a multi-gigabyte file is an error, not a
//! hang or an exhausted memory.

use std::io::{Error, ErrorKind};
use std::path::Path;

/// Largest input file read, bytes. The biggest legitimate input, a saved world of the
/// maximum 100 000 bodies, takes about 200 MB of text.
pub const MAX_INPUT_BYTES: u64 = 256 * 1024 * 1024;

/// The file's text without a leading byte-order mark, or an error when it is not a regular
/// file, is larger than `MAX_INPUT_BYTES` or cannot be read as UTF-8.
pub fn read_text(path: &Path) -> Result<String, Error> {
    let metadata = std::fs::metadata(path)?;
    if !metadata.is_file() {
        return Err(Error::new(ErrorKind::InvalidInput, "not a regular file"));
    }
    if metadata.len() > MAX_INPUT_BYTES {
        let message = format!(
            "{} bytes, more than the {MAX_INPUT_BYTES} read",
            metadata.len()
        );
        return Err(Error::new(ErrorKind::InvalidInput, message));
    }
    let text = std::fs::read_to_string(path)?;
    // Some editors start UTF-8 files with a byte-order mark, which no parser here expects.
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_owned(),
        None => text,
    })
}
