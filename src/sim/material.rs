//! What a surface is made of: the [`Material`] (the parameters a region may give part of the
//! puppet), Table 1 of the paper as named [`Preset`]s, and custom presets in a human-readable
//! TOML file (`[[material]]` tables with a `name` and any material fields; missing fields
//! take the defaults).
//!
//! One rule for presets everywhere: choosing a preset replaces the whole material (Table 1's
//! four values, `f_min` and the stiffening, which Table 1's springs do not have: 0), and
//! nothing else. The solver and the world are not part of a material, so no preset can
//! change them.

use super::range::{clamp, first_failure, ParamError};
use super::MAX_STIFFNESS;

/// Largest bone-spring stiffening exponent.
pub const MAX_STIFFENING: u32 = 4;

/// The parameters of one kind of surface: each vertex has one (the base material, or a
/// blend of it with regions').
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Material {
    /// `C_vd`: share of velocity kept per reference step, 0..1 (0.99 jelly, 0.7 dull).
    pub damping: f32,
    /// `D`: dimensionless spring constant, 0..[`MAX_STIFFNESS`] (see the `sim` docs).
    pub stiffness: f32,
    /// `d_B` = `f_bd`: bone distance factor, 0..1 (0 puts the bones on the surface).
    pub bone_distance: f32,
    /// `sl_max` = `f_max`: maximum bone-spring length factor, 1..3.
    pub max_length: f32,
    /// `f_min`: minimum bone-spring length factor, 0..1 (spring reduction only).
    pub min_length: f32,
    /// Stiffening exponent `e` of the bone springs, 0..[`MAX_STIFFENING`] (0: Hooke). A bone
    /// spring stretched by `s` pulls with `s (|s| / ρ)^e` instead of `s`, `ρ = (sl_max − 1) L`
    /// being the circumsphere radius: soft near rest, as stiff as Hooke's at the constraint
    /// and `1 + e` times as stiff in its slope there (d'Aulignac's non-linear springs).
    pub stiffening: u32,
}

impl Default for Material {
    /// The "skin" preset of Table 1.
    fn default() -> Self {
        Material {
            damping: 0.85,
            stiffness: 1.0,
            bone_distance: 0.2,
            max_length: 1.25,
            min_length: 0.8,
            stiffening: 0,
        }
    }
}

fn lerp(a: f32, b: f32, w: f32) -> f32 {
    a + (b - a) * w
}

impl Material {
    /// The same material clamped into the valid ranges (NaN takes the default), so no
    /// slider position can make the step unstable.
    pub fn sanitized(&self) -> Material {
        let d = Material::default();
        Material {
            damping: clamp(self.damping, 0.0, 1.0, d.damping),
            stiffness: clamp(self.stiffness, 0.0, MAX_STIFFNESS, d.stiffness),
            bone_distance: clamp(self.bone_distance, 0.0, 1.0, d.bone_distance),
            max_length: clamp(self.max_length, 1.0, 3.0, d.max_length),
            min_length: clamp(self.min_length, 0.0, 1.0, d.min_length),
            stiffening: self.stiffening.min(MAX_STIFFENING),
        }
    }

    /// Checks every field against its documented range (files: a file is not a slider,
    /// silently clamping it would hide a typo).
    pub fn check(&self) -> Result<(), ParamError> {
        first_failure(&[
            ("damping", self.damping, 0.0, 1.0, "0..1"),
            ("stiffness", self.stiffness, 0.0, MAX_STIFFNESS, "0..1"),
            ("bone_distance", self.bone_distance, 0.0, 1.0, "0..1"),
            ("max_length", self.max_length, 1.0, 3.0, "1..3"),
            ("min_length", self.min_length, 0.0, 1.0, "0..1"),
        ])?;
        if self.stiffening > MAX_STIFFENING {
            return Err(ParamError {
                field: "stiffening",
                value: self.stiffening as f64,
                range: "0..4",
            });
        }
        Ok(())
    }

    /// True when the material leaves no room for elastic movement (Table 1's "plastic"):
    /// bones on the surface or `sl_max = 1`. Such a vertex is not integrated at all.
    pub fn is_static(&self) -> bool {
        self.bone_distance <= 0.0 || self.max_length <= 1.0
    }

    /// This material blended towards `other` by `w` (0..1): the numbers linearly, the
    /// stiffening exponent `other`'s where `w` is at least ½.
    pub fn blend(&self, other: &Material, w: f32) -> Material {
        Material {
            damping: lerp(self.damping, other.damping, w),
            stiffness: lerp(self.stiffness, other.stiffness, w),
            bone_distance: lerp(self.bone_distance, other.bone_distance, w),
            max_length: lerp(self.max_length, other.max_length, w),
            min_length: lerp(self.min_length, other.min_length, w),
            stiffening: if w >= 0.5 {
                other.stiffening
            } else {
                self.stiffening
            },
        }
    }

    /// The preset of this name (see [`presets`]), or `None`.
    pub fn preset(name: &str) -> Option<Material> {
        presets()
            .into_iter()
            .find(|p| p.name == name)
            .map(|p| p.material)
    }
}

/// A named material: one of Table 1's, or one from a materials file.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Preset {
    /// The name panels and rig files use.
    pub name: String,
    /// The material.
    #[serde(flatten)]
    pub material: Material,
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

fn preset(name: &str, damping: f32, stiffness: f32, bone_distance: f32, max_length: f32) -> Preset {
    Preset {
        name: name.to_string(),
        material: Material {
            damping,
            stiffness,
            bone_distance,
            max_length,
            ..Material::default()
        },
    }
}

/// Table 1 (C_vd, D, d_B, sl_max). "plastic" has `var` for C_vd and D in the paper: it is
/// static whatever they are; the defaults are used.
pub fn presets() -> Vec<Preset> {
    let d = Material::default();
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
    material: Vec<Preset>,
}

/// Writes named materials as TOML.
pub fn write_materials(materials: &[Preset]) -> String {
    toml::to_string_pretty(&File {
        material: materials.to_vec(),
    })
    .unwrap_or_default()
}

/// Reads named materials from TOML. Values outside the documented ranges are errors (a file
/// is not a slider: silently clamping it would hide a typo).
pub fn parse_materials(text: &str) -> Result<Vec<Preset>, MaterialError> {
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
        m.material.check().map_err(|error| MaterialError::Range {
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
        assert_eq!(Material::preset("skin"), Some(Material::default()));
        assert_eq!(Material::preset("rubber"), None);
    }

    #[test]
    fn partial_and_bad_files() {
        let m = parse_materials("[[material]]\nname = \"jelly\"\ndamping = 0.98\n").unwrap();
        assert_eq!(m[0].material.damping, 0.98);
        assert_eq!(m[0].material.stiffness, Material::default().stiffness);
        let e = parse_materials("[[material]]\nname = \"x\"\nmax_length = 0.5\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "material 'x': max_length = 0.5 is outside 1..3"
        );
        assert!(parse_materials("[[material]]\nname = \"x\"\nstiffening = -1\n").is_err());
        assert!(parse_materials("not toml at all [").is_err());
        assert!(parse_materials("[[material]]\nname = \"\"\n").is_err());
    }

    #[test]
    fn blend_is_linear_and_takes_the_exponent_from_half() {
        let a = Material::default();
        let b = Material {
            damping: 0.95,
            stiffening: 3,
            ..a
        };
        assert_eq!(a.blend(&b, 0.0), a);
        assert_eq!(a.blend(&b, 1.0), b);
        let half = a.blend(&b, 0.5);
        assert_eq!((half.damping, half.stiffening), (0.9, 3));
        assert_eq!(a.blend(&b, 0.49).stiffening, 0);
    }
}
