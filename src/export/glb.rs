//! glTF binary (`.glb`): the mesh (indices, rest positions, normals) with one morph target
//! per exported frame and an animation of the morph weights (linear; at frame `k` target `k`
//! has weight 1, so between two frames two targets are active). Blender imports the targets
//! as shape keys, game engines play the animation. The JSON is built with `gltf-json`.

use super::{ExportError, Frames};
use gltf::json;
use json::validation::Checked::Valid;
use json::validation::USize64;
use std::borrow::Cow;

/// The bytes of a `.glb`.
///
/// # Errors
/// [`ExportError`] when a frame does not fit the mesh or the file would pass 4 GiB.
pub fn write(take: &Frames) -> Result<Vec<u8>, ExportError> {
    take.check()?;
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
    let v = view(
        &mut root,
        &mut bin,
        vec3s(&take.rest),
        None,
        Some(B::ArrayBuffer),
    );
    let positions = root.push(accessor(
        v,
        0,
        n,
        C::F32,
        T::Vec3,
        Some(bounds(&mut take.rest.iter().copied())),
    ));
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
    let mut deltas = Vec::with_capacity(frames * n * 12);
    let mut ranges = Vec::with_capacity(frames);
    for frame in &take.frames {
        let d: Vec<glam::Vec3> = frame.iter().zip(&take.rest).map(|(p, r)| *p - *r).collect();
        deltas.extend_from_slice(&vec3s(&d));
        ranges.push(bounds(&mut d.into_iter()));
    }
    let v = view(&mut root, &mut bin, deltas, Some(12), Some(B::ArrayBuffer));
    let mut targets = Vec::with_capacity(frames);
    for (k, range) in ranges.into_iter().enumerate() {
        let a = root.push(accessor(v, k * n * 12, n, C::F32, T::Vec3, Some(range)));
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
        ..Default::default()
    });
    let scene = root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: None,
        nodes: vec![node],
    });
    root.scene = Some(scene);

    // The weights over time: frame k at k / fps, target k at 1, the others at 0.
    let fps = if take.fps.is_finite() && take.fps > 0.0 {
        take.fps
    } else {
        30.0
    };
    let mut times = Vec::with_capacity(frames * 4);
    for k in 0..frames {
        f32s(&mut times, (k as f64 / fps) as f32);
    }
    let last = ((frames - 1) as f64 / fps) as f32;
    let v = view(&mut root, &mut bin, times, None, None);
    let input = root.push(accessor(
        v,
        0,
        frames,
        C::F32,
        T::Scalar,
        Some((
            json::Value::from(vec![0.0f32]),
            json::Value::from(vec![last]),
        )),
    ));
    let mut weights = Vec::with_capacity(frames * frames * 4);
    for k in 0..frames {
        for j in 0..frames {
            f32s(&mut weights, if j == k { 1.0 } else { 0.0 });
        }
    }
    let v = view(&mut root, &mut bin, weights, None, None);
    let output = root.push(accessor(v, 0, frames * frames, C::F32, T::Scalar, None));
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
