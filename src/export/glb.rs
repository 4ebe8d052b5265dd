//! glTF binary (`.glb`): the mesh (indices, rest positions, normals) with one morph target
//! per exported frame and an animation of the morph weights (linear; at frame `k` target `k`
//! has weight 1, so between two frames two targets are active). Blender imports the targets
//! as shape keys, game engines play the animation. The JSON is built with `gltf-json`.

use super::{ExportError, Frames};
use gltf::json;
use json::validation::Checked::Valid;
use json::validation::USize64;
use std::borrow::Cow;

/// The bytes of a `.glb` (32-bit floats).
///
/// # Errors
/// [`ExportError`] when a frame does not fit the mesh or the file would pass 4 GiB.
pub fn write(take: &Frames) -> Result<Vec<u8>, ExportError> {
    write_with(take, false)
}

/// 16-bit quantisation (`KHR_mesh_quantization`): positions and target displacements as
/// integers on one grid, which the node's translation and uniform scale map back. The grid
/// step is the half-extent of everything the take visits over 16383, so a displacement
/// (a difference of two grid points) still fits 16 bits; the error is at most half a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// The grid's origin.
    pub center: glam::Vec3,
    /// Mesh units per grid step.
    pub scale: f32,
}

/// Grid points from the centre to the edge of the visited box (half the `i16` range, so
/// that the difference of two points fits).
const GRID_HALF: f32 = 16383.0;

impl Grid {
    /// The grid of a take: every rest and frame position on it.
    pub fn of(take: &Frames) -> Grid {
        let (lo, hi) = take
            .frames
            .iter()
            .flatten()
            .chain(&take.rest)
            .fold((glam::Vec3::MAX, glam::Vec3::MIN), |(lo, hi), p| {
                (lo.min(*p), hi.max(*p))
            });
        let center = (lo + hi) * 0.5;
        let half = ((hi - lo) * 0.5).max_element();
        let scale = if half.is_finite() && half > 0.0 {
            half / GRID_HALF
        } else {
            1.0
        };
        Grid { center, scale }
    }

    /// The grid point of `p`.
    pub fn point(&self, p: glam::Vec3) -> [i32; 3] {
        ((p - self.center) / self.scale)
            .round()
            .clamp(glam::Vec3::splat(-GRID_HALF), glam::Vec3::splat(GRID_HALF))
            .as_ivec3()
            .to_array()
    }
}

/// The bytes of a `.glb`; `quantize` writes positions and targets as 16-bit integers
/// ([`Grid`]) instead of 32-bit floats (about two thirds of the size).
///
/// # Errors
/// [`ExportError`] when a frame does not fit the mesh or the file would pass 4 GiB.
pub fn write_with(take: &Frames, quantize: bool) -> Result<Vec<u8>, ExportError> {
    take.check()?;
    let grid = quantize.then(|| Grid::of(take));
    let (n, frames) = (take.rest.len(), take.frames.len());
    let mut bin: Vec<u8> = Vec::new();
    let mut root = json::Root {
        asset: json::Asset {
            generator: Some(format!("puppet {}", env!("CARGO_PKG_VERSION"))),
            ..Default::default()
        },
        ..Default::default()
    };
    let buffer = json::Index::new(0);
    // Appends a buffer view over `bytes` (4-byte aligned by construction: every element is
    // a 4-byte number).
    let view = |root: &mut json::Root,
                bin: &mut Vec<u8>,
                bytes: Vec<u8>,
                stride: Option<usize>,
                target: Option<json::buffer::Target>| {
        let offset = bin.len();
        let length = bytes.len();
        bin.extend_from_slice(&bytes);
        root.push(json::buffer::View {
            buffer,
            byte_length: USize64::from(length),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: stride.map(json::buffer::Stride),
            extensions: None,
            extras: Default::default(),
            name: None,
            target: target.map(Valid),
        })
    };
    let f32s = |v: &mut Vec<u8>, x: f32| v.extend_from_slice(&x.to_le_bytes());
    let vec3s = |points: &[glam::Vec3]| {
        let mut out = Vec::with_capacity(points.len() * 12);
        for p in points {
            for c in p.to_array() {
                f32s(&mut out, c);
            }
        }
        out
    };
    let bounds = |points: &mut dyn Iterator<Item = glam::Vec3>| {
        let (lo, hi) = points.fold(
            (glam::Vec3::splat(f32::MAX), glam::Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(p), hi.max(p)),
        );
        (
            json::Value::from(lo.to_array().to_vec()),
            json::Value::from(hi.to_array().to_vec()),
        )
    };
    let accessor = |view: json::Index<json::buffer::View>,
                    offset: usize,
                    count: usize,
                    component: json::accessor::ComponentType,
                    type_: json::accessor::Type,
                    min_max: Option<(json::Value, json::Value)>| {
        let (min, max) = min_max.unzip();
        json::Accessor {
            buffer_view: Some(view),
            byte_offset: Some(USize64::from(offset)),
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        }
    };
    use json::accessor::{ComponentType as C, Type as T};
    use json::buffer::Target as B;

    // The mesh.
    let mut indices = Vec::with_capacity(take.triangles.len() * 12);
    for t in &take.triangles {
        for v in t {
            indices.extend_from_slice(&v.to_le_bytes());
        }
    }
    let v = view(
        &mut root,
        &mut bin,
        indices,
        None,
        Some(B::ElementArrayBuffer),
    );
    let indices = root.push(accessor(
        v,
        0,
        take.triangles.len() * 3,
        C::U32,
        T::Scalar,
        None,
    ));
    // Three 16-bit integers padded to 8 bytes (vertex attributes are 4-byte aligned).
    let shorts = |points: &mut dyn Iterator<Item = [i32; 3]>| {
        let mut out = Vec::new();
        let (mut lo, mut hi) = ([i32::MAX; 3], [i32::MIN; 3]);
        for q in points {
            for (c, &x) in q.iter().enumerate() {
                lo[c] = lo[c].min(x);
                hi[c] = hi[c].max(x);
                out.extend_from_slice(&(x as i16).to_le_bytes());
            }
            out.extend_from_slice(&[0, 0]);
        }
        let range = (
            json::Value::from(lo.to_vec()),
            json::Value::from(hi.to_vec()),
        );
        (out, range)
    };
    let positions = match &grid {
        None => {
            let v = view(
                &mut root,
                &mut bin,
                vec3s(&take.rest),
                None,
                Some(B::ArrayBuffer),
            );
            root.push(accessor(
                v,
                0,
                n,
                C::F32,
                T::Vec3,
                Some(bounds(&mut take.rest.iter().copied())),
            ))
        }
        Some(g) => {
            let (bytes, range) = shorts(&mut take.rest.iter().map(|&p| g.point(p)));
            let v = view(&mut root, &mut bin, bytes, Some(8), Some(B::ArrayBuffer));
            root.push(accessor(v, 0, n, C::I16, T::Vec3, Some(range)))
        }
    };
    let normals: Vec<glam::Vec3> = take
        .normals
        .iter()
        .map(|m| m.normalize_or(glam::Vec3::Z))
        .chain(std::iter::repeat(glam::Vec3::Z))
        .take(n)
        .collect();
    let v = view(
        &mut root,
        &mut bin,
        vec3s(&normals),
        None,
        Some(B::ArrayBuffer),
    );
    let normals = root.push(accessor(v, 0, n, C::F32, T::Vec3, None));

    // One target per frame: its displacement from the rest surface.
    let size = if grid.is_some() { 8 } else { 12 };
    let mut deltas = Vec::with_capacity(frames * n * size);
    let mut ranges = Vec::with_capacity(frames);
    let rest_points: Vec<[i32; 3]> = match &grid {
        Some(g) => take.rest.iter().map(|&p| g.point(p)).collect(),
        None => Vec::new(),
    };
    for frame in &take.frames {
        match &grid {
            None => {
                let d: Vec<glam::Vec3> =
                    frame.iter().zip(&take.rest).map(|(p, r)| *p - *r).collect();
                deltas.extend_from_slice(&vec3s(&d));
                ranges.push(bounds(&mut d.into_iter()));
            }
            Some(g) => {
                let (bytes, range) = shorts(&mut frame.iter().zip(&rest_points).map(|(&p, r)| {
                    let q = g.point(p);
                    [q[0] - r[0], q[1] - r[1], q[2] - r[2]]
                }));
                deltas.extend_from_slice(&bytes);
                ranges.push(range);
            }
        }
    }
    let v = view(
        &mut root,
        &mut bin,
        deltas,
        Some(size),
        Some(B::ArrayBuffer),
    );
    let mut targets = Vec::with_capacity(frames);
    let component = if grid.is_some() { C::I16 } else { C::F32 };
    for (k, range) in ranges.into_iter().enumerate() {
        let a = root.push(accessor(
            v,
            k * n * size,
            n,
            component,
            T::Vec3,
            Some(range),
        ));
        targets.push(json::mesh::MorphTarget {
            positions: Some(a),
            normals: None,
            tangents: None,
        });
    }
    let mut attributes = std::collections::BTreeMap::new();
    attributes.insert(Valid(json::mesh::Semantic::Positions), positions);
    attributes.insert(Valid(json::mesh::Semantic::Normals), normals);
    let mesh = root.push(json::Mesh {
        extensions: None,
        extras: Default::default(),
        name: Some("puppet".into()),
        primitives: vec![json::mesh::Primitive {
            attributes,
            extensions: None,
            extras: Default::default(),
            indices: Some(indices),
            material: None,
            mode: Valid(json::mesh::Mode::Triangles),
            targets: Some(targets),
        }],
        weights: Some(vec![0.0; frames]),
    });
    let node = root.push(json::Node {
        mesh: Some(mesh),
        name: Some("puppet".into()),
        // The quantisation grid back to mesh units.
        translation: grid.map(|g| g.center.to_array()),
        scale: grid.map(|g| [g.scale; 3]),
        ..Default::default()
    });
    if grid.is_some() {
        root.extensions_used.push("KHR_mesh_quantization".into());
        root.extensions_required
            .push("KHR_mesh_quantization".into());
    }
    let scene = root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: None,
        nodes: vec![node],
    });
    root.scene = Some(scene);

    // The weights over the animation's clock: glTF time t shows the state at time t. Target
    // j (frame `first + j × step`) is 1 at that frame's time `number / fps`, the others 0;
    // a take from frame 1 starts with the rest surface at 0 (every weight 0), where the
    // simulation starts, and one from a later first frame starts at that frame's time.
    let rest_key = take.first <= 1;
    let keys = frames + usize::from(rest_key);
    let mut times = Vec::with_capacity(keys * 4);
    if rest_key {
        f32s(&mut times, 0.0);
    }
    for j in 0..frames {
        f32s(&mut times, take.time(j) as f32);
    }
    let (first_time, last_time) = (
        if rest_key { 0.0 } else { take.time(0) as f32 },
        take.time(frames - 1) as f32,
    );
    let v = view(&mut root, &mut bin, times, None, None);
    let input = root.push(accessor(
        v,
        0,
        keys,
        C::F32,
        T::Scalar,
        Some((
            json::Value::from(vec![first_time]),
            json::Value::from(vec![last_time]),
        )),
    ));
    let mut weights = Vec::with_capacity(keys * frames * 4);
    if rest_key {
        for _ in 0..frames {
            f32s(&mut weights, 0.0);
        }
    }
    for k in 0..frames {
        for j in 0..frames {
            f32s(&mut weights, if j == k { 1.0 } else { 0.0 });
        }
    }
    let v = view(&mut root, &mut bin, weights, None, None);
    let output = root.push(accessor(v, 0, keys * frames, C::F32, T::Scalar, None));
    root.push(json::Animation {
        extensions: None,
        extras: Default::default(),
        channels: vec![json::animation::Channel {
            sampler: json::Index::new(0),
            target: json::animation::Target {
                extensions: None,
                extras: Default::default(),
                node,
                path: Valid(json::animation::Property::MorphTargetWeights),
            },
            extensions: None,
            extras: Default::default(),
        }],
        name: Some("take".into()),
        samplers: vec![json::animation::Sampler {
            extensions: None,
            extras: Default::default(),
            input,
            interpolation: Valid(json::animation::Interpolation::Linear),
            output,
        }],
    });
    root.push(json::Buffer {
        byte_length: USize64::from(bin.len()),
        extensions: None,
        extras: Default::default(),
        name: None,
        uri: None,
    });

    let text = json::serialize::to_string(&root).map_err(|e| ExportError::Gltf(e.to_string()))?;
    let mut json_bytes = text.into_bytes();
    while json_bytes.len() % 4 != 0 {
        json_bytes.push(b' ');
    }
    let length = 12 + 8 + json_bytes.len() + 8 + bin.len();
    let length = u32::try_from(length).map_err(|_| {
        ExportError::TooLarge(format!("a .glb holds at most 4 GiB ({length} bytes)"))
    })?;
    let glb = gltf::binary::Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length,
        },
        json: Cow::Owned(json_bytes),
        bin: Some(Cow::Owned(bin)),
    };
    glb.to_vec().map_err(|e| ExportError::Gltf(e.to_string()))
}
