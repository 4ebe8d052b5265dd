//! A glTF file's skins and clips: every node's transform at rest, the skinned vertices put
//! where the file's skinning puts them at rest, the joints with their hierarchy and weight,
//! and each animation sampled as the joints' transforms over time ([`crate::mesh::Skin`]).

use super::accessor::{self, Data};
use super::{bad, MeshError};
use crate::mesh::skin::{Clip, Skin, SkinJoint, Weights, NO_WEIGHTS};
use glam::{DMat4, DQuat, DVec3};

/// Frames per second clips are sampled at.
const CLIP_FPS: f64 = 30.0;

/// The longest clip read, in frames (an hour at 30 fps).
const MAX_FRAMES: usize = 108_000;

/// How far a vertex's weights may sum from 1 (the validator's tolerance is about 2e-7 per
/// weight; exporters that write 8-bit weights round to 1/255).
const WEIGHT_SUM_TOLERANCE: f64 = 0.01;

/// One node's rest transform as translation, rotation, scale.
#[derive(Clone, Copy)]
struct Trs {
    t: DVec3,
    r: DQuat,
    s: DVec3,
}

impl Trs {
    fn matrix(&self) -> DMat4 {
        DMat4::from_scale_rotation_translation(self.s, self.r, self.t)
    }
}

/// The nodes, the joints among them, and what the skinned primitives put on each joint.
pub(super) struct Skinning {
    /// Per node, its parent.
    parent: Vec<Option<usize>>,
    /// Nodes, parents first.
    order: Vec<usize>,
    /// Per node, its rest transform.
    rest: Vec<Trs>,
    /// Per node, its transform in the scene at rest.
    globals: Vec<DMat4>,
    /// Per node, whether some skin has it as a joint, and the weight it carries.
    joint: Vec<bool>,
    weight: Vec<f64>,
    /// Per vertex of the soup so far, its four largest weights by node, largest first
    /// (`(u32::MAX, 0)` where it has fewer; all so for a vertex no skin moves).
    weights: Vec<Weights>,
    /// Vertices whose weights were not numbers, given a neighbour's.
    pub borrowed: usize,
}

impl Skinning {
    /// The file's nodes when it has a skin; `None` without one (nothing is done then).
    ///
    /// # Errors
    /// A node with two parents, or one that is its own ancestor.
    pub fn of(doc: &gltf::Document) -> Result<Option<Skinning>, MeshError> {
        if doc.skins().next().is_none() {
            return Ok(None);
        }
        let n = doc.nodes().count();
        let mut parent = vec![None; n];
        for node in doc.nodes() {
            for child in node.children() {
                if parent[child.index()].replace(node.index()).is_some() {
                    return Err(bad(format!("node {} has two parents", child.index())));
                }
            }
        }
        // Parents first: by depth, a chain longer than the nodes being a cycle.
        let mut depth = vec![0usize; n];
        for (i, d) in depth.iter_mut().enumerate() {
            let mut at = i;
            while let Some(p) = parent[at] {
                *d += 1;
                at = p;
                if *d > n {
                    return Err(bad(format!("node {i} is its own ancestor")));
                }
            }
        }
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by_key(|&i| depth[i]);
        let rest: Vec<Trs> = doc
            .nodes()
            .map(|node| {
                let (t, r, s) = node.transform().decomposed();
                Trs {
                    t: glam::Vec3::from(t).as_dvec3(),
                    r: glam::Quat::from_array(r).as_dquat().normalize(),
                    s: glam::Vec3::from(s).as_dvec3(),
                }
            })
            .collect();
        let mut joint = vec![false; n];
        for skin in doc.skins() {
            for j in skin.joints() {
                joint[j.index()] = true;
            }
        }
        let mut skinning = Skinning {
            parent,
            order,
            rest,
            globals: vec![DMat4::IDENTITY; n],
            joint,
            weight: vec![0.0; n],
            weights: Vec::new(),
            borrowed: 0,
        };
        skinning.globals = skinning.pose(&skinning.rest);
        Ok(Some(skinning))
    }

    /// Every node's transform in the scene for these local transforms.
    fn pose(&self, locals: &[Trs]) -> Vec<DMat4> {
        let mut globals = vec![DMat4::IDENTITY; locals.len()];
        for &i in &self.order {
            let local = locals[i].matrix();
            globals[i] = match self.parent[i] {
                Some(p) => globals[p] * local,
                None => local,
            };
        }
        globals
    }

    /// Notes `count` vertices that no skin moves (a primitive placed by its node).
    pub fn unskinned(&mut self, count: usize) {
        self.weights.extend(std::iter::repeat_n(NO_WEIGHTS, count));
    }

    /// The rest positions of a primitive skinned by `skin`: each vertex by its joints' rest
    /// transforms (`global · inverse bind`) and its weights, every `JOINTS_n`/`WEIGHTS_n`
    /// set counted; `None` when the primitive has no joints or weights (then it is placed
    /// by its node). The weights go to the joints' carried weight.
    ///
    /// A vertex whose weights are not numbers (as some exporters write a few) takes the
    /// joints and weights of the nearest vertex over the primitive's triangles `indices`
    /// that has numbers ([`Skinning::borrowed`] counts them).
    ///
    /// # Errors
    /// Joint numbers past the skin's joints, weights that do not sum to 1, a vertex whose
    /// weights are not numbers on a piece with none that are (nothing says where the skin
    /// holds it: its node's transform is another frame), a missing or short inverse bind
    /// matrix accessor.
    pub fn place(
        &mut self,
        skin: &gltf::Skin,
        prim: &gltf::Primitive,
        data: &Data,
        positions: &[f32],
        indices: &[u32],
    ) -> Result<Option<Vec<DVec3>>, MeshError> {
        let count = positions.len() / 3;
        let mut sets = Vec::new();
        for k in 0.. {
            match (
                prim.get(&gltf::Semantic::Joints(k)),
                prim.get(&gltf::Semantic::Weights(k)),
            ) {
                (Some(j), Some(w)) => {
                    let joints = accessor::unsigned(&j, data, 4)?;
                    let weights = accessor::floats(&w, data, 4)?;
                    if joints.len() != count * 4 || weights.len() != count * 4 {
                        return Err(bad(format!(
                            "JOINTS_{k} or WEIGHTS_{k} has not one element per vertex"
                        )));
                    }
                    sets.push((joints, weights));
                }
                _ => break,
            }
        }
        if sets.is_empty() {
            return Ok(None);
        }
        let nodes: Vec<usize> = skin.joints().map(|j| j.index()).collect();
        let inverse: Vec<DMat4> = match skin.inverse_bind_matrices() {
            Some(a) => {
                let m = accessor::floats(&a, data, 16)?;
                if m.len() < nodes.len() * 16 {
                    return Err(bad(format!(
                        "skin {}: fewer inverse bind matrices than joints",
                        skin.index()
                    )));
                }
                m.chunks_exact(16)
                    .map(|c| glam::Mat4::from_cols_slice(c).as_dmat4())
                    .collect()
            }
            None => vec![DMat4::IDENTITY; nodes.len()],
        };
        let matrices: Vec<DMat4> = nodes
            .iter()
            .zip(&inverse)
            .map(|(&node, ibm)| self.globals[node] * *ibm)
            .collect();
        // Each vertex's joints (by number in the skin) and weights, as the file gives them.
        let pairs = |v: usize| {
            sets.iter().flat_map(move |(joints, weights)| {
                (0..4)
                    .map(move |c| (joints[4 * v + c] as usize, weights[4 * v + c] as f64))
                    .filter(|&(_, w)| w != 0.0)
            })
        };
        let mut lost = Vec::new();
        for v in 0..count {
            if let Some((j, _)) = pairs(v).find(|&(j, _)| j >= matrices.len()) {
                return Err(bad(format!(
                    "skin {}: vertex {v} names joint {j}, but the skin has {}",
                    skin.index(),
                    nodes.len()
                )));
            }
            let sum: f64 = pairs(v).map(|(_, w)| w).sum();
            if !sum.is_finite() {
                // Weights that are not numbers (as an exporter wrote a few): a neighbour's.
                lost.push(v);
            } else if (sum - 1.0).abs() > WEIGHT_SUM_TOLERANCE {
                return Err(bad(format!(
                    "skin {}: vertex {v}'s weights sum to {sum}, not 1",
                    skin.index()
                )));
            }
        }
        // The vertex whose weights each vertex takes: its own, or a neighbour's.
        let source = borrow_weights(count, &lost, indices).map_err(|v| {
            bad(format!(
                "skin {}: vertex {v}'s weights are not numbers, nor any on its piece",
                skin.index()
            ))
        })?;
        self.borrowed += lost.len();
        let mut out = Vec::with_capacity(count);
        for (v, &from) in source.iter().enumerate() {
            let p = glam::Vec3::from_slice(&positions[3 * v..3 * v + 3]).as_dvec3();
            let (mut at, mut sum) = (DVec3::ZERO, 0.0);
            let mut top = NO_WEIGHTS;
            for (j, w) in pairs(from) {
                at += w * matrices[j].transform_point3(p);
                sum += w;
                self.weight[nodes[j]] += w;
                // Into the four largest, in order (a joint named twice adds up).
                let node = nodes[j] as u32;
                match top.iter().position(|t| t.0 == node) {
                    Some(k) => top[k].1 += w as f32,
                    None if (w as f32) > top[3].1 => top[3] = (node, w as f32),
                    None => {}
                }
                top.sort_by(|a, b| b.1.total_cmp(&a.1));
            }
            out.push(at / sum);
            for t in &mut top {
                t.1 /= sum as f32;
            }
            self.weights.push(top);
        }
        Ok(Some(out))
    }

    /// The joints, parents first, with their clips.
    ///
    /// # Errors
    /// A clip whose times or values are bad.
    pub fn finish(self, doc: &gltf::Document, data: &Data) -> Result<Skin, MeshError> {
        let nodes: Vec<usize> = self
            .order
            .iter()
            .copied()
            .filter(|&i| self.joint[i])
            .collect();
        let mut index = vec![usize::MAX; self.parent.len()];
        for (k, &node) in nodes.iter().enumerate() {
            index[node] = k;
        }
        let names: Vec<String> = doc
            .nodes()
            .map(|n| match n.name() {
                Some(name) if !name.trim().is_empty() => name.to_string(),
                _ => format!("joint {}", n.index()),
            })
            .collect();
        let joints = nodes
            .iter()
            .map(|&node| {
                let mut up = self.parent[node];
                while let Some(p) = up.filter(|&p| !self.joint[p]) {
                    up = self.parent[p];
                }
                SkinJoint {
                    name: names[node].clone(),
                    parent: up.map(|p| index[p]),
                    rest: self.globals[node],
                    weight: self.weight[node],
                }
            })
            .collect();
        let clips = doc
            .animations()
            .map(|a| self.clip(&a, data, &nodes))
            .collect::<Result<Vec<_>, _>>()?;
        let weights: Vec<Weights> = self
            .weights
            .iter()
            .map(|w| {
                w.map(|(node, x)| match node {
                    u32::MAX => (u32::MAX, 0.0),
                    node => (index[node as usize] as u32, x),
                })
            })
            .collect();
        Ok(Skin {
            joints,
            clips,
            vertex_joint: weights.iter().map(|w| w[0].0).collect(),
            weights,
        })
    }

    /// One animation sampled at [`CLIP_FPS`]: the joints' transforms in the scene.
    fn clip(
        &self,
        animation: &gltf::Animation,
        data: &Data,
        joints: &[usize],
    ) -> Result<Clip, MeshError> {
        use gltf::animation::Property;
        let name = match animation.name() {
            Some(n) if !n.trim().is_empty() => n.to_string(),
            _ => format!("clip {}", animation.index()),
        };
        let what = |e: String| bad(format!("animation '{name}': {e}"));
        let mut channels = Vec::new();
        let mut morph_channels = 0;
        for channel in animation.channels() {
            let property = channel.target().property();
            if property == Property::MorphTargetWeights {
                morph_channels += 1;
                continue;
            }
            let sampler = channel.sampler();
            let times = accessor::floats(&sampler.input(), data, 1)?;
            if times.iter().any(|t| !t.is_finite() || *t < 0.0)
                || times.windows(2).any(|w| w[1] < w[0])
            {
                return Err(what(
                    "key times that are negative, not finite or not increasing".into(),
                ));
            }
            let width = if property == Property::Rotation { 4 } else { 3 };
            let values = accessor::floats(&sampler.output(), data, width)?;
            let cubic = sampler.interpolation() == gltf::animation::Interpolation::CubicSpline;
            let per_key = if cubic { 3 * width } else { width };
            if times.is_empty() || values.len() != times.len() * per_key {
                return Err(what(format!(
                    "a channel with {} key times and {} values",
                    times.len(),
                    values.len() / width
                )));
            }
            if values.iter().any(|v| !v.is_finite()) {
                return Err(what("a value that is not finite".into()));
            }
            channels.push(Channel {
                node: channel.target().node().index(),
                property,
                times,
                values,
                width,
                interpolation: sampler.interpolation(),
            });
        }
        let duration = channels
            .iter()
            .filter_map(|c| c.times.last().copied())
            .fold(0.0f32, f32::max) as f64;
        let count = (duration * CLIP_FPS).ceil() as usize + 1;
        if count > MAX_FRAMES {
            return Err(what(format!("{duration} s long, more than an hour")));
        }
        let mut frames = Vec::with_capacity(count);
        let mut locals = self.rest.clone();
        for k in 0..count {
            let t = (k as f64 / CLIP_FPS).min(duration);
            for c in &channels {
                let v = c.sample(t as f32);
                let l = &mut locals[c.node];
                match c.property {
                    Property::Translation => l.t = DVec3::new(v[0], v[1], v[2]),
                    Property::Scale => l.s = DVec3::new(v[0], v[1], v[2]),
                    Property::Rotation => {
                        l.r = DQuat::from_xyzw(v[0], v[1], v[2], v[3]).normalize();
                    }
                    Property::MorphTargetWeights => {}
                }
            }
            let globals = self.pose(&locals);
            frames.push(joints.iter().map(|&j| globals[j]).collect());
        }
        Ok(Clip {
            name,
            fps: CLIP_FPS,
            duration,
            frames,
            morph_channels,
        })
    }
}

/// One animated property of one node.
struct Channel {
    node: usize,
    property: gltf::animation::Property,
    times: Vec<f32>,
    values: Vec<f32>,
    width: usize,
    interpolation: gltf::animation::Interpolation,
}

/// Per vertex of a primitive of `count`, the vertex whose weights it takes: itself, or for
/// each of `lost` (weights that are not numbers) the nearest vertex over the triangles
/// `indices` that has weights (fewest edges; of those, the first found).
///
/// # Errors
/// The first vertex of `lost` that no vertex with weights reaches.
fn borrow_weights(count: usize, lost: &[usize], indices: &[u32]) -> Result<Vec<usize>, usize> {
    let mut from: Vec<Option<usize>> = (0..count).map(Some).collect();
    if lost.is_empty() {
        return Ok((0..count).collect());
    }
    for &v in lost {
        from[v] = None;
    }
    let edges: Vec<(u32, u32)> = indices
        .chunks_exact(3)
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .collect();
    let (start, neighbours) = crate::mesh::neighbours(count, &edges);
    let mut queue: std::collections::VecDeque<usize> =
        (0..count).filter(|&v| from[v].is_some()).collect();
    while let Some(v) = queue.pop_front() {
        for &u in &neighbours[start[v] as usize..start[v + 1] as usize] {
            let u = u as usize;
            if from[u].is_none() {
                from[u] = from[v];
                queue.push_back(u);
            }
        }
    }
    from.iter().enumerate().map(|(v, f)| f.ok_or(v)).collect()
}

impl Channel {
    /// The value at `t`, as the glTF spec interpolates it (rotations by slerp, cubic
    /// splines by Hermite), held before the first key and after the last.
    fn sample(&self, t: f32) -> [f64; 4] {
        use gltf::animation::Interpolation;
        let w = self.width;
        let cubic = self.interpolation == Interpolation::CubicSpline;
        let per_key = if cubic { 3 * w } else { w };
        // The value of key k (the middle of a cubic triplet), and its tangents.
        let value = |k: usize, part: usize| -> [f64; 4] {
            let at = k * per_key + if cubic { part * w } else { 0 };
            let mut out = [0.0; 4];
            for (o, v) in out.iter_mut().zip(&self.values[at..at + w]) {
                *o = *v as f64;
            }
            out
        };
        let n = self.times.len();
        let next = self.times.partition_point(|&x| x <= t);
        if next == 0 {
            return value(0, 1);
        }
        if next >= n {
            return value(n - 1, 1);
        }
        let (k, t0, t1) = (next - 1, self.times[next - 1], self.times[next]);
        let span = (t1 - t0) as f64;
        let s = if span > 0.0 {
            (t - t0) as f64 / span
        } else {
            0.0
        };
        match self.interpolation {
            Interpolation::Step => value(k, 1),
            Interpolation::Linear => {
                let (a, b) = (value(k, 1), value(k + 1, 1));
                if w == 4 {
                    let qa = DQuat::from_array(a).normalize();
                    let qb = DQuat::from_array(b).normalize();
                    qa.slerp(qb, s).to_array()
                } else {
                    std::array::from_fn(|c| a[c] + (b[c] - a[c]) * s)
                }
            }
            Interpolation::CubicSpline => {
                let (v0, b0) = (value(k, 1), value(k, 2));
                let (a1, v1) = (value(k + 1, 0), value(k + 1, 1));
                let (s2, s3) = (s * s, s * s * s);
                std::array::from_fn(|c| {
                    (2.0 * s3 - 3.0 * s2 + 1.0) * v0[c]
                        + (s3 - 2.0 * s2 + s) * span * b0[c]
                        + (-2.0 * s3 + 3.0 * s2) * v1[c]
                        + (s3 - s2) * span * a1[c]
                })
            }
        }
    }
}
