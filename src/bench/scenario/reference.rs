//! The accuracy reference: the simulation's equations in `f64`, written plainly and
//! independently of the optimized solver (input vertex order, one array of vectors per
//! quantity, no tiles, no sleeping). Run with a much smaller time step and refined until it
//! stops changing, it is the "converged solution" that every configuration's error is
//! measured against; run at the normal step it is the "f64" configuration.

use super::Scenario;
use crate::sim::{Constraint, Params, REFERENCE_STEP};
use glam::{DAffine3, DVec3};
use rayon::prelude::*;

/// The `f64` solver.
pub struct Reference {
    rest: Vec<DVec3>,
    normal: Vec<DVec3>,
    bone_length: Vec<f64>,
    start: Vec<usize>,
    neighbour: Vec<usize>,
    neighbour_rest: Vec<f64>,
    neighbour_stiffness: Vec<f64>,
    section_of: Vec<u16>,
    params: Params,
    h: f64,
    cur: Vec<DVec3>,
    prev: Vec<DVec3>,
    next: Vec<DVec3>,
}

impl Reference {
    /// At rest, stepping by `h` seconds.
    pub fn new(scenario: &Scenario, params: Params, h: f64) -> Reference {
        let params = params.sanitized();
        let mesh = &scenario.mesh;
        let n = mesh.positions.len();
        let mut adj = vec![Vec::new(); n];
        for (a, b) in crate::mesh::unique_edges(&mesh.triangles) {
            adj[a as usize].push(b as usize);
            adj[b as usize].push(a as usize);
        }
        let mut start = vec![0];
        let mut neighbour = Vec::new();
        let mut neighbour_rest = Vec::new();
        for (i, list) in adj.iter().enumerate() {
            for &j in list {
                neighbour.push(j);
                neighbour_rest.push((mesh.positions[j] - mesh.positions[i]).length());
            }
            start.push(neighbour.len());
        }
        // Each spring's stiffness: the mean rest length over its own (see `crate::rig`).
        let mean = neighbour_rest.iter().sum::<f64>() / neighbour_rest.len().max(1) as f64;
        // (A spring shorter than `mean / MAX_STIFFNESS` pulls toward that length.)
        let most = f64::from(crate::rig::MAX_STIFFNESS);
        let neighbour_stiffness: Vec<f64> = neighbour_rest
            .iter_mut()
            .map(|rest| {
                if *rest > 0.0 && mean / *rest <= most {
                    mean / *rest
                } else {
                    *rest = mean / most;
                    most
                }
            })
            .collect();
        let f_bd = params.material.bone_distance as f64;
        Reference {
            rest: mesh.positions.clone(),
            normal: scenario.normals.clone(),
            bone_length: scenario.distance.iter().map(|d| f_bd * d).collect(),
            start,
            neighbour,
            neighbour_rest,
            neighbour_stiffness,
            section_of: scenario.joints.section_of().to_vec(),
            params,
            h,
            cur: mesh.positions.clone(),
            prev: mesh.positions.clone(),
            next: mesh.positions.clone(),
        }
    }

    /// Current positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.cur
    }

    /// One step with the sections' world transforms `world`.
    pub fn step(&mut self, world: &[DAffine3]) {
        let p = self.params;
        let ratio = self.h / REFERENCE_STEP as f64;
        let k = p.material.stiffness as f64 * ratio * ratio;
        let c = (p.material.damping as f64).powf(ratio);
        let mut next = std::mem::take(&mut self.next);
        let this = &*self;
        let update = |i: usize| -> DVec3 {
            let t = world
                .get(this.section_of[i] as usize)
                .copied()
                .unwrap_or(DAffine3::IDENTITY);
            let r = t.transform_point3(this.rest[i]);
            let n = t.transform_vector3(this.normal[i]).normalize_or_zero();
            let l = this.bone_length[i];
            let (bi, bo) = (r - l * n, r + l * n);
            let x = this.cur[i];
            let mut f = DVec3::ZERO;
            let mut mass = 2.0;
            for s in this.start[i]..this.start[i + 1] {
                let stiffness = this.neighbour_stiffness[s];
                f += stiffness * stretch(this.cur[this.neighbour[s]] - x, this.neighbour_rest[s]);
                mass += stiffness;
            }
            f += stretch(bi - x, l);
            f += stretch(bo - x, l);
            let y = x + c * (x - this.prev[i]) + (k / mass) * f;
            match p.solver.constraint {
                Constraint::Circumsphere => {
                    let rho = (p.material.max_length as f64 - 1.0) * l;
                    let v = y - r;
                    if v.length() <= rho {
                        y
                    } else {
                        r + v * (rho / v.length())
                    }
                }
                Constraint::SpringReduction => reduce(y, r, n, l, &p),
            }
        };
        next.par_iter_mut()
            .enumerate()
            .for_each(|(i, y)| *y = update(i));
        self.next = next;
        std::mem::swap(&mut self.prev, &mut self.cur);
        std::mem::swap(&mut self.cur, &mut self.next);
    }
}

fn stretch(d: DVec3, rest: f64) -> DVec3 {
    let len = d.length();
    if len > 0.0 {
        d * ((len - rest) / len)
    } else {
        DVec3::ZERO
    }
}

/// Provot's spring reduction on both bone springs, as in the solver, in `f64`.
fn reduce(mut y: DVec3, r: DVec3, n: DVec3, l: f64, p: &Params) -> DVec3 {
    let (inner, outer) = (r - l * n, r + l * n);
    let (lo, hi) = (
        p.material.min_length as f64 * l,
        p.material.max_length as f64 * l,
    );
    let ok = |y: DVec3| {
        let slack = 1e-12 * hi.max(1e-300);
        [inner, outer].iter().all(|b| {
            let len = (y - *b).length();
            len >= lo - slack && len <= hi + slack
        })
    };
    for _ in 0..p.solver.reduction_iterations {
        let mut violated = false;
        for (b, away) in [(inner, n), (outer, -n)] {
            let v = y - b;
            let len = v.length();
            if len > hi {
                y = b + v * (hi / len);
                violated = true;
            } else if len < lo {
                y = if len > 0.0 {
                    b + v * (lo / len)
                } else {
                    b + away * lo
                };
                violated = true;
            }
        }
        if !violated {
            return y;
        }
    }
    if ok(y) {
        return y;
    }
    let (mut feasible, mut infeasible) = (0.0, 1.0);
    for _ in 0..50 {
        let s = 0.5 * (feasible + infeasible);
        if ok(r + (y - r) * s) {
            feasible = s;
        } else {
            infeasible = s;
        }
    }
    r + (y - r) * feasible
}
