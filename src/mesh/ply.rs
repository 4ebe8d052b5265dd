//! PLY (ASCII and binary) through the `ply-rs-bw` crate: the `vertex` element's `x`, `y`,
//! `z` and the `face` element's `vertex_indices` (or `vertex_index`) list; other elements
//! and properties are skipped. Polygons are split into a fan, as in OBJ.

use super::soup::Soup;
use super::MeshError;
use glam::DVec3;
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{Property, PropertyAccess, PropertyAccessResult};

/// One element of either kind: a vertex's coordinates or a face's corners.
#[derive(Default)]
struct Element {
    xyz: [f64; 3],
    corners: Vec<i64>,
}

fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(x) => f64::from(x),
        Property::UChar(x) => f64::from(x),
        Property::Short(x) => f64::from(x),
        Property::UShort(x) => f64::from(x),
        Property::Int(x) => f64::from(x),
        Property::UInt(x) => f64::from(x),
        Property::Float(x) => f64::from(x),
        Property::Double(x) => x,
        _ => return None,
    })
}

fn list(p: Property) -> Option<Vec<i64>> {
    Some(match p {
        Property::ListChar(v) => v.into_iter().map(i64::from).collect(),
        Property::ListUChar(v) => v.into_iter().map(i64::from).collect(),
        Property::ListShort(v) => v.into_iter().map(i64::from).collect(),
        Property::ListUShort(v) => v.into_iter().map(i64::from).collect(),
        Property::ListInt(v) => v.into_iter().map(i64::from).collect(),
        Property::ListUInt(v) => v.into_iter().map(i64::from).collect(),
        _ => return None,
    })
}

impl PropertyAccess for Element {
    fn new() -> Self {
        Element::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        let axis = match name {
            "x" => Some(0),
            "y" => Some(1),
            "z" => Some(2),
            _ => None,
        };
        if let Some(k) = axis {
            if let Some(x) = scalar(&property) {
                self.xyz[k] = x;
            }
        } else if name == "vertex_indices" || name == "vertex_index" {
            if let Some(c) = list(property) {
                self.corners = c;
            }
        }
        PropertyAccessResult::Set
    }
}

/// Parses a PLY file held in memory.
///
/// # Errors
/// [`MeshError::Parse`] with the parser's message, a missing `vertex` or `face` element, or
/// a face naming a vertex that does not exist.
pub fn parse(bytes: &[u8]) -> Result<Soup, MeshError> {
    let parser = Parser::<Element>::new();
    let mut reader = std::io::Cursor::new(bytes);
    let ply = parser
        .read_ply(&mut reader)
        .map_err(|e| MeshError::Parse(format!("PLY: {}", super::one_line(&e.to_string()))))?;
    let vertices = ply
        .payload
        .get("vertex")
        .ok_or_else(|| MeshError::Parse("PLY: no vertex element".into()))?;
    let faces = ply
        .payload
        .get("face")
        .ok_or_else(|| MeshError::Parse("PLY: no face element".into()))?;
    let n = vertices.len() as i64;
    let mut soup = Soup {
        positions: vertices.iter().map(|e| DVec3::from_array(e.xyz)).collect(),
        triangles: Vec::with_capacity(faces.len()),
        objects: 1,
    };
    for (f, face) in faces.iter().enumerate() {
        if face.corners.len() < 3 {
            return Err(MeshError::Parse(format!(
                "PLY: face {f} has {} vertices, expected at least 3",
                face.corners.len()
            )));
        }
        if let Some(&bad) = face.corners.iter().find(|&&c| c < 0 || c >= n) {
            return Err(MeshError::Parse(format!(
                "PLY: face {f} names vertex {bad}, but the file has {n} vertices"
            )));
        }
        let c = &face.corners;
        for k in 1..c.len() - 1 {
            soup.triangles
                .push([c[0] as u32, c[k] as u32, c[k + 1] as u32]);
        }
    }
    Ok(soup)
}
