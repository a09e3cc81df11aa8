//! A body's material: either the name of a scene material or an inline material.
//!
//! Written by hand rather than as an untagged enum so that a typo inside an inline material
//! reports the offending field instead of "data did not match any variant".

use std::fmt;

use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde::{Deserialize, de::value::MapAccessDeserializer};

use crate::physics::Material;

/// A body's `material` field: a name or an inline material; omitted, the engine's default
/// (density 1000 kg/m³, restitution 0.3, friction 0.5).
#[derive(Clone, Debug, PartialEq)]
pub enum MaterialRef {
    /// `material: "rubber"`: a key of the scene's `materials`.
    Named(String),
    /// `material: (density: 7800, restitution: 0.5, friction: 0.4)`.
    Inline(Material),
}

impl Default for MaterialRef {
    fn default() -> Self {
        MaterialRef::Inline(Material::default())
    }
}

impl<'de> Deserialize<'de> for MaterialRef {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(MaterialRefVisitor)
    }
}

struct MaterialRefVisitor;

impl<'de> Visitor<'de> for MaterialRefVisitor {
    type Value = MaterialRef;

    fn expecting(&self, formatter: &mut fmt::Formatter) -> fmt::Result {
        formatter
            .write_str("a material name or an inline (density: …, restitution: …, friction: …)")
    }

    fn visit_str<E: de::Error>(self, name: &str) -> Result<MaterialRef, E> {
        Ok(MaterialRef::Named(name.to_owned()))
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<MaterialRef, A::Error> {
        Material::deserialize(MapAccessDeserializer::new(map)).map(MaterialRef::Inline)
    }
}
