//! glTF 2.0 input (`.glb`, or `.gltf` with its buffers embedded as data URIs) through the
//! `gltf` crate: every triangle primitive of every mesh in the default scene (or the first),
//! placed by its node's transform, becomes part of one soup (then welded and validated like
//! any other file). The vertex order is the order primitives and their vertices appear.
//! Primitives with different materials are the mesh's groups ([`super::groups`]).
//!
//! Besides plain files it reads quantized ones (`KHR_mesh_quantization`: integer positions,
//! as puppet's own `--quantize` takes write them) and compressed ones
//! (`EXT_meshopt_compression`, as gltfpack writes them).
//!
//! # Files
//! * this file: the document, its scene and its primitives;
//! * `accessor`: an accessor's elements, whatever their component type;
//! * `meshopt`: decoding compressed buffer views;
//! * `skin`: skins and clips (a skinned primitive is placed at rest by its skinning).

mod accessor;
mod meshopt;
mod skin;

use super::groups::FaceGroups;
use super::soup::Soup;
use super::MeshError;
use glam::{DMat4, Mat4};

fn bad(what: impl std::fmt::Display) -> MeshError {
    MeshError::Parse(format!("glTF: {}", super::one_line(&what.to_string())))
}

/// Every primitive's `POSITION` names an accessor the file has, its indices, if any, are
/// unsigned integers, and every animation channel names a sampler and a node the file
/// has: three bugs of the crates, checked here before they run.
///
/// 1. gltf-json 1.4.1 (`mesh.rs:151`, `primitive_validate_hook`) indexes `root.accessors`
///    with a primitive's `POSITION` before that index is validated, so `Gltf::from_slice`
///    panics ("index out of bounds: the len is 13 but the index is 91") on a file whose
///    `POSITION` names a missing accessor, instead of returning its validation error.
///    Reproducer: any valid `.glb` with the digit `9` put before its `POSITION` index (and
///    one character of a name dropped to keep the length): `tests/readers.rs`,
///    `a_glb_naming_a_missing_position_accessor_is_an_error`.
/// 2. gltf 1.4.1 (`mesh/mod.rs:396`, `Reader::read_indices`) reaches `unreachable!()` when
///    the indices' accessor holds floats or signed integers, which its validation lets
///    through. Reproducer: a valid `.glb` whose indices accessor's `componentType` 5125 is
///    changed to 5126: `tests/readers.rs`, `a_glb_with_float_indices_is_an_error`.
///
/// `guard` catches what else such a bug could do (the mutation test in `tests/readers.rs`
/// counts on it).
fn check_accessors(root: &gltf::json::Root) -> Result<(), MeshError> {
    use gltf::json::accessor::ComponentType;
    use gltf::json::validation::Checked;
    let accessors = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let position = prim
                .attributes
                .get(&Checked::Valid(gltf::json::mesh::Semantic::Positions));
            if let Some(index) = position {
                if index.value() >= accessors {
                    return Err(bad(format!(
                        "mesh {m} primitive {p}: POSITION is accessor {}, but the file has {accessors}",
                        index.value()
                    )));
                }
            }
            let kind = prim
                .indices
                .and_then(|i| root.accessors.get(i.value()))
                .map(|a| &a.component_type);
            if let Some(Checked::Valid(kind)) = kind {
                let unsigned = matches!(
                    kind.0,
                    ComponentType::U8 | ComponentType::U16 | ComponentType::U32
                );
                if !unsigned {
                    return Err(bad(format!(
                        "mesh {m} primitive {p}: the indices are not unsigned integers"
                    )));
                }
            }
        }
    }
    // 3. gltf 1.4.1 (`animation/mod.rs:157`, `:211`, `:217`, `:257`) unwraps a channel's
    //    sampler, target node and path, and a sampler's interpolation, none of which its
    //    validation checks: a bad one panics (`tests/readers.rs` met it mutating a
    //    skinned glb).
    for (a, animation) in root.animations.iter().enumerate() {
        for (c, channel) in animation.channels.iter().enumerate() {
            if channel.sampler.value() >= animation.samplers.len()
                || channel.target.node.value() >= root.nodes.len()
            {
                return Err(bad(format!(
                    "animation {a} channel {c} names a sampler or node the file does not have"
                )));
            }
            if !matches!(channel.target.path, Checked::Valid(_)) {
                return Err(bad(format!(
                    "animation {a} channel {c}: an unknown target path"
                )));
            }
        }
        for (k, sampler) in animation.samplers.iter().enumerate() {
            if !matches!(sampler.interpolation, Checked::Valid(_)) {
                return Err(bad(format!(
                    "animation {a} sampler {k}: an unknown interpolation"
                )));
            }
        }
    }
    Ok(())
}

/// The Draco mesh compression extension, which this reader does not decode.
const DRACO: &str = "KHR_draco_mesh_compression";

/// Parses a glTF file held in memory.
///
/// # Errors
/// [`MeshError::Parse`] saying what is wrong (an external buffer file included: this
/// reader takes `.glb` and `.gltf` with embedded buffers).
pub fn parse(bytes: &[u8]) -> Result<Soup, MeshError> {
    let raw = gltf::Gltf::from_slice_without_validation(bytes).map_err(bad)?;
    let mut json = raw.document.into_json();
    check_accessors(&json)?;
    // Draco, which this reader does not decode: said so, with what to do.
    if json.extensions_required.iter().any(|e| e == DRACO) {
        return Err(bad(format!(
            "its meshes are compressed with Draco ({DRACO}), which puppet does not decode: export it again without Draco (Blender: File > Export > glTF, Compression off)"
        )));
    }
    // The extensions this reader handles itself, which the crate's validation refuses.
    let compressed = json.extensions_used.iter().any(|e| e == meshopt::EXTENSION);
    json.extensions_required
        .retain(|e| e != "KHR_mesh_quantization" && e != meshopt::EXTENSION);
    // The crate drops extensions it does not know: the compressed views' descriptions are
    // read from the raw JSON, only in a file that uses them.
    let raw_json: serde_json::Value = if compressed {
        let text = match gltf::Glb::from_slice(bytes) {
            Ok(glb) => glb.json.into_owned(),
            Err(_) => bytes.to_vec(),
        };
        serde_json::from_slice(&text).map_err(bad)?
    } else {
        serde_json::Value::Null
    };
    let gltf = gltf::Gltf {
        document: gltf::Document::from_json(json).map_err(bad)?,
        blob: raw.blob,
    };
    let mut buffers: Vec<Vec<u8>> = Vec::new();
    for b in gltf.buffers() {
        if compressed && meshopt::is_fallback(&raw_json, b.index()) {
            buffers.push(Vec::new());
            continue;
        }
        let data = match b.source() {
            gltf::buffer::Source::Bin => gltf
                .blob
                .clone()
                .ok_or_else(|| bad("the binary chunk the file refers to is missing"))?,
            gltf::buffer::Source::Uri(uri) => match uri.strip_prefix("data:") {
                Some(rest) => {
                    let (_, data) = rest
                        .split_once(";base64,")
                        .ok_or_else(|| bad("a data URI that is not base64"))?;
                    base64(data).ok_or_else(|| bad("a data URI with invalid base64"))?
                }
                None => {
                    return Err(bad(format!(
                        "the buffer is in a separate file ('{uri}'); export as .glb (binary glTF) instead"
                    )))
                }
            },
        };
        if data.len() < b.length() {
            return Err(bad("a buffer is shorter than the file says"));
        }
        buffers.push(data);
    }
    let decoded = if compressed {
        meshopt::decode_views(&raw_json, &buffers)?
    } else {
        Vec::new()
    };
    let data = accessor::Data { buffers, decoded };
    // A skin that cannot be read (weights that are NaN, a joint past the skin's) is left
    // out with the reason, as other readers leave it: the shape is still the file's.
    let skinning = skin::Skinning::of(&gltf);
    let first = match skinning {
        Ok(skinning) => gather(&gltf, &data, skinning),
        Err(e) => Err(Failure::Skin(e)),
    };
    match first {
        Ok(soup) => Ok(soup),
        Err(Failure::Other(e)) => Err(e),
        Err(Failure::Skin(why)) => {
            let mut soup = gather(&gltf, &data, None).map_err(Failure::error)?;
            soup.unread_skin = Some(why.to_string());
            Ok(soup)
        }
    }
}

/// Why [`gather`] failed: the skin (the file reads without it), or anything else.
enum Failure {
    Skin(MeshError),
    Other(MeshError),
}

impl Failure {
    fn error(self) -> MeshError {
        match self {
            Failure::Skin(e) | Failure::Other(e) => e,
        }
    }
}

impl From<MeshError> for Failure {
    fn from(e: MeshError) -> Failure {
        Failure::Other(e)
    }
}

/// The scene's triangles, placed at rest by `skinning` where the file has a skin, else by
/// their nodes.
fn gather(
    gltf: &gltf::Gltf,
    data: &accessor::Data,
    mut skinning: Option<skin::Skinning>,
) -> Result<Soup, Failure> {
    let mut soup = Soup {
        loose_comments: 0,
        objects: 0,
        ..Soup::default()
    };
    let scene = gltf.default_scene().or_else(|| gltf.scenes().next());
    let roots: Vec<gltf::Node> = match &scene {
        Some(s) => s.nodes().collect(),
        None => Vec::new(),
    };
    let mut stack: Vec<(gltf::Node, DMat4)> =
        roots.into_iter().map(|n| (n, DMat4::IDENTITY)).collect();
    let mut depth = 0usize;
    // Each primitive's material, by name (or number), and its face count.
    let mut materials: Vec<(String, usize)> = Vec::new();
    while let Some((node, parent)) = stack.pop() {
        depth += 1;
        if depth > 1_000_000 {
            return Err(bad("the node tree is too deep or has a cycle").into());
        }
        let local = Mat4::from_cols_array_2d(&node.transform().matrix()).as_dmat4();
        let world = parent * local;
        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                if prim.mode() != gltf::mesh::Mode::Triangles {
                    continue;
                }
                let Some(positions) = prim.get(&gltf::Semantic::Positions) else {
                    continue;
                };
                let positions = accessor::floats(&positions, data, 3)?;
                let base = soup.positions.len() as u32;
                let count = positions.len() / 3;
                let indices: Vec<u32> = match prim.indices() {
                    Some(i) => accessor::unsigned(&i, data, 1)?,
                    None => (0..count as u32).collect(),
                };
                if indices.iter().any(|&i| i as usize >= count) {
                    return Err(bad("a triangle names a missing vertex").into());
                }
                let skinned = match (&mut skinning, node.skin()) {
                    (Some(s), Some(skin)) => s
                        .place(&skin, &prim, data, &positions, &indices)
                        .map_err(Failure::Skin)?,
                    _ => None,
                };
                match skinned {
                    Some(at_rest) => soup.positions.extend(at_rest),
                    None => {
                        // Placed by its node; in a skinned file, noted as moved by no joint.
                        if let Some(s) = &mut skinning {
                            s.unskinned(count);
                        }
                        soup.positions.extend(
                            positions.chunks_exact(3).map(|p| {
                                world.transform_point3(glam::Vec3::from_slice(p).as_dvec3())
                            }),
                        )
                    }
                }
                let before = soup.triangles.len();
                soup.triangles.extend(
                    indices
                        .chunks_exact(3)
                        .map(|t| [base + t[0], base + t[1], base + t[2]]),
                );
                soup.objects += 1;
                let material = prim.material();
                let name = match (material.name(), material.index()) {
                    (Some(name), _) if !name.trim().is_empty() => name.to_string(),
                    (_, Some(k)) => format!("material {k}"),
                    (_, None) => "default material".to_string(),
                };
                materials.push((name, soup.triangles.len() - before));
            }
        }
        stack.extend(node.children().map(|c| (c, world)));
    }
    soup.objects = soup.objects.max(1);
    if let Some(s) = skinning {
        soup.borrowed_weights = s.borrowed;
        soup.skin = Some(s.finish(gltf, data).map_err(Failure::Skin)?);
    }
    soup.groups = FaceGroups::from_names(
        materials
            .iter()
            .flat_map(|(name, faces)| std::iter::repeat_n(Some(name.as_str()), *faces)),
    );
    Ok(soup)
}

/// Standard base64 (with or without padding); `None` on any other character.
fn base64(text: &str) -> Option<Vec<u8>> {
    let value = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let clean: Vec<u8> = text.bytes().filter(|&c| c != b'=').collect();
    let mut out = Vec::with_capacity(clean.len() * 3 / 4);
    for chunk in clean.chunks(4) {
        let mut acc = 0u32;
        for &c in chunk {
            acc = (acc << 6) | value(c)?;
        }
        acc <<= 6 * (4 - chunk.len()) as u32;
        let bytes = acc.to_be_bytes();
        match chunk.len() {
            4 => out.extend_from_slice(&bytes[1..4]),
            3 => out.extend_from_slice(&bytes[1..3]),
            2 => out.push(bytes[1]),
            _ => return None,
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn base64_decodes() {
        assert_eq!(base64("aGVsbG8=").unwrap(), b"hello");
        assert_eq!(base64("aGVsbG8").unwrap(), b"hello");
        assert_eq!(base64("AAAA").unwrap(), vec![0, 0, 0]);
        assert!(base64("a$==").is_none());
        assert!(base64("a").is_none());
    }

    /// A tetrahedron as `.gltf` JSON with its buffer in a data URI, under a node that moves
    /// it by +10 in x.
    fn tetrahedron() -> String {
        let positions: [[f32; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
        let indices: [u16; 12] = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3];
        let mut bin = Vec::new();
        for p in positions {
            for c in p {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
        for i in indices {
            bin.extend_from_slice(&i.to_le_bytes());
        }
        let b64 = encode(&bin);
        format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
            "nodes":[{{"mesh":0,"translation":[10,0,0]}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],
            "buffers":[{{"byteLength":{len},"uri":"data:application/octet-stream;base64,{b64}"}}],
            "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":48}},{{"buffer":0,"byteOffset":48,"byteLength":24}}],
            "accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,1]}},
            {{"bufferView":1,"componentType":5123,"count":12,"type":"SCALAR"}}]}}"#,
            len = bin.len()
        )
    }

    /// Standard base64 of `bin`.
    fn encode(bin: &[u8]) -> String {
        const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut b64 = String::new();
        for chunk in bin.chunks(3) {
            let n = chunk.iter().fold(0u32, |a, &b| a << 8 | b as u32) << (8 * (3 - chunk.len()));
            for k in 0..=chunk.len() {
                b64.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            }
        }
        b64
    }

    /// A tetrahedron skinned to two joints (node 1, and node 2 below it moved by +1 in
    /// x): vertex 1 all on joint `joint1`, the rest on joint 0, vertex 3's weights
    /// `w3`; `children` the joints' children lists.
    fn skinned(joint1: u8, w3: [f32; 2], children: (&str, &str)) -> String {
        let positions: [[f32; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
        let indices: [u16; 12] = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3];
        let joints: [[u8; 4]; 4] = [[0; 4], [joint1, 0, 0, 0], [0; 4], [0, 1, 0, 0]];
        let weights: [[f32; 4]; 4] = [
            [1., 0., 0., 0.],
            [1., 0., 0., 0.],
            [1., 0., 0., 0.],
            [w3[0], w3[1], 0., 0.],
        ];
        let mut bin = Vec::new();
        positions
            .iter()
            .flatten()
            .for_each(|c| bin.extend_from_slice(&c.to_le_bytes()));
        indices
            .iter()
            .for_each(|i| bin.extend_from_slice(&i.to_le_bytes()));
        joints.iter().flatten().for_each(|&j| bin.push(j));
        weights
            .iter()
            .flatten()
            .for_each(|c| bin.extend_from_slice(&c.to_le_bytes()));
        format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
            "nodes":[{{"mesh":0,"skin":0}},{{"name":"hip","children":{c1}}},
                     {{"name":"knee","translation":[1,0,0],"children":{c2}}}],
            "skins":[{{"joints":[1,2]}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"JOINTS_0":2,"WEIGHTS_0":3}},"indices":1}}]}}],
            "buffers":[{{"byteLength":{len},"uri":"data:application/octet-stream;base64,{b64}"}}],
            "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":48}},{{"buffer":0,"byteOffset":48,"byteLength":24}},
                           {{"buffer":0,"byteOffset":72,"byteLength":16}},{{"buffer":0,"byteOffset":88,"byteLength":64}}],
            "accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,1]}},
            {{"bufferView":1,"componentType":5123,"count":12,"type":"SCALAR"}},
            {{"bufferView":2,"componentType":5121,"count":4,"type":"VEC4"}},
            {{"bufferView":3,"componentType":5126,"count":4,"type":"VEC4"}}]}}"#,
            len = bin.len(),
            b64 = encode(&bin),
            c1 = children.0,
            c2 = children.1,
        )
    }

    /// A skinned primitive is placed at rest by its skinning, and its joints read with
    /// their hierarchy, names and weights.
    #[test]
    fn a_skinned_primitive_is_placed_by_its_joints() {
        let soup = parse(skinned(1, [0.5, 0.5], ("[2]", "[]")).as_bytes()).unwrap();
        // Vertex 1 rides joint 1 (moved +1 in x, no inverse bind): at 2; vertex 3 half.
        assert_eq!(soup.positions[1], DVec3::new(2.0, 0.0, 0.0));
        assert_eq!(soup.positions[3], DVec3::new(0.5, 0.0, 1.0));
        let skin = soup.skin.unwrap();
        let names: Vec<&str> = skin.joints.iter().map(|j| j.name.as_str()).collect();
        assert_eq!(names, ["hip", "knee"]);
        assert_eq!(skin.joints[1].parent, Some(0));
        assert_eq!(skin.joints[1].weight, 1.5);
        assert_eq!(skin.vertex_joint, [0, 1, 0, 0]);
    }

    /// A bad skin is left out, with one line that says why: weights that do not sum to
    /// 1, a joint number past the skin's joints; the shape is still read, placed by its
    /// nodes. A joint that is its own ancestor is a cycle in the node tree: the file is
    /// refused in one line.
    #[test]
    fn bad_skins_are_left_out_saying_why() {
        let cycle = parse(skinned(1, [0.5, 0.5], ("[2]", "[1]")).as_bytes());
        let e = cycle.expect_err("a cycle").to_string();
        assert!(!e.contains('\n'), "{e}");
        for (text, says) in [
            (skinned(1, [0.5, 0.3], ("[2]", "[]")), "weights sum to 0.8"),
            (
                skinned(7, [0.5, 0.5], ("[2]", "[]")),
                "names joint 7, but the skin has 2",
            ),
        ] {
            let soup = parse(text.as_bytes()).expect("the shape reads without its skin");
            assert!(soup.skin.is_none());
            assert_eq!(soup.triangles.len(), 4);
            let why = soup.unread_skin.expect("a reason");
            assert!(why.contains(says) && !why.contains('\n'), "{why}");
        }
    }

    /// A vertex whose weights are not numbers (as an exporter wrote a few) keeps the skin:
    /// it takes the joints of its nearest neighbour with weights, and the skin is read
    /// whole, the character keeping the skeleton it came with.
    #[test]
    fn a_vertex_whose_weights_are_not_numbers_takes_a_neighbours() {
        for w3 in [[f32::NAN, 0.5], [f32::INFINITY, 0.0]] {
            let soup = parse(skinned(1, w3, ("[2]", "[]")).as_bytes()).expect("reads");
            assert!(soup.unread_skin.is_none(), "{:?}", soup.unread_skin);
            assert_eq!(soup.borrowed_weights, 1);
            let skin = soup.skin.expect("the skin is kept");
            // Vertex 3's neighbours: 0 and 2 on joint 0 (first by number), 1 on joint 1.
            assert_eq!(skin.vertex_joint, [0, 1, 0, 0]);
            assert_eq!(soup.positions[3], DVec3::new(0.0, 0.0, 1.0));
            assert!(skin.joints.iter().all(|j| j.weight.is_finite()));
        }
    }

    #[test]
    fn an_embedded_gltf_reads_with_its_node_transform() {
        let soup = parse(tetrahedron().as_bytes()).unwrap();
        assert_eq!(soup.positions.len(), 4);
        assert_eq!(soup.triangles.len(), 4);
        assert_eq!(soup.positions[1], DVec3::new(11.0, 0.0, 0.0));
    }

    #[test]
    fn bad_gltf_says_what() {
        let text = tetrahedron();
        let external = text.replace(
            &text[text.find("data:").unwrap()
                ..text.find("\"}],\n            \"bufferViews").unwrap()],
            "mesh.bin",
        );
        let e = parse(external.as_bytes()).unwrap_err().to_string();
        assert!(e.contains("separate file ('mesh.bin')"), "{e}");
        assert!(parse(b"glTF\x02\x00\x00\x00").is_err());
        assert!(parse(b"{\"asset\": 3}").is_err());
        // Draco: one line that says what and what to do, not a line per accessor.
        let draco = text.replacen(
            r#"{"asset":{"version":"2.0"},"#,
            r#"{"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],"extensionsRequired":["KHR_draco_mesh_compression"],"#,
            1,
        );
        assert_ne!(draco, text);
        let e = parse(draco.as_bytes()).unwrap_err().to_string();
        assert!(
            e.contains("compressed with Draco") && e.contains("Compression off"),
            "{e}"
        );
    }
}
