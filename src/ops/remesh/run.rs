//! Isotropic remeshing (Botsch & Kobbelt 2004) one pass at a time, for a student to watch the
//! loop work on the live mesh: [`RemeshRun`] holds what the loop reads before its first pass
//! (the target length, the input surface to project onto, the input's tips and the feature
//! edges) and makes one pass a call.
//!
//! A run makes, for each iteration, the passes [`Pass::ITERATION`] (split, collapse, flip,
//! relax, project; see the [`remesh`](super) module doc for what each does), then after the
//! last iteration one [`Pass::Finish`] (tips and grooves put back, thin triangles cleaned
//! up, the vertices fitted to the input, the corners nearest the far spots pulled towards
//! them). Each pass edits the world (splits on the entities;
//! collapses and flips made on tables, as the local operations make them, and written back;
//! moves), and the mesh is valid between any two. The first pass drops the mesh's attributes,
//! which remeshing does not carry. [`remesh_with_progress`](super::remesh_with_progress) is
//! this loop run to the end, so a run stepped by hand ends in the very same mesh, to the bit.
//!
//! The relaxation and the projection are two passes, where the loop once projected inside the
//! last smoothing step: the steps are Jacobi (every new position from the old ones), so
//! projecting the relaxed positions afterwards gives the same bits.
//!
//! ```text
//!   start ─▶ [split ▶ collapse ▶ flip ▶ relax ▶ project] × iterations ▶ finish ─▶ None
//! ```

use bevy::ecs::entity::EntityHashSet;
use bevy::math::Vec3;
use bevy::prelude::World;

use crate::mesh::attributes::drop_attributes;
use crate::mesh::ids::{ElementId, MeshId, VertexId};
use crate::mesh::tables::{Connectivity, MeshTables, extract};
use crate::ops::Refusal;
use crate::ops::geometry::closest::Reference;

use super::collapse::collapse_short;
use super::far_spots::pull_to_far_spots;
use super::features::feature_rows;
use super::finish::{DETAIL_TOLERANCE, clean_up_thin, detail_points, fill_grooves, restore_tips};
use super::flip::flip_to_valence;
use super::pass::{Pass, PassReport, Touched};
use super::relax::{Smoother, project};
use super::split::split_long;
use super::{RemeshParams, RemeshSummary};
use crate::ops::geometry::surface_fit::fit_to_input;

/// A remesh under way, one pass a call to [`RemeshRun::next_pass`].
///
/// It holds the input surface (for the projections and the finish) and the feature edges,
/// which the splits extend; it assumes the mesh changes only through it between passes. It
/// holds no borrow of the world, so it can wait between frames (it is `Send + Sync`).
pub struct RemeshRun {
    mesh: MeshId,
    iterations: u32,
    smoothing_steps: u32,
    /// The target length L, and 4/3 L and 4/5 L.
    length: f32,
    high: f32,
    low: f32,
    /// The input surface, for the projections and the finish.
    reference: Reference,
    /// The input's points [`restore_tips`] may put back ([`detail_points`]): its interior
    /// vertices (the first `vertex_tips`, which the fit measures too), then the centres of
    /// its coarse triangles.
    tips: Vec<Vec3>,
    vertex_tips: usize,
    features: EntityHashSet,
    summary: RemeshSummary,
    done: usize,
    /// The vertices the last relax pass could move, which the project pass puts back onto
    /// the input.
    relaxed: Vec<VertexId>,
}

/// Refuses a target `length` whose triangles would not fit the memory budget: a surface of
/// area A remeshed to edges of length L has about A / (√3/4 · L²) triangles (equilateral ones
/// tile it), whatever the iterations.
///
/// # Refusals
/// [`Refusal::OverBudget`], [`Refusal::BadParameter`] for a length that is not positive.
fn check_budget(t: &Connectivity, length: f32, iterations: u32) -> Result<(), Refusal> {
    if !(length > 0.0 && length.is_finite()) {
        return Err(Refusal::BadParameter(format!(
            "the target edge length must be positive (it is {length})"
        )));
    }
    let area: f64 = t
        .faces()
        .map(|f| 0.5 * f64::from(t.triangle_area_vector(f).length()))
        .sum();
    let triangle = 3f64.sqrt() / 4.0 * f64::from(length).powi(2);
    let faces = (area / triangle).min(u64::MAX as f64 / 8.0) as u64;
    crate::memory_budget::check(&crate::memory_budget::Estimate {
        what: format!("remeshing to edges of {length} ({iterations} iterations)"),
        faces,
        rows: crate::memory_budget::Estimate::triangle_rows(faces),
        instead: "use a longer target length",
    })
    .map_err(Refusal::from)
}

impl RemeshRun {
    /// Reads `mesh` for a remesh with `params`: the target length (the mean edge length when
    /// `params` gives none), the input surface, the input's interior vertices and the feature
    /// edges. Changes nothing.
    ///
    /// # Refusals
    /// [`Refusal::Stale`] for a mesh that is not there, [`Refusal::NotTriangle`] on a polygon,
    /// [`Refusal::OverBudget`] when triangles of the target length would not fit the memory
    /// budget.
    pub fn start(world: &World, mesh: MeshId, params: &RemeshParams) -> Result<Self, Refusal> {
        if world.get::<crate::mesh::MeshInfo>(mesh.0).is_none() {
            return Err(Refusal::Stale(ElementId::Mesh(mesh)));
        }
        // One read of the mesh into tables: every walk below is over rows.
        let MeshTables { tables: t, members } = extract(world, mesh);
        if let Some(f) = t.first_non_triangle() {
            return Err(Refusal::NotTriangle(ElementId::Face(
                members.faces[f.index()],
            )));
        }
        let length = params.target_length.unwrap_or_else(|| {
            let sum: f32 = t.edges().map(|e| t.edge_length(e)).sum();
            sum / t.edge_count().max(1) as f32
        });
        check_budget(&t, length, params.iterations)?;
        let reference =
            Reference::from_triangles(t.faces().map(|f| t.triangle_corners(f)).collect());
        let (tips, vertex_tips) = detail_points(&t, length);
        let cos_limit = params.feature_angle_deg.to_radians().cos();
        let features: EntityHashSet = feature_rows(&t, cos_limit)
            .iter()
            .zip(&members.edges)
            .filter(|&(&feature, _)| feature)
            .map(|(_, e)| e.0)
            .collect();
        Ok(Self {
            mesh,
            iterations: params.iterations,
            smoothing_steps: params.smoothing_steps,
            length,
            high: 4.0 / 3.0 * length,
            low: 4.0 / 5.0 * length,
            reference,
            tips,
            vertex_tips,
            features,
            summary: RemeshSummary {
                target_length: length,
                splits: 0,
                collapses: 0,
                flips: 0,
            },
            done: 0,
            relaxed: Vec::new(),
        })
    }

    /// The mesh being remeshed.
    pub fn mesh(&self) -> MeshId {
        self.mesh
    }

    /// How many passes the whole run makes: five an iteration and the finish, or none for no
    /// iterations.
    pub fn passes_total(&self) -> usize {
        match self.iterations {
            0 => 0,
            n => n as usize * Pass::ITERATION.len() + 1,
        }
    }

    /// How many passes have been made.
    pub fn passes_done(&self) -> usize {
        self.done
    }

    /// The pass [`RemeshRun::next_pass`] makes next and its iteration, or `None` when the run
    /// is over.
    pub fn upcoming(&self) -> Option<(Pass, u32)> {
        let per = Pass::ITERATION.len();
        if self.done >= self.passes_total() {
            None
        } else if self.done + 1 == self.passes_total() {
            Some((Pass::Finish, self.iterations))
        } else {
            Some((Pass::ITERATION[self.done % per], (self.done / per) as u32))
        }
    }

    /// The target length and the splits, collapses and flips made so far.
    pub fn summary(&self) -> RemeshSummary {
        self.summary
    }

    /// Makes the next pass (see [`RemeshRun::upcoming`]) and says what it did; `None`, with the
    /// world untouched, when the run is over or the mesh is gone (which ends the run).
    pub fn next_pass(&mut self, world: &mut World) -> Option<PassReport> {
        let (pass, iteration) = self.upcoming()?;
        if world.get::<crate::mesh::MeshInfo>(self.mesh.0).is_none() {
            self.done = self.passes_total();
            return None;
        }
        let mesh = self.mesh;
        if self.done == 0 {
            // The passes on tables carry no attributes: none is left to go stale.
            drop_attributes(world, mesh);
        }
        let mut touched = Touched::default();
        let count = match pass {
            Pass::Split => {
                touched = split_long(world, mesh, self.high, &mut self.features);
                self.summary.splits += touched.vertices.len();
                touched.vertices.len()
            }
            Pass::Collapse => {
                let (collapses, survivors) =
                    collapse_short(world, mesh, self.low, self.high, &self.features);
                touched.vertices = survivors;
                self.summary.collapses += collapses;
                collapses
            }
            Pass::Flip => {
                touched.edges = flip_to_valence(world, mesh, &self.features);
                self.summary.flips += touched.edges.len();
                touched.edges.len()
            }
            Pass::Relax => {
                // Small steps over one connectivity, read once and written once.
                let mut smoother = Smoother::new(world, mesh, &self.features);
                for _ in 0..self.smoothing_steps.max(1) {
                    smoother.step();
                }
                let relaxed = smoother.write(world);
                self.relaxed = relaxed.free;
                touched.vertices = relaxed.moved;
                touched.vertices.len()
            }
            Pass::Project => {
                let relaxed = std::mem::take(&mut self.relaxed);
                touched.vertices = project(world, &relaxed, &self.reference);
                touched.vertices.len()
            }
            Pass::Finish => self.finish(world, &mut touched),
        };
        self.done += 1;
        Some(PassReport {
            pass,
            iteration,
            count,
            touched,
        })
    }

    /// The finishing pass: tips and grooves put back, the thin triangles cleaned up, then the
    /// vertices fitted to the input.
    /// Fills `touched` with the vertices added and the edges flipped; returns the splits plus
    /// the flips.
    fn finish(&mut self, world: &mut World, touched: &mut Touched) -> usize {
        let (mesh, length) = (self.mesh, self.length);
        let tolerance = DETAIL_TOLERANCE * length;
        let (reference, features) = (&self.reference, &self.features);
        let pinned = restore_tips(
            world, mesh, &self.tips, reference, features, length, tolerance,
        );
        let grooves = fill_grooves(world, mesh, reference, features, tolerance);
        let flipped = clean_up_thin(
            world,
            mesh,
            features,
            &pinned,
            reference,
            self.low / 16.0,
            tolerance,
        );
        let vertices = &self.tips[..self.vertex_tips];
        fit_to_input(world, mesh, reference, vertices, features, &pinned);
        pull_to_far_spots(
            world, mesh, &self.tips, reference, features, &pinned, length,
        );
        let splits = pinned.len() + grooves.len();
        self.summary.splits += splits;
        self.summary.flips += flipped.len();
        touched.vertices = pinned.iter().map(|&v| VertexId(v)).collect();
        touched.vertices.sort_unstable();
        touched.vertices.extend(grooves);
        touched.edges = flipped.clone();
        touched.edges.sort_unstable();
        touched.edges.dedup();
        splits + flipped.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::elements::{Edge, InMesh, Vertex};
    use crate::mesh::ids::EdgeId;
    use crate::mesh::members::MeshMembers;
    use crate::mesh::topology::MeshRef;
    use crate::mesh::{MeshInfo, build_mesh, shapes, validate};
    use crate::ops::remesh::remesh_with_progress;
    use crate::ops::remesh::tests::{Case, built, cases, counts, fingerprint, pinned};
    use std::collections::HashMap;

    /// Whether `v` is alive and in `mesh`.
    fn vertex_in(world: &World, mesh: MeshId, v: VertexId) -> bool {
        world.get::<Vertex>(v.0).is_some() && world.get::<InMesh>(v.0) == Some(&InMesh(mesh))
    }

    /// Whether `e` is alive and in `mesh`.
    fn edge_in(world: &World, mesh: MeshId, e: EdgeId) -> bool {
        world.get::<Edge>(e.0).is_some() && world.get::<InMesh>(e.0) == Some(&InMesh(mesh))
    }

    /// Every vertex of `mesh` with its position.
    fn positions(world: &World, mesh: MeshId) -> HashMap<VertexId, Vec3> {
        let m = MeshRef::new(world);
        MeshMembers::collect(world, mesh)
            .vertices
            .into_iter()
            .map(|v| (v, m.position(v)))
            .collect()
    }

    /// `p` as bits.
    fn bits(p: Vec3) -> [u32; 3] {
        p.to_array().map(f32::to_bits)
    }

    /// `case` run to its end pass by pass, checking each pass against the mesh before and after
    /// it (see the assertions); returns the world, the mesh, the run and its reports.
    fn stepped(case: &Case, validate_each: bool) -> (World, MeshId, RemeshRun, Vec<PassReport>) {
        let (mut world, mesh) = built(case);
        let mut run = RemeshRun::start(&world, mesh, &case.params).unwrap();
        let mut reports = Vec::new();
        loop {
            let before = positions(&world, mesh);
            let upcoming = run.upcoming();
            let Some(report) = run.next_pass(&mut world) else {
                assert_eq!(upcoming, None);
                break;
            };
            assert_eq!(upcoming, Some((report.pass, report.iteration)));
            assert_eq!(run.passes_done(), reports.len() + 1);
            if validate_each {
                validate(&world, mesh).unwrap();
            }
            let name = format!("{}: {:?} {}", case.name, report.pass, report.iteration);
            let touched = &report.touched;
            for &v in &touched.vertices {
                assert!(vertex_in(&world, mesh, v), "{name}: {v:?} is gone");
            }
            for &e in &touched.edges {
                assert!(edge_in(&world, mesh, e), "{name}: {e:?} is gone");
            }
            let mut distinct = touched.vertices.clone();
            distinct.sort_unstable();
            distinct.dedup();
            assert_eq!(distinct.len(), touched.vertices.len(), "{name}: twice");
            let after = positions(&world, mesh);
            let new: Vec<VertexId> = after
                .keys()
                .filter(|v| !before.contains_key(v))
                .copied()
                .collect();
            let moved: Vec<VertexId> = {
                let mut moved: Vec<VertexId> = after
                    .iter()
                    .filter(|(v, p)| before.get(v).is_some_and(|&q| bits(q) != bits(**p)))
                    .map(|(&v, _)| v)
                    .collect();
                moved.sort_unstable();
                moved
            };
            match report.pass {
                Pass::Split => {
                    // The new vertices, all of them, and nothing moved.
                    assert_eq!(report.count, new.len(), "{name}");
                    assert_eq!(report.count, touched.vertices.len(), "{name}");
                    assert!(touched.vertices.iter().all(|v| !before.contains_key(v)));
                    assert!(moved.is_empty(), "{name}");
                    // Each touched edge has a new end.
                    let m = MeshRef::new(&world);
                    for &e in &touched.edges {
                        let (a, b) = m.edge_vertices(e);
                        assert!(!before.contains_key(&a) || !before.contains_key(&b));
                    }
                }
                Pass::Collapse => {
                    // One vertex gone a collapse, none made; the survivors are old ones.
                    assert!(new.is_empty(), "{name}");
                    assert_eq!(before.len() - after.len(), report.count, "{name}");
                    assert!(touched.vertices.len() <= report.count, "{name}");
                    assert!(touched.vertices.iter().all(|v| before.contains_key(v)));
                    assert!(touched.edges.is_empty());
                }
                Pass::Flip => {
                    assert!(new.is_empty() && moved.is_empty(), "{name}");
                    assert_eq!(before.len(), after.len());
                    assert_eq!(report.count, touched.edges.len(), "{name}");
                    let mut distinct = touched.edges.clone();
                    distinct.sort_unstable();
                    distinct.dedup();
                    assert_eq!(distinct.len(), touched.edges.len(), "{name}: twice");
                }
                Pass::Relax | Pass::Project => {
                    // Exactly the vertices whose position changed by a bit.
                    assert!(new.is_empty(), "{name}");
                    let mut touched = touched.vertices.clone();
                    touched.sort_unstable();
                    assert_eq!(touched, moved, "{name}");
                    assert_eq!(report.count, moved.len(), "{name}");
                    assert!(report.touched.edges.is_empty());
                }
                Pass::Finish => {
                    // The added vertices, all of them; the flips beside them.
                    let mut added = touched.vertices.clone();
                    added.sort_unstable();
                    let mut new = new.clone();
                    new.sort_unstable();
                    assert_eq!(added, new, "{name}");
                    assert!(report.count >= added.len() + touched.edges.len(), "{name}");
                    let mut distinct = touched.edges.clone();
                    distinct.dedup();
                    assert_eq!(distinct.len(), touched.edges.len(), "{name}: twice");
                }
            }
            reports.push(report);
        }
        (world, mesh, run, reports)
    }

    #[test]
    fn a_run_stepped_to_its_end_is_the_remesh_to_the_bit() {
        for case in cases() {
            // Validating after every pass of the big models is slow in a debug build.
            let small = case.soup.positions.len() < 1000;
            let (world, mesh, run, reports) = stepped(&case, small);
            validate(&world, mesh).unwrap();
            let print = fingerprint(&world, mesh);
            assert_eq!(
                (counts(&run.summary()), print),
                pinned(case.name),
                "{}",
                case.name
            );
            let (mut again, mesh) = built(&case);
            let summary = crate::ops::remesh::remesh(&mut again, mesh, &case.params).unwrap();
            assert_eq!(summary, run.summary(), "{}", case.name);
            assert_eq!(fingerprint(&again, mesh), print, "{}", case.name);

            // The passes in order, five an iteration and the finish.
            let n = case.params.iterations;
            let mut expected: Vec<(Pass, u32)> = (0..n)
                .flat_map(|i| Pass::ITERATION.map(|p| (p, i)))
                .collect();
            expected.push((Pass::Finish, n));
            let made: Vec<(Pass, u32)> = reports.iter().map(|r| (r.pass, r.iteration)).collect();
            assert_eq!(made, expected, "{}", case.name);
            assert_eq!(run.passes_total(), n as usize * 5 + 1);
            assert_eq!(run.passes_done(), run.passes_total());

            // The counts add up to the summary: the finish's count is its splits (the
            // vertices it added) and its flips.
            let sum = |pass: Pass| -> usize {
                reports
                    .iter()
                    .filter(|r| r.pass == pass)
                    .map(|r| r.count)
                    .sum()
            };
            let finish = reports.last().unwrap();
            let finish_splits = finish.touched.vertices.len();
            let s = run.summary();
            assert_eq!(sum(Pass::Split) + finish_splits, s.splits, "{}", case.name);
            assert_eq!(sum(Pass::Collapse), s.collapses, "{}", case.name);
            assert_eq!(
                sum(Pass::Flip) + finish.count - finish_splits,
                s.flips,
                "{}",
                case.name
            );
            println!(
                "{}: {}",
                case.name,
                reports
                    .iter()
                    .map(|r| format!("{}{} {}", r.pass.name(), r.iteration, r.count))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
    }

    #[test]
    fn the_cubes_first_iteration_splits_its_diagonals_at_the_face_centres() {
        // The cube [-1, 1]³ in triangles: edges of 2 (features, 90°) and six diagonals of
        // 2√2. With L = 1.6, 4/3 L = 2.13: only the diagonals are long, and each splits at its
        // face's centre into four spokes of √2 (over 4/5 L = 1.28: nothing collapses). A spoke
        // flip would put the new edge through the centre (refused); and each centre is its
        // one-ring's centroid, so the relaxation moves nothing.
        let case = Case {
            name: "cube",
            soup: shapes::triangulate_fans(&shapes::cube()),
            params: RemeshParams {
                target_length: Some(1.6),
                iterations: 1,
                ..Default::default()
            },
        };
        let (mut world, mesh) = built(&case);
        let mut run = RemeshRun::start(&world, mesh, &case.params).unwrap();
        assert_eq!(run.passes_total(), 6);
        let split = run.next_pass(&mut world).unwrap();
        assert_eq!(
            (split.pass, split.iteration, split.count),
            (Pass::Split, 0, 6)
        );
        let m = MeshRef::new(&world);
        let mut centres: Vec<[i32; 3]> = split
            .touched
            .vertices
            .iter()
            .map(|&v| m.position(v).to_array().map(|c| c as i32))
            .collect();
        centres.sort_unstable();
        assert_eq!(
            centres,
            [
                [-1, 0, 0],
                [0, -1, 0],
                [0, 0, -1],
                [0, 0, 1],
                [0, 1, 0],
                [1, 0, 0]
            ]
        );
        for &v in &split.touched.vertices {
            assert_eq!(m.vertex_neighbors(v).count(), 4);
            assert_eq!(m.position(v).length(), 1.0);
        }
        assert_eq!(split.touched.edges.len(), 24);
        for &e in &split.touched.edges {
            let (a, b) = m.edge_vertices(e);
            assert_eq!(m.position(a).distance(m.position(b)), 2f32.sqrt());
        }
        for pass in [Pass::Collapse, Pass::Flip, Pass::Relax] {
            let report = run.next_pass(&mut world).unwrap();
            assert_eq!((report.pass, report.count), (pass, 0));
            assert_eq!(report.touched, Touched::default());
        }
        let summary = run.summary();
        assert_eq!(
            (summary.splits, summary.collapses, summary.flips),
            (6, 0, 0)
        );
        validate(&world, mesh).unwrap();
    }

    #[test]
    fn stopping_early_leaves_the_mesh_the_stepped_run_has_at_that_pass() {
        let cases = cases();
        let case = cases.iter().find(|c| c.name == "wavy grid").unwrap();
        assert_eq!(case.params.iterations, 4);
        for stop in [3, 4, 9] {
            let (mut world, mesh) = built(case);
            let mut calls = 0;
            let summary = remesh_with_progress(&mut world, mesh, &case.params, |fraction| {
                calls += 1;
                assert_eq!(fraction, calls as f32 / 21.0);
                calls < stop
            })
            .unwrap();
            assert_eq!(calls, stop);
            validate(&world, mesh).unwrap();
            let (mut by_hand, hand_mesh) = built(case);
            let mut run = RemeshRun::start(&by_hand, hand_mesh, &case.params).unwrap();
            for _ in 0..stop {
                run.next_pass(&mut by_hand).unwrap();
            }
            assert_eq!(summary, run.summary());
            assert_eq!(fingerprint(&world, mesh), fingerprint(&by_hand, hand_mesh));
        }
    }

    #[test]
    fn polygons_stale_meshes_and_no_iterations() {
        let mut world = World::new();
        let quads = build_mesh(&mut world, &shapes::cube(), MeshInfo::default()).unwrap();
        let before = fingerprint(&world, quads.mesh);
        let params = RemeshParams::default();
        assert!(matches!(
            RemeshRun::start(&world, quads.mesh, &params),
            Err(Refusal::NotTriangle(_))
        ));
        let triangles = shapes::triangulate_fans(&shapes::cube());
        let cube = build_mesh(&mut world, &triangles, MeshInfo::default()).unwrap();
        let mut run = RemeshRun::start(&world, cube.mesh, &params).unwrap();
        crate::mesh::despawn_mesh(&mut world, quads.mesh);
        assert_eq!(
            RemeshRun::start(&world, quads.mesh, &params).err(),
            Some(Refusal::Stale(ElementId::Mesh(quads.mesh)))
        );
        // A run whose mesh goes ends.
        assert!(run.next_pass(&mut world).is_some());
        crate::mesh::despawn_mesh(&mut world, cube.mesh);
        assert!(run.next_pass(&mut world).is_none());
        assert_eq!(run.upcoming(), None);

        let (mut world, mesh) = built(&Case {
            name: "grid",
            soup: shapes::grid(3, 3),
            params,
        });
        let still = fingerprint(&world, mesh);
        let none = RemeshParams {
            iterations: 0,
            ..params
        };
        let mut run = RemeshRun::start(&world, mesh, &none).unwrap();
        assert_eq!((run.passes_total(), run.upcoming()), (0, None));
        assert!(run.next_pass(&mut world).is_none());
        assert_eq!(fingerprint(&world, mesh), still);
        assert_ne!(before, still);
    }

    #[test]
    fn the_first_pass_drops_the_attributes_the_run_does_not_carry() {
        let mut soup = shapes::icosphere(2);
        soup.corner_uvs = Some(
            soup.indices
                .iter()
                .map(|&i| soup.positions[i as usize].truncate())
                .collect(),
        );
        soup.vertex_colors = Some(vec![[9, 9, 9]; soup.positions.len()]);
        let mut world = World::new();
        let mesh = build_mesh(&mut world, &soup, MeshInfo::default())
            .unwrap()
            .mesh;
        let had = crate::mesh::attributes::MeshAttributes::of(&world, mesh);
        assert!(had.uv && had.colors);
        let mut run = RemeshRun::start(&world, mesh, &RemeshParams::default()).unwrap();
        // Before the flips on tables could leave a corner's UV on the wrong vertex.
        assert_eq!(run.next_pass(&mut world).unwrap().pass, Pass::Split);
        assert!(crate::mesh::attributes::MeshAttributes::of(&world, mesh).is_empty());
        validate(&world, mesh).unwrap();
    }

    #[test]
    fn a_run_can_wait_between_frames() {
        fn send_sync<T: Send + Sync + 'static>() {}
        send_sync::<RemeshRun>();
        send_sync::<PassReport>();
    }
}
