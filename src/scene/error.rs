//! Scene errors. Every message starts with the file, then names what is wrong as precisely as
//! it can: the body (by name, or by index when it has none), the field, and the value.

use thiserror::Error;

/// Why a scene could not be loaded or built. `file` is the scene's origin (its path as
/// given, or `scenes/<name>.ron` for a built-in one); the message starts with it.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SceneError {
    /// Raised by `load_file` when the file is missing, not a regular file, larger than
    /// `input_file::MAX_INPUT_BYTES` or not UTF-8.
    #[error("{file}: cannot read: {message}")]
    Read {
        /// The path as given.
        file: String,
        /// The operating system's reason, or which of those checks failed.
        message: String,
    },

    /// Raised by `parse` when the text does not read as a scene: RON syntax, a wrong type,
    /// an unknown or missing field. `body` and `field` are filled when the error lies inside
    /// one.
    #[error("{file}:{line}:{column}: {}{message}", describe(.body, .field))]
    Format {
        /// The scene's origin.
        file: String,
        /// Where the parser stopped, counted from 1.
        line: usize,
        /// Where on that line, in characters, counted from 1.
        column: usize,
        /// `'name'`, or `#index` when the body has no name or it cannot be read.
        body: Option<String>,
        /// Path to the value, inside the body if there is one: `shape.half_extents.x`.
        field: Option<String>,
        /// What the parser expected or found.
        message: String,
    },

    /// A scene-level value is out of bounds: `settings.dt`, `camera.eye`,
    /// `forces[1].coefficient`, `name`.
    #[error("{file}: field '{field}': {message}")]
    Field {
        /// The scene's origin.
        file: String,
        /// Path to the value, components included: `camera.eye.x`.
        field: String,
        /// What is wrong, with the value found.
        message: String,
    },

    /// A material of `materials` has a bad `density` (not positive), `restitution` (outside
    /// [0, 1]) or `friction` (outside [0, `MAX_FRICTION`]). Inline materials are reported as
    /// `Body` errors on `material.…`.
    #[error("{file}: material '{material}' field '{field}': {message}")]
    Material {
        /// The scene's origin.
        file: String,
        /// Its key in `materials`.
        material: String,
        /// `density`, `restitution` or `friction`.
        field: String,
        /// What is wrong, with the value found.
        message: String,
    },

    /// A body's value is invalid: a shape dimension, a rotation, a non-finite vector, an unknown material,
    /// a mass that is not positive, a generator, or a mass or momentum that overflows.
    /// `body` is `'name'`, or `#index` (position in `bodies`) for an unnamed body. Errors in a
    /// generator template name the template.
    #[error("{file}: body {body} field '{field}': {message}")]
    Body {
        /// The scene's origin.
        file: String,
        /// `'name'` or `#index`.
        body: String,
        /// Path to the value inside the body: `shape.parts[2].shape.radius`.
        field: String,
        /// What is wrong, with the value found.
        message: String,
    },

    /// A joint cannot be made: a body name that names no body or several, a non-finite
    /// anchor, a zero axis, limits out of order, an option its kind does not have, or any
    /// other `JointError` of the engine. `joint` is `'name'`, or `#index` (position in
    /// `joints`); a joint of a `Chain` is `'name'[k]`, the k-th joint it makes (the pin first).
    #[error("{file}: joint {joint} field '{field}': {message}")]
    Joint {
        /// The scene's origin.
        file: String,
        /// `'name'`, `#index`, or either followed by `[k]` for a chain's k-th joint.
        joint: String,
        /// Path to the value inside the joint: `kind.axis`, `body_b`, `limits`.
        field: String,
        /// What is wrong, with the value found.
        message: String,
    },

    /// The bodies, generators expanded, outnumber `MAX_BODIES`; checked before any is built.
    #[error("{file}: {count} bodies after generators, more than the limit of {limit}")]
    TooManyBodies {
        /// The scene's origin.
        file: String,
        /// Bodies the scene would make (saturating at `u64::MAX`).
        count: u64,
        /// `MAX_BODIES`.
        limit: usize,
    },

    /// Raised by `load` when the name is neither a built-in scene nor the path of an
    /// existing file.
    #[error("no built-in scene is named '{name}' and no such file exists (built-in: {available})")]
    UnknownScene {
        /// The name or path asked for.
        name: String,
        /// The built-in scene names, comma-separated.
        available: String,
    },
}

fn describe(body: &Option<String>, field: &Option<String>) -> String {
    match (body, field) {
        (Some(body), Some(field)) => format!("body {body} field '{field}': "),
        (Some(body), None) => format!("body {body}: "),
        (None, Some(field)) => format!("field '{field}': "),
        (None, None) => String::new(),
    }
}

/// How an error names a body: `'crate_3'`, or `#3` when the body has no name.
pub(crate) fn body_label(name: &str, index: usize) -> String {
    if name.is_empty() {
        format!("#{index}")
    } else {
        format!("'{name}'")
    }
}

/// A bad value found while checking one body or material, before the file and body are known
/// to the checking function; the caller adds them.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FieldError {
    pub field: String,
    pub message: String,
}

impl FieldError {
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        FieldError {
            field: field.into(),
            message: message.into(),
        }
    }

    /// The same error one level down: `radius` inside `shape` becomes `shape.radius`.
    pub fn within(self, prefix: &str) -> Self {
        FieldError {
            field: format!("{prefix}.{}", self.field),
            ..self
        }
    }

    pub fn in_body(self, file: &str, body: &str) -> SceneError {
        SceneError::Body {
            file: file.to_owned(),
            body: body.to_owned(),
            field: self.field,
            message: self.message,
        }
    }

    pub fn in_joint(self, file: &str, joint: &str) -> SceneError {
        SceneError::Joint {
            file: file.to_owned(),
            joint: joint.to_owned(),
            field: self.field,
            message: self.message,
        }
    }

    pub fn in_material(self, file: &str, material: &str) -> SceneError {
        SceneError::Material {
            file: file.to_owned(),
            material: material.to_owned(),
            field: self.field,
            message: self.message,
        }
    }

    pub fn in_scene(self, file: &str) -> SceneError {
        SceneError::Field {
            file: file.to_owned(),
            field: self.field,
            message: self.message,
        }
    }
}
