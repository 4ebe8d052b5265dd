//! The rig file: everything but the mesh itself that makes a puppet (skeleton method,
//! material, cuts), as TOML or JSON by extension.
//!
//! ```toml
//! mesh = "spot.obj"              # relative to the rig file; the command line may override
//! skeleton = "fitted-ball"       # fitted-ball | shrinking-ball | pole | mean
//! material = "skin"              # a Table 1 preset, or "custom" (the defaults)
//! constraint = "circumsphere"    # or "spring-reduction"
//! root = "body"                  # name of the uncut section (default "root")
//!
//! [params]                       # optional: any simulation parameter, over the preset
//! damping = 0.9
//!
//! [[cut]]
//! name = "head"                  # the new section (the side the normal points to)
//! section = "body"               # the section it cuts (default: the root)
//! point = [0.0, 0.0, 0.45]       # a point on the plane
//! normal = [0.0, 0.0, 1.0]
//! pivot = [0.0, 0.1, 0.45]       # optional; default: see `joints`
//! band = 4.0                     # optional: joint band half-width in local medial radii
//!
//! [[cut]]
//! name = "jaw"
//! section = "head"
//! shape = "box"                  # plane (default) | sphere | box: the section is inside;
//!                                # skin: the skin joint of the cut's name and those below it
//! point = [0.0, -0.05, 0.6]      # the centre
//! size = [0.2, 0.1, 0.15]        # a box's extents along its axes (a sphere: radius = 0.1)
//! normal = [0.0, 0.0, 1.0]       # a box's third axis (default +z; see `joints::Shape`)
//! shared_pivot = true            # the head turns about the jaw's pivot too
//!
//! [[region]]                     # optional: another material on part of the surface
//! name = "belly"
//! material = "water"             # a preset, or "custom" (the defaults)
//! sections = ["head"]            # weight 1 on every vertex of these sections
//! painted = "0*1200 255*40 0*1690"   # painted weights per welded vertex (see `paint`)
//! [region.params]                # optional: material fields over the preset
//! stiffening = 2
//!
//! [pin]                          # optional: glue the surface to its bones
//! sections = ["body"]
//! painted = "0*2900 255*30"
//! ```
//!
//! [`RigFile::to_toml`] writes every parameter and every resolved pivot, so a rig written
//! and read back gives the same simulation bit for bit.

use super::paint::{self, Paint};
use crate::files::{self, Format};
use crate::joints::{Cut, JointError, Joints, Shape, ROOT};
use crate::mesh::orientation::Up;
use crate::sim::{Constraint, Material, Params};
use crate::skeleton::Method;
use glam::DVec3;
use std::path::{Path, PathBuf};

/// A cut's shape as written.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
enum ShapeName {
    #[default]
    Plane,
    Sphere,
    Box,
    Skin,
}

/// A cut as written in a rig file.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct CutEntry {
    name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    section: Option<String>,
    #[serde(default, skip_serializing_if = "is_plane")]
    shape: ShapeName,
    point: [f64; 3],
    /// Required for a plane; a box's third axis (default +z); unused by a sphere.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    normal: Option<[f64; 3]>,
    /// A sphere's radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    radius: Option<f64>,
    /// A box's full extents.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    size: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pivot: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    connected: bool,
    /// Joint band half-width in local medial radii (0: a hinge; unset: the default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    band: Option<f64>,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    shared_pivot: bool,
}

fn is_plane(shape: &ShapeName) -> bool {
    *shape == ShapeName::Plane
}

impl CutEntry {
    /// The cut this entry writes, in a rig whose root is `root`; `at` names it in errors.
    fn cut(self, root: &str, at: &str) -> Result<Cut, RigError> {
        let fail = |problem: &str| Err(RigError(format!("{at}: {problem}")));
        let shape = match (self.shape, self.radius, self.size) {
            (ShapeName::Plane, None, None) => Shape::Plane,
            (ShapeName::Sphere, Some(radius), None) => Shape::Sphere { radius },
            (ShapeName::Box, None, Some(size)) => Shape::Box { size: size.into() },
            (ShapeName::Skin, None, None) => Shape::Skin,
            (ShapeName::Skin, ..) => return fail("a skin cut has no radius or size"),
            (ShapeName::Plane, ..) => return fail("a plane has no radius or size"),
            (ShapeName::Sphere, _, Some(_)) => return fail("a sphere has a radius, not a size"),
            (ShapeName::Sphere, None, _) => return fail("a sphere needs a radius"),
            (ShapeName::Box, Some(_), _) => return fail("a box has a size, not a radius"),
            (ShapeName::Box, None, None) => return fail("a box needs a size"),
        };
        let normal = match (self.normal, shape) {
            (Some(n), _) => DVec3::from(n),
            (None, Shape::Plane) => return fail("a plane needs a normal"),
            (None, Shape::Skin) => return fail("a skin cut needs a normal"),
            (None, _) => DVec3::Z,
        };
        let cut = Cut {
            section: self.section.unwrap_or_else(|| root.to_string()),
            name: self.name,
            shape,
            point: self.point.into(),
            normal,
            pivot: self.pivot.map(DVec3::from),
            connected: self.connected,
            band: self.band,
            shared_pivot: self.shared_pivot,
        };
        if !cut.point.is_finite()
            || !cut.normal.is_finite()
            || cut.pivot.is_some_and(|p| !p.is_finite())
        {
            return fail("every value must be a finite number");
        }
        if cut.normal.length_squared() == 0.0 {
            return fail("the normal is zero");
        }
        if !shape.is_valid() {
            return fail(&format!("a {}'s size must be positive", shape.name()));
        }
        Ok(cut)
    }
}

/// A material region as written.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct RegionEntry {
    name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    material: Option<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    sections: Vec<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    groups: Vec<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    painted: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    params: Option<toml::Table>,
}

/// The pinning as written.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct PinEntry {
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    sections: Vec<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    groups: Vec<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    painted: Option<String>,
}

/// The rig file as written.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct RigEntry {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    mesh: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    skeleton: Option<Method>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    material: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    constraint: Option<Constraint>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    root: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    up: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    front: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    params: Option<toml::Table>,
    #[serde(default)]
    cut: Vec<CutEntry>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    region: Vec<RegionEntry>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pin: Option<PinEntry>,
}

/// A material region: a material and where it applies (see [`Paint`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// The name panels show.
    pub name: String,
    /// The preset its material started from, or "custom" (the file's `material`).
    pub preset: String,
    /// Its material (the preset, then the file's overrides).
    pub material: Material,
    /// Where it applies.
    pub paint: Paint,
}

/// A rig: everything but the mesh itself that makes a puppet.
#[derive(Clone, Debug, PartialEq)]
pub struct RigFile {
    /// Mesh file, resolved against the rig file's folder.
    pub mesh: Option<PathBuf>,
    /// Skeleton method.
    pub method: Method,
    /// The preset the base material started from, or "custom" (the file's `material`).
    pub preset: String,
    /// Simulation parameters (the preset's material, then the file's overrides).
    pub params: Params,
    /// Name of the root section.
    pub root: String,
    /// The up direction the mesh is modelled with, when the file says (else it is found
    /// from the mesh's shape when joints are suggested).
    pub up: Option<Up>,
    /// The way the character faces, when the file says (else the mesh file's format's, or
    /// found from the shape): it names left and right. Across up.
    pub front: Option<Up>,
    /// Cuts in order.
    pub cuts: Vec<Cut>,
    /// Material regions, blended over the base material in order.
    pub regions: Vec<Region>,
    /// Where the surface is pinned to its bones.
    pub pin: Paint,
}

impl Default for RigFile {
    fn default() -> Self {
        RigFile {
            mesh: None,
            method: Method::default(),
            preset: "skin".into(),
            params: Params::default(),
            root: ROOT.into(),
            up: None,
            front: None,
            cuts: Vec::new(),
            regions: Vec::new(),
            pin: Paint::default(),
        }
    }
}

/// A preset's material by name, or the default material for "custom".
fn preset(name: &str) -> Result<Material, RigError> {
    if name == "custom" {
        return Ok(Material::default());
    }
    Material::preset(name).ok_or_else(|| {
        let names: Vec<String> = crate::sim::presets().into_iter().map(|m| m.name).collect();
        RigError(format!(
            "material '{name}' is not a preset (presets: {}; or \"custom\")",
            names.join(", ")
        ))
    })
}

/// Painted weights from a file, the error saying where.
fn painted(text: Option<&str>, at: &str) -> Result<Vec<f32>, RigError> {
    text.map_or(Ok(Vec::new()), |t| {
        paint::decode(t).map_err(|e| RigError(format!("{at}: painted: {e}")))
    })
}

/// What is wrong with a rig file; the message says where.
#[derive(Debug, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct RigError(pub String);

impl RigFile {
    /// Reads a rig file.
    pub fn load(path: &Path) -> Result<RigFile, RigError> {
        let text = files::read_text(path).map_err(|e| RigError(e.to_string()))?;
        let base = path.parent().unwrap_or(Path::new(""));
        RigFile::parse(&text, Format::of(path), base)
    }

    /// Parses a rig; a relative mesh path is taken relative to `base`.
    pub fn parse(text: &str, format: Format, base: &Path) -> Result<RigFile, RigError> {
        let entry: RigEntry = files::parse(text, format).map_err(|e| RigError(e.to_string()))?;
        let base_preset = entry.material.unwrap_or_else(|| "skin".into());
        let mut params = Params::from(preset(&base_preset)?);
        if let Some(c) = entry.constraint {
            params.solver.constraint = c;
        }
        if let Some(overrides) = entry.params {
            params = overlay(params, overrides)?;
        }
        params
            .check()
            .map_err(|e| RigError(format!("params: {e}")))?;
        let root = entry.root.unwrap_or_else(|| ROOT.into());
        if root.trim().is_empty() {
            return Err(RigError("root: the name is empty".into()));
        }
        let cuts = entry
            .cut
            .into_iter()
            .enumerate()
            .map(|(k, c)| {
                let at = format!("cut {} ('{}')", k + 1, c.name);
                c.cut(&root, &at)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut regions = Vec::new();
        for (k, r) in entry.region.into_iter().enumerate() {
            let at = format!("region {} ('{}')", k + 1, r.name);
            if r.name.trim().is_empty() {
                return Err(RigError(format!("region {}: the name is empty", k + 1)));
            }
            let name = r.material.unwrap_or_else(|| "custom".into());
            let material = preset(&name).map_err(|e| RigError(format!("{at}: {e}")))?;
            // Over the material alone: a region has no solver or world of its own, so a
            // `time_step` or `gravity` there is an error, not a value silently dropped.
            let material = match r.params {
                Some(overrides) => {
                    overlay(material, overrides).map_err(|e| RigError(format!("{at}: {e}")))?
                }
                None => material,
            };
            let params = Params::from(material);
            params
                .check()
                .map_err(|e| RigError(format!("{at}: params: {e}")))?;
            regions.push(Region {
                paint: Paint {
                    sections: r.sections,
                    groups: r.groups,
                    weights: painted(r.painted.as_deref(), &at)?,
                },
                name: r.name,
                preset: name,
                material: params.material,
            });
        }
        let pin = entry.pin.unwrap_or_default();
        let pin = Paint {
            weights: painted(pin.painted.as_deref(), "pin")?,
            sections: pin.sections,
            groups: pin.groups,
        };
        for c in &cuts {
            if let Some(b) = c.band {
                if !(b.is_finite() && (0.0..=crate::joints::MAX_BAND).contains(&b)) {
                    return Err(RigError(format!(
                        "cut '{}': band = {b} must be in 0..={} (local medial radii; 0 is a hinge)",
                        c.name,
                        crate::joints::MAX_BAND
                    )));
                }
            }
        }
        let up = match &entry.up {
            Some(text) => Some(
                text.parse::<Up>()
                    .map_err(|e| RigError(format!("up = {e}")))?,
            ),
            None => None,
        };
        let front = match &entry.front {
            Some(text) => Some(
                text.parse::<Up>()
                    .map_err(|e| RigError(format!("front = {e}")))?,
            ),
            None => None,
        };
        if let (Some(up), Some(front)) = (up, front) {
            if !up.is_across(front) {
                return Err(RigError(format!(
                    "front = \"{front}\" lies along up = \"{up}\": a front lies across up"
                )));
            }
        }
        Ok(RigFile {
            up,
            front,
            mesh: entry.mesh.map(|m| base.join(m)),
            method: entry.skeleton.unwrap_or_default(),
            preset: base_preset,
            params,
            root,
            cuts,
            regions,
            pin,
        })
    }

    /// The rig as TOML with every parameter written out; `mesh` is written as given.
    /// Numbers are as short as reads back the same (the parameters' `f32`s as their
    /// shortest decimals) and small vectors stay on one line, so a person can read and
    /// edit it; written, read and written again, it gives the same bytes.
    pub fn to_toml(&self, mesh: Option<&str>) -> String {
        toml::to_string(&self.entry(mesh)).unwrap_or_default()
    }

    /// The text of this rig as the file `path` (TOML, or JSON by its extension), its mesh
    /// written relative to the file's folder (so the folder can move with its mesh), or
    /// as it is where no relative path leads there (another drive).
    pub fn text_for(&self, path: &Path) -> String {
        let mesh = self.mesh.as_ref().map(|m| {
            let folder = path.parent().unwrap_or(Path::new(""));
            relative(folder, m).display().to_string()
        });
        match Format::of(path) {
            Format::Json => self.to_json(mesh.as_deref()),
            Format::Toml => self.to_toml(mesh.as_deref()),
        }
    }

    /// The rig as JSON, like [`RigFile::to_toml`].
    pub fn to_json(&self, mesh: Option<&str>) -> String {
        serde_json::to_string_pretty(&self.entry(mesh)).unwrap_or_default()
    }

    /// The rig as written.
    fn entry(&self, mesh: Option<&str>) -> RigEntry {
        let mut params = shortest_floats(toml::Table::try_from(self.params).unwrap_or_default());
        params.remove("constraint");
        RigEntry {
            mesh: mesh.map(str::to_string),
            skeleton: Some(self.method),
            material: Some(self.preset.clone()),
            constraint: Some(self.params.solver.constraint),
            root: Some(self.root.clone()),
            up: self.up.map(|u| u.to_string()),
            front: self.front.map(|f| f.to_string()),
            params: Some(params),
            cut: self
                .cuts
                .iter()
                .map(|c| CutEntry {
                    name: c.name.clone(),
                    section: Some(c.section.clone()),
                    shape: match c.shape {
                        Shape::Plane => ShapeName::Plane,
                        Shape::Sphere { .. } => ShapeName::Sphere,
                        Shape::Box { .. } => ShapeName::Box,
                        Shape::Skin => ShapeName::Skin,
                    },
                    point: c.point.into(),
                    normal: Some(c.normal.into()),
                    radius: match c.shape {
                        Shape::Sphere { radius } => Some(radius),
                        _ => None,
                    },
                    size: match c.shape {
                        Shape::Box { size } => Some(size.into()),
                        _ => None,
                    },
                    pivot: c.pivot.map(Into::into),
                    connected: c.connected,
                    band: c.band,
                    shared_pivot: c.shared_pivot,
                })
                .collect(),
            region: self
                .regions
                .iter()
                .map(|r| RegionEntry {
                    name: r.name.clone(),
                    material: Some(r.preset.clone()),
                    sections: r.paint.sections.clone(),
                    groups: r.paint.groups.clone(),
                    painted: written(&r.paint.weights),
                    params: Some(shortest_floats(
                        toml::Table::try_from(r.material).unwrap_or_default(),
                    )),
                })
                .collect(),
            pin: (!self.pin.is_empty()).then(|| PinEntry {
                sections: self.pin.sections.clone(),
                groups: self.pin.groups.clone(),
                painted: written(&self.pin.weights),
            }),
        }
    }

    /// This rig's cuts applied to `uncut` (joints without cuts; the root takes this rig's
    /// name). The error names the cut.
    pub fn joints(&self, uncut: Joints) -> Result<Joints, JointError> {
        let mut joints = uncut.without_cuts(&self.root);
        joints.add_cuts(self.cuts.iter().cloned())?;
        Ok(joints)
    }
}

/// A table of `f32` parameters with each number as its shortest decimal
/// ([`crate::files::shortest`]): `0.2`, not `0.20000000298023224`.
fn shortest_floats(table: toml::Table) -> toml::Table {
    fn short(v: toml::Value) -> toml::Value {
        match v {
            toml::Value::Float(f) => toml::Value::Float(crate::files::shortest(f)),
            toml::Value::Array(a) => toml::Value::Array(a.into_iter().map(short).collect()),
            v => v,
        }
    }
    table.into_iter().map(|(k, v)| (k, short(v))).collect()
}

/// `to` as a path from the folder `from` (both made absolute against the working folder
/// first, and resolved where they exist): `../meshes/cow.obj`. Where they share no root
/// (another drive), `to` made absolute.
fn relative(from: &Path, to: &Path) -> PathBuf {
    let absolute = |p: &Path| {
        let p = if p.is_absolute() {
            p.to_path_buf()
        } else {
            std::env::current_dir().unwrap_or_default().join(p)
        };
        p.canonicalize().unwrap_or(p)
    };
    let (from, to) = (absolute(from), absolute(to));
    let (a, b): (Vec<_>, Vec<_>) = (from.components().collect(), to.components().collect());
    if a.first() != b.first() {
        return to;
    }
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..a.len() {
        out.push("..");
    }
    for c in &b[common..] {
        out.push(c);
    }
    out
}

/// Painted weights as written: `None` when nothing is painted.
fn written(weights: &[f32]) -> Option<String> {
    weights
        .iter()
        .any(|&w| w > 0.0)
        .then(|| paint::encode(weights))
}

/// `base` with the fields of `overrides` replaced; unknown fields are errors.
fn overlay<T: serde::Serialize + serde::de::DeserializeOwned>(
    base: T,
    overrides: toml::Table,
) -> Result<T, RigError> {
    let mut table = toml::Table::try_from(base).map_err(|e| RigError(e.to_string()))?;
    for (k, v) in overrides {
        if !table.contains_key(&k) {
            let known: Vec<&str> = table.keys().map(String::as_str).collect();
            return Err(RigError(format!(
                "params: unknown field `{k}` (known: {})",
                known.join(", ")
            )));
        }
        table.insert(k, v);
    }
    toml::Value::Table(table)
        .try_into()
        .map_err(|e: toml::de::Error| RigError(format!("params: {}", e.message())))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<RigFile, RigError> {
        RigFile::parse(text, Format::Toml, Path::new("/rigs"))
    }

    #[test]
    fn presets_overrides_and_defaults() {
        let r = parse("mesh = \"cow.obj\"\nmaterial = \"water\"\nconstraint = \"spring-reduction\"\n[params]\ndamping = 0.5\n").unwrap();
        assert_eq!(r.mesh, Some(PathBuf::from("/rigs/cow.obj")));
        assert_eq!(r.params.material.damping, 0.5);
        assert_eq!(r.params.material.max_length, 1.4, "from the water preset");
        assert_eq!(r.params.solver.constraint, Constraint::SpringReduction);
        assert_eq!(parse("").unwrap(), RigFile::default());
    }

    #[test]
    fn bad_rigs_say_what_and_where() {
        let bad = |t: &str| parse(t).unwrap_err().0;
        assert!(bad("material = \"rubber\"").contains("not a preset"));
        assert!(bad("[params]\ndamping = 2.0\n").contains("damping = 2 is outside 0..1"));
        assert!(bad("[params]\ndampnig = 0.5\n").contains("unknown field `dampnig`"));
        // A region has only a material: its solver's and world's fields are refused, not
        // dropped.
        for field in [
            "time_step = 0.01",
            "gravity = [0.0, -1.0, 0.0]",
            "floor = true",
        ] {
            let text = format!("[[region]]\nname = \"belly\"\n[region.params]\n{field}\n");
            let e = bad(&text);
            let key = field.split(' ').next().unwrap();
            assert!(e.contains(&format!("unknown field `{key}`")), "{e}");
            assert!(
                e.contains("region 1 ('belly')") && e.contains("damping"),
                "{e}"
            );
        }
        assert!(bad("[params]\ndamping = \"x\"\n").starts_with("params:"));
        assert!(
            bad("[[cut]]\nname = \"a\"\npoint = [0, 0, 0]\nnormal = [0, 0, 0]\n")
                .contains("cut 1 ('a'): the normal is zero")
        );
        let cut = |body: &str| bad(&format!("[[cut]]\nname = \"a\"\npoint = [0, 0, 0]\n{body}"));
        assert!(cut("").contains("cut 1 ('a'): a plane needs a normal"));
        assert!(cut("shape = \"sphere\"").contains("a sphere needs a radius"));
        assert!(cut("shape = \"sphere\"\nradius = -1").contains("a sphere's size must be positive"));
        assert!(cut("shape = \"sphere\"\nradius = nan").contains("positive"));
        assert!(cut("shape = \"box\"").contains("a box needs a size"));
        assert!(cut("shape = \"box\"\nsize = [1, 0, 1]").contains("a box's size must be positive"));
        assert!(cut("shape = \"box\"\nradius = 1").contains("a box has a size, not a radius"));
        assert!(cut("shape = \"cone\"").contains("unknown variant `cone`"));
        assert!(cut("normal = [0, 0, 1]\nradius = 1").contains("a plane has no radius or size"));
        assert!(
            bad("[[cut]]\nname = \"a\"\npoint = [0, nan, 0]\nnormal = [0, 0, 1]\n")
                .contains("finite")
        );
        assert!(
            bad("[[cut]]\nname = \"a\"\npoint = [0, 0]\nnormal = [0, 0, 1]\n").contains("line")
        );
        assert!(bad("skeleton = \"magic\"").contains("line 1"));
        assert!(bad("[params]\ndamping = nan\n").contains("outside"));
    }

    #[test]
    fn toml_round_trip_is_exact() {
        let spec = RigFile {
            params: Params::from(Material {
                damping: 0.123_456_79,
                ..Material::default()
            }),
            root: "body".into(),
            cuts: vec![Cut {
                name: "head".into(),
                section: "body".into(),
                point: DVec3::new(0.1, 1.0 / 3.0, -2.0),
                normal: DVec3::new(0.0, 1.0, 1e-17),
                pivot: Some(DVec3::new(std::f64::consts::PI, 0.0, 1.0)),
                connected: true,
                band: None,
                shape: Shape::Plane,
                shared_pivot: false,
            }]
            .into_iter()
            .chain(
                [
                    (Shape::Sphere { radius: 0.3 }, true),
                    (
                        Shape::Box {
                            size: DVec3::new(0.1, 0.2, 1.0 / 3.0),
                        },
                        false,
                    ),
                ]
                .into_iter()
                .enumerate()
                .map(|(k, (shape, shared_pivot))| Cut {
                    name: format!("part {k}"),
                    section: "head".into(),
                    shape,
                    point: DVec3::new(0.1, 0.2, 0.3),
                    normal: DVec3::X,
                    pivot: Some(DVec3::ZERO),
                    connected: false,
                    band: Some(2.5),
                    shared_pivot,
                }),
            )
            .collect(),
            ..RigFile::default()
        };
        let text = spec.to_toml(None);
        assert_eq!(parse(&text).unwrap(), spec);
        let json = serde_json::to_string(&toml::from_str::<RigEntry>(&text).unwrap()).unwrap();
        assert_eq!(
            RigFile::parse(&json, Format::Json, Path::new("/rigs")).unwrap(),
            spec
        );
    }

    #[test]
    fn written_read_and_written_again_gives_the_same_bytes() {
        let mut spec = RigFile {
            root: "body".into(),
            cuts: vec![Cut {
                name: "head".into(),
                section: "body".into(),
                point: DVec3::new(0.1, 1.0 / 3.0, -2.0),
                normal: DVec3::new(0.0, 0.7, 0.7),
                pivot: Some(DVec3::new(std::f64::consts::PI, 0.0, 1.0)),
                connected: true,
                band: Some(2.5),
                shape: Shape::Sphere { radius: 0.3 },
                shared_pivot: false,
            }
            .rounded()],
            regions: vec![Region {
                name: "belly".into(),
                preset: "water".into(),
                material: Material::preset("water").unwrap(),
                paint: Paint {
                    sections: vec!["head".into()],
                    groups: vec!["eyes".into()],
                    weights: vec![0.0, 0.5, 1.0],
                },
            }],
            ..RigFile::default()
        };
        spec.params.world.gravity = [0.0, -0.3, 0.0];
        let text = spec.to_toml(Some("../cow.obj"));
        assert!(text.contains("damping = 0.85\n"), "{text}");
        assert!(text.contains("gravity = [0.0, -0.3, 0.0]\n"), "{text}");
        assert!(text.contains("point = [0.1, 0.33333334, -2.0]\n"), "{text}");
        assert!(text.contains("pivot = [3.1415927, 0.0, 1.0]\n"), "{text}");
        let back = parse(&text).unwrap();
        assert_eq!(
            back.params, spec.params,
            "every f32 parameter reads back the same"
        );
        assert_eq!(back.to_toml(Some("../cow.obj")), text);
        let json = spec.to_json(Some("../cow.obj"));
        let back = RigFile::parse(&json, Format::Json, Path::new("/rigs")).unwrap();
        assert_eq!(back.to_json(Some("../cow.obj")), json);
    }

    #[test]
    fn a_mesh_is_written_relative_to_its_rig_file() {
        assert_eq!(
            relative(Path::new("/a/rigs"), Path::new("/a/meshes/cow.obj")),
            PathBuf::from("../meshes/cow.obj")
        );
        assert_eq!(
            relative(Path::new("/a"), Path::new("/a/cow.obj")),
            PathBuf::from("cow.obj")
        );
        let spec = RigFile {
            mesh: Some(PathBuf::from("/models/spot/spot.obj")),
            ..RigFile::default()
        };
        let text = spec.text_for(Path::new("/models/rigs/spot.rig.toml"));
        assert!(text.starts_with("mesh = \"../spot/spot.obj\"\n"), "{text}");
        let back = RigFile::parse(&text, Format::Toml, Path::new("/models/rigs")).unwrap();
        assert_eq!(
            back.mesh.map(|m| m.components().collect::<PathBuf>()),
            Some(PathBuf::from("/models/rigs/../spot/spot.obj"))
        );
        assert!(spec
            .text_for(Path::new("/models/rigs/spot.rig.json"))
            .starts_with("{"));
    }
}
