//! Mesh parameterization: a UV layout per face corner, from the barycentric (Tutte) mapping with
//! three weights or from least-squares conformal maps, with seams.
//!
//! # Methods
//! - **Barycentric / Tutte mapping** ([`tutte`]): the outer boundary fixed on a convex polygon
//!   (a circle or the unit square, by arc length: [`boundary`]), every other vertex the weighted
//!   mean of its neighbours (Tutte 1963; Floater 1997). The weights ([`weights`]): uniform
//!   (`1/n_i`), mean-value (Floater 2003) and harmonic (Eck et al. 1995; Pinkall & Polthier
//!   1993). Uniform and mean-value weights are positive, so by Tutte's theorem (Floater's
//!   version for any positive weights) the layout has no flipped triangle; harmonic weights go
//!   negative beside obtuse angles, and the flips that may bring are counted, not hidden.
//! - **LSCM** ([`lscm`]): least-squares conformal maps (Lévy et al. 2002), a free boundary, two
//!   pinned vertices.
//!
//! # Seams and topology
//! The mesh is cut open *virtually* along the seam edges ([`cut`]): corners on either side of a
//! seam become different vertices of the solve, so they get different UVs. The cut mesh must be
//! one connected piece of genus 0 with a boundary; several boundary loops are fine (the longest
//! is the outer boundary; Tutte fills the others virtually, LSCM needs no filling). A closed
//! genus-0 mesh is cut automatically (the shortest path between two far-apart vertices) when
//! [`ParamParams::auto_cut`] is set (the default). Anything else is refused with a
//! [`ParamError`] saying why and how to fix it; a refusal is a value, nothing is half-written.
//!
//! # Output: per corner
//! [`Parameterization::uv`] has one entry per **halfedge row** of the tables it was computed
//! from: for a face halfedge `h`, the UV of the corner at `to_vertex(h)` inside `face(h)` (the
//! convention of the per-corner UV attribute, stored on that halfedge). Boundary (faceless)
//! halfedges hold `f32::NAN` in both coordinates. Without seams every corner of a vertex has
//! the same UV ([`Parameterization::vertex_uvs`] then gives them per vertex). The layout is
//! normalised into `[0, 1]²` by one uniform scale and a translation (the longer side of its
//! bounding box is 1), so a texture tiles once.
//!
//! # Entry points
//! - [`parameterize`]: tables (from [`crate::mesh::tables::extract`]) and [`ParamParams`] →
//!   [`Parameterization`] (UVs and a [`ParamReport`]) or [`ParamError`]. Seams are edge rows of
//!   those same tables (map `EdgeId`s to rows through `crate::mesh::tables::MeshTables::members`).
//! - [`parameterize_in_place`]: the same, writing the layout onto the mesh as corner UVs (what
//!   the registered `param` operation runs, [`Parameterize`]).
//! - [`tutte::solve_fixed`]: the barycentric solve with any fixed boundary positions (what the
//!   exact reproduction tests use).

pub mod boundary;
pub mod cut;
pub mod distortion;
pub mod lscm;
mod operation;
pub mod params;
pub mod sparse;
pub mod tutte;
pub mod weights;

use std::time::Instant;

use bevy::math::{DVec2, Vec2};
use bevy::prelude::World;

use crate::mesh::attributes::{CornerUv, MeshAttributes, set_record};
use crate::mesh::ids::MeshId;
use crate::mesh::tables::{Connectivity, EdgeRow, NONE, extract};

pub use cut::CutMesh;
pub use distortion::Distortion;
pub use operation::{PARAMETERIZE, Parameterize};
pub use params::{BoundaryShape, ParamError, ParamMethod, ParamParams, UnknownName};
pub use tutte::Solver;

/// What a parameterization did and how good it is.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParamReport {
    /// The method.
    pub method: ParamMethod,
    /// The boundary shape (`None` for LSCM's free boundary).
    pub boundary: Option<BoundaryShape>,
    /// Fanned triangles measured (a polygon counts once per fan triangle).
    pub triangles: usize,
    /// Triangles with signed UV area ≤ 0 though their 3D area is > 0.
    pub flipped: usize,
    /// Triangles laid out with zero area (three corners on one line) though their 3D area is
    /// not: not turned over, but they get no texture.
    pub degenerate: usize,
    /// Mean |angle in UV − angle in 3D| over triangle corners, degrees.
    pub angle_distortion_deg: f64,
    /// The conformal (LSCM) energy over the UV area: ≥ 0, 0 for a conformal map.
    pub conformal_energy: f64,
    /// Area distortion: the 3D-area-weighted mean |ln(UV area share / 3D area share)|.
    pub area_distortion: f64,
    /// Vertices of the cut mesh (original vertices, plus one per extra side of a seam).
    pub cut_vertices: usize,
    /// Seam edges cut (given and automatic).
    pub seam_edges: usize,
    /// Of those, how many the automatic cut added.
    pub auto_seam_edges: usize,
    /// Boundary loops of the cut mesh.
    pub boundary_loops: usize,
    /// Holes filled virtually for a fixed-boundary solve (the loops but the outer one).
    pub filled_holes: usize,
    /// The factorization used.
    pub solver: Solver,
    /// Milliseconds in the sparse assembly, factorization and solve.
    pub solve_ms: f64,
    /// Milliseconds for the whole call (cutting, weights, solve, measuring).
    pub total_ms: f64,
}

/// A UV layout per corner, and its report.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Parameterization {
    /// By halfedge row: the UV of the corner at `to_vertex(h)` in `face(h)`, in `[0, 1]²`;
    /// `f32::NAN` in both coordinates for a boundary (faceless) halfedge.
    pub uv: Vec<Vec2>,
    /// What was done, and the distortion.
    pub report: ParamReport,
}

impl Parameterization {
    /// The UV of each vertex row, when every face corner of each vertex has the same UV (no
    /// seam runs through it); `None` otherwise. A vertex with no face gets NaN.
    pub fn vertex_uvs(&self, t: &Connectivity) -> Option<Vec<Vec2>> {
        let mut out = vec![Vec2::NAN; t.vertex_count()];
        for h in t.halfedges() {
            if t.is_boundary(h) {
                continue;
            }
            let slot = &mut out[t.to_vertex(h).index()];
            if slot.x.is_nan() {
                *slot = self.uv[h.index()];
            } else if *slot != self.uv[h.index()] {
                return None;
            }
        }
        Some(out)
    }
}

/// Parameterizes the mesh held in `t` (see the module doc).
///
/// # Errors
/// Every [`ParamError`]: no faces, a seam out of range, several pieces, not a disk after
/// cutting (genus, loops, and how to fix it named), a boundary too short for the shape, a
/// failed solve. Nothing is returned in part.
pub fn parameterize(
    t: &Connectivity,
    params: &ParamParams,
) -> Result<Parameterization, ParamError> {
    parameterize_then(t, params, |_| ()).map(|(p, ())| p)
}

/// [`parameterize`], handing the corner UVs to `meanwhile` as soon as they are known: it runs
/// while a second thread measures the distortion for the report (what
/// [`parameterize_in_place`] uses to write the layout onto the mesh in that time).
///
/// # Errors
/// As [`parameterize`]; `meanwhile` is not called then.
pub fn parameterize_then<R>(
    t: &Connectivity,
    params: &ParamParams,
    meanwhile: impl FnOnce(&[Vec2]) -> R,
) -> Result<(Parameterization, R), ParamError> {
    parameterize_reporting(t, params, &mut |_| true, meanwhile)
}

/// [`parameterize_then`], calling `progress` as its phases end: the mesh cut open (0.2), the
/// system solved (0.7). The return value is not read: a half-solved layout is no layout, so a
/// parameterization cannot stop early.
fn parameterize_reporting<R>(
    t: &Connectivity,
    params: &ParamParams,
    progress: &mut dyn FnMut(f32) -> bool,
    meanwhile: impl FnOnce(&[Vec2]) -> R,
) -> Result<(Parameterization, R), ParamError> {
    let start = Instant::now();
    let cut = cut::cut(t, &params.seams, params.auto_cut)?;
    progress(0.2);
    let (uv, solver, solve_ms, filled) = solve(&cut, params)?;
    progress(0.7);
    let (d, corner_uv, result) = std::thread::scope(|scope| {
        let distortion = scope.spawn(|| distortion::measure(&cut.positions, &uv, &cut.triangles));
        let normalised = normalise(&uv);
        let corner_uv: Vec<Vec2> = cut
            .corner
            .iter()
            .map(|&c| {
                if c == NONE {
                    Vec2::NAN
                } else {
                    normalised[c as usize].as_vec2()
                }
            })
            .collect();
        let result = meanwhile(&corner_uv);
        let d = distortion
            .join()
            .expect("measuring the distortion does not panic");
        (d, corner_uv, result)
    });
    let report = ParamReport {
        method: params.method,
        boundary: params.method.fixed_boundary().then_some(params.boundary),
        triangles: cut.triangles.len(),
        flipped: d.flipped,
        degenerate: d.degenerate,
        angle_distortion_deg: d.angle_deg,
        conformal_energy: d.conformal,
        area_distortion: d.area,
        cut_vertices: cut.vertex_count(),
        seam_edges: cut.seams.len(),
        auto_seam_edges: cut.auto_seams,
        boundary_loops: cut.loops.len(),
        filled_holes: filled,
        solver,
        solve_ms,
        total_ms: start.elapsed().as_secs_f64() * 1e3,
    };
    Ok((
        Parameterization {
            uv: corner_uv,
            report,
        },
        result,
    ))
}

/// Parameterizes `mesh` and stores the layout on it: a [`CornerUv`] on every face halfedge, and
/// UVs in the mesh's attribute record (its other attributes stay). UVs the mesh had before are
/// replaced. Without seams in `params`, the edges the mesh marks with
/// [`crate::mesh::attributes::Seam`] are the seams. On a refusal the world is not changed.
///
/// `progress` is called as the phases end (the tables read, the mesh cut, the system solved);
/// a parameterization cannot stop early, so its return value is not read.
///
/// # Errors
/// As [`parameterize`].
pub fn parameterize_in_place(
    world: &mut World,
    mesh: MeshId,
    params: &ParamParams,
    progress: &mut dyn FnMut(f32) -> bool,
) -> Result<ParamReport, ParamError> {
    let tables = extract(world, mesh);
    progress(0.05);
    let mut params = params.clone();
    if params.seams.is_empty()
        && let Some(marks) = &tables.tables.attributes.seams
    {
        params.seams = marks
            .iter()
            .enumerate()
            .filter(|&(_, &seam)| seam)
            .map(|(row, _)| EdgeRow::new(row as u32))
            .collect();
    }
    let t = &tables.tables;
    let (p, ()) = parameterize_reporting(t, &params, progress, |uv| {
        let corners: Vec<_> = t
            .halfedges()
            .filter(|&h| !t.is_boundary(h))
            .map(|h| {
                (
                    tables.members.halfedges[h.index()].0,
                    CornerUv(uv[h.index()]),
                )
            })
            .collect();
        world.insert_batch(corners);
    })?;
    let mut has = MeshAttributes::of(world, mesh);
    has.uv = true;
    set_record(world, mesh, has);
    Ok(p.report)
}

/// Solves on the cut mesh: UV per cut vertex, the factorization, milliseconds, holes filled.
fn solve(
    cut: &CutMesh,
    params: &ParamParams,
) -> Result<(Vec<DVec2>, Solver, f64, usize), ParamError> {
    let n = cut.vertex_count();
    if params.method == ParamMethod::Lscm {
        let pins = boundary::far_pair(&cut.positions, &cut.loops[0]);
        let start = Instant::now();
        let uv = lscm::lscm(&cut.positions, &cut.triangles, &cut.loops, pins)?;
        return Ok((uv, Solver::Cholesky, start.elapsed().as_secs_f64() * 1e3, 0));
    }
    let outer = boundary::map_loop(&cut.positions, &cut.loops[0], params.boundary)?;
    let holes = &cut.loops[1..];
    let (mut positions, mut triangles);
    let (positions, triangles) = if holes.is_empty() {
        (&cut.positions, &cut.triangles)
    } else {
        positions = cut.positions.clone();
        triangles = cut.triangles.clone();
        tutte::fill_holes(&mut positions, &mut triangles, holes);
        (&positions, &triangles)
    };
    let mut fixed = vec![None; positions.len()];
    for (&c, &p) in cut.loops[0].iter().zip(&outer) {
        fixed[c as usize] = Some(p);
    }
    let start = Instant::now();
    let (mut uv, solver) = tutte::solve_triangles(params.method, positions, triangles, &fixed)?;
    let ms = start.elapsed().as_secs_f64() * 1e3;
    uv.truncate(n);
    Ok((uv, solver, ms, holes.len()))
}

/// `uv` moved and scaled uniformly into `[0, 1]²`: the bounding box's corner to the origin,
/// its longer side to 1.
fn normalise(uv: &[DVec2]) -> Vec<DVec2> {
    let (mut lo, mut hi) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
    for &p in uv {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let size = (hi - lo).max_element();
    let scale = if size > 0.0 { 1.0 / size } else { 1.0 };
    uv.iter().map(|&p| (p - lo) * scale).collect()
}

/// The tables of `soup` built into a fresh world (for the tests of this module).
#[cfg(test)]
pub(crate) fn test_tables(soup: &crate::mesh::PolygonSoup) -> Connectivity {
    let mut world = World::new();
    let built = crate::mesh::build_mesh(&mut world, soup, crate::mesh::MeshInfo::default())
        .expect("a test shape builds");
    extract(&world, built.mesh).tables
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;
    use crate::mesh::tables::EdgeRow;
    use crate::ops::named::Named;

    #[test]
    fn names_round_trip() {
        for &(m, name) in ParamMethod::ALL {
            assert_eq!(m.name(), name);
            assert_eq!(name.parse::<ParamMethod>(), Ok(m));
            assert_eq!(m.to_string(), name);
        }
        for &(b, name) in BoundaryShape::ALL {
            assert_eq!(b.name(), name);
            assert_eq!(name.parse::<BoundaryShape>(), Ok(b));
        }
        let e = "meanvalue".parse::<ParamMethod>().unwrap_err();
        assert!(
            e.to_string().contains("uniform|mean-value|harmonic|lscm"),
            "{e}"
        );
        assert!("triangle".parse::<BoundaryShape>().is_err());
    }

    /// Every corner has a finite UV in [0, 1]², boundary halfedges NaN.
    fn check_layout(t: &Connectivity, p: &Parameterization) {
        assert_eq!(p.uv.len(), t.halfedge_count());
        for h in t.halfedges() {
            let uv = p.uv[h.index()];
            if t.is_boundary(h) {
                assert!(uv.x.is_nan() && uv.y.is_nan());
            } else {
                assert!(uv.is_finite(), "{uv}");
                assert!(
                    uv.min_element() >= -1e-6 && uv.max_element() <= 1.0 + 1e-6,
                    "{uv}"
                );
            }
        }
    }

    #[test]
    fn every_method_lays_out_a_grid_with_holes_without_flips() {
        let t = test_tables(&shapes::grid_with_holes(3));
        for &(method, _) in ParamMethod::ALL {
            for &(boundary, _) in BoundaryShape::ALL {
                let p = parameterize(
                    &t,
                    &ParamParams {
                        boundary,
                        ..ParamParams::new(method)
                    },
                )
                .unwrap();
                check_layout(&t, &p);
                let r = &p.report;
                assert!(r.boundary_loops > 1, "{r:?}");
                if method.fixed_boundary() {
                    assert_eq!(r.filled_holes, r.boundary_loops - 1);
                }
                if boundary == BoundaryShape::Circle || !method.fixed_boundary() {
                    assert_eq!(r.flipped, 0, "{method:?} {boundary:?}: {r:?}");
                }
                assert!(p.vertex_uvs(&t).is_some());
            }
        }
    }

    #[test]
    fn a_closed_cube_is_cut_automatically_and_its_corners_differ_across_the_cut() {
        let t = test_tables(&shapes::cube());
        for method in [ParamMethod::MeanValue, ParamMethod::Lscm] {
            let p = parameterize(&t, &ParamParams::new(method)).unwrap();
            check_layout(&t, &p);
            let r = &p.report;
            assert!(
                r.auto_seam_edges >= 2 && r.seam_edges == r.auto_seam_edges,
                "{r:?}"
            );
            assert_eq!(r.boundary_loops, 1);
            assert_eq!(r.flipped, 0, "{method:?}: {r:?}");
            assert!(r.cut_vertices > t.vertex_count());
            assert!(p.vertex_uvs(&t).is_none());
        }
    }

    #[test]
    fn a_sphere_with_the_automatic_cut_has_different_uvs_on_either_side_of_the_seam() {
        let t = test_tables(&shapes::icosphere(3));
        let p = parameterize(&t, &ParamParams::new(ParamMethod::MeanValue)).unwrap();
        check_layout(&t, &p);
        assert_eq!(p.report.flipped, 0, "{:?}", p.report);
        let seams = cut::auto_seams(&t);
        for &e in &seams[1..seams.len() - 1] {
            // Inside the path, both corners of each side at the edge's tip differ.
            let h = t.edge_halfedge(e);
            let o = t.twin(h);
            assert_ne!(p.uv[h.index()], p.uv[t.prev(o).index()]);
        }
    }

    #[test]
    fn refusals_name_the_genus_and_the_pieces() {
        let torus = test_tables(&shapes::torus(12, 8));
        let e = parameterize(&torus, &ParamParams::new(ParamMethod::Lscm)).unwrap_err();
        assert_eq!(
            e,
            ParamError::NotADisk {
                genus: 1,
                loops: 0,
                seams: 0
            }
        );
        assert!(e.to_string().contains("genus 1"), "{e}");
        assert!(e.to_string().contains("mark seams"), "{e}");
        let mut two = shapes::grid(2, 2);
        let mut other = shapes::grid(2, 2);
        let offset = two.positions.len() as u32;
        for p in &mut other.positions {
            p.z += 5.0;
        }
        let faces: Vec<Vec<u32>> = two
            .faces()
            .map(<[u32]>::to_vec)
            .chain(
                other
                    .faces()
                    .map(|f| f.iter().map(|v| v + offset).collect()),
            )
            .collect();
        two.positions.extend(other.positions);
        let soup = crate::mesh::PolygonSoup::from_faces(two.positions, &faces);
        assert_eq!(
            parameterize(&test_tables(&soup), &ParamParams::default()).unwrap_err(),
            ParamError::Components { components: 2 }
        );
        let closed = ParamParams {
            auto_cut: false,
            ..ParamParams::default()
        };
        assert!(matches!(
            parameterize(&test_tables(&shapes::cube()), &closed),
            Err(ParamError::NotADisk { loops: 0, .. })
        ));
        let bad = ParamParams {
            seams: vec![EdgeRow::new(10_000)],
            ..ParamParams::default()
        };
        assert!(matches!(
            parameterize(&torus, &bad),
            Err(ParamError::SeamOutOfRange { edge: 10_000, .. })
        ));
    }

    #[test]
    fn a_torus_cut_along_two_loops_is_a_disk() {
        // The torus's quads at ring 0 (around the tube) and side 0 (around the axis): the two
        // generators; cutting both opens it into one rectangle.
        let soup = shapes::torus(12, 8);
        let t = test_tables(&soup);
        let (rings, sides) = (12u32, 8u32);
        let at =
            |i: u32, j: u32| crate::mesh::tables::VertexRow::new((i % rings) * sides + (j % sides));
        let mut seams = Vec::new();
        for j in 0..sides {
            seams.push(t.edge(t.find_halfedge(at(0, j), at(0, j + 1)).unwrap()));
        }
        for i in 0..rings {
            seams.push(t.edge(t.find_halfedge(at(i, 0), at(i + 1, 0)).unwrap()));
        }
        let params = ParamParams {
            seams,
            ..ParamParams::new(ParamMethod::MeanValue)
        };
        let p = parameterize(&t, &params).unwrap();
        check_layout(&t, &p);
        assert_eq!(p.report.boundary_loops, 1);
        assert_eq!(p.report.flipped, 0);
        assert_eq!(
            p.report.cut_vertices,
            t.vertex_count() + (rings + sides + 1) as usize
        );
    }
}
