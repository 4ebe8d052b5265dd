//! OBJ input and output.
//!
//! Faces, polygons, groups and objects are read by `tobj` (polygons are fan-triangulated,
//! all objects merged). The `v` and `f` lines are also scanned here, cheaply, for two reasons:
//! errors name the offending line, and vertices keep the order of the file (tobj renumbers
//! them by first use), so `puppet skeleton` output lines up with the input file.

use super::{validate, weld, Mesh, MeshError, MAX_COORDINATE};
use glam::DVec3;
use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

/// What loading did to the file's contents, for the summary and the warnings.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct LoadReport {
    /// Objects/groups merged into one mesh.
    pub objects: usize,
    /// `v` lines in the file.
    pub file_vertices: usize,
    /// Triangles after triangulating polygons.
    pub file_triangles: usize,
    /// Vertices merged into another by welding (exact duplicates included).
    pub welded: usize,
    /// Faces dropped because welding collapsed them (repeated vertex).
    pub dropped_degenerate: usize,
    /// Vertices no face uses, removed.
    pub unreferenced: usize,
    /// Faces with zero area kept (they are needed to close the surface).
    pub zero_area: usize,
    /// True when the whole mesh was inside out and was flipped.
    pub flipped: bool,
}

impl LoadReport {
    /// Human-readable warnings, one per line, empty when the file was clean.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        if self.welded > 0 {
            w.push(format!("welded {} duplicate vertices", self.welded));
        }
        if self.dropped_degenerate > 0 {
            w.push(format!(
                "dropped {} degenerate faces (a repeated vertex after welding)",
                self.dropped_degenerate
            ));
        }
        if self.unreferenced > 0 {
            w.push(format!("removed {} unused vertices", self.unreferenced));
        }
        if self.zero_area > 0 {
            w.push(format!("{} faces have zero area", self.zero_area));
        }
        if self.flipped {
            w.push("the mesh was inside out; faces were flipped".to_string());
        }
        w
    }
}

/// Loads, welds and validates an OBJ file.
///
/// Relative weld tolerance is `1e-7` of the bounding-box diagonal.
pub fn load_obj(path: &Path) -> Result<(Mesh, LoadReport), MeshError> {
    if path.is_dir() {
        return Err(MeshError::Io("is a directory".into()));
    }
    let bytes = std::fs::read(path).map_err(|e| MeshError::Io(crate::files::io_message(&e)))?;
    parse_obj(&bytes)
}

/// Parses, welds and validates OBJ text held in memory.
pub fn parse_obj(bytes: &[u8]) -> Result<(Mesh, LoadReport), MeshError> {
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        return Err(MeshError::Parse("the file is empty".into()));
    }
    if let Some(pos) = bytes.iter().position(|&b| b == 0) {
        return Err(MeshError::NotText(format!("NUL byte at offset {pos}")));
    }
    let text = std::str::from_utf8(bytes)
        .map_err(|e| MeshError::NotText(format!("invalid UTF-8 at byte {}", e.valid_up_to())))?;
    let file_positions = scan(text)?;

    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut reader = std::io::BufReader::new(bytes);
    let (models, _materials) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| MeshError::Parse(format!("OBJ parser: {e}")))?;

    // tobj renumbers vertices per model by first use; map them back to file order through
    // the exact bit patterns (both sides parse the same text with `f64::from_str`).
    let mut index_of: HashMap<[u64; 3], u32> = HashMap::with_capacity(file_positions.len());
    for (i, p) in file_positions.iter().enumerate() {
        index_of
            .entry([p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
            .or_insert(i as u32);
    }
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    for model in &models {
        let m = &model.mesh;
        let local: Vec<u32> = m
            .positions
            .chunks_exact(3)
            .map(|c| {
                let key = [c[0].to_bits(), c[1].to_bits(), c[2].to_bits()];
                index_of.get(&key).copied().ok_or_else(|| {
                    MeshError::Parse("OBJ parser returned a vertex not in the file".into())
                })
            })
            .collect::<Result<_, _>>()?;
        for t in m.indices.chunks_exact(3) {
            let tri = [t[0], t[1], t[2]].map(|k| local.get(k as usize).copied());
            match tri {
                [Some(a), Some(b), Some(c)] => triangles.push([a, b, c]),
                _ => return Err(MeshError::Parse("face index out of range".into())),
            }
        }
    }
    let mut report = LoadReport {
        objects: models.len(),
        file_vertices: file_positions.len(),
        file_triangles: triangles.len(),
        ..Default::default()
    };
    if triangles.is_empty() {
        return Err(MeshError::Empty {
            vertices: file_positions.len(),
        });
    }
    // Only vertices that faces use are checked and kept.
    let mut used = vec![false; file_positions.len()];
    for t in &triangles {
        for &v in t {
            used[v as usize] = true;
        }
    }
    for (i, p) in file_positions.iter().enumerate() {
        if !used[i] {
            continue;
        }
        for value in p.to_array() {
            if !value.is_finite() {
                return Err(MeshError::NonFinite {
                    vertex: i + 1,
                    value,
                });
            }
            if value.abs() > MAX_COORDINATE {
                return Err(MeshError::TooLarge {
                    vertex: i + 1,
                    value,
                    max: MAX_COORDINATE,
                });
            }
        }
    }
    let mut mesh = Mesh {
        positions: file_positions,
        triangles,
    };
    let stats = weld(&mut mesh, 1e-7);
    report.welded = stats.merged;
    report.dropped_degenerate = stats.dropped_faces;
    report.unreferenced = stats.removed_vertices.saturating_sub(stats.merged);
    let topo = validate(&mut mesh)?;
    report.zero_area = topo.zero_area_faces;
    report.flipped = topo.flipped;
    Ok((mesh, report))
}

/// Checks every `v` and `f` line and returns the positions in file order.
fn scan(text: &str) -> Result<Vec<DVec3>, MeshError> {
    let mut positions = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line_no = n + 1;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let mut xyz = [0.0f64; 3];
                for (k, slot) in xyz.iter_mut().enumerate() {
                    let word = words.next().ok_or_else(|| MeshError::Syntax {
                        line: line_no,
                        message: format!("vertex has {k} coordinates, expected 3"),
                    })?;
                    *slot = word.parse().map_err(|_| MeshError::Syntax {
                        line: line_no,
                        message: format!("'{word}' is not a number"),
                    })?;
                }
                positions.push(DVec3::from_array(xyz));
            }
            Some("f") => {
                let mut count = 0;
                for word in words {
                    count += 1;
                    let first = word.split('/').next().unwrap_or("");
                    let idx: i64 = first.parse().map_err(|_| MeshError::Syntax {
                        line: line_no,
                        message: format!("'{word}' is not a vertex index"),
                    })?;
                    let n = positions.len() as i64;
                    let resolved = if idx < 0 { n + idx } else { idx - 1 };
                    if idx == 0 || resolved < 0 || resolved >= n {
                        return Err(MeshError::Syntax {
                            line: line_no,
                            message: format!(
                                "vertex index {idx} is out of range (the file has {n} vertices so far)"
                            ),
                        });
                    }
                }
                if count < 3 {
                    return Err(MeshError::Syntax {
                        line: line_no,
                        message: format!("face has {count} vertices, expected at least 3"),
                    });
                }
            }
            _ => {}
        }
    }
    Ok(positions)
}

/// Writes `positions` and 1-based triangles as a plain OBJ.
pub fn write_obj(
    out: &mut dyn Write,
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    header: &str,
) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::new(out);
    for line in header.lines() {
        writeln!(w, "# {line}")?;
    }
    for p in positions {
        writeln!(w, "v {} {} {}", p.x, p.y, p.z)?;
    }
    for t in triangles {
        writeln!(w, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
    }
    w.flush()
}
