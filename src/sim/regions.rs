//! Several materials on one puppet (paper §5) and pinning, per vertex.
//!
//! [`Regions`] holds material [`Layer`]s, each a material with a weight 0..1 per rig vertex,
//! and a pin weight per vertex (0: simulated, 1: glued to its bones). A vertex's parameters
//! are the simulation's own [`Params`] blended towards each layer's in turn by the layer's
//! weight there, so a painted brush with a soft edge gives a soft change of material. Of a
//! layer's material the step takes the per-vertex fields, `C_vd`, `D`, `d_B`, `sl_max`,
//! `f_min` and the stiffening exponent (the layer's where its weight is at least ½); the
//! constraint, time step, gravity and floor are the simulation's.
//!
//! The step keeps one pass: when no layer has weight anywhere and nothing is pinned,
//! nothing of this exists ([`Regions::is_uniform`]) and the kernel reads its constants from
//! the parameters as before; otherwise it reads them per slot from [`PerSlot`].

use super::{Params, REFERENCE_STEP};

/// A material and where it applies.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layer {
    /// The material.
    pub params: Params,
    /// Per rig vertex: how much of the material applies, 0..1 (missing entries: 0).
    pub weight: Vec<f32>,
}

/// Material layers and pin weights of every rig vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Regions {
    /// Layers, blended over the base material in order.
    pub layers: Vec<Layer>,
    /// Per rig vertex: pin weight 0..1 (empty: nothing pinned).
    pub pin: Vec<f32>,
}

/// A weight read as 0..1 (NaN and missing entries count as 0).
fn weight(w: &[f32], i: usize) -> f32 {
    let w = w.get(i).copied().unwrap_or(0.0);
    if w.is_nan() {
        0.0
    } else {
        w.clamp(0.0, 1.0)
    }
}

fn lerp(a: f32, b: f32, w: f32) -> f32 {
    a + (b - a) * w
}

impl Regions {
    /// True when every vertex has the base material and nothing is pinned.
    pub fn is_uniform(&self) -> bool {
        !self.is_mixed() && !self.is_pinned()
    }

    /// True when some vertex has some of another material than the base one.
    pub fn is_mixed(&self) -> bool {
        // NaN is not above 0: the same as `weight`'s reading.
        self.layers
            .iter()
            .any(|l| l.weight.iter().any(|&w| w > 0.0))
    }

    /// True when some vertex is pinned.
    pub fn is_pinned(&self) -> bool {
        self.pin.iter().any(|&w| w > 0.0)
    }

    /// The parameters of vertex `i`: `base` blended towards each layer's material.
    pub fn params_of(&self, i: usize, base: &Params) -> Params {
        let mut p = *base;
        for layer in &self.layers {
            let w = weight(&layer.weight, i);
            if w <= 0.0 {
                continue;
            }
            let m = layer.params.sanitized();
            p.damping = lerp(p.damping, m.damping, w);
            p.stiffness = lerp(p.stiffness, m.stiffness, w);
            p.bone_distance = lerp(p.bone_distance, m.bone_distance, w);
            p.max_length = lerp(p.max_length, m.max_length, w);
            p.min_length = lerp(p.min_length, m.min_length, w);
            if w >= 0.5 {
                p.stiffening = m.stiffening;
            }
        }
        p.sanitized()
    }

    /// Pin weight of vertex `i`, 0..1.
    pub fn pin_of(&self, i: usize) -> f32 {
        weight(&self.pin, i)
    }
}

/// The per-slot constants the kernel reads for mixed materials, in solver order.
#[derive(Clone, Debug, Default)]
pub(super) struct PerSlot {
    /// `C_vd^(h/h₀)`.
    pub damping: Vec<f32>,
    /// `D (h/h₀)²`.
    pub stiffness: Vec<f32>,
    /// `sl_max − 1`.
    pub reach: Vec<f32>,
    /// `f_min` and `sl_max`.
    pub min_length: Vec<f32>,
    pub max_length: Vec<f32>,
    /// The stiffening exponent, as a float.
    pub exponent: Vec<f32>,
    /// The largest exponent.
    pub max_exponent: u32,
}

impl PerSlot {
    /// The constants of every slot from each rig vertex's parameters (`order`: slot →
    /// rig vertex; `base` gives the step).
    pub fn new(of_vertex: &[Params], base: &Params, order: &[u32]) -> PerSlot {
        let ratio = base.time_step / REFERENCE_STEP;
        let mut out = PerSlot::default();
        for &v in order {
            let p = &of_vertex[v as usize];
            out.damping.push(p.damping.powf(ratio));
            out.stiffness.push(p.stiffness * ratio * ratio);
            out.reach.push(p.max_length - 1.0);
            out.min_length.push(p.min_length);
            out.max_length.push(p.max_length);
            out.exponent.push(p.stiffening as f32);
            out.max_exponent = out.max_exponent.max(p.stiffening);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_of_blends_only_the_material_fields() {
        let base = Params {
            gravity: [0.0, -1.0, 0.0],
            time_step: 1.0 / 120.0,
            ..Params::default()
        };
        let water = Params {
            damping: 0.99,
            bone_distance: 1.0,
            max_length: 1.4,
            time_step: 1.0 / 60.0,
            stiffening: 3,
            ..Params::default()
        };
        let r = Regions {
            layers: vec![Layer {
                params: water,
                weight: vec![0.0, 1.0, 0.5, f32::NAN],
            }],
            pin: vec![0.0, f32::NAN, 2.0],
        };
        assert!(r.is_mixed() && r.is_pinned() && !r.is_uniform());
        assert_eq!(r.params_of(0, &base), base);
        let p = r.params_of(1, &base);
        assert_eq!((p.damping, p.max_length, p.stiffening), (0.99, 1.4, 3));
        assert_eq!((p.gravity, p.time_step), (base.gravity, base.time_step));
        let half = r.params_of(2, &base);
        assert_eq!(half.bone_distance, 0.6);
        assert_eq!(r.params_of(3, &base), base, "NaN weight: the base");
        assert_eq!(r.params_of(9, &base), base, "past the end: the base");
        assert_eq!((r.pin_of(0), r.pin_of(1), r.pin_of(2)), (0.0, 0.0, 1.0));
        assert!(Regions::default().is_uniform());
    }
}
