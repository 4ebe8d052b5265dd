//! Occlusion in creases from the medial balls: how much of the sky each surface vertex
//! sees past the body's own flesh, as the viewport shades it (an armpit, a mouth, the
//! inside of a bent elbow, where a part presses on another).
//!
//! The skeleton gives every vertex `v` a medial ball near the surface at `v` (centre its
//! skeletal point, radius its skeletal distance `d_v`), and their union is the inside. A
//! ball of radius `r` whose centre lies at distance `d` from a point, at angle `θ` from
//! its normal, hides about `cos θ (r / d)²` of its sky (the classic sphere occluder; a ball on the point's
//! own side of its tangent plane hides nothing). So a point on a convex or flat stretch of
//! skin, whose balls all lie below it, is open, and one in a crease, with balls of the
//! other side above its tangent plane, is shaded. The balls follow the surface as it is
//! now: each keeps its offset from its vertex, turned as the vertex's normal turned since
//! rest, so a pose that folds a limb onto the body shades the fold, within one section or
//! across two, and at rest every centre is its skeletal point (inside the body: a convex
//! stretch is open).
//!
//! * **Which balls**: those [`super::balls::thin`] keeps, at rest (most balls are nearly
//!   inside a bigger one, and add nothing a bigger one does not hide).
//! * **How far**: a ball hides points within [`REACH`] of its radii from its centre, its
//!   share eased to zero there, so a ball drifting out of reach fades instead of popping.
//! * **Where**: at **samples**, points about half their own medial radius apart
//!   ([`SPACING`]), each vertex then taking the weighted mean of its [`NEAR`] nearest in
//!   its section (a crease is as wide as the balls that make it, so what they hide changes
//!   over a radius, not an edge).
//! * **What moves**: a section moves nearly rigidly, so what a section's own balls hide
//!   of its own skin is found once, at rest ([`Occluders::new`]), and a frame adds only
//!   what the other sections' balls hide ([`Occluders::shade`]). A puppet without cuts
//!   costs nothing a frame. Made once per puppet and per change of its sections: 0.1 s at
//!   46,850 vertices, 0.33 s at 187,394 on this machine (`bench draw`, its renderers'
//!   first frames). Measured on Spot subdivided
//!   twice (46,850 vertices, its head nodding, `puppet bench draw`'s scene): every ball
//!   at every vertex cost 20 ms a frame on this machine, the other sections' balls at
//!   every vertex 6 ms, at its 1,084 samples 1.0 ms.
//! * **Broad phase**: grids of cells doubling in size from the 10th percentile reach up,
//!   each ball in the one whose cells are at least as wide as its reach, so it is listed
//!   in at most eight cells; one table of buckets hashed from the cells and their grid,
//!   counted then filled, so a frame allocates nothing once grown; the balls of a section
//!   together in a bucket. A point reads its own cell's bucket in each grid, stepping over
//!   its own section's balls a run at a time. A ball bigger than the largest grid's cells
//!   (a statue's plinth, past [`GRIDS`] doublings) is tested against every point.
//!
//! The shares add up, and a point's occlusion is `1 − e^(−Σ)` (0: open sky; towards 1: a
//! deep crease).

use glam::{DVec3, IVec3, Quat, Vec3};

/// How far a ball hides points, in its radii from its centre.
pub const REACH: f32 = 3.0;

/// How far apart the points are where the other sections' balls are added up, in their
/// own medial radius (at least the 10th percentile ball's; see the module docs).
const SPACING: f32 = 0.5;

/// How many of those points a vertex's share of the other sections' occlusion is
/// interpolated from.
const NEAR: usize = 4;

/// Grids at most, each with cells twice as wide as the one before (see the module docs);
/// a ball whose reach is wider than the last's cells is tested against every point.
const GRIDS: usize = 10;

/// The balls that shade a surface, what each section's own balls hide of its skin, and
/// the storage a frame's [`Occluders::shade`] reuses.
#[derive(Clone, Debug, Default)]
pub struct Occluders {
    /// Each ball's vertex, radius and section, its centre's offset from the vertex at
    /// rest, and the vertex's normal at rest; ordered by section.
    vertex: Vec<u32>,
    radius: Vec<f32>,
    section: Vec<u16>,
    offset: Vec<Vec3>,
    normal: Vec<Vec3>,
    /// Each vertex's section, and the sum of the shares its own section's balls hide
    /// (see the module docs), at rest.
    vertex_section: Vec<u16>,
    own: Vec<f32>,
    /// More than one section: a frame has work.
    sections: bool,
    /// The first grid's cell (world units), how many grids there are, and each ball's.
    cell: f32,
    grids: usize,
    grid_of: Vec<u8>,
    /// The points where the balls are added up (see the module docs), and each vertex's
    /// nearest of them in its section with their weights.
    samples: Vec<u32>,
    near: Vec<[(u32, f32); NEAR]>,
    /// What a frame reuses.
    scratch: Scratch,
}

/// Storage [`Occluders::shade`] reuses from frame to frame (nothing in it outlives a call).
#[derive(Clone, Debug, Default)]
struct Scratch {
    /// The balls posed for the surface now: centres.
    centre: Vec<Vec3>,
    /// The bucket table: each bucket's first entry in `entries`, and the balls listed
    /// (by section within a bucket), each with the entry after its section's run there.
    start: Vec<u32>,
    entries: Vec<u32>,
    run_end: Vec<u32>,
    /// The last ball listed in each bucket (a ball meets several cells that may share a
    /// bucket: it is listed there once), and where the next goes.
    last: Vec<u32>,
    fill: Vec<u32>,
    /// The balls too big for the grids.
    huge: Vec<u32>,
    /// What the other sections' balls hide at each sample.
    sampled: Vec<f32>,
}

/// Which balls a pass adds up for a point.
#[derive(Clone, Copy, PartialEq)]
enum Whose {
    /// Its own section's.
    Own,
    /// Every other section's.
    Others,
}

impl Occluders {
    /// The balls of a surface whose vertices lie at `rest` (the faces `triangles`), have
    /// the skeletal points `points` and distances `radius`, and lie in the sections
    /// `section_of` (one each; a vertex without a ball, radius zero or not finite, shades
    /// nothing; without sections every vertex is in one). What each section's balls hide
    /// of its own skin is found here.
    pub fn new(
        rest: &[DVec3],
        triangles: &[[u32; 3]],
        points: &[DVec3],
        radius: &[f64],
        section_of: &[u16],
    ) -> Occluders {
        let n = rest.len().min(points.len()).min(radius.len());
        let section = |i: usize| section_of.get(i).copied().unwrap_or(0);
        let mut kept = super::balls::thin(&points[..n], &radius[..n], &[]);
        kept.sort_by_key(|&i| (section(i), i));
        let positions: Vec<Vec3> = rest.iter().map(|p| p.as_vec3()).collect();
        let mut normals = Vec::new();
        crate::mesh::area_normals_into(&positions, triangles, &mut normals);
        let reach = |i: usize| REACH * radius[i] as f32;
        let mut reaches: Vec<f32> = kept.iter().map(|&i| reach(i)).collect();
        reaches.sort_by(f32::total_cmp);
        let cell = reaches
            .get(reaches.len() / 10)
            .copied()
            .unwrap_or(1.0)
            .max(f32::MIN_POSITIVE);
        // Each ball's grid: the first whose cells are at least as wide as its reach.
        let grid_of: Vec<u8> = kept
            .iter()
            .map(|&i| {
                let doublings = (reach(i) / cell).log2().ceil().max(0.0);
                doublings.min(GRIDS as f32) as u8
            })
            .collect();
        let grids = grid_of
            .iter()
            .map(|&g| usize::from(g) + 1)
            .max()
            .unwrap_or(0);
        let vertex_section: Vec<u16> = (0..rest.len()).map(section).collect();
        let mut occluders = Occluders {
            vertex: kept.iter().map(|&i| i as u32).collect(),
            radius: kept.iter().map(|&i| radius[i] as f32).collect(),
            section: kept.iter().map(|&i| section(i)).collect(),
            offset: kept
                .iter()
                .map(|&i| (points[i] - rest[i]).as_vec3())
                .collect(),
            normal: kept.iter().map(|&i| normals[i]).collect(),
            sections: vertex_section.iter().any(|&s| s != vertex_section[0]),
            vertex_section,
            cell,
            grids: grids.min(GRIDS),
            grid_of,
            ..Occluders::default()
        };
        // Each point's spacing: its own radius's share, at least the 10th percentile
        // ball's.
        let least = reaches.get(reaches.len() / 10).map_or(0.0, |r| r / REACH);
        let spacing: Vec<f32> = (0..positions.len())
            .map(|i| SPACING * (radius.get(i).map_or(0.0, |&r| r as f32)).max(least))
            .collect();
        (occluders.samples, occluders.near) =
            samples(&positions, &occluders.vertex_section, &spacing);
        // What the sections' own balls hide, at the samples, spread to every vertex.
        let (mut scratch, mut at_samples) = (Scratch::default(), Vec::new());
        occluders.add_up(
            &mut scratch,
            (&positions, &normals),
            (Whose::Own, Some(&occluders.samples)),
            &mut at_samples,
        );
        occluders.own = occluders.spread(&at_samples).collect();
        occluders.scratch = scratch;
        occluders
    }

    /// Per vertex, the weighted mean of `at_samples` (one per sample) over its nearest
    /// samples.
    fn spread<'a>(&'a self, at_samples: &'a [f32]) -> impl Iterator<Item = f32> + 'a {
        self.near.iter().map(move |near| {
            near.iter()
                .map(|&(s, w)| w * at_samples.get(s as usize).copied().unwrap_or(0.0))
                .sum()
        })
    }

    /// Each vertex's occlusion (see the module docs) into `out`, for the surface with
    /// `positions` and unit `normals` now (one each, as at rest; a ball whose vertex lies
    /// beyond them shades nothing).
    pub fn shade(&mut self, positions: &[Vec3], normals: &[Vec3], out: &mut Vec<f32>) {
        let n = positions.len().min(normals.len());
        let mut scratch = std::mem::take(&mut self.scratch);
        let mut sampled = std::mem::take(&mut scratch.sampled);
        if self.sections {
            self.add_up(
                &mut scratch,
                (positions, normals),
                (Whose::Others, Some(&self.samples)),
                &mut sampled,
            );
        } else {
            sampled.clear();
        }
        out.clear();
        out.extend(
            self.spread(&sampled)
                .zip(&self.own)
                .take(n)
                .map(|(others, own)| 1.0 - (-(others + own)).exp()),
        );
        out.resize(n, 0.0);
        scratch.sampled = sampled;
        self.scratch = scratch;
    }

    /// Per point (each of `at`, or every one), the sum of the shares `whose` balls hide
    /// (see the module docs) into `out`, the balls posed for the surface's `positions` and
    /// `normals`, in `scratch`.
    fn add_up(
        &self,
        scratch: &mut Scratch,
        (positions, normals): (&[Vec3], &[Vec3]),
        (whose, at): (Whose, Option<&[u32]>),
        out: &mut Vec<f32>,
    ) {
        let n = positions.len().min(normals.len());
        out.clear();
        out.resize(at.map_or(n, <[u32]>::len), 0.0);
        // The balls where the surface is now.
        scratch.centre.clear();
        scratch.centre.extend((0..self.vertex.len()).map(|b| {
            let v = self.vertex[b] as usize;
            if v < n {
                positions[v] + Quat::from_rotation_arc(self.normal[b], normals[v]) * self.offset[b]
            } else {
                Vec3::NAN
            }
        }));
        self.grid(scratch);
        let scratch = &*scratch;
        let bucket = Hash::new(scratch.start.len() - 1, self.cell);
        let (centre, radius, section) = (&scratch.centre, &self.radius, &self.section);
        let fade = 1.0 / (REACH * REACH);
        let share = |b: usize, i: usize, p: Vec3, normal: Vec3| {
            let d = centre[b] - p;
            let (r, along) = (radius[b], d.dot(normal));
            let d2 = d.length_squared();
            if along <= 0.0 || d2 >= (REACH * r).powi(2) || self.vertex[b] as usize == i {
                return 0.0;
            }
            // cos θ (r / d)², eased to zero at the reach; a point inside a ball (the balls
            // reach a little past a crevice's surface) counts as on it.
            along / d2.sqrt() * (r * r / d2.max(r * r) - fade) / (1.0 - fade)
        };
        for (k, o) in out.iter_mut().enumerate() {
            let i = at.map_or(k, |at| at[k] as usize);
            if i >= n || !positions[i].is_finite() {
                continue;
            }
            let (p, normal) = (positions[i], normals[i]);
            let own = self.vertex_section.get(i).copied().unwrap_or(0);
            let counts = |b: usize| (section[b] == own) == (whose == Whose::Own);
            let mut sum = 0.0;
            for grid in 0..self.grids {
                let at = bucket.of_point(p, grid);
                let (mut k, end) = (scratch.start[at] as usize, scratch.start[at + 1] as usize);
                while k < end {
                    let b = scratch.entries[k] as usize;
                    if !counts(b) {
                        k = scratch.run_end[k] as usize;
                        continue;
                    }
                    // (A bucket may hold another grid's cells too: each ball counts in
                    // its own grid's, once.)
                    if usize::from(self.grid_of[b]) == grid {
                        sum += share(b, i, p, normal);
                    }
                    k += 1;
                }
            }
            for &b in &scratch.huge {
                let b = b as usize;
                if counts(b) {
                    sum += share(b, i, p, normal);
                }
            }
            *o = sum;
        }
    }

    /// Lists each posed ball in the buckets of the cells its reach meets in its grid (see
    /// the module docs), or among the huge ones.
    fn grid(&self, s: &mut Scratch) {
        let balls = self.vertex.len();
        let buckets = (8 * balls).next_power_of_two().max(64);
        let cell = self.cell;
        let (centre, radius, grid_of) = (&s.centre, &self.radius, &self.grid_of);
        let huge = |b: usize| usize::from(grid_of[b]) >= GRIDS;
        let cells_of = |b: usize| {
            let (reach, grid) = (REACH * radius[b], i32::from(grid_of[b]));
            let key = |p: Vec3| (p / (cell * (1 << grid) as f32)).floor().as_ivec3();
            (key(centre[b] - reach), key(centre[b] + reach), grid)
        };
        let hashed = Hash::new(buckets, cell);
        s.start.clear();
        s.start.resize(buckets + 1, 0);
        s.last.clear();
        s.last.resize(buckets, u32::MAX);
        s.huge.clear();
        // Counted, then listed in ball order (so by section within a bucket).
        for (b, c) in centre.iter().enumerate() {
            if c.is_finite() && huge(b) {
                s.huge.push(b as u32);
            }
        }
        // Calls `f` with each (ball, bucket) once, `last` the last ball met per bucket.
        let listings = |last: &mut [u32], f: &mut dyn FnMut(usize, usize)| {
            last.iter_mut().for_each(|l| *l = u32::MAX);
            for (b, c) in centre.iter().enumerate() {
                if !c.is_finite() || huge(b) {
                    continue;
                }
                let (lo, hi, grid) = cells_of(b);
                for_cells(lo, hi, |k| {
                    let at = hashed.cell(k, grid);
                    if last[at] != b as u32 {
                        last[at] = b as u32;
                        f(b, at);
                    }
                });
            }
        };
        let start = &mut s.start;
        listings(&mut s.last, &mut |_, at| start[at + 1] += 1);
        for at in 0..buckets {
            s.start[at + 1] += s.start[at];
        }
        let total = s.start[buckets] as usize;
        s.entries.clear();
        s.entries.resize(total, 0);
        s.fill.clear();
        s.fill.extend_from_slice(&s.start[..buckets]);
        let (entries, fill) = (&mut s.entries, &mut s.fill);
        listings(&mut s.last, &mut |b, at| {
            entries[fill[at] as usize] = b as u32;
            fill[at] += 1;
        });
        // Each entry's run of its section within its bucket: where it ends.
        s.run_end.clear();
        s.run_end.resize(total, 0);
        for at in 0..buckets {
            let (first, end) = (s.start[at] as usize, s.start[at + 1] as usize);
            let mut next = end;
            for k in (first..end).rev() {
                if k + 1 < end
                    && self.section[s.entries[k] as usize]
                        != self.section[s.entries[k + 1] as usize]
                {
                    next = k + 1;
                }
                s.run_end[k] = next as u32;
            }
        }
    }
}

/// Points of `positions` at least their own `spacing` apart (per point) with every other
/// within its spacing of one in its `section` (greedily, in order), and per point its
/// [`NEAR`] nearest of them within twice its spacing in its section, weighted by how near
/// (their weights add up to one; all zero where none lies that near).
fn samples(
    positions: &[Vec3],
    section: &[u16],
    spacing: &[f32],
) -> (Vec<u32>, Vec<[(u32, f32); NEAR]>) {
    let n = positions.len().min(section.len()).min(spacing.len());
    let mut sorted: Vec<f32> = spacing[..n].iter().copied().filter(|s| *s > 0.0).collect();
    sorted.sort_by(f32::total_cmp);
    // Cells as wide as the median point's reach for its nearest samples: most points read
    // 27 cells.
    let cell = 2.0
        * sorted
            .get(sorted.len() / 2)
            .copied()
            .unwrap_or(1.0)
            .max(f32::MIN_POSITIVE);
    let key = |p: Vec3| {
        let k = (p / cell).floor().as_ivec3();
        [k.x, k.y, k.z]
    };
    type Grid = super::cells::Cells<[i32; 3], Vec<u32>>;
    // Calls `f` with every sample listed within `reach` of `p` (and some farther); a
    // reach of more than 4 cells (a plinth's vertex on a statue) is read as 4.
    let around = |grid: &Grid, p: Vec3, reach: f32, f: &mut dyn FnMut(u32)| {
        let reach = reach.min(4.0 * cell);
        let (lo, hi) = (key(p - reach), key(p + reach));
        for_cells(IVec3::from(lo), IVec3::from(hi), |k| {
            if let Some(list) = grid.get(&k.to_array()) {
                list.iter().for_each(|&s| f(s));
            }
        });
    };
    let mut grid = Grid::default();
    let mut chosen: Vec<u32> = Vec::new();
    for i in 0..n {
        let p = positions[i];
        if !p.is_finite() {
            continue;
        }
        let mut covered = false;
        around(&grid, p, spacing[i], &mut |s| {
            let j = chosen[s as usize] as usize;
            covered |= section[j] == section[i] && positions[j].distance(p) < spacing[i];
        });
        if !covered {
            grid.entry(key(p)).or_default().push(chosen.len() as u32);
            chosen.push(i as u32);
        }
    }
    let near = (0..n)
        .map(|i| {
            let (p, wide) = (positions[i], 2.0 * spacing[i]);
            let mut best = [(0u32, f32::INFINITY); NEAR];
            if p.is_finite() {
                around(&grid, p, wide, &mut |s| {
                    let j = chosen[s as usize] as usize;
                    let d = positions[j].distance(p);
                    if section[j] == section[i] && d < wide && d < best[NEAR - 1].1 {
                        best[NEAR - 1] = (s, d);
                        best.sort_by(|a, b| a.1.total_cmp(&b.1));
                    }
                });
            }
            // Weights easing to zero at twice the spacing, adding up to one.
            let weight = |d: f32| {
                if d.is_finite() {
                    (1.0 - d / wide).max(0.0).powi(2)
                } else {
                    0.0
                }
            };
            let total: f32 = best.iter().map(|&(_, d)| weight(d)).sum();
            best.map(|(s, d)| (s, if total > 0.0 { weight(d) / total } else { 0.0 }))
        })
        .collect();
    (chosen, near)
}

/// The buckets of the grids' cells: `mask + 1` of them (a power of two), the first grid's
/// cells `cell` wide.
#[derive(Clone, Copy)]
struct Hash {
    mask: usize,
    cell: f32,
}

impl Hash {
    /// `buckets` buckets (a power of two), the first grid's cells `cell` wide.
    fn new(buckets: usize, cell: f32) -> Hash {
        Hash {
            mask: buckets - 1,
            cell,
        }
    }

    /// The bucket of cell `k` of grid `grid`.
    fn cell(&self, k: IVec3, grid: i32) -> usize {
        let h = (k.x as u32).wrapping_mul(73_856_093)
            ^ (k.y as u32).wrapping_mul(19_349_663)
            ^ (k.z as u32).wrapping_mul(83_492_791)
            ^ (grid as u32).wrapping_mul(2_654_435_761);
        h as usize & self.mask
    }

    /// The bucket of the cell of grid `grid` that holds `p`.
    fn of_point(&self, p: Vec3, grid: usize) -> usize {
        let k = (p / (self.cell * (1u32 << grid) as f32)).floor().as_ivec3();
        self.cell(k, grid as i32)
    }
}

/// Calls `f` for every cell from `lo` to `hi` (inclusive).
fn for_cells(lo: IVec3, hi: IVec3, mut f: impl FnMut(IVec3)) {
    for x in lo.x..=hi.x {
        for y in lo.y..=hi.y {
            for z in lo.z..=hi.z {
                f(IVec3::new(x, y, z));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The balls of a sphere's surface: each vertex's skeletal point the centre.
    fn sphere_balls(m: &crate::mesh::Mesh, centre: DVec3, r: f64) -> (Vec<DVec3>, Vec<f64>) {
        (vec![centre; m.positions.len()], vec![r; m.positions.len()])
    }

    fn normals(m: &crate::mesh::Mesh, positions: &[Vec3]) -> Vec<Vec3> {
        let mut out = Vec::new();
        crate::mesh::area_normals_into(positions, &m.triangles, &mut out);
        out
    }

    /// A sphere alone is open everywhere; a second sphere (another section) pressed
    /// against it shades the skin around where they touch, the more the nearer, and
    /// nothing on the far side.
    #[test]
    fn a_ball_shades_the_skin_it_presses_on_and_nothing_behind() {
        let one = crate::mesh::shapes::uv_sphere(1.0, 24, 16);
        let n = one.positions.len();
        // Two spheres, the second 2.2 radii along x: a gap of a fifth of a radius.
        let mut mesh = one.clone();
        mesh.positions
            .extend(one.positions.iter().map(|p| *p + DVec3::new(2.2, 0.0, 0.0)));
        mesh.triangles
            .extend(one.triangles.iter().map(|t| t.map(|i| i + n as u32)));
        let (mut points, mut radii) = sphere_balls(&one, DVec3::ZERO, 1.0);
        let (p2, r2) = sphere_balls(&one, DVec3::new(2.2, 0.0, 0.0), 1.0);
        points.extend(p2);
        radii.extend(r2);
        let positions: Vec<Vec3> = mesh.positions.iter().map(|p| p.as_vec3()).collect();
        let normals = normals(&mesh, &positions);
        let sections: Vec<u16> = (0..2 * n).map(|i| u16::from(i >= n)).collect();
        let mut alone = Occluders::new(
            &one.positions,
            &one.triangles,
            &points[..n],
            &radii[..n],
            &sections[..n],
        );
        let mut out = Vec::new();
        alone.shade(&positions[..n], &normals[..n], &mut out);
        assert!(
            out.iter().all(|&o| o < 1e-6),
            "{:?}",
            out.iter().fold(0f32, |a, &b| a.max(b))
        );
        let mut two = Occluders::new(&mesh.positions, &mesh.triangles, &points, &radii, &sections);
        two.shade(&positions, &normals, &mut out);
        let facing = (0..n)
            .filter(|&i| positions[i].x > 0.95)
            .map(|i| out[i])
            .fold(0f32, f32::max);
        let behind = (0..n)
            .filter(|&i| positions[i].x < 0.0)
            .map(|i| out[i])
            .fold(0f32, f32::max);
        assert!(facing > 0.2, "the skin facing the other ball: {facing}");
        assert!(behind < 0.01, "the far side: {behind}");
        // Nearer is darker: the same pair half as far apart (a tenth of a radius).
        let shifted: Vec<Vec3> = positions
            .iter()
            .enumerate()
            .map(|(i, p)| if i >= n { *p - Vec3::X * 0.1 } else { *p })
            .collect();
        let mut nearer = Vec::new();
        two.shade(&shifted, &normals, &mut nearer);
        let near = (0..n)
            .filter(|&i| positions[i].x > 0.95)
            .map(|i| nearer[i])
            .fold(0f32, f32::max);
        assert!(near > facing, "{near} against {facing}");
    }

    /// The grid finds what testing every ball finds: balls of radii a hundred times apart
    /// in three sections, some too big for the grid, their own sections' at rest (each
    /// normal up, the rest's without faces) and the others' as posed.
    #[test]
    fn the_grid_finds_every_ball_that_reaches_a_point() {
        let mut rng = crate::random::SplitMix(11);
        let mut unit = move || (rng.next_u64() >> 11) as f32 / (1u64 << 53) as f32;
        let n = 2000;
        let positions: Vec<Vec3> = (0..n)
            .map(|_| Vec3::new(unit(), unit(), unit()) * 10.0)
            .collect();
        let normals: Vec<Vec3> = (0..n)
            .map(|_| (Vec3::new(unit(), unit(), unit()) - 0.5).normalize_or(Vec3::Y))
            .collect();
        let radii: Vec<f64> = (0..n)
            .map(|i| {
                if i % 97 == 0 {
                    200.0
                } else {
                    0.03 + 0.3 * f64::from(unit())
                }
            })
            .collect();
        // Each ball beside its point; the big ones (for the huge list) far off, reaching
        // over the whole cloud without swallowing its small balls.
        let points: Vec<DVec3> = (0..n)
            .map(|i| {
                if radii[i] > 1.0 {
                    DVec3::new(-radii[i] - 5.0 - i as f64 * 0.01, 5.0, 5.0)
                } else {
                    (positions[i] - normals[i] * radii[i] as f32).as_dvec3()
                }
            })
            .collect();
        let rest: Vec<DVec3> = positions.iter().map(|p| p.as_dvec3()).collect();
        let sections: Vec<u16> = (0..n).map(|i| (i % 3) as u16).collect();
        let occluders = Occluders::new(&rest, &[], &points, &radii, &sections);
        let (mut own_sums, mut others) = (Vec::new(), Vec::new());
        let up = vec![Vec3::Y; n];
        let mut scratch = Scratch::default();
        occluders.add_up(
            &mut scratch,
            (&positions, &up),
            (Whose::Own, None),
            &mut own_sums,
        );
        occluders.add_up(
            &mut scratch,
            (&positions, &normals),
            (Whose::Others, None),
            &mut others,
        );
        let fade = 1.0 / (REACH * REACH);
        for i in 0..n {
            let (mut own_sum, mut others_sum) = (0.0, 0.0);
            for (b, &v) in occluders.vertex.iter().enumerate() {
                let v = v as usize;
                let r = occluders.radius[b];
                let own = sections[v] == sections[i];
                let (centre, normal) = if own {
                    (points[v].as_vec3(), Vec3::Y)
                } else {
                    (scratch.centre[b], normals[i])
                };
                let d = centre - positions[i];
                let along = d.dot(normal);
                let d2 = d.length_squared();
                if along > 0.0 && d2 < (REACH * r).powi(2) && v != i {
                    let share = along / d2.sqrt() * (r * r / d2.max(r * r) - fade) / (1.0 - fade);
                    if own {
                        own_sum += share;
                    } else {
                        others_sum += share;
                    }
                }
            }
            assert!(
                (own_sums[i] - own_sum).abs() < 1e-4,
                "{i}: {} against {own_sum}",
                own_sums[i]
            );
            assert!(
                (others[i] - others_sum).abs() < 1e-4,
                "{i}: {} against {others_sum}",
                others[i]
            );
        }
        let out = others;
        assert!(
            !scratch.huge.is_empty() && occluders.grids > 4 && out.iter().any(|&o| o > 0.1),
            "{} huge, {} grids, {} balls",
            scratch.huge.len(),
            occluders.grids,
            occluders.vertex.len()
        );
    }
}
