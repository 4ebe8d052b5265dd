//! Every simulation parameter, with the paper's names, in three parts: the [`Material`] (what
//! the surface is made of: a region may have its own), the [`Solver`] (how the equations are
//! integrated) and the [`World`] (gravity and the floor). [`Params`] holds the three; files
//! write their fields side by side (`serde(flatten)`), as one table.
//!
//! Each part has the rules for the values a slider or a file may give: `sanitized` clamps
//! (sliders), `check` refuses (files).

use super::material::Material;
pub use super::range::ParamError;
use super::range::{clamp, first_failure};
use super::{MIN_STEP, REFERENCE_STEP};

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

/// How the equations are integrated: the same for every vertex, whatever its material.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Solver {
    /// Which constraint.
    pub constraint: Constraint,
    /// Spring-reduction passes per step, 1..64.
    pub reduction_iterations: u32,
    /// Fixed simulation step `h` in seconds, [`MIN_STEP`]..[`REFERENCE_STEP`].
    pub time_step: f32,
}

impl Default for Solver {
    /// The circumsphere constraint at 60 steps/s.
    fn default() -> Self {
        Solver {
            constraint: Constraint::Circumsphere,
            reduction_iterations: 4,
            time_step: REFERENCE_STEP,
        }
    }
}

/// What acts on the whole puppet from outside: gravity and the floor.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct World {
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
    /// Share of a touching mass point's sliding motion the floor (and a contact between
    /// sections) takes away per reference step, 0..1 (0 ice, 1 glue).
    pub floor_friction: f32,
    /// Sections collide: a mass point of one section stays out of the medial balls of
    /// the others ([`super::contact`]). Off by default, so rig files written before it
    /// behave as they did.
    pub collision: bool,
    /// Gap kept between a mass point and another section's balls, as a share of the
    /// mesh's bounding-box diagonal, 0..[`MAX_MARGIN`].
    pub collision_margin: f32,
    /// How far the flesh of a part nearer the root gives under a part pressed into it (an
    /// arm dents a belly), as a share of its medial balls' radii, 0..[`MAX_FLESH`]: the
    /// pressing part sinks that far into the balls, and its own balls, grown by that
    /// share, push the other's surface in ([`super::contact`]). 0 (the default): hard,
    /// only the pressing part squashes, as rig files written before it behave.
    pub flesh: f32,
}

/// Largest collision margin (a share of the diagonal).
pub const MAX_MARGIN: f32 = 0.05;

/// Largest give of the flesh (a share of a medial ball's radius).
pub const MAX_FLESH: f32 = 0.5;

impl Default for World {
    /// No gravity, no floor.
    fn default() -> Self {
        World {
            gravity: [0.0; 3],
            floor: false,
            floor_height: 0.0,
            floor_friction: 0.5,
            collision: false,
            collision_margin: 0.002,
            flesh: 0.0,
        }
    }
}

/// Every simulation parameter: the base material, the solver and the world. Files write the
/// three parts' fields side by side in one table.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Params {
    /// The base material: every vertex's, where no region gives it another.
    #[serde(flatten)]
    pub material: Material,
    /// How the equations are integrated.
    #[serde(flatten)]
    pub solver: Solver,
    /// Gravity and the floor.
    #[serde(flatten)]
    pub world: World,
}

/// Largest gravity component, in g.
pub const MAX_GRAVITY: f32 = 10.0;
/// Standard gravity (m/s²), the unit of [`World::gravity`].
pub const STANDARD_GRAVITY: f32 = 9.81;
/// Largest floor height accepted (mesh units).
const MAX_HEIGHT: f32 = 1e9;

impl Solver {
    /// The same settings clamped into their valid ranges (NaN takes the default).
    pub fn sanitized(&self) -> Solver {
        let d = Solver::default();
        Solver {
            constraint: self.constraint,
            reduction_iterations: self.reduction_iterations.clamp(1, 64),
            time_step: clamp(self.time_step, MIN_STEP, REFERENCE_STEP, d.time_step),
        }
    }

    /// Checks every field against its documented range.
    pub fn check(&self) -> Result<(), ParamError> {
        first_failure(&[(
            "time_step",
            self.time_step,
            MIN_STEP,
            REFERENCE_STEP,
            "1/2000..1/60 s",
        )])?;
        if self.reduction_iterations == 0 || self.reduction_iterations > 64 {
            return Err(ParamError {
                field: "reduction_iterations",
                value: self.reduction_iterations as f64,
                range: "1..64",
            });
        }
        Ok(())
    }
}

impl World {
    /// The same settings clamped into their valid ranges (NaN takes the default).
    pub fn sanitized(&self) -> World {
        let d = World::default();
        World {
            gravity: self
                .gravity
                .map(|g| clamp(g, -MAX_GRAVITY, MAX_GRAVITY, 0.0)),
            floor: self.floor,
            floor_height: clamp(self.floor_height, -MAX_HEIGHT, MAX_HEIGHT, 0.0),
            floor_friction: clamp(self.floor_friction, 0.0, 1.0, d.floor_friction),
            collision: self.collision,
            collision_margin: clamp(self.collision_margin, 0.0, MAX_MARGIN, d.collision_margin),
            flesh: clamp(self.flesh, 0.0, MAX_FLESH, d.flesh),
        }
    }

    /// Checks every field against its documented range.
    pub fn check(&self) -> Result<(), ParamError> {
        let [gx, gy, gz] = self.gravity;
        let (lo, hi) = (-MAX_GRAVITY, MAX_GRAVITY);
        first_failure(&[
            ("gravity[0]", gx, lo, hi, "-10..10"),
            ("gravity[1]", gy, lo, hi, "-10..10"),
            ("gravity[2]", gz, lo, hi, "-10..10"),
            (
                "floor_height",
                self.floor_height,
                -MAX_HEIGHT,
                MAX_HEIGHT,
                "-1e9..1e9",
            ),
            ("floor_friction", self.floor_friction, 0.0, 1.0, "0..1"),
            (
                "collision_margin",
                self.collision_margin,
                0.0,
                MAX_MARGIN,
                "0..0.05",
            ),
            ("flesh", self.flesh, 0.0, MAX_FLESH, "0..0.5"),
        ])
    }

    /// True when gravity pulls (some component is not zero).
    pub fn has_gravity(&self) -> bool {
        self.gravity.iter().any(|&g| g != 0.0)
    }
}

impl From<Material> for Params {
    /// A material with the default solver and world.
    fn from(material: Material) -> Params {
        Params {
            material,
            ..Params::default()
        }
    }
}

impl Params {
    /// The same parameters clamped into their valid ranges (NaN takes the default), so no
    /// slider position or file value can make the step unstable.
    pub fn sanitized(&self) -> Params {
        Params {
            material: self.material.sanitized(),
            solver: self.solver.sanitized(),
            world: self.world.sanitized(),
        }
    }

    /// Checks every field against its documented range: the material's, the solver's, then
    /// the world's. Files use this (a file is not a slider: silently clamping it would hide
    /// a typo); sliders use [`Params::sanitized`].
    pub fn check(&self) -> Result<(), ParamError> {
        self.material.check()?;
        self.solver.check()?;
        self.world.check()
    }

    /// True when the base material leaves no room for elastic movement (see
    /// [`Material::is_static`]).
    pub fn is_static(&self) -> bool {
        self.material.is_static()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::MAX_STIFFENING;

    #[test]
    fn new_fields_are_checked_and_sanitized() {
        let bad = |p: Params| p.check().unwrap_err().to_string();
        let d = Params::default();
        assert!(d.check().is_ok());
        assert!(
            !d.world.has_gravity() && !d.world.floor && d.material.stiffening == 0,
            "all off by default"
        );
        let world = |w: World| Params { world: w, ..d };
        assert_eq!(
            bad(world(World {
                gravity: [0.0, -11.0, 0.0],
                ..d.world
            })),
            "gravity[1] = -11 is outside -10..10"
        );
        assert!(bad(world(World {
            gravity: [f32::NAN, 0.0, 0.0],
            ..d.world
        }))
        .starts_with("gravity[0]"));
        assert!(bad(world(World {
            floor_friction: 1.5,
            ..d.world
        }))
        .starts_with("floor_friction"));
        assert!(bad(world(World {
            floor_height: f32::INFINITY,
            ..d.world
        }))
        .starts_with("floor_height"));
        assert!(bad(Params {
            material: Material {
                stiffening: 5,
                ..d.material
            },
            ..d
        })
        .starts_with("stiffening"));
        assert!(bad(Params {
            solver: Solver {
                reduction_iterations: 0,
                ..d.solver
            },
            ..d
        })
        .starts_with("reduction_iterations"));
        let s = Params {
            world: World {
                gravity: [f32::NAN, 1e9, -1e9],
                floor_height: f32::NAN,
                floor_friction: -1.0,
                ..d.world
            },
            material: Material {
                stiffening: 99,
                ..d.material
            },
            ..d
        }
        .sanitized();
        assert_eq!(s.world.gravity, [0.0, MAX_GRAVITY, -MAX_GRAVITY]);
        assert_eq!(
            (
                s.world.floor_height,
                s.world.floor_friction,
                s.material.stiffening
            ),
            (0.0, 0.0, MAX_STIFFENING)
        );
        assert!(s.check().is_ok());
    }

    #[test]
    fn files_write_the_three_parts_as_one_table() {
        let p = Params::default();
        let table = toml::Table::try_from(p).unwrap();
        for field in [
            "damping",
            "stiffness",
            "bone_distance",
            "max_length",
            "min_length",
            "stiffening",
            "constraint",
            "reduction_iterations",
            "time_step",
            "gravity",
            "floor",
            "floor_height",
            "floor_friction",
            "collision",
            "collision_margin",
            "flesh",
        ] {
            assert!(table.contains_key(field), "{field}");
        }
        assert_eq!(table.len(), 16);
        let back: Params = toml::Value::Table(table).try_into().unwrap();
        assert_eq!(back, p);
        let partial: Params =
            toml::from_str("damping = 0.5\nfloor = true\ntime_step = 0.01\n").unwrap();
        assert_eq!(
            (
                partial.material.damping,
                partial.world.floor,
                partial.solver.time_step
            ),
            (0.5, true, 0.01)
        );
        assert_eq!(partial.material.stiffness, p.material.stiffness);
    }
}
