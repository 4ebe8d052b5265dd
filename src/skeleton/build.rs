//! Building a skeleton: the tetrahedralization, the shrinking or fitted balls on its edge
//! hook, the thickness rays cast in its idle time, then the clamp (see the module docs of
//! [`crate::skeleton`] for the stages).

use super::shrinking_ball::{ball_distances, ShrinkingBalls};
use super::thickness::{clamp, ring_bounds, Rays};
use super::voronoi::voronoi_distances;
use super::{Method, Skeleton, SkeletonError, SkeletonParams, Tangent};
use crate::delaunay::Delaunay;
use crate::geom::bvh::{Bvh, PACKET};
use crate::geom::inside::InsideTest;
use crate::mesh::Mesh;
use crate::progress::Progress;
use glam::DVec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::OnceLock;
use std::time::Instant;

/// Builds the skeleton of a validated mesh with unit outward `normals`. Riders (small
/// separate parts, [`crate::mesh::Parts`]) are left out of it: each rider vertex gets
/// `d = 0`, `sp = p`. Where the body is in several parts, each part's skeleton is built on
/// that part alone: parts that overlap (an arm modelled apart and pushed into the torso, a
/// jacket over a body) would otherwise stop each other's balls with their buried vertices,
/// while the inside is the union of the parts' insides (the winding number counts an
/// overlap twice, [`crate::geom::inside`]).
pub fn build(
    mesh: &Mesh,
    normals: &[DVec3],
    params: &SkeletonParams,
    progress: Progress,
) -> Result<Skeleton, SkeletonError> {
    let n = mesh.positions.len();
    if normals.len() != n {
        return Err(SkeletonError::Normals(normals.len(), n));
    }
    let parts = crate::mesh::Parts::of(mesh);
    let body = parts.body_parts();
    if parts.riders() == 0 && body.len() <= 1 {
        return build_with(
            mesh,
            normals,
            params,
            progress,
            Overlap::UntilTetrahedralized,
        );
    }
    let mut whole = Skeleton {
        distance: vec![0.0; n],
        points: mesh.positions.clone(),
        fallback: 0,
        clamped: 0,
        riders: n,
        tetrahedra: 0,
        inside_voronoi_vertices: 0,
        seconds: Vec::new(),
    };
    for (i, &k) in body.iter().enumerate() {
        let (part, old) = parts.part(mesh, k, i == 0);
        let part_normals: Vec<DVec3> = old.iter().map(|&v| normals[v as usize]).collect();
        let sk = build_with(
            &part,
            &part_normals,
            params,
            progress,
            Overlap::UntilTetrahedralized,
        )?;
        for (j, &v) in old.iter().enumerate() {
            whole.distance[v as usize] = sk.distance[j];
            whole.points[v as usize] = sk.points[j];
        }
        whole.riders -= old.len();
        whole.fallback += sk.fallback;
        whole.clamped += sk.clamped;
        whole.tetrahedra += sk.tetrahedra;
        whole.inside_voronoi_vertices += sk.inside_voronoi_vertices;
        for (stage, s) in sk.seconds {
            match whole.seconds.iter_mut().find(|(name, _)| *name == stage) {
                Some((_, total)) => *total += s,
                None => whole.seconds.push((stage, s)),
            }
        }
    }
    Ok(whole)
}

/// How much of the thickness stage runs alongside the tetrahedralization.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Overlap {
    /// As many vertices as fit before the tetrahedralization ends (the real pipeline).
    UntilTetrahedralized,
    /// None or all of them (tests: both paths must give the same skeleton).
    #[cfg(test)]
    Nothing,
    #[cfg(test)]
    Everything,
}

pub(super) fn build_with(
    mesh: &Mesh,
    normals: &[DVec3],
    params: &SkeletonParams,
    progress: Progress,
    overlap: Overlap,
) -> Result<Skeleton, SkeletonError> {
    let n = mesh.positions.len();
    if normals.len() != n {
        return Err(SkeletonError::Normals(normals.len(), n));
    }
    let mut seconds = Vec::new();
    let clock = Instant::now();
    // The shrinking ball needs normals far more accurate than an uneven fan gives, and
    // where the ball is limited by the surface's own curvature, a better estimate of it
    // than the chord to a neighbour (`Tangent`).
    let fit;
    let (normals, tangents, fit) = match params.method {
        Method::FittedBall => {
            progress("normals", 0.0);
            fit = crate::mesh::fit_surface(mesh, normals);
            seconds.push(("normal fit", clock.elapsed().as_secs_f64()));
            (&fit.normals[..], Tangent::fitted(&fit), Some(&fit))
        }
        Method::ShrinkingBall => {
            let plain = normals.iter().map(|&n| Tangent::plain(n)).collect();
            (normals, plain, None)
        }
        Method::Mean | Method::Pole => (normals, Vec::new(), None),
    };

    // 1. Tetrahedralize. Meanwhile, on the other core: the inside oracle and the BVH, then
    // the thickness along -n of as many vertices as it can before the tetrahedralization
    // ends (stage 4 needs only the mesh, so it overlaps the tetrahedralization instead of
    // following it; whatever is left is done in stage 4).
    progress("tetrahedralize", 0.0);
    let pts = &mesh.positions;
    let t_min = 1e-9 * mesh.diagonal();
    let tetrahedralized = AtomicBool::new(false);
    let more = || match overlap {
        Overlap::UntilTetrahedralized => !tetrahedralized.load(Ordering::Relaxed),
        #[cfg(test)]
        Overlap::Nothing => false,
        #[cfg(test)]
        Overlap::Everything => true,
    };
    // The rays, once the other core has prepared them.
    let rays = OnceLock::new();
    let waiting = AtomicUsize::new(0);
    let ((built, t_tets), (inside, t_aux)) = rayon::join(
        || {
            let t = Instant::now();
            let progress = |f| progress("tetrahedralize", f);
            // While this thread waits for the other side of a parallel phase, it casts.
            let idle = || {
                let cast = more() && rays.get().is_some_and(|r: &Rays| r.cast_next());
                waiting.fetch_add(usize::from(cast), Ordering::Relaxed);
                cast
            };
            // The shrinking ball is taken over the edges as they are made.
            let built = match params.method {
                Method::ShrinkingBall | Method::FittedBall => {
                    Delaunay::with_edge_hook(pts, &progress, &idle, |order| {
                        ShrinkingBalls::new(&tangents, order, fit)
                    })
                    .map(|(delaunay, balls)| (delaunay, Some(balls)))
                }
                _ => Delaunay::with_progress(pts, &progress).map(|delaunay| (delaunay, None)),
            };
            tetrahedralized.store(true, Ordering::Relaxed);
            (built, t.elapsed().as_secs_f64())
        },
        || {
            let t = Instant::now();
            // The tetrahedralization's parallel phases come first (this thread runs the
            // second worker when it is waiting).
            let poll = || {
                rayon::yield_now();
            };
            let bvh = || Bvh::with_poll(pts, &mesh.triangles, &poll);
            let (inside, bvh) = if params.method.needs_oracle() {
                let (i, b) = rayon::join(|| InsideTest::new(mesh), bvh);
                (Some(i), b)
            } else {
                (None, bvh())
            };
            // How far each ray must look: twice a bound on `d` where the method has one.
            let reach = params
                .method
                .is_ball()
                .then(|| ring_bounds(pts, &tangents, &mesh.triangles, &poll));
            let rays = rays.get_or_init(|| Rays::new(bvh, pts, normals, t_min, reach));
            while more() {
                if let Some(rayon::Yield::Executed) = rayon::yield_now() {
                    continue;
                }
                if !rays.cast_next() {
                    break;
                }
            }
            (inside, t.elapsed().as_secs_f64())
        },
    );
    let Some(rays) = rays.into_inner() else {
        unreachable!("stage 1 prepares the rays")
    };
    let (delaunay, balls) = built?;
    seconds.push(("tetrahedralize", t_tets));
    let aux = if inside.is_some() {
        "inside-oracle+bvh+thickness (parallel)"
    } else {
        "bvh+thickness (parallel)"
    };
    seconds.push((aux, t_aux));
    // The fitted balls whose Delaunay minimum may have missed a vertex hidden behind their
    // patch are searched.
    let balls = balls.map(|mut balls| {
        let t = Instant::now();
        let (searched, gave_up) = balls.settle(&delaunay, pts);
        log::debug!("fitted balls: {searched} searched, {gave_up} gave up");
        if params.method == Method::FittedBall {
            seconds.push(("search", t.elapsed().as_secs_f64()));
        }
        balls.into_radii()
    });

    // 2–3. Per-vertex distance from the cells.
    progress("distance", 0.0);
    let (mut distance, fallback, used, tetrahedra) = match (&inside, &balls) {
        (Some(inside), _) => voronoi_distances(&delaunay, pts, inside, params, &mut seconds),
        (None, Some(balls)) => ball_distances(&delaunay, balls, &mut seconds),
        // Stage 1 makes one or the other, by the method.
        (None, None) => unreachable!("neither an inside oracle nor tangent balls"),
    };
    // Duplicated positions (only possible without welding) share their vertex's cell;
    // neither path counted them as fallbacks.
    for i in 0..n {
        if let Some(v) = delaunay.duplicate_of(i) {
            distance[i] = distance[v as usize];
        }
    }

    // 4. Clamp to half the thickness along -n: only a hit closer than 2d can clamp. Stage 1
    // measured the first vertices up to their reach (enough unless d exceeds its bound,
    // which exact arithmetic rules out, so only by rounding or a degenerate tie); the
    // others get a segment query of length 2d here, pruned to the local scale. Both give
    // the same answer.
    let t = Instant::now();
    progress("thickness", 0.0);
    // Casts in `order`, as in stage 1, in packets of neighbours; stage 1 measured the
    // first ones.
    let measured = rays.measured();
    let mut th = vec![f64::INFINITY; n];
    th.par_chunks_mut(PACKET)
        .zip(rays.order.par_chunks(PACKET))
        .enumerate()
        .for_each(|(c, (th, verts))| {
            let mut far = [0.0; PACKET];
            for (j, (f, &v)) in far.iter_mut().zip(verts).enumerate() {
                let d = distance[v as usize];
                let k = c * PACKET + j;
                *f = if d == 0.0 {
                    // The fallback (`d = 0`) needs no thickness.
                    0.0
                } else if k < measured && 2.0 * d <= rays.reach(v) {
                    th[j] = rays.known(k);
                    0.0
                } else {
                    2.0 * d
                };
            }
            rays.cast(verts, &far[..verts.len()], th);
        });
    let mut clamped = 0;
    for (&i, th) in rays.order.iter().zip(th) {
        clamped += usize::from(clamp(&mut distance[i as usize], th));
    }
    log::debug!(
        "thickness: {measured} of {n} vertices measured during the tetrahedralization ({} \
         packets while it waited for its other side), {clamped} clamped",
        waiting.into_inner()
    );
    seconds.push(("thickness", t.elapsed().as_secs_f64()));

    let points = pts
        .iter()
        .zip(normals)
        .zip(&distance)
        .map(|((p, nrm), d)| *p - *d * *nrm)
        .collect();
    seconds.push(("total", clock.elapsed().as_secs_f64()));
    progress("done", 1.0);
    Ok(Skeleton {
        riders: 0,
        distance,
        points,
        fallback,
        clamped,
        tetrahedra,
        inside_voronoi_vertices: used,
        seconds,
    })
}
