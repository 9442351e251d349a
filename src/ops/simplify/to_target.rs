//! Simplifying to the target in one go: the mesh read once into flat tables ([`super::flat`]),
//! every collapse made on rows in the order the stepped run ([`super::QemRun`]) would make it,
//! the survivors written back and the removed elements despawned at the end. It uses the
//! quadrics, placements and keys of [`super`], which do not call it.

use super::fidelity::DistanceCheck;
use super::fit::InputSurface;
use super::*;
use crate::ops::geometry::surface_fit::apply_moves;

/// Simplifies `mesh` (triangles only) until it has at most the target's faces or no
/// legal collapse remains.
///
/// # Refusals
/// [`Refusal::NotTriangle`] if a face is not a triangle (the mesh is unchanged); a stale mesh.
pub fn simplify(
    world: &mut World,
    mesh: MeshId,
    params: &SimplifyParams,
) -> Result<SimplifySummary, Refusal> {
    simplify_with_progress(world, mesh, params, |_| true)
}

/// [`simplify`], calling `progress(fraction done)` every few hundred collapses; returning
/// `false` stops early (the mesh is then valid but less simplified).
///
/// # Refusals
/// As [`simplify`].
pub fn simplify_with_progress(
    world: &mut World,
    mesh: MeshId,
    params: &SimplifyParams,
    progress: impl FnMut(f32) -> bool,
) -> Result<SimplifySummary, Refusal> {
    simplify_inner(world, mesh, params, progress, |_| {}).map(|(summary, _)| summary)
}

/// [`simplify_with_progress`], handing every collapse it makes to `record` in order, as
/// [`crate::ops::progressive`] keeps it to split them back: a [`SlotRecord`] whose slots are
/// vertex rows, numbered as [`crate::mesh::MeshMembers::collect`] lists the mesh's vertices at the start.
/// Returns, with the summary, the vertex in each slot afterwards (`None`: collapsed away).
///
/// # Refusals
/// As [`simplify`].
pub fn simplify_recorded(
    world: &mut World,
    mesh: MeshId,
    params: &SimplifyParams,
    progress: impl FnMut(f32) -> bool,
    record: impl FnMut(SlotRecord),
) -> Result<(SimplifySummary, Vec<Option<VertexId>>), Refusal> {
    simplify_inner(world, mesh, params, progress, record)
}

/// The run to the end, on flat tables ([`flat`]): the mesh is read once, every collapse is
/// made on rows in the order [`QemRun`] would make it, and the survivors are written back and
/// the removed elements despawned in one pass at the end.
fn simplify_inner(
    world: &mut World,
    mesh: MeshId,
    params: &SimplifyParams,
    mut progress: impl FnMut(f32) -> bool,
    mut record: impl FnMut(SlotRecord),
) -> Result<(SimplifySummary, Vec<Option<VertexId>>), Refusal> {
    let MeshTables { tables: t, members } = read_triangles(world, mesh)?;
    // Edges are numbered by heap slot in the flat tables, which are laid out meanwhile.
    let (base, slots) = edge_slot_range(&members.edges);
    let slot_of_row: Vec<u32> = members
        .edges
        .iter()
        .map(|e| e.0.index_u32() - base)
        .collect();
    let vertex_order = |v: u32| members.vertices[v as usize].0.to_bits();
    let keyed = |quadric: &[Quadric], slot: u32, [(a, pa), (b, pb)]: [(u32, Vec3); 2]| {
        let c = placement(quadric[a as usize] + quadric[b as usize], pa, pb, || {
            vertex_order(a) < vertex_order(b)
        });
        (heap_key(c.cost, slot), c.position)
    };
    let (mut flat, (mut quadric, mut heap, mut target, mut check)) = std::thread::scope(|scope| {
        let flat = scope.spawn(|| flat::FlatTriangles::new(&t, &slot_of_row, slots));
        let quadric = vertex_quadrics(&t, params);
        let mut target = vec![Vec3::ZERO; slots];
        let entries = t
            .edges()
            .map(|e| {
                let h = t.edge_halfedge(e);
                let ends = [t.from_vertex(h), t.to_vertex(h)];
                let slot = slot_of_row[e.index()];
                let (key, at) = keyed(
                    &quadric,
                    slot,
                    ends.map(|v| (v.index() as u32, t.position(v))),
                );
                target[slot as usize] = at;
                key
            })
            .collect::<Vec<Key>>();
        let sizes = [slots, t.vertex_count()];
        let check = DistanceCheck::for_run(&t, params.distance_weight, sizes, &entries);
        let heap = IndexedHeap::from_entries(slots, entries);
        let flat = flat
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (flat, (quadric, heap, target, check))
    });
    let faces_before = t.face_count();
    // The run needs only its own tables from here on (and the fit, the input's surface).
    let mut fit = params
        .fit_to_input
        .then(|| FitAtEnd::start(t, quadric.len()));
    let limit = params.max_normal_change_deg.to_radians().cos();
    let target_faces = params.target.faces(faces_before);
    let to_remove = faces_before.saturating_sub(target_faces).max(1);
    let (mut faces, mut collapses) = (faces_before, 0usize);
    let mut ring = Vec::new();
    while faces > target_faces {
        let Some(entry) = heap.pop() else { break };
        let e = slot_of(entry);
        let Some(plan) = flat.plan(flat.edge_halfedge(e), target[e as usize], limit) else {
            continue;
        };
        if let Some(check) = &mut check {
            check.read_faces(flat.reshaped_faces(&plan));
            let ends = plan.ends().map(|v| v as usize);
            if let Some(key) = check.review(entry, ends, heap_key) {
                heap.set(key);
                continue;
            }
        }
        ring.clear();
        let done = flat.apply(plan, |e, tip, at| ring.push((e, tip, at)));
        for e in done.removed_edges.into_iter().flatten() {
            heap.remove(e);
        }
        faces -= done.triangles_removed();
        collapses += 1;
        let (a, b) = (done.kept as usize, done.removed as usize);
        quadric[a] = quadric[a] + quadric[b];
        if let Some(fit) = &mut fit {
            fit.kept[a] = true;
        }
        if let Some(check) = &mut check {
            check.collapsed(a, ring.iter().map(|&(_, tip, _)| tip as usize));
        }
        for &(e, tip, at) in &ring {
            let (key, position) = keyed(&quadric, e, [(done.kept, done.position), (tip, at)]);
            target[e as usize] = position;
            if let Some(check) = &mut check {
                check.queued(key);
            }
            heap.set(key);
        }
        record(done.record());
        if collapses % 512 == 0 {
            let fraction = (faces_before - faces) as f32 / to_remove as f32;
            if !progress(fraction.min(1.0)) {
                break;
            }
        }
    }
    let slots = match fit {
        Some(fit) => fit.finish(world, flat, &members, &slot_of_row),
        None => flat.write_back(world, &members, &slot_of_row),
    };
    let summary = SimplifySummary {
        faces_before,
        faces_after: faces,
        collapses,
        reached_target: faces <= target_faces,
    };
    Ok((summary, slots))
}

/// The fit to the input at the end of a one-go run ([`SimplifyParams::fit_to_input`]): the
/// input's surface, built on the core the loop leaves idle, each face row's halfedge (which
/// no collapse changes), and which vertex rows a collapse kept (the others stay where they
/// are).
struct FitAtEnd {
    input: std::thread::JoinHandle<InputSurface>,
    face_halfedge: Vec<u32>,
    kept: Vec<bool>,
}

impl FitAtEnd {
    /// Starts building the surface of the input in `t`, which has `vertices` vertex rows.
    fn start(t: Connectivity, vertices: usize) -> Self {
        Self {
            face_halfedge: t.face_halfedge.clone(),
            input: std::thread::spawn(move || InputSurface::of_tables(&t)),
            kept: vec![false; vertices],
        }
    }

    /// Writes `flat` back into its entities (`members`, the edges numbered by `edge_number`)
    /// and fits them to the input, the fit's searches running on the simplification's rows
    /// beside the writing; returns the vertex behind each row now, as
    /// [`flat::FlatTriangles::write_back`] does.
    fn finish(
        self,
        world: &mut World,
        flat: flat::FlatTriangles,
        members: &MeshMembers,
        edge_number: &[u32],
    ) -> Vec<Option<VertexId>> {
        let input = self
            .input
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        let held = |row: usize, boundary: bool| boundary || !self.kept[row];
        let elements = flat.fit_elements(members, edge_number, &self.face_halfedge, held);
        let (moves, slots) = std::thread::scope(|scope| {
            let moves = scope.spawn(|| input.moves(&elements));
            let slots = flat.write_back(world, members, edge_number);
            let moves = moves
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            (moves, slots)
        });
        apply_moves(world, &moves);
        slots
    }
}
