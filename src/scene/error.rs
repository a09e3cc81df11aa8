//! Scene errors. Every message starts with the file, then names what is wrong as precisely as
//! it can: the body (by name, or by index when it has none), the field, and the value.

use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum SceneError {
    #[error("{file}: cannot read: {message}")]
    Read { file: String, message: String },

    /// RON syntax, a wrong type, an unknown or missing field. `body` and `field` are filled
    /// when the error lies inside one.
    #[error("{file}:{line}:{column}: {}{message}", describe(.body, .field))]
    Format {
        file: String,
        line: usize,
        column: usize,
        body: Option<String>,
        field: Option<String>,
        message: String,
    },

    /// A scene-level value: `settings.dt`, `camera.eye`, `forces[1].coefficient`, `name`.
    #[error("{file}: field '{field}': {message}")]
    Field {
        file: String,
        field: String,
        message: String,
    },

    #[error("{file}: material '{material}' field '{field}': {message}")]
    Material {
        file: String,
        material: String,
        field: String,
        message: String,
    },

    /// `body` is `'name'`, or `#index` (position in `bodies`) for an unnamed body. Errors in a
    /// generator template name the template.
    #[error("{file}: body {body} field '{field}': {message}")]
    Body {
        file: String,
        body: String,
        field: String,
        message: String,
    },

    #[error("{file}: {count} bodies after generators, more than the limit of {limit}")]
    TooManyBodies {
        file: String,
        count: u64,
        limit: usize,
    },

    #[error("no built-in scene is named '{name}' and no such file exists (built-in: {available})")]
    UnknownScene { name: String, available: String },
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
