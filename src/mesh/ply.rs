//! PLY (ASCII and binary) through the `ply-rs-bw` crate: the `vertex` element's `x`, `y`,
//! `z` and the `face` element's `vertex_indices` (or `vertex_index`) list, or a `tristrips`
//! element's (triangle strips, `-1` restarting a strip, as scanners wrote them); other
//! elements and properties are skipped. Polygons are split into a fan, as in OBJ.

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

/// The triangles of triangle strips: `-1` ends a strip; in each, triangle `k` is corners
/// `k, k + 1, k + 2`, every other one turned so that all face the same way; triangles with
/// a repeated corner (strips joined by repeating a vertex) are skipped.
fn strip_triangles(strip: &[i64], out: &mut Vec<[u32; 3]>) {
    for run in strip.split(|&c| c < 0) {
        for (k, w) in run.windows(3).enumerate() {
            let (a, b, c) = (w[0] as u32, w[1] as u32, w[2] as u32);
            if a == b || b == c || a == c {
                continue;
            }
            out.push(if k % 2 == 0 { [a, b, c] } else { [b, a, c] });
        }
    }
}

/// The words a PLY header line may start with.
const HEADER_WORDS: [&str; 7] = [
    "ply",
    "format",
    "element",
    "property",
    "comment",
    "obj_info",
    "end_header",
];

/// The file with each header line that starts with no keyword made a comment (an old
/// Blender wrote its comment lines bare; other readers take them), and how many; `None`
/// when there is none.
fn loose_comments(bytes: &[u8]) -> (Option<Vec<u8>>, usize) {
    let Some(end) = bytes.windows(10).position(|w| w == b"end_header") else {
        return (None, 0);
    };
    let Ok(header) = std::str::from_utf8(&bytes[..end]) else {
        return (None, 0);
    };
    let mut loose = 0;
    let mut out = String::with_capacity(header.len() + 64);
    for line in header.split_inclusive('\n') {
        let word = line.split_whitespace().next();
        if word.is_some_and(|w| !HEADER_WORDS.contains(&w)) {
            loose += 1;
            out.push_str("comment ");
        }
        out.push_str(line);
    }
    if loose == 0 {
        return (None, 0);
    }
    let mut fixed = out.into_bytes();
    fixed.extend_from_slice(&bytes[end..]);
    (Some(fixed), loose)
}

/// Parses a PLY file held in memory.
///
/// # Errors
/// [`MeshError::Parse`] with the parser's message, a missing `vertex` element, neither a
/// `face` nor a `tristrips` element, or a face or strip naming a vertex that does not
/// exist.
pub fn parse(bytes: &[u8]) -> Result<Soup, MeshError> {
    let parser = Parser::<Element>::new();
    let (fixed, loose_comments) = loose_comments(bytes);
    let mut reader = std::io::Cursor::new(fixed.as_deref().unwrap_or(bytes));
    let ply = parser
        .read_ply(&mut reader)
        .map_err(|e| MeshError::Parse(format!("PLY: {}", super::one_line(&e.to_string()))))?;
    let vertices = ply
        .payload
        .get("vertex")
        .ok_or_else(|| MeshError::Parse("PLY: no vertex element".into()))?;
    let no_faces = Vec::new();
    let (faces, strips) = match (ply.payload.get("face"), ply.payload.get("tristrips")) {
        (None, None) => return Err(MeshError::Parse("PLY: no face or tristrips element".into())),
        (faces, strips) => (faces.unwrap_or(&no_faces), strips.unwrap_or(&no_faces)),
    };
    let n = vertices.len() as i64;
    let mut soup = Soup {
        positions: vertices.iter().map(|e| DVec3::from_array(e.xyz)).collect(),
        triangles: Vec::with_capacity(faces.len()),
        objects: 1,
        groups: None,
        skin: None,
        unread_skin: None,
        borrowed_weights: 0,
        loose_comments,
    };
    for (s, strip) in strips.iter().enumerate() {
        if let Some(&bad) = strip.corners.iter().find(|&&c| c < -1 || c >= n) {
            return Err(MeshError::Parse(format!(
                "PLY: triangle strip {s} names vertex {bad}, but the file has {n} vertices"
            )));
        }
        strip_triangles(&strip.corners, &mut soup.triangles);
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_alternate_their_turn_and_restart_at_minus_one() {
        let mut t = Vec::new();
        strip_triangles(&[0, 1, 2, 3, -1, 4, 5, 6, 6, 7], &mut t);
        assert_eq!(t, vec![[0, 1, 2], [2, 1, 3], [4, 5, 6]]);
    }

    #[test]
    fn a_tetrahedron_as_one_strip_reads_closed() {
        // The tetrahedron 0 1 2 3 as the strip 0 1 2 3 0 1: four triangles, one way round.
        let text = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n6 0 1 2 3 0 1\n";
        let soup = parse(text.as_bytes()).unwrap();
        assert_eq!(soup.triangles.len(), 4);
        let (mesh, _) = crate::mesh::parse(
            text.as_bytes(),
            crate::mesh::Format::Ply,
            &crate::mesh::LoadOptions::default(),
            crate::progress::silent(),
        )
        .unwrap();
        assert_eq!(mesh.triangles.len(), 4, "a closed oriented tetrahedron");
        let bad = text.replace("6 0 1 2 3 0 1", "6 0 1 2 9 0 1");
        assert!(parse(bad.as_bytes())
            .unwrap_err()
            .to_string()
            .contains("strip 0 names vertex 9"));
        let none = text.replace("tristrips", "edges");
        assert!(parse(none.as_bytes())
            .unwrap_err()
            .to_string()
            .contains("no face or tristrips element"));
    }

    /// A header line with no keyword (an old Blender's comment) is read as a comment and
    /// counted; the same file with `comment` reads the same.
    #[test]
    fn a_bare_header_line_is_a_comment() {
        let body = "element vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
        let bare = format!("ply\nformat ascii 1.0\nCreated by Blender 2.49\n{body}");
        let marked = format!("ply\nformat ascii 1.0\ncomment Created by Blender 2.49\n{body}");
        let (a, b) = (
            parse(bare.as_bytes()).unwrap(),
            parse(marked.as_bytes()).unwrap(),
        );
        assert_eq!((a.loose_comments, b.loose_comments), (1, 0));
        assert_eq!((a.positions, a.triangles), (b.positions, b.triangles));
    }
}
