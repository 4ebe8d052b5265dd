//! STL (ASCII and binary) through the `stl_io` crate. STL stores every triangle with its
//! own three corners (in `f32`); the crate shares the corners that are bit-identical and
//! welding does the rest. The vertex order is the order corners first appear.

use super::soup::Soup;
use super::MeshError;
use glam::DVec3;

/// Parses an STL file held in memory.
///
/// # Errors
/// [`MeshError::Parse`] with the reader's message.
pub fn parse(bytes: &[u8]) -> Result<Soup, MeshError> {
    let mut reader = std::io::Cursor::new(bytes);
    let mesh = stl_io::read_stl(&mut reader).map_err(|e| {
        MeshError::Parse(if e.kind() == std::io::ErrorKind::UnexpectedEof {
            "STL: the file ends before its last triangle (cut short, or not an STL file)".into()
        } else {
            format!("STL: {}", super::one_line(&e.to_string()))
        })
    })?;
    let n = mesh.vertices.len();
    let mut soup = Soup {
        loose_comments: 0,
        positions: mesh
            .vertices
            .iter()
            .map(|v| DVec3::new(f64::from(v.0[0]), f64::from(v.0[1]), f64::from(v.0[2])))
            .collect(),
        triangles: Vec::with_capacity(mesh.faces.len()),
        objects: 1,
        groups: None,
        skin: None,
        unread_skin: None,
        borrowed_weights: 0,
    };
    for f in &mesh.faces {
        if f.vertices.iter().any(|&v| v >= n) {
            return Err(MeshError::Parse(
                "STL: a face names a missing vertex".into(),
            ));
        }
        soup.triangles.push(f.vertices.map(|v| v as u32));
    }
    Ok(soup)
}
