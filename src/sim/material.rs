//! Materials: Table 1 of the paper as presets, and custom materials in a human-readable TOML
//! file (`[[material]]` tables with a `name` and any [`Params`] fields; missing fields take
//! the defaults).

use super::{ParamError, Params};

/// A named parameter set.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Material {
    /// The name panels and rig files use.
    pub name: String,
    /// Its parameters.
    #[serde(flatten)]
    pub params: Params,
}

/// Why a materials file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum MaterialError {
    /// Not TOML, or not a materials file (one line, with the position).
    #[error("{0}")]
    Syntax(String),
    /// A value outside its range.
    #[error("material '{name}': {error}")]
    Range {
        /// The material's name.
        name: String,
        /// Which value, and its range.
        error: ParamError,
    },
    /// A material without a name (its position in the file, from 1).
    #[error("material {0} has an empty name")]
    NoName(usize),
}

fn preset(
    name: &str,
    damping: f32,
    stiffness: f32,
    bone_distance: f32,
    max_length: f32,
) -> Material {
    Material {
        name: name.to_string(),
        params: Params {
            damping,
            stiffness,
            bone_distance,
            max_length,
            ..Params::default()
        },
    }
}

/// Table 1 (C_vd, D, d_B, sl_max). "plastic" has `var` for C_vd and D in the paper: it is
/// static whatever they are; the defaults are used.
pub fn presets() -> Vec<Material> {
    let d = Params::default();
    vec![
        preset("thick skin", 0.7, 1.0, 0.5, 1.3),
        preset("water", 0.99, 1.0, 1.0, 1.4),
        preset("plastic", d.damping, d.stiffness, 0.0, 1.0),
        preset("skin", 0.85, 1.0, 0.2, 1.25),
        preset("tight cloth", 0.85, 0.2, 0.4, 1.35),
    ]
}

#[derive(serde::Serialize, serde::Deserialize)]
struct File {
    material: Vec<Material>,
}

/// Writes materials as TOML.
pub fn write_materials(materials: &[Material]) -> String {
    toml::to_string_pretty(&File {
        material: materials.to_vec(),
    })
    .unwrap_or_default()
}

/// Reads materials from TOML. Values outside the documented ranges are errors (a file is
/// not a slider: silently clamping it would hide a typo).
pub fn parse_materials(text: &str) -> Result<Vec<Material>, MaterialError> {
    let file: File = toml::from_str(text).map_err(|e| {
        MaterialError::Syntax(
            e.to_string()
                .lines()
                .next()
                .unwrap_or("invalid TOML")
                .to_string(),
        )
    })?;
    for (k, m) in file.material.iter().enumerate() {
        if m.name.trim().is_empty() {
            return Err(MaterialError::NoName(k + 1));
        }
        m.params.check().map_err(|error| MaterialError::Range {
            name: m.name.clone(),
            error,
        })?;
    }
    Ok(file.material)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_round_trip_through_toml() {
        let text = write_materials(&presets());
        assert!(text.contains("name = \"thick skin\""));
        assert_eq!(parse_materials(&text).unwrap(), presets());
    }

    #[test]
    fn partial_and_bad_files() {
        let m = parse_materials("[[material]]\nname = \"jelly\"\ndamping = 0.98\n").unwrap();
        assert_eq!(m[0].params.damping, 0.98);
        assert_eq!(m[0].params.stiffness, Params::default().stiffness);
        let e = parse_materials("[[material]]\nname = \"x\"\nmax_length = 0.5\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "material 'x': max_length = 0.5 is outside 1..3"
        );
        assert!(parse_materials("[[material]]\nname = \"x\"\nconstraint = \"glue\"\n").is_err());
        assert!(parse_materials("not toml at all [").is_err());
        assert!(parse_materials("[[material]]\nname = \"\"\n").is_err());
    }
}
