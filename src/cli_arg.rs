//! Command-line values the binaries share.

use std::ffi::OsStr;

use clap::builder::TypedValueParser;
use clap::error::ErrorKind;

/// Parses a text argument (a scene name or path) and, when it is not valid UTF-8, says which
/// argument, where clap's own check names none.
#[derive(Clone, Copy, Debug)]
pub struct Utf8Text;

impl TypedValueParser for Utf8Text {
    type Value = String;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<String, clap::Error> {
        value.to_str().map(str::to_owned).ok_or_else(|| {
            let name = arg.map_or_else(|| "an argument".to_owned(), |a| a.to_string());
            let message = format!("{name} is not valid UTF-8: '{}'\n", value.to_string_lossy());
            clap::Error::raw(ErrorKind::InvalidUtf8, message).with_cmd(cmd)
        })
    }
}
