//! Scenes shipped inside the binary, from `scenes/*.ron`.

use crate::scene::error::SceneError;
use crate::scene::file::Scene;
use crate::scene::parse::parse;

/// A scene file compiled into the binary.
#[derive(Clone, Copy, Debug)]
pub struct BuiltinScene {
    /// What `load` and the viewer's scene list call it: the file name without `.ron`.
    pub name: &'static str,
    /// The RON text, as in `scenes/<name>.ron`.
    pub source: &'static str,
}

impl BuiltinScene {
    /// Parses the scene; errors name it as `scenes/<name>.ron`.
    pub fn parse(&self) -> Result<Scene, SceneError> {
        parse(self.source, &format!("scenes/{}.ron", self.name))
    }
}

macro_rules! builtin {
    ($($name:literal),* $(,)?) => {
        &[$(BuiltinScene {
            name: $name,
            source: include_str!(concat!("../../scenes/", $name, ".ron")),
        }),*]
    };
}

const BUILTIN_SCENES: &[BuiltinScene] = builtin![
    "falling_box",
    "pachinko",
    "bounce",
    "stack",
    "pyramid",
    "dzhanibekov",
    "rain",
    "hulls",
    "cradle_strings",
    "chain",
    "rope_bridge",
    "car",
    "door",
    "ragdolls",
    "windmills",
];

/// Every built-in scene, in menu order.
pub fn builtin_scenes() -> &'static [BuiltinScene] {
    BUILTIN_SCENES
}

/// Their names, in menu order.
pub fn builtin_scene_names() -> impl Iterator<Item = &'static str> {
    BUILTIN_SCENES.iter().map(|scene| scene.name)
}

/// The built-in scene called `name`, if there is one.
pub fn find_builtin(name: &str) -> Option<&'static BuiltinScene> {
    BUILTIN_SCENES.iter().find(|scene| scene.name == name)
}
