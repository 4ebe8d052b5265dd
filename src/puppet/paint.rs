//! Painted weights: where a material region or the pinning applies.
//!
//! A [`Paint`] is a set of sections (weight 1 on each of their vertices) and painted
//! weights per welded vertex (the order [`crate::mesh`] gives a file's vertices after
//! welding, which does not depend on how the file lists its corners). In a rig file the
//! painted weights are quantised to 0..255 and run-length encoded: `"0*1200 255*40 128 0*1689"`
//! is 1,200 vertices at 0, 40 at 1, one at 128/255, 1,689 at 0. A paint may also name the
//! mesh file's groups ([`crate::mesh::Groups`]: its materials, as `eyes` or `skin`). A
//! weight is the largest of the painted one, its section's and its groups'.

use crate::joints::Joints;
use crate::mesh::Groups;

/// Where something applies: whole sections, and painted weights per welded vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Paint {
    /// Sections (by name) whose every vertex has weight 1.
    pub sections: Vec<String>,
    /// Groups of the mesh file (by name), each vertex with its share of the group's faces.
    pub groups: Vec<String>,
    /// Painted weight per welded vertex, each a multiple of 1/255 (empty: nothing
    /// painted).
    pub weights: Vec<f32>,
}

/// Largest quantised weight.
const LEVELS: f32 = 255.0;

/// `w` quantised to a multiple of 1/255 in 0..1, as stored (NaN counts as 0).
pub fn quantise(w: f32) -> f32 {
    level(w) as f32 / LEVELS
}

fn level(w: f32) -> u8 {
    if w.is_nan() {
        0
    } else {
        (w.clamp(0.0, 1.0) * LEVELS).round() as u8
    }
}

/// Encodes weights as runs (see the module docs).
pub fn encode(weights: &[f32]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < weights.len() {
        let v = level(weights[i]);
        let mut n = 1;
        while i + n < weights.len() && level(weights[i + n]) == v {
            n += 1;
        }
        out.push(if n == 1 {
            v.to_string()
        } else {
            format!("{v}*{n}")
        });
        i += n;
    }
    out.join(" ")
}

/// Decodes runs (see the module docs); the error says which run is wrong.
pub fn decode(text: &str) -> Result<Vec<f32>, String> {
    /// Runs longer than this are a typo (no mesh is that large).
    const MAX_RUN: usize = 1 << 28;
    let mut out = Vec::new();
    for (k, run) in text.split_whitespace().enumerate() {
        let bad = || {
            format!(
                "run {} ('{run}') is not LEVEL or LEVEL*COUNT (0..255)",
                k + 1
            )
        };
        let (v, n) = match run.split_once('*') {
            Some((v, n)) => (v, n.parse::<usize>().map_err(|_| bad())?),
            None => (run, 1),
        };
        let v: u8 = v.parse().map_err(|_| bad())?;
        if n == 0 || n > MAX_RUN || out.len() + n > MAX_RUN {
            return Err(bad());
        }
        out.extend(std::iter::repeat_n(v as f32 / LEVELS, n));
    }
    Ok(out)
}

impl Paint {
    /// True when it applies nowhere.
    pub fn is_empty(&self) -> bool {
        self.sections.is_empty() && self.groups.is_empty() && self.weights.iter().all(|&w| w <= 0.0)
    }

    /// The weight of every vertex of a puppet with `joints` and the mesh file's `groups`.
    /// `strict`: a section or group name the puppet does not have, or painted weights for
    /// another number of vertices, are errors (a file); otherwise they are skipped (a
    /// session whose cuts changed).
    pub fn resolve(
        &self,
        joints: &Joints,
        groups: &Groups,
        strict: bool,
    ) -> Result<Vec<f32>, String> {
        let section_of = joints.section_of();
        let n = section_of.len();
        let mut w = vec![0.0f32; n];
        if !self.weights.is_empty() {
            if self.weights.len() != n {
                if strict {
                    return Err(format!(
                        "painted weights are for {} vertices, the mesh has {n}",
                        self.weights.len()
                    ));
                }
            } else {
                w.copy_from_slice(&self.weights);
            }
        }
        for name in &self.sections {
            match joints.sections().iter().position(|s| &s.name == name) {
                Some(k) => {
                    for (wi, &s) in w.iter_mut().zip(section_of) {
                        if s as usize == k {
                            *wi = 1.0;
                        }
                    }
                }
                None if strict => return Err(format!("no section '{name}'")),
                None => {}
            }
        }
        for name in &self.groups {
            match groups.weights_of(name) {
                Some(g) if g.len() == n => {
                    for (wi, &gi) in w.iter_mut().zip(g) {
                        *wi = wi.max(gi);
                    }
                }
                _ if strict => {
                    return Err(if groups.is_empty() {
                        format!("no group '{name}': the mesh file names no groups")
                    } else {
                        format!(
                            "no group '{name}' (the mesh file's groups: {})",
                            groups.names.join(", ")
                        )
                    })
                }
                _ => {}
            }
        }
        Ok(w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_round_trip_and_bad_runs_say_which() {
        let w = [0.0, 0.0, 0.0, 1.0, 1.0, 0.5, quantise(0.25), 0.0];
        let text = encode(&w);
        assert_eq!(text, "0*3 255*2 128 64 0");
        let back = decode(&text).unwrap();
        assert_eq!(back.len(), w.len());
        for (a, b) in back.iter().zip(w) {
            assert_eq!(*a, quantise(b));
        }
        assert_eq!(decode("").unwrap(), Vec::<f32>::new());
        assert!(decode("0*3 256").unwrap_err().starts_with("run 2 ('256')"));
        assert!(decode("1*0").is_err());
        assert!(decode("1*x").is_err());
        assert!(decode("-1").is_err());
        assert!(decode("0*999999999999").is_err());
        assert_eq!(quantise(f32::NAN), 0.0);
        assert_eq!(quantise(7.0), 1.0);
    }
}
