//! RON text → `Scene`, turning serde's errors into ones that say which body and field.

use std::fmt;

use serde::Deserialize;
use serde::de::{Deserializer, IgnoredAny, MapAccess, Visitor};
use serde_path_to_error::{Path, Segment};

use crate::scene::error::{SceneError, body_label};
use crate::scene::file::Scene;

/// `mass: 2.0` instead of `mass: Some(2.0)`, `repeat: Grid(…)` instead of `Some(Grid(…))`.
fn options() -> ron::Options {
    ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
}

/// Parses and fully validates a scene. `origin` names the text in error messages (a path).
pub fn parse(text: &str, origin: &str) -> Result<Scene, SceneError> {
    let mut scene = deserialize(text, origin)?;
    scene.origin = origin.to_owned();
    // Building every body and joint description is the validation: the same code builds the
    // world.
    let bodies = scene.body_descs()?;
    scene.joint_descs(&bodies)?;
    scene.body_to_follow(&bodies)?;
    Ok(scene)
}

fn deserialize(text: &str, origin: &str) -> Result<Scene, SceneError> {
    let mut deserializer = ron::Deserializer::from_str_with_options(text, &options())
        .map_err(|error| syntax_error(origin, &error, None))?;
    let scene: Scene = serde_path_to_error::deserialize(&mut deserializer).map_err(|error| {
        let spanned = deserializer.span_error(error.inner().clone());
        syntax_error(origin, &spanned, Some((text, error.path())))
    })?;
    deserializer
        .end()
        .map_err(|error| syntax_error(origin, &deserializer.span_error(error), None))?;
    Ok(scene)
}

fn syntax_error(
    origin: &str,
    error: &ron::error::SpannedError,
    path: Option<(&str, &Path)>,
) -> SceneError {
    let mut located = Located::default();
    if let Some((text, path)) = path {
        located = locate(text, path);
    }
    let mut message = error.code.to_string();
    // Name an unknown or missing field in the field slot, where a reader looks for it, and drop
    // RON's "in `Struct`" / "in enum `Enum`", which name Rust types, not anything in the file.
    match &error.code {
        ron::Error::NoSuchStructField { found, .. } => {
            located.end_with_field(found);
            let expected = message.split_once(", ").map_or("", |(_, rest)| rest);
            message = format!("unknown field, {expected}");
        }
        ron::Error::NoSuchEnumVariant { found, .. } => {
            let expected = message.split_once(", ").map_or("", |(_, rest)| rest);
            message = format!("unknown variant `{found}`, {expected}");
        }
        ron::Error::MissingStructField { field, .. } => {
            located.end_with_field(field);
            message = "missing".to_owned();
        }
        ron::Error::DuplicateStructField { field, .. } => {
            located.end_with_field(field);
            message = "given twice".to_owned();
        }
        _ => {}
    }
    SceneError::Format {
        file: origin.to_owned(),
        line: error.span.start.line,
        column: error.span.start.col,
        body: located.body,
        field: located.field,
        message,
    }
}

#[derive(Default)]
struct Located {
    body: Option<String>,
    field: Option<String>,
}

impl Located {
    /// Appends `name` to the field path unless the path already ends with it (serde's path
    /// includes an unknown key, but not a missing one).
    fn end_with_field(&mut self, name: &str) {
        self.field = Some(match self.field.take() {
            Some(path) if path == name || path.ends_with(&format!(".{name}")) => path,
            Some(prefix) => format!("{prefix}.{name}"),
            None => name.to_owned(),
        });
    }
}

/// Splits a serde path such as `bodies[3].shape.Cuboid.half_extents[0]` into the body
/// (`#3`, or its name) and the field (`shape.half_extents[0]`; enum variant names dropped).
fn locate(text: &str, path: &Path) -> Located {
    let segments: Vec<&Segment> = path.iter().collect();
    let (body, rest) = match segments.as_slice() {
        [Segment::Map { key }, Segment::Seq { index }, rest @ ..] if key == "bodies" => {
            (Some(body_name(text, *index)), rest)
        }
        _ => (None, segments.as_slice()),
    };
    let field = render_field(rest);
    Located {
        body,
        field: (!field.is_empty()).then_some(field),
    }
}

/// Fields that hold a `DVec3`, written `(x, y, z)`: their elements are named `.x`, `.y`, `.z`.
const VECTOR_FIELDS: &[&str] = &[
    "position",
    "velocity",
    "angular_velocity",
    "half_extents",
    "spacing",
    "stagger",
    "eye",
    "target",
    "acceleration",
    "axis",
    "angle_axis",
    "anchor",
    "anchor_a",
    "anchor_b",
    "linear",
    "angular",
];

fn render_field(segments: &[&Segment]) -> String {
    let mut field = String::new();
    for (at, segment) in segments.iter().enumerate() {
        let previous = at.checked_sub(1).map(|i| segments[i]);
        match segment {
            Segment::Map { key } => {
                if !field.is_empty() {
                    field.push('.');
                }
                field.push_str(key);
            }
            Segment::Seq { index } if *index < 3 && in_vector(previous, at, segments) => {
                field.push_str([".x", ".y", ".z"][*index]);
            }
            Segment::Seq { index } => field.push_str(&format!("[{index}]")),
            Segment::Enum { .. } | Segment::Unknown => {}
        }
    }
    field
}

/// Whether the element at `segments[at]` is a component of a vector: directly under a vector
/// field, or a point of a hull (`points[i]`).
fn in_vector(previous: Option<&Segment>, at: usize, segments: &[&Segment]) -> bool {
    match previous {
        Some(Segment::Map { key }) => VECTOR_FIELDS.contains(&key.as_str()),
        Some(Segment::Seq { .. }) => {
            matches!(at.checked_sub(2).map(|i| segments[i]), Some(Segment::Map { key }) if key == "points")
        }
        _ => false,
    }
}

/// The body's label for an error at `bodies[index]`: its name when a lenient second reading
/// of the file (which ignores everything but the names) can find it, else its index.
fn body_name(text: &str, index: usize) -> String {
    #[derive(Deserialize)]
    #[serde(rename = "Scene")]
    struct Names {
        #[serde(default)]
        bodies: Vec<Name>,
    }
    let name = options()
        .from_str::<Names>(text)
        .ok()
        .and_then(|names| names.bodies.into_iter().nth(index))
        .map(|body| body.0)
        .unwrap_or_default();
    body_label(&name, index)
}

/// A body's first `name`, every other field skipped unread, so that a body whose error is a
/// second `name` (or any other field given twice) is still named.
struct Name(String);

impl<'de> Deserialize<'de> for Name {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct FirstName;
        impl<'de> Visitor<'de> for FirstName {
            type Value = Name;

            fn expecting(&self, formatter: &mut fmt::Formatter) -> fmt::Result {
                formatter.write_str("a body")
            }

            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Name, A::Error> {
                let mut name = None;
                while let Some(key) = map.next_key::<String>()? {
                    if key == "name" && name.is_none() {
                        name = Some(map.next_value::<String>()?);
                    } else {
                        map.next_value::<IgnoredAny>()?;
                    }
                }
                Ok(Name(name.unwrap_or_default()))
            }
        }
        deserializer.deserialize_struct("BodySpec", &["name"], FirstName)
    }
}
