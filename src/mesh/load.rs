//! From a file to a validated [`Mesh`]: read, parse (OBJ, PLY or STL), weld, repair what
//! can be repaired, validate. Each stage is timed; the report says what was done to the
//! file's contents, for the warnings.

use super::edges::HalfEdges;
use super::groups::Groups;
use super::parts::Parts;
use super::repair::{
    drop_duplicate_faces, drop_fins, drop_lone_faces, fill_holes, orient, weld_seams, Holes,
};
use super::soup::Soup;
use super::split::split_sheets;
use super::validate::validate_with;
use super::{gltf, guard, obj, ply, stl, weld, Mesh, MeshError};
use crate::progress::{silent, Progress};
use std::path::Path;
use std::time::Instant;

/// Largest hole (a boundary loop, in edges) filled unless the user says otherwise: every
/// hole (a scan's open base, a character's open neck); `--fill-holes` lowers it.
pub const FILL_HOLES: usize = usize::MAX;

/// Relative weld tolerance: vertices closer than this times the bounding-box diagonal are
/// one vertex.
pub const WELD_TOLERANCE: f64 = 1e-7;

/// What loading may repair.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct LoadOptions {
    /// Largest hole, in boundary edges, that is closed; 0 closes none. Default
    /// [`FILL_HOLES`].
    pub fill_holes: usize,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            fill_holes: FILL_HOLES,
        }
    }
}

/// The mesh file formats read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    /// Wavefront OBJ.
    Obj,
    /// Stanford PLY.
    Ply,
    /// Stereolithography STL.
    Stl,
    /// glTF 2.0 (`.glb`, or `.gltf` with embedded buffers).
    Gltf,
}

impl Format {
    /// The format of a file: by its extension (`.obj`, `.ply`, `.stl`, `.glb`, `.gltf`, any
    /// case), otherwise by its first bytes (`ply`; `glTF`; a binary STL's size; `solid` then
    /// `facet`), otherwise OBJ.
    pub fn of(path: Option<&Path>, bytes: &[u8]) -> Format {
        let ext = path
            .and_then(|p| p.extension())
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("obj") => return Format::Obj,
            Some("ply") => return Format::Ply,
            Some("stl") => return Format::Stl,
            Some("glb" | "gltf") => return Format::Gltf,
            _ => {}
        }
        if bytes.starts_with(b"glTF") {
            return Format::Gltf;
        }
        if bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r\n") {
            return Format::Ply;
        }
        let binary_stl = bytes.len() >= 84 && {
            let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
            bytes.len() == 84 + 50 * n
        };
        let head = &bytes[..bytes.len().min(512)];
        let ascii_stl = head.starts_with(b"solid") && head.windows(5).any(|w| w == b"facet");
        if binary_stl || ascii_stl {
            return Format::Stl;
        }
        Format::Obj
    }

    /// The name users know.
    pub fn name(self) -> &'static str {
        match self {
            Format::Obj => "OBJ",
            Format::Ply => "PLY",
            Format::Stl => "STL",
            Format::Gltf => "glTF",
        }
    }
}

/// What loading did to the file's contents, for the summary and the warnings.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct LoadReport {
    /// The file's format.
    pub format: Format,
    /// Objects/groups merged into one mesh.
    pub objects: usize,
    /// Vertices in the file.
    pub file_vertices: usize,
    /// Triangles after splitting polygons.
    pub file_triangles: usize,
    /// Vertices merged into another by welding (exact duplicates included).
    pub welded: usize,
    /// Faces dropped because welding collapsed them (repeated vertex).
    pub dropped_degenerate: usize,
    /// Vertices no face uses, removed.
    pub unreferenced: usize,
    /// Vertices of open seams welded to their neighbour across the gap.
    pub seams_welded: usize,
    /// Faces turned to agree with their neighbours.
    pub reoriented: usize,
    /// Holes closed.
    pub holes_filled: usize,
    /// Faces added to close them.
    pub hole_faces: usize,
    /// Vertices added inside them.
    pub hole_vertices: usize,
    /// Holes whose outline folded over itself, closed with a fan about the centre.
    pub hole_fans: usize,
    /// Vertices where separate sheets of the surface touched, given one copy per sheet.
    pub split_vertices: usize,
    /// Edges of more than two faces (sheets along one edge), opened into one per pair.
    pub opened_edges: usize,
    /// Small separate parts that ride along with the body.
    pub riders: usize,
    /// Faces with zero area kept (they are needed to close the surface).
    pub zero_area: usize,
    /// Parts that were inside out and were flipped.
    pub flipped_parts: usize,
    /// Faces over the same three vertices as an earlier one, dropped.
    pub duplicate_faces: usize,
    /// Faces of fins dropped: open flaps of a few faces hanging off an edge a larger piece
    /// shares.
    pub fins: usize,
    /// Lone faces joined to no other along any edge, dropped (filled, each would close
    /// into a solid of no volume).
    pub stray_faces: usize,
    /// Larger open pieces hanging so, and closed ones meeting a larger piece at an edge
    /// that cannot be paired, given their own copies of the vertices they shared.
    pub detached: usize,
    /// PLY header lines read as comments though they lack the `comment` keyword.
    pub loose_comments: usize,
    /// Connected parts of the loaded mesh.
    pub parts: usize,
    /// Seconds per stage (read, parse, weld, repair, check), in order.
    pub seconds: Vec<(&'static str, f64)>,
    /// The file's named groups (OBJ materials or groups, glTF materials), carried to the
    /// loaded mesh's vertices.
    pub groups: Groups,
    /// Where the repairs are on the loaded mesh (the window's overlay shows them).
    #[serde(skip)]
    pub marks: RepairMarks,
    /// Why the file's skin was left out (a glTF skin that cannot be read).
    pub unread_skin: Option<String>,
    /// Skinned vertices whose weights were not numbers, given their nearest neighbour's.
    pub borrowed_weights: usize,

    /// The skeleton and clips the file comes with (a glTF skin), shared by every copy.
    #[serde(skip)]
    pub skin: Option<std::sync::Arc<super::Skin>>,
}

/// Where repairs changed the loaded mesh, by vertex and face number.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RepairMarks {
    /// Vertices split where separate sheets met: each original and its copies.
    pub split_vertices: Vec<u32>,
    /// Faces added to close holes.
    pub hole_faces: Vec<u32>,
}

impl RepairMarks {
    /// Nothing was repaired where it shows.
    pub fn is_empty(&self) -> bool {
        self.split_vertices.is_empty() && self.hole_faces.is_empty()
    }
}

impl LoadReport {
    fn new(format: Format) -> LoadReport {
        LoadReport {
            format,
            objects: 0,
            file_vertices: 0,
            file_triangles: 0,
            welded: 0,
            dropped_degenerate: 0,
            unreferenced: 0,
            seams_welded: 0,
            reoriented: 0,
            holes_filled: 0,
            hole_faces: 0,
            hole_vertices: 0,
            hole_fans: 0,
            split_vertices: 0,
            opened_edges: 0,
            riders: 0,
            zero_area: 0,
            flipped_parts: 0,
            duplicate_faces: 0,
            fins: 0,
            stray_faces: 0,
            detached: 0,
            loose_comments: 0,
            parts: 0,
            seconds: Vec::new(),
            groups: Groups::default(),
            marks: RepairMarks::default(),
            skin: None,
            unread_skin: None,
            borrowed_weights: 0,
        }
    }

    /// Total seconds from file to validated mesh.
    pub fn total_seconds(&self) -> f64 {
        self.seconds.iter().map(|s| s.1).sum()
    }

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
        if self.duplicate_faces > 0 {
            w.push(format!(
                "removed {} over the same corners as another",
                plural(self.duplicate_faces, "duplicate face")
            ));
        }
        if self.borrowed_weights > 0 {
            w.push(format!(
                "gave {} whose skin weights are not numbers the joints of the nearest vertex with weights",
                match self.borrowed_weights {
                    1 => "1 vertex".to_string(),
                    n => format!("{n} vertices"),
                }
            ));
        }
        if let Some(why) = &self.unread_skin {
            w.push(format!(
                "left its skin out ({why}): joints are suggested from its shape"
            ));
        }
        if self.loose_comments > 0 {
            w.push(format!(
                "read {} of the PLY header without a keyword as comments",
                plural(self.loose_comments, "line")
            ));
        }
        if self.detached > 0 {
            w.push(format!(
                "gave {} meeting a larger one along an edge of three or more faces (trousers or a skirt sewn to a body at its waist, an eye set into a head) {} own copies of the vertices there",
                plural(self.detached, "piece"),
                if self.detached == 1 { "its" } else { "their" }
            ));
        }
        if self.fins > 0 {
            w.push(format!(
                "dropped {} hanging off an edge the surface shares with {}",
                plural(self.fins, "fin face"),
                if self.fins == 1 { "it" } else { "them" }
            ));
        }
        if self.stray_faces > 0 {
            w.push(format!(
                "dropped {} joined to no other face (a lone triangle encloses nothing)",
                plural(self.stray_faces, "stray face")
            ));
        }
        if self.seams_welded > 0 {
            w.push(format!(
                "closed open seams by welding {} across their gaps",
                plural(self.seams_welded, "vertex pair")
            ));
        }
        if self.reoriented > 0 {
            w.push(format!(
                "turned {} oriented against {} neighbours",
                plural(self.reoriented, "face"),
                if self.reoriented == 1 { "its" } else { "their" }
            ));
        }
        if self.split_vertices > 0 {
            let edges = match self.opened_edges {
                0 => String::new(),
                n => format!(
                    ", opening {} shared by more than two faces",
                    plural(n, "edge")
                ),
            };
            w.push(format!(
                "gave each sheet of the surface its own copy of {} where sheets touched{edges}",
                match self.split_vertices {
                    1 => "1 vertex".to_string(),
                    n => format!("{n} vertices"),
                }
            ));
        }
        if self.holes_filled > 0 {
            let fans = match self.hole_fans {
                0 => String::new(),
                n => format!(" ({n} folded: a fan)"),
            };
            w.push(format!(
                "filled {} with {} and {}{fans}",
                plural(self.holes_filled, "hole"),
                plural(self.hole_faces, "new face"),
                match self.hole_vertices {
                    1 => "1 new vertex".to_string(),
                    n => format!("{n} new vertices"),
                }
            ));
        }
        if self.riders > 0 {
            w.push(format!(
                "{} along with the body (no skeleton of {} own)",
                if self.riders == 1 {
                    "1 small separate part rides".to_string()
                } else {
                    format!("{} small separate parts ride", self.riders)
                },
                if self.riders == 1 { "its" } else { "their" }
            ));
        }
        if self.zero_area > 0 {
            w.push(format!("{} faces have zero area", self.zero_area));
        }
        if self.flipped_parts > 0 {
            w.push(match (self.flipped_parts, self.parts) {
                (_, 0 | 1) => "the mesh was inside out; its faces were flipped".to_string(),
                (1, n) => format!("1 of its {n} parts was inside out; its faces were flipped"),
                (k, n) if k == n => {
                    format!("all {n} of its parts were inside out; their faces were flipped")
                }
                (k, n) => {
                    format!("{k} of its {n} parts were inside out; their faces were flipped")
                }
            });
        }
        w
    }
}

/// `1 hole`, `2 holes`.
fn plural(n: usize, word: &str) -> String {
    if n == 1 {
        format!("1 {word}")
    } else {
        format!("{n} {word}s")
    }
}

/// Loads a mesh file with the default repairs.
pub fn load(path: &Path) -> Result<(Mesh, LoadReport), MeshError> {
    load_with(path, &LoadOptions::default(), silent())
}

/// Loads, welds, repairs and validates a mesh file, reporting each stage to `progress`
/// (`reading`, `parsing`, `welding`, `repairing`, `checking`).
///
/// # Errors
/// [`MeshError`] saying what is wrong (never naming the file: the caller adds it).
pub fn load_with(
    path: &Path,
    options: &LoadOptions,
    progress: Progress,
) -> Result<(Mesh, LoadReport), MeshError> {
    if path.is_dir() {
        return Err(MeshError::Io("is a directory".into()));
    }
    progress("reading", 0.0);
    let t = Instant::now();
    let bytes = std::fs::read(path).map_err(|e| MeshError::Io(crate::files::io_message(&e)))?;
    let read = t.elapsed().as_secs_f64();
    let format = Format::of(Some(path), &bytes);
    let (mesh, mut report) = parse(&bytes, format, options, progress)?;
    report.seconds.insert(0, ("read", read));
    Ok((mesh, report))
}

/// The mesh exactly as the file holds it: every vertex in the file's order (unused ones
/// too) and every face split into triangles; nothing welded, repaired or checked beyond
/// what parsing needs. What a point cache in the file's vertex order is written against.
///
/// # Errors
/// [`MeshError`] when the file cannot be read or parsed.
pub fn file_mesh(path: &Path) -> Result<Mesh, MeshError> {
    let bytes = std::fs::read(path).map_err(|e| MeshError::Io(crate::files::io_message(&e)))?;
    parse_file_mesh(&bytes, Format::of(Some(path), &bytes))
}

/// [`file_mesh`] of a file held in memory.
///
/// # Errors
/// [`MeshError`] when the bytes cannot be parsed.
pub fn parse_file_mesh(bytes: &[u8], format: Format) -> Result<Mesh, MeshError> {
    Ok(read_soup(bytes, format)?.into_mesh()?.0)
}

/// The positions and triangles as the file holds them, by the format's reader; the crates'
/// readers held to one error line whatever the bytes (`guard`).
fn read_soup(bytes: &[u8], format: Format) -> Result<Soup, MeshError> {
    match format {
        Format::Obj => obj::parse(bytes),
        Format::Ply => guard::contained("PLY", || ply::parse(bytes)),
        Format::Stl => guard::contained("STL", || stl::parse(bytes)),
        Format::Gltf => guard::contained("glTF", || gltf::parse(bytes)),
    }
}

/// Parses, welds and validates OBJ text held in memory (default repairs).
pub fn parse_obj(bytes: &[u8]) -> Result<(Mesh, LoadReport), MeshError> {
    parse(bytes, Format::Obj, &LoadOptions::default(), silent())
}

/// Parses, welds, repairs and validates a mesh file held in memory.
///
/// # Errors
/// [`MeshError`] saying what is wrong.
pub fn parse(
    bytes: &[u8],
    format: Format,
    options: &LoadOptions,
    progress: Progress,
) -> Result<(Mesh, LoadReport), MeshError> {
    let mut report = LoadReport::new(format);
    let mut clock = Instant::now();
    // Ends a stage and announces the next.
    let mut lap = |report: &mut LoadReport, stage: &'static str, next: &str| {
        let now = Instant::now();
        report.seconds.push((stage, (now - clock).as_secs_f64()));
        clock = now;
        progress(next, 0.0);
    };
    progress("parsing", 0.0);
    let mut soup = read_soup(bytes, format)?;
    report.objects = soup.objects;
    report.loose_comments = soup.loose_comments;
    report.unread_skin = soup.unread_skin.take();
    report.borrowed_weights = soup.borrowed_weights;
    // The skin's vertices are carried by position too, once the repairs are done.
    let skinned = soup.skin.take().map(|s| (s, soup.positions.clone()));
    report.file_vertices = soup.positions.len();
    report.file_triangles = soup.triangles.len();
    // The groups are carried by position once the repairs are done (a copy only where the
    // file has groups).
    let grouped = soup
        .groups
        .take()
        .map(|g| (g, soup.positions.clone(), soup.triangles.clone()));
    let (mut mesh, _) = soup.into_mesh()?;
    lap(&mut report, "parse", "welding");

    let stats = weld(&mut mesh, WELD_TOLERANCE);
    report.welded = stats.merged;
    report.dropped_degenerate = stats.dropped_faces;
    report.unreferenced = stats.removed_vertices.saturating_sub(stats.merged);
    if mesh.triangles.is_empty() {
        return Err(MeshError::Degenerate(
            "no triangles left: every face collapses when its vertices are welded".into(),
        ));
    }
    lap(&mut report, "weld", "checking");

    let mut half = HalfEdges::new(mesh.positions.len(), &mesh.triangles);
    // The check and the parts in parallel (finding the parts is mostly one thread's work).
    let (closed, measured) = rayon::join(|| half.is_closed_manifold(), || Parts::measured(&mesh));
    let (mut closed, mut measured) = (Some(closed), Some(measured));
    let mut holes = Holes::default();
    // The copies a detached piece was given, kept from welding back to what they left.
    let mut apart: Vec<u32> = Vec::new();
    if closed == Some(false) {
        let c = half.census(&|_| true);
        (closed, measured) = (None, None);
        // A face written twice makes its edges look shared by more than two faces.
        if c.nonmanifold > 0 {
            report.duplicate_faces = drop_duplicate_faces(&mut mesh);
            let fins = drop_fins(&mut mesh);
            (report.fins, report.detached) = (fins.dropped, fins.detached);
            apart = fins.copies;
            if report.duplicate_faces + report.fins + report.detached > 0 {
                // A dropped flap can leave a vertex no face uses.
                let identity: Vec<u32> = (0..mesh.positions.len() as u32).collect();
                let removed = super::weld::remap(&mut mesh, &identity).removed_vertices;
                report.unreferenced += removed;
                // The copies come last and are used: each moves down by what was removed.
                for c in &mut apart {
                    *c -= removed as u32;
                }
                half = HalfEdges::new(mesh.positions.len(), &mesh.triangles);
            }
        }
        // A detached piece's or a dropped fin's edges are new boundaries.
        let boundary = c.boundary > 0 || report.fins + report.detached > 0;
        if boundary {
            report.seams_welded = weld_seams(&mut mesh, &half, &apart);
            if report.seams_welded > 0 {
                half = HalfEdges::new(mesh.positions.len(), &mesh.triangles);
            }
        }
        if c.inconsistent > 0 {
            if let Some(turned) = orient(&mut mesh, &half) {
                report.reoriented = turned;
                half = HalfEdges::new(mesh.positions.len(), &mesh.triangles);
            }
        }
        // Sheets touching at a vertex or along an edge: each its own copy of what they
        // share (before the holes, whose loops may run through such a vertex).
        let split = split_sheets(&mut mesh);
        report.split_vertices = split.vertices;
        report.marks.split_vertices = split.marked;
        report.opened_edges = split.edges;
        if split.vertices > 0 {
            half = HalfEdges::new(mesh.positions.len(), &mesh.triangles);
        }
        if boundary && options.fill_holes > 0 {
            report.stray_faces = drop_lone_faces(&mut mesh);
            if report.stray_faces > 0 {
                let identity: Vec<u32> = (0..mesh.positions.len() as u32).collect();
                report.unreferenced += super::weld::remap(&mut mesh, &identity).removed_vertices;
                half = HalfEdges::new(mesh.positions.len(), &mesh.triangles);
            }
        }
        if boundary && options.fill_holes > 0 {
            let before = mesh.triangles.len() as u32;
            holes = fill_holes(&mut mesh, &half, options.fill_holes);
            report.marks.hole_faces = (before..mesh.triangles.len() as u32).collect();
            report.holes_filled = holes.filled;
            report.hole_faces = holes.faces;
            report.hole_vertices = holes.vertices;
            report.hole_fans = holes.fans;
            if holes.filled > 0 {
                half = HalfEdges::new(mesh.positions.len(), &mesh.triangles);
            }
        } else if boundary {
            holes = fill_holes(&mut mesh.clone(), &half, 0);
        }
        lap(&mut report, "repair", "checking");
    }

    let topo = validate_with(&mut mesh, &half, closed, measured).map_err(|e| match e {
        MeshError::Topology(m) if holes.too_large > 0 && m.contains("boundary") => {
            MeshError::Topology(if options.fill_holes == 0 {
                format!(
                    "{m}; {} (hole filling is off)",
                    plural(holes.too_large, "hole")
                )
            } else {
                format!(
                    "{m}; {} larger than the {} edges filled (the largest has {}: \
                     --fill-holes {} closes it)",
                    plural(holes.too_large, "hole"),
                    options.fill_holes,
                    holes.largest_left,
                    holes.largest_left
                )
            })
        }
        e => e,
    })?;
    report.zero_area = topo.zero_area_faces;
    report.flipped_parts = topo.flipped_parts;
    report.parts = topo.components;
    report.riders = topo.riders;
    if let Some((faces, positions, triangles)) = grouped {
        report.groups = Groups::carry(&faces, &positions, &triangles, &mesh);
    }
    if let Some((mut skin, positions)) = skinned {
        skin.carry(&positions, &mesh);
        report.skin = Some(std::sync::Arc::new(skin));
    }
    lap(&mut report, "check", "checked");
    Ok((mesh, report))
}
