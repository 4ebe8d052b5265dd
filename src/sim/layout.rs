//! The solver's memory layout: the rig's data renumbered along a Hilbert curve and cut into
//! tiles.
//!
//! * **Order.** Vertex `v` of the rig is solver slot `slot[v]`; slot `k` holds vertex
//!   `order[k]`. Slots follow the 3D Hilbert curve of the rest positions, so a vertex's
//!   neighbours sit in nearby slots and the step's neighbour gathers hit cache lines that are
//!   already loaded (it matters most on Loop-subdivided meshes, which append every new vertex
//!   at the end).
//! * **Tiles.** Consecutive runs of [`Layout::tile`] slots. A tile is the unit of work of one
//!   parallel task and the unit of sleeping: Hilbert tiles are compact patches of the surface,
//!   so a still region is a set of whole tiles. For each tile the layout keeps the sections its
//!   vertices belong to (a pose change wakes exactly those tiles) and the tiles its springs
//!   reach (motion wakes neighbours).
//! * Per-slot constants the step reads ([`Slots`]: rest position, normal, section, bone
//!   length `L`, the measured rest lengths of both bone springs, `1/m`) as struct-of-arrays,
//!   so the kernel loads eight slots of one constant with one instruction; positions
//!   [`Packed`] 16 bytes apart, so a neighbour is one 16-byte load.
//! * The surface springs twice: as a CSR of `(neighbour slot, stiffness)` (the
//!   layout's own bookkeeping), and as the kernel reads them, in spring rows per group of
//!   [`Layout::LANES`] slots (see `lane_stiffness`).

use crate::rig::Rig;
use glam::Vec3;

/// Length of `(x, y, z)` exactly as the step's kernel computes it (so rest lengths measured
/// here give exactly zero force at rest).
#[inline(always)]
pub(super) fn len3(x: f32, y: f32, z: f32) -> f32 {
    (x * x + y * y + z * z).sqrt()
}

/// Struct-of-arrays vectors.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Soa {
    /// The x coordinates.
    pub x: Vec<f32>,
    /// The y coordinates.
    pub y: Vec<f32>,
    /// The z coordinates.
    pub z: Vec<f32>,
}

impl Soa {
    /// Vector `k`.
    #[inline(always)]
    pub fn get(&self, k: usize) -> Vec3 {
        Vec3::new(self.x[k], self.y[k], self.z[k])
    }

    /// Number of vectors.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// True when there is none.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }
}

/// Points packed 16 bytes apart (`x, y, z` and an unused fourth `f32`): the step's
/// neighbour loads then touch one cache line per neighbour instead of three.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Packed(pub Vec<[f32; 4]>);

impl Packed {
    /// Point `k`.
    #[inline(always)]
    pub fn get(&self, k: usize) -> Vec3 {
        let [x, y, z, _] = self.0[k];
        Vec3::new(x, y, z)
    }

    #[inline(always)]
    pub(super) fn set(&mut self, k: usize, p: Vec3) {
        self.0[k] = [p.x, p.y, p.z, 0.0];
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// True when there is none.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Copies slots `range` from `other`.
    pub(super) fn copy_range(&mut self, other: &Packed, range: std::ops::Range<usize>) {
        self.0[range.clone()].copy_from_slice(&other.0[range]);
    }
}

/// The constants of every slot, struct-of-arrays.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Slots {
    /// Rest position `p_i`.
    pub rest: Soa,
    /// Unit normal `n_i`.
    pub normal: Soa,
    /// Bone length `L_i`.
    pub bone_length: Vec<f32>,
    /// Rest length of the inner bone spring as the kernel measures it.
    pub inner_rest: Vec<f32>,
    /// Rest length of the outer bone spring as the kernel measures it.
    pub outer_rest: Vec<f32>,
    /// Joint section.
    pub section: Vec<u16>,
    /// `1 / m`, the mass being the sum of the point's spring stiffnesses (its surface
    /// springs' and 1 for each of its two bone springs; see [`crate::rig`]).
    pub inv_mass: Vec<f32>,
}

/// A surface half-spring in the CSR: the neighbour's slot and the stiffness (the rest
/// length is the rig's; the kernel needs none, see `lane_stiffness`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct Edge {
    /// The neighbour's slot.
    pub neighbour: u32,
    /// The spring's stiffness ([`crate::rig::stiffness`]).
    pub stiffness: f32,
}

/// The rig in solver order (see the module docs).
#[derive(Clone, Debug)]
pub struct Layout {
    /// Slot -> rig vertex.
    pub order: Vec<u32>,
    /// Rig vertex -> slot.
    pub slot: Vec<u32>,
    /// Per-slot constants.
    pub slots: Slots,
    /// CSR of surface springs by slot: the springs of slot `k` are
    /// `edges[start[k]..start[k+1]]`.
    pub start: Vec<u32>,
    /// The half-springs (see `start`).
    pub edges: Vec<Edge>,
    /// The surface springs in the kernel's order: the slots of each tile in groups of
    /// [`Layout::LANES`] (the last group of a tile may be short), and for group `g` the
    /// entries `group_start[g]..group_start[g + 1]` of the offsets ([`Layout::lane_offsets`])
    /// and `lane_stiffness` as rows of `LANES`, row `r` holding the `r`-th spring (CSR
    /// order) of each slot of the group: its neighbour, as the offset of that slot's point
    /// in the packed positions counted in `f32` (4 × the slot: x86 addressing scales it by 4
    /// into bytes, so the kernel's loads need no shift), and its stiffness `c`. The kernel
    /// needs no rest length: `c · rest = ℓ̄` ([`Layout::spring_length`]), so the force
    /// `c (len − rest) / len · d` is `(c − ℓ̄ / len) · d`. Rows are padded to the group's
    /// largest valence with the slot itself and stiffness 0 (a zero-length spring, zero
    /// force). Lanes past a short group's end repeat its last slot's springs, so the
    /// kernel's results in those lanes are exactly that slot's.
    ///
    /// Invariant the kernel's unchecked loads rely on: every offset + 4 ≤ 4 × [`Layout::len`].
    /// `build_lanes` is the only writer and keeps it (private, read through the method).
    lane_offset: Vec<u32>,
    /// Stiffnesses of the spring rows (see above).
    pub lane_stiffness: Vec<f32>,
    /// The surface springs' mean rest length `ℓ̄` ([`Rig::spring_length`]).
    pub spring_length: f32,
    /// Where each group's rows start (see above).
    pub group_start: Vec<u32>,
    /// Slots per tile.
    pub tile: usize,
    /// Sections present in tile `t`: `tile_sections[tile_section_start[t]..[t+1]]`.
    pub tile_section_start: Vec<u32>,
    /// The sections of all tiles (see `tile_section_start`).
    pub tile_sections: Vec<u16>,
    /// Tiles reached by the springs of tile `t` (itself excluded), same CSR shape.
    pub tile_neighbour_start: Vec<u32>,
    /// The neighbours of all tiles (see `tile_neighbour_start`).
    pub tile_neighbours: Vec<u32>,
}

impl Layout {
    /// Renumbers `rig` along the Hilbert curve and cuts it into tiles of `tile` slots (at
    /// least 1).
    pub fn new(rig: &Rig, tile: usize) -> Layout {
        let n = rig.len();
        let points: Vec<glam::DVec3> = rig.rest.iter().map(|p| p.as_dvec3()).collect();
        let order = crate::geom::hilbert::hilbert_order(&points);
        let mut slot = vec![0u32; n];
        for (k, &v) in order.iter().enumerate() {
            slot[v as usize] = k as u32;
        }
        let mut start = Vec::with_capacity(n + 1);
        let mut edges = Vec::with_capacity(rig.neighbour.len());
        start.push(0u32);
        for &v in &order {
            let (a, b) = (
                rig.start[v as usize] as usize,
                rig.start[v as usize + 1] as usize,
            );
            let first = edges.len();
            edges.extend((a..b).map(|s| Edge {
                neighbour: slot[rig.neighbour[s] as usize],
                stiffness: rig.neighbour_stiffness[s],
            }));
            // Neighbours in slot order: the gathers then walk memory forwards.
            edges[first..].sort_unstable_by_key(|e| e.neighbour);
            start.push(edges.len() as u32);
        }
        let soa = |f: &dyn Fn(usize) -> Vec3| {
            let v: Vec<Vec3> = order.iter().map(|&i| f(i as usize)).collect();
            Soa {
                x: v.iter().map(|p| p.x).collect(),
                y: v.iter().map(|p| p.y).collect(),
                z: v.iter().map(|p| p.z).collect(),
            }
        };
        let slots = Slots {
            rest: soa(&|i| rig.rest[i]),
            normal: soa(&|i| rig.normals[i]),
            bone_length: vec![0.0; n],
            inner_rest: vec![0.0; n],
            outer_rest: vec![0.0; n],
            section: vec![0; n],
            inv_mass: (0..n)
                .map(|k| {
                    let springs = &edges[start[k] as usize..start[k + 1] as usize];
                    1.0 / (springs.iter().map(|e| e.stiffness).sum::<f32>() + 2.0)
                })
                .collect(),
        };
        let tile = tile.max(1);
        let mut layout = Layout {
            lane_offset: Vec::new(),
            lane_stiffness: Vec::new(),
            spring_length: rig.spring_length,
            group_start: Vec::new(),
            slots,
            start,
            edges,
            tile,
            tile_section_start: Vec::new(),
            tile_sections: Vec::new(),
            tile_neighbour_start: Vec::new(),
            tile_neighbours: Vec::new(),
            order,
            slot,
        };
        layout.set_bone_length(rig);
        layout.build_tile_neighbours();
        layout.build_lanes();
        layout.build_tile_sections();
        layout
    }

    /// Number of slots.
    pub fn len(&self) -> usize {
        self.order.len()
    }

    /// True for a rig without vertices.
    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// Number of tiles.
    pub fn tiles(&self) -> usize {
        self.len().div_ceil(self.tile)
    }

    /// Slots of tile `t`.
    pub fn tile_range(&self, t: usize) -> std::ops::Range<usize> {
        t * self.tile..((t + 1) * self.tile).min(self.len())
    }

    /// Rest positions by slot.
    pub fn rest_positions(&self) -> Packed {
        Packed(
            (0..self.len())
                .map(|k| self.slots.rest.get(k).extend(0.0).to_array())
                .collect(),
        )
    }

    /// Refreshes `L` and the bone springs' rest lengths after the rig's bone distance changed.
    pub fn set_bone_length(&mut self, rig: &Rig) {
        let d = &mut self.slots;
        for (k, &v) in self.order.iter().enumerate() {
            let l = rig.bone_length[v as usize];
            let (p, m) = (d.rest.get(k), d.normal.get(k));
            // The same expressions as the kernel: inner = p - L m, outer = p + L m.
            let (bi, bo) = (p - l * m, p + l * m);
            d.bone_length[k] = l;
            d.inner_rest[k] = len3(bi.x - p.x, bi.y - p.y, bi.z - p.z);
            d.outer_rest[k] = len3(bo.x - p.x, bo.y - p.y, bo.z - p.z);
        }
    }

    /// Assigns sections (by rig vertex) and rebuilds each tile's section list.
    pub fn set_sections(&mut self, section_of: &[u16]) {
        for (s, &v) in self.slots.section.iter_mut().zip(&self.order) {
            *s = section_of[v as usize];
        }
        self.build_tile_sections();
    }

    fn build_tile_sections(&mut self) {
        self.tile_section_start.clear();
        self.tile_sections.clear();
        self.tile_section_start.push(0);
        for t in 0..self.tiles() {
            let first = self.tile_sections.len();
            for k in self.tile_range(t) {
                let s = self.slots.section[k];
                if !self.tile_sections[first..].contains(&s) {
                    self.tile_sections.push(s);
                }
            }
            self.tile_section_start
                .push(self.tile_sections.len() as u32);
        }
    }

    fn build_tile_neighbours(&mut self) {
        self.tile_neighbour_start.clear();
        self.tile_neighbours.clear();
        self.tile_neighbour_start.push(0);
        for t in 0..self.tiles() {
            let r = self.tile_range(t);
            let (s0, s1) = (self.start[r.start] as usize, self.start[r.end] as usize);
            let first = self.tile_neighbours.len();
            self.tile_neighbours.extend(
                self.edges[s0..s1]
                    .iter()
                    .map(|e| (e.neighbour as usize / self.tile) as u32)
                    .filter(|&u| u as usize != t),
            );
            self.tile_neighbours[first..].sort_unstable();
            let mut kept = first;
            for j in first..self.tile_neighbours.len() {
                if kept == first || self.tile_neighbours[kept - 1] != self.tile_neighbours[j] {
                    self.tile_neighbours[kept] = self.tile_neighbours[j];
                    kept += 1;
                }
            }
            self.tile_neighbours.truncate(kept);
            self.tile_neighbour_start
                .push(self.tile_neighbours.len() as u32);
        }
    }

    /// Lanes of the kernel (eight `f32` fill an AVX2 register).
    pub const LANES: usize = super::lanes::LANES;

    /// The neighbour offsets of the spring rows (see the field docs above `lane_rest`).
    pub fn lane_offsets(&self) -> &[u32] {
        &self.lane_offset
    }

    /// Groups of [`Layout::LANES`] slots in a full tile.
    pub fn groups_per_tile(&self) -> usize {
        self.tile.div_ceil(Self::LANES)
    }

    /// Builds `lane_offset`, `lane_stiffness` and `group_start` (see their docs).
    fn build_lanes(&mut self) {
        const L: usize = Layout::LANES;
        let padded = self.edges.len() + self.edges.len() / 4;
        self.lane_offset = Vec::with_capacity(padded);
        self.lane_stiffness = Vec::with_capacity(padded);
        self.group_start = vec![0];
        for t in 0..self.tiles() {
            let r = self.tile_range(t);
            for g in (r.start..r.end).step_by(L) {
                let group = g..(g + L).min(r.end);
                let rows = group
                    .clone()
                    .map(|k| (self.start[k + 1] - self.start[k]) as usize)
                    .max()
                    .unwrap_or(0);
                for row in 0..rows {
                    for lane in 0..L {
                        let k = (g + lane).min(group.end - 1);
                        let e = self.start[k] as usize + row;
                        let (q, stiffness) = if e < self.start[k + 1] as usize {
                            (self.edges[e].neighbour, self.edges[e].stiffness)
                        } else {
                            (k as u32, 0.0)
                        };
                        self.lane_offset.push(4 * q);
                        self.lane_stiffness.push(stiffness);
                    }
                }
                self.group_start.push(self.lane_offset.len() as u32);
            }
        }
    }

    /// Sections of tile `t`.
    pub fn sections_of_tile(&self, t: usize) -> &[u16] {
        &self.tile_sections
            [self.tile_section_start[t] as usize..self.tile_section_start[t + 1] as usize]
    }

    /// Tiles adjacent to tile `t`.
    pub fn neighbours_of_tile(&self, t: usize) -> &[u32] {
        &self.tile_neighbours
            [self.tile_neighbour_start[t] as usize..self.tile_neighbour_start[t + 1] as usize]
    }
}
