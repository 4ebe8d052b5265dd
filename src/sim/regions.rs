//! Several materials on one puppet (paper §5) and pinning, per vertex.
//!
//! [`Regions`] holds material [`Layer`]s, each a material with a weight 0..1 per rig vertex,
//! and a pin weight per vertex (0: simulated, 1: glued to its bones). A vertex's
//! [`Material`] is the simulation's base material blended towards each layer's in turn by
//! the layer's weight there ([`Material::blend`]), so a painted brush with a soft edge gives
//! a soft change of material. The solver and the world are the simulation's.
//!
//! The step keeps one pass: when no layer has weight anywhere and nothing is pinned,
//! nothing of this exists ([`Regions::is_uniform`]) and the kernel reads its constants from
//! the parameters as before; otherwise it reads them per slot from [`PerSlot`].

use super::{Material, REFERENCE_STEP};

/// A material and where it applies.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layer {
    /// The material.
    pub material: Material,
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

    /// The material of vertex `i`: `base` blended towards each layer's material.
    pub fn material_of(&self, i: usize, base: &Material) -> Material {
        let mut m = *base;
        for layer in &self.layers {
            let w = weight(&layer.weight, i);
            if w > 0.0 {
                m = m.blend(&layer.material.sanitized(), w);
            }
        }
        m.sanitized()
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
    /// The constants of every slot from each rig vertex's material (`order`: slot → rig
    /// vertex) at the step `time_step`.
    pub fn new(of_vertex: &[Material], time_step: f32, order: &[u32]) -> PerSlot {
        let ratio = time_step / REFERENCE_STEP;
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
    fn material_of_blends_the_layers() {
        let base = Material::default();
        let water = Material {
            damping: 0.99,
            bone_distance: 1.0,
            max_length: 1.4,
            stiffening: 3,
            ..Material::default()
        };
        let r = Regions {
            layers: vec![Layer {
                material: water,
                weight: vec![0.0, 1.0, 0.5, f32::NAN],
            }],
            pin: vec![0.0, f32::NAN, 2.0],
        };
        assert!(r.is_mixed() && r.is_pinned() && !r.is_uniform());
        assert_eq!(r.material_of(0, &base), base);
        assert_eq!(r.material_of(1, &base), water);
        let half = r.material_of(2, &base);
        assert_eq!((half.bone_distance, half.stiffening), (0.6, 3));
        assert_eq!(r.material_of(3, &base), base, "NaN weight: the base");
        assert_eq!(r.material_of(9, &base), base, "past the end: the base");
        assert_eq!((r.pin_of(0), r.pin_of(1), r.pin_of(2)), (0.0, 0.0, 1.0));
        assert!(Regions::default().is_uniform());
    }
}
