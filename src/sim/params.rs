//! Every simulation parameter in one struct, with the paper's names, and the rules for the
//! values a slider or a file may give.

use super::{MAX_STIFFNESS, MIN_STEP, REFERENCE_STEP};

/// Which constraint keeps the mass points near their bones.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum Constraint {
    /// A mass point stays within `(f_max − 1) L` of its posed rest position.
    #[default]
    Circumsphere,
    /// Both bone springs are clamped into `[f_min L, f_max L]`, iterated (Provot).
    SpringReduction,
}

impl Constraint {
    /// Both constraints.
    pub const ALL: [Constraint; 2] = [Constraint::Circumsphere, Constraint::SpringReduction];

    /// The name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            Constraint::Circumsphere => "circumsphere",
            Constraint::SpringReduction => "spring-reduction",
        }
    }
}

impl std::fmt::Display for Constraint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Every simulation parameter, with the paper's names.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Params {
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
    /// Which constraint.
    pub constraint: Constraint,
    /// Spring-reduction passes per step, 1..64.
    pub reduction_iterations: u32,
    /// Fixed simulation step `h` in seconds, [`MIN_STEP`]..[`REFERENCE_STEP`].
    pub time_step: f32,
    /// Gravity, in g (each component −[`MAX_GRAVITY`]..[`MAX_GRAVITY`]): `[0, −1, 0]` pulls
    /// down with 9.81 m/s² on a puppet whose bounding-box diagonal is one metre, whatever
    /// the mesh's units (so a setting looks the same on every mesh). Off (`[0, 0, 0]`) by
    /// default. A static material does not sag.
    pub gravity: [f32; 3],
    /// An optional ground plane `y = lowest rest point + floor_height` that no mass point
    /// passes (up is +y).
    pub floor: bool,
    /// Height of the floor above the rest mesh's lowest point, in mesh units (0: the floor
    /// touches the puppet at rest).
    pub floor_height: f32,
    /// Share of a touching mass point's sliding motion the floor takes away per reference
    /// step, 0..1 (0 ice, 1 glue).
    pub floor_friction: f32,
    /// Stiffening exponent `e` of the bone springs, 0..[`MAX_STIFFENING`] (0: Hooke). A bone
    /// spring stretched by `s` pulls with `s (|s| / ρ)^e` instead of `s`, `ρ = (sl_max − 1) L`
    /// being the circumsphere radius: soft near rest, as stiff as Hooke's at the constraint
    /// and `1 + e` times as stiff in its slope there (d'Aulignac's non-linear springs).
    pub stiffening: u32,
}

/// Largest gravity component, in g.
pub const MAX_GRAVITY: f32 = 10.0;
/// Largest bone-spring stiffening exponent.
pub const MAX_STIFFENING: u32 = 4;
/// Standard gravity (m/s²), the unit of [`Params::gravity`].
pub const STANDARD_GRAVITY: f32 = 9.81;

impl Default for Params {
    /// The "skin" preset of Table 1 with the circumsphere constraint at 60 steps/s.
    fn default() -> Self {
        Params {
            damping: 0.85,
            stiffness: 1.0,
            bone_distance: 0.2,
            max_length: 1.25,
            min_length: 0.8,
            constraint: Constraint::Circumsphere,
            reduction_iterations: 4,
            time_step: REFERENCE_STEP,
            gravity: [0.0; 3],
            floor: false,
            floor_height: 0.0,
            floor_friction: 0.5,
            stiffening: 0,
        }
    }
}

/// A parameter outside its documented range.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{field} = {value} is outside {range}")]
pub struct ParamError {
    /// The field's name as files write it.
    pub field: &'static str,
    /// The value given.
    pub value: f64,
    /// The valid range, as text.
    pub range: &'static str,
}

impl Params {
    /// The same parameters clamped into their valid ranges (NaN takes the default), so no
    /// slider position or file value can make the step unstable.
    pub fn sanitized(&self) -> Params {
        let d = Params::default();
        let clamp =
            |v: f32, lo: f32, hi: f32, def: f32| if v.is_nan() { def } else { v.clamp(lo, hi) };
        Params {
            damping: clamp(self.damping, 0.0, 1.0, d.damping),
            stiffness: clamp(self.stiffness, 0.0, MAX_STIFFNESS, d.stiffness),
            bone_distance: clamp(self.bone_distance, 0.0, 1.0, d.bone_distance),
            max_length: clamp(self.max_length, 1.0, 3.0, d.max_length),
            min_length: clamp(self.min_length, 0.0, 1.0, d.min_length),
            constraint: self.constraint,
            reduction_iterations: self.reduction_iterations.clamp(1, 64),
            time_step: clamp(self.time_step, MIN_STEP, REFERENCE_STEP, d.time_step),
            gravity: self
                .gravity
                .map(|g| clamp(g, -MAX_GRAVITY, MAX_GRAVITY, 0.0)),
            floor: self.floor,
            floor_height: clamp(self.floor_height, -MAX_HEIGHT, MAX_HEIGHT, 0.0),
            floor_friction: clamp(self.floor_friction, 0.0, 1.0, d.floor_friction),
            stiffening: self.stiffening.min(MAX_STIFFENING),
        }
    }

    /// Checks every field against its documented range. Files use this (a file is not a
    /// slider: silently clamping it would hide a typo); sliders use [`Params::sanitized`].
    pub fn check(&self) -> Result<(), ParamError> {
        let checks: [(&'static str, f32, f32, f32, &'static str); 11] = [
            ("damping", self.damping, 0.0, 1.0, "0..1"),
            ("stiffness", self.stiffness, 0.0, MAX_STIFFNESS, "0..1"),
            ("bone_distance", self.bone_distance, 0.0, 1.0, "0..1"),
            ("max_length", self.max_length, 1.0, 3.0, "1..3"),
            ("min_length", self.min_length, 0.0, 1.0, "0..1"),
            (
                "time_step",
                self.time_step,
                MIN_STEP,
                REFERENCE_STEP,
                "1/2000..1/60 s",
            ),
            (
                "gravity[0]",
                self.gravity[0],
                -MAX_GRAVITY,
                MAX_GRAVITY,
                "-10..10",
            ),
            (
                "gravity[1]",
                self.gravity[1],
                -MAX_GRAVITY,
                MAX_GRAVITY,
                "-10..10",
            ),
            (
                "gravity[2]",
                self.gravity[2],
                -MAX_GRAVITY,
                MAX_GRAVITY,
                "-10..10",
            ),
            (
                "floor_height",
                self.floor_height,
                -MAX_HEIGHT,
                MAX_HEIGHT,
                "-1e9..1e9",
            ),
            ("floor_friction", self.floor_friction, 0.0, 1.0, "0..1"),
        ];
        for (field, value, lo, hi, range) in checks {
            if !(lo..=hi).contains(&value) {
                return Err(ParamError {
                    field,
                    value: value as f64,
                    range,
                });
            }
        }
        if self.stiffening > MAX_STIFFENING {
            return Err(ParamError {
                field: "stiffening",
                value: self.stiffening as f64,
                range: "0..4",
            });
        }
        if self.reduction_iterations == 0 || self.reduction_iterations > 64 {
            return Err(ParamError {
                field: "reduction_iterations",
                value: self.reduction_iterations as f64,
                range: "1..64",
            });
        }
        Ok(())
    }

    /// True when the parameters leave no room for elastic movement (Table 1's "plastic"):
    /// bones on the surface or `sl_max = 1`. Such a rig is not integrated at all.
    pub fn is_static(&self) -> bool {
        self.bone_distance <= 0.0 || self.max_length <= 1.0
    }

    /// True when gravity pulls (some component is not zero).
    pub fn has_gravity(&self) -> bool {
        self.gravity.iter().any(|&g| g != 0.0)
    }
}

/// Largest floor height accepted (mesh units).
const MAX_HEIGHT: f32 = 1e9;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn new_fields_are_checked_and_sanitized() {
        let bad = |p: Params| p.check().unwrap_err().to_string();
        let d = Params::default();
        assert!(d.check().is_ok());
        assert!(
            !d.has_gravity() && !d.floor && d.stiffening == 0,
            "all off by default"
        );
        assert_eq!(
            bad(Params {
                gravity: [0.0, -11.0, 0.0],
                ..d
            }),
            "gravity[1] = -11 is outside -10..10"
        );
        assert!(bad(Params {
            gravity: [f32::NAN, 0.0, 0.0],
            ..d
        })
        .starts_with("gravity[0]"));
        assert!(bad(Params {
            floor_friction: 1.5,
            ..d
        })
        .starts_with("floor_friction"));
        assert!(bad(Params {
            floor_height: f32::INFINITY,
            ..d
        })
        .starts_with("floor_height"));
        assert!(bad(Params { stiffening: 5, ..d }).starts_with("stiffening"));
        let s = Params {
            gravity: [f32::NAN, 1e9, -1e9],
            floor_height: f32::NAN,
            floor_friction: -1.0,
            stiffening: 99,
            ..d
        }
        .sanitized();
        assert_eq!(s.gravity, [0.0, MAX_GRAVITY, -MAX_GRAVITY]);
        assert_eq!(
            (s.floor_height, s.floor_friction, s.stiffening),
            (0.0, 0.0, 4)
        );
        assert!(s.check().is_ok());
    }
}
