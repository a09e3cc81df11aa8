//! Generators: the copies a `Repeat` makes of a body template, as (name suffix, offset).

use glam::DVec3;

use crate::scene::error::FieldError;
use crate::scene::file::Repeat;
use crate::scene::validate;

/// How many bodies a template makes, without building them (used against `MAX_BODIES`
/// before any memory is spent). Saturating: three u32 counts can overflow even u64.
pub(crate) fn count(repeat: Option<&Repeat>) -> u64 {
    match repeat {
        None => 1,
        Some(Repeat::Grid { count, .. }) => {
            (count.0 as u64 * count.1 as u64).saturating_mul(count.2 as u64)
        }
        Some(Repeat::Pyramid { layers, .. }) => {
            let layers = *layers as u64;
            layers * (layers + 1) / 2
        }
    }
}

pub(crate) fn check(repeat: &Repeat) -> Result<(), FieldError> {
    match *repeat {
        Repeat::Grid {
            count,
            spacing,
            stagger,
        } => {
            for (axis, n) in ["x", "y", "z"].iter().zip([count.0, count.1, count.2]) {
                if n == 0 {
                    return Err(FieldError::new(
                        format!("count.{axis}"),
                        "must be at least 1, got 0",
                    ));
                }
            }
            validate::vector("spacing", spacing)?;
            validate::vector("stagger", stagger)
        }
        Repeat::Pyramid { layers, spacing } => {
            if layers == 0 {
                return Err(FieldError::new("layers", "must be at least 1, got 0"));
            }
            validate::finite("spacing.0", spacing.0)?;
            validate::finite("spacing.1", spacing.1)
        }
    }
}

/// Offsets from the template's position, in generation order. A body without `repeat` is a
/// single copy at offset zero; its name is then left as written.
pub(crate) fn offsets(repeat: Option<&Repeat>) -> Vec<DVec3> {
    match repeat {
        None => vec![DVec3::ZERO],
        Some(Repeat::Grid {
            count,
            spacing,
            stagger,
        }) => grid(*count, *spacing, *stagger),
        Some(Repeat::Pyramid { layers, spacing }) => pyramid(*layers, *spacing),
    }
}

fn grid(count: (u32, u32, u32), spacing: DVec3, stagger: DVec3) -> Vec<DVec3> {
    let mut offsets = Vec::new();
    for j in 0..count.1 {
        let shift = if j % 2 == 1 { stagger } else { DVec3::ZERO };
        for k in 0..count.2 {
            for i in 0..count.0 {
                let index = DVec3::new(i as f64, j as f64, k as f64);
                offsets.push(index * spacing + shift);
            }
        }
    }
    offsets
}

fn pyramid(layers: u32, spacing: (f64, f64)) -> Vec<DVec3> {
    let mut offsets = Vec::new();
    for layer in 0..layers {
        for i in 0..layers - layer {
            let x = (i as f64 + layer as f64 / 2.0) * spacing.0;
            offsets.push(DVec3::new(x, layer as f64 * spacing.1, 0.0));
        }
    }
    offsets
}
