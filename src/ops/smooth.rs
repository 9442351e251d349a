//! Smoothing: moving vertices by a discrete Laplacian, keeping the connectivity.
//!
//! - **Uniform** (the umbrella operator): `x_i += λ (mean of the neighbours − x_i)`, over the
//!   mesh's edges, so polygons smooth by their real sides.
//! - **Cotangent**: `x_i += λ Σ w_ij (x_j − x_i) / Σ w_ij` with the cotangent weights of the
//!   fanned triangles ([`super::geometry::Surface`]): it moves vertices across the surface far less
//!   than the umbrella (a planar mesh is a fixed point, whatever its triangles: the cotangent
//!   Laplacian reproduces linear functions). A vertex whose weights sum to zero or less stays.
//! - **Implicit** mean-curvature flow (Desbrun, Meyer, Schröder & Barr 1999): one backward Euler
//!   step `(M − h L) x' = M x` per iteration, with `L` the cotangent stiffness matrix, `M` the
//!   mixed areas ([`super::geometry::mixed_areas`]) and `h = λ · ℓ²` (`ℓ` the mean edge length,
//!   so λ is scale-free). `M − h L` is symmetric positive definite for `h > 0` (the cotangent
//!   stiffness matrix is positive semi-definite), solved by faer's sparse Cholesky. Unconditionally
//!   stable: large steps are allowed.
//! - **Taubin** λ|μ (Taubin 1995): each iteration a uniform step with λ, then one with μ < −λ
//!   (`μ = −λ/(1 − λ k_PB)`, pass-band `k_PB = 0.1`): low frequencies pass, so the mesh does not
//!   shrink as it does under the umbrella alone.
//!
//! Step mode runs it an iteration a step ([`SmoothSteps`]).
//!
//! Held vertices do not move: the boundary when [`SmoothParams::hold_boundary`] is set (the
//! default), and every vertex named in [`SmoothParams::held`]. In the implicit step they are
//! Dirichlet conditions (their columns move to the right-hand side, keeping the matrix
//! symmetric).

use bevy::math::DVec3;
use bevy::prelude::World;
use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};

use crate::mesh::ids::{ElementId, MeshId, VertexId};
use crate::mesh::tables::{Connectivity, MeshTables, extract};
use crate::mesh::{MeshInfo, Position};

use super::Refusal;
use super::geometry::{Surface, cotan_edges, mixed_areas};
use super::named::Named;

use crate::ops::declaration::{Declaration, Names, Parameter};
use crate::ops::operation::stepping::{
    Ended, GoesBack, Moved, StepLine, StepList, StepShape, StepShow, Steps, TOUCHED, even_sample,
};
use crate::ops::operation::{Applied, EditContext, MeshOperation, Redraw, Values};

/// Smoothing as a registered operation: the `smooth` step, the O key and its row in the
/// panel. Only positions change; the vertices it names (the editor's selected vertices) stay,
/// and so does the boundary unless it is set free. A job on a large mesh.
pub const SMOOTH: Declaration = Declaration::new("smooth")
    .titled("Smooth")
    .described("move each vertex toward its neighbours by the method's Laplacian")
    .on_key("O")
    .naming(Names::MeshHolding)
    .with_parameters(&[
        Parameter::choice("METHOD", METHODS, 0),
        Parameter::whole("ITERATIONS", 1, 1, 10_000),
        Parameter::real("STEP", 0.5, 1e-6, 1e6).automatic_by_default("0.5, or 1 for implicit"),
        Parameter::choice("BOUNDARY", &["hold-boundary", "free-boundary"], 0),
    ])
    .as_job()
    .stepping();

/// The methods' words, in [`SmoothMethod::ALL`]'s order (a test checks).
const METHODS: &[&str] = &["uniform", "cotan", "implicit", "taubin"];

/// Smoothing, declared by [`SMOOTH`].
pub struct Smooth;

impl MeshOperation for Smooth {
    fn declaration(&self) -> &'static Declaration {
        &SMOOTH
    }

    fn apply(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
        context: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let params = SmoothParams::from_values(values);
        let s = smooth_with_progress(world, mesh, &params, &mut *context.progress)?;
        let stopped = match s.iterations < params.iterations {
            true => format!(
                " (stopped after {} of {} iterations)",
                s.iterations, params.iterations
            ),
            false => String::new(),
        };
        Ok(Applied::whole(format!(
            "{} free vertices moved {:.3e} on average{stopped}",
            s.free, s.mean_move
        )))
    }

    /// An iteration a step ([`SmoothSteps`]).
    fn step_through(
        &self,
        world: &mut World,
        mesh: MeshId,
        values: Values<'_>,
    ) -> Option<Result<Box<dyn Steps>, Refusal>> {
        let steps = SmoothSteps::start(world, mesh, &SmoothParams::from_values(values));
        Some(steps.map(|s| Box::new(s) as Box<dyn Steps>))
    }
}

/// Which Laplacian moves the vertices.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SmoothMethod {
    /// The umbrella operator, explicit.
    #[default]
    Uniform,
    /// Normalised cotangent weights, explicit.
    Cotan,
    /// Implicit mean-curvature flow (backward Euler, a sparse solve a step).
    Implicit,
    /// Taubin's λ|μ: no shrinking.
    Taubin,
}

impl Named for SmoothMethod {
    /// Every method, with its name on the command line and in the panel.
    const ALL: &'static [(Self, &'static str)] = &[
        (SmoothMethod::Uniform, "uniform"),
        (SmoothMethod::Cotan, "cotan"),
        (SmoothMethod::Implicit, "implicit"),
        (SmoothMethod::Taubin, "taubin"),
    ];
}

impl SmoothMethod {
    /// The step λ it uses by default: 0.5 for the explicit ones, 1 for the implicit flow.
    pub fn default_step(self) -> f64 {
        match self {
            SmoothMethod::Implicit => 1.0,
            _ => 0.5,
        }
    }
}

/// How to smooth. The same struct serves the command line, the editor and the tests.
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothParams {
    /// The Laplacian. Default uniform.
    pub method: SmoothMethod,
    /// Iterations. Default 1.
    pub iterations: u32,
    /// The step λ: the fraction of the way to the neighbours' mean for the explicit methods
    /// (0 < λ ≤ 1), the time step over the squared mean edge length for the implicit flow.
    /// Default [`SmoothMethod::default_step`].
    pub step: f64,
    /// Boundary vertices stay. Default true.
    pub hold_boundary: bool,
    /// These vertices stay too (the editor's selection).
    pub held: Vec<VertexId>,
}

impl SmoothParams {
    /// `method` with its default step, one iteration, the boundary held.
    pub fn new(method: SmoothMethod) -> Self {
        Self {
            method,
            iterations: 1,
            step: method.default_step(),
            hold_boundary: true,
            held: Vec::new(),
        }
    }
}

impl SmoothParams {
    /// The parameters [`SMOOTH`]'s values give: the method, its iterations, the step (the
    /// method's own when left automatic), the boundary held or free, the named vertices held.
    pub fn from_values(values: Values<'_>) -> Self {
        let method = SmoothMethod::ALL[values.choice(0)].0;
        Self {
            method,
            iterations: values.whole(1),
            step: values.given(2).unwrap_or(method.default_step()),
            hold_boundary: values.choice(3) == 0,
            held: values.vertices(),
        }
    }
}

impl Default for SmoothParams {
    fn default() -> Self {
        Self::new(SmoothMethod::Uniform)
    }
}

/// What a smoothing did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmoothSummary {
    /// Vertices that moved freely.
    pub free: usize,
    /// The mean distance a free vertex moved, over all iterations.
    pub mean_move: f64,
    /// The iterations run: all of them, unless the progress callback stopped it.
    pub iterations: u32,
}

/// The pass-band frequency of Taubin's filter.
const TAUBIN_PASS_BAND: f64 = 0.1;

/// Smooths `mesh` (see the module doc).
///
/// # Refusals
/// As [`smooth_with_progress`].
pub fn smooth(
    world: &mut World,
    mesh: MeshId,
    params: &SmoothParams,
) -> Result<SmoothSummary, Refusal> {
    smooth_with_progress(world, mesh, params, &mut |_| true)
}

/// [`smooth`], calling `progress` with the fraction of the iterations done after each one;
/// `false` stops after that iteration, and the mesh then holds the iterations run (each one a
/// whole smoothing step, so the mesh is as valid as after any number of them).
///
/// # Refusals
/// A stale mesh; a step that is not finite and positive ([`Refusal::BadParameter`]); the mesh is
/// then unchanged.
pub fn smooth_with_progress(
    world: &mut World,
    mesh: MeshId,
    params: &SmoothParams,
    progress: &mut dyn FnMut(f32) -> bool,
) -> Result<SmoothSummary, Refusal> {
    let mut run = Smoothing::start(world, mesh, params)?;
    let mut iterations = 0;
    while iterations < params.iterations {
        run.iterate()?;
        iterations += 1;
        if !progress(iterations as f32 / params.iterations as f32) {
            break;
        }
    }
    run.write(world);
    Ok(run.summary(iterations))
}

/// A smoothing in progress: the mesh's tables, which vertices are held, and every vertex's
/// position before the first iteration and now, in `f64` (written back as `f32` only at the
/// end, or at each step of a stepped run, so the two give the same bits).
struct Smoothing {
    read: MeshTables,
    held: Vec<bool>,
    start: Vec<DVec3>,
    x: Vec<DVec3>,
    method: SmoothMethod,
    step: f64,
}

impl Smoothing {
    /// Checks `params` and reads `mesh`.
    ///
    /// # Refusals
    /// As [`smooth_with_progress`].
    fn start(world: &World, mesh: MeshId, params: &SmoothParams) -> Result<Self, Refusal> {
        if world.get::<MeshInfo>(mesh.0).is_none() {
            return Err(Refusal::Stale(ElementId::Mesh(mesh)));
        }
        let explicit_ok = params.method == SmoothMethod::Implicit || params.step <= 1.0;
        if !(params.step.is_finite() && params.step > 0.0 && explicit_ok) {
            return Err(Refusal::BadParameter(format!(
                "smoothing step {} (explicit methods take 0 < λ ≤ 1, the implicit flow any λ > 0)",
                params.step
            )));
        }
        let read = extract(world, mesh);
        let t = &read.tables;
        let mut held: Vec<bool> = t
            .vertices()
            .map(|v| params.hold_boundary && t.is_boundary_vertex(v))
            .collect();
        let rows = read.members.vertex_rows();
        for v in &params.held {
            if let Some(&row) = rows.get(&v.0) {
                held[row as usize] = true;
            }
        }
        let start: Vec<DVec3> = t.positions.iter().map(|p| p.as_dvec3()).collect();
        Ok(Self {
            x: start.clone(),
            start,
            read,
            held,
            method: params.method,
            step: params.step,
        })
    }

    /// One iteration of the method.
    ///
    /// # Refusals
    /// The implicit flow's system that cannot be solved; the positions are then as before.
    fn iterate(&mut self) -> Result<(), Refusal> {
        let (t, held, x, step) = (&self.read.tables, &self.held, &mut self.x, self.step);
        match self.method {
            SmoothMethod::Uniform => umbrella_step(t, held, x, step),
            SmoothMethod::Taubin => {
                let mu = step / (TAUBIN_PASS_BAND * step - 1.0);
                umbrella_step(t, held, x, step);
                umbrella_step(t, held, x, mu);
            }
            SmoothMethod::Cotan => cotan_step(t, held, x, step),
            SmoothMethod::Implicit => implicit_step(t, held, x, step)?,
        }
        Ok(())
    }

    /// Writes the positions now to the mesh's vertices.
    fn write(&self, world: &mut World) {
        for (row, v) in self.read.members.vertices.iter().enumerate() {
            if let Some(mut p) = world.get_mut::<Position>(v.0) {
                p.0 = self.x[row].as_vec3();
            }
        }
    }

    /// Free vertices.
    fn free(&self) -> usize {
        self.held.iter().filter(|h| !**h).count()
    }

    /// What it did, `iterations` iterations in.
    fn summary(&self, iterations: u32) -> SmoothSummary {
        let free = self.free();
        let moved: f64 = self
            .x
            .iter()
            .zip(&self.start)
            .map(|(a, b)| a.distance(*b))
            .sum();
        SmoothSummary {
            free,
            mean_move: if free > 0 { moved / free as f64 } else { 0.0 },
            iterations,
        }
    }
}

/// Smoothing stepped iteration by iteration, for the editor's step mode: a step is one
/// iteration of [`Smoothing::iterate`], the very one [`smooth_with_progress`] makes, and the
/// positions are written after each, so a run taken to its end leaves the bits the unstepped
/// smoothing leaves. Each free vertex's path since the start is drawn (an even sample) and
/// each iteration's mean move listed. Back restores the nearest kept iteration at or before
/// the one asked for and iterates from there: [`SmoothSteps::KEPT`] of them at most, evenly
/// spaced, and no more than [`SmoothSteps::KEPT_BYTES`] of positions in all.
pub struct SmoothSteps {
    run: Smoothing,
    /// The iteration the mesh shows.
    at: usize,
    /// The iterations the run makes in all.
    total: usize,
    /// Kept positions: iteration `i · every` at index `i`.
    kept: Vec<Vec<DVec3>>,
    every: usize,
    /// The mean distance a free vertex moved in each iteration made (index 0: the first).
    moves: Vec<f64>,
}

impl SmoothSteps {
    /// The most iterations a run keeps the positions of.
    pub const KEPT: usize = 64;
    /// The most bytes of kept positions.
    pub const KEPT_BYTES: usize = 256 << 20;

    /// A stepped smoothing of `mesh` as `params` say, before its first iteration.
    ///
    /// # Errors
    /// As [`smooth_with_progress`] (the mesh is untouched).
    pub fn start(world: &World, mesh: MeshId, params: &SmoothParams) -> Result<Self, Refusal> {
        let run = Smoothing::start(world, mesh, params)?;
        let total = params.iterations as usize;
        let bytes = run.x.len().max(1) * size_of::<DVec3>();
        let kept = (Self::KEPT_BYTES / bytes).clamp(1, Self::KEPT);
        Ok(Self {
            kept: vec![run.start.clone()],
            every: total.div_ceil(kept).max(1),
            run,
            at: 0,
            total,
            moves: Vec::new(),
        })
    }

    /// The mean move of a free vertex in the iteration that took the positions from `before`
    /// to the run's.
    fn mean_move(&self, before: &[DVec3]) -> f64 {
        let free = self.run.free().max(1);
        let sum: f64 = (self.run.x.iter().zip(before))
            .zip(&self.run.held)
            .filter(|(_, held)| !**held)
            .map(|((a, b), _)| a.distance(*b))
            .sum();
        sum / free as f64
    }
}

impl Steps for SmoothSteps {
    fn at(&self) -> usize {
        self.at
    }

    fn made(&self) -> usize {
        self.total
    }

    fn finished(&self) -> bool {
        self.at == self.total
    }

    fn goes_back(&self) -> GoesBack {
        GoesBack::Scrubs
    }

    fn go_to(
        &mut self,
        world: &mut World,
        _: MeshId,
        k: usize,
        _: Option<ElementId>,
    ) -> Result<Moved, Refusal> {
        let k = k.min(self.total);
        if k < self.at {
            let i = (k / self.every).min(self.kept.len() - 1);
            self.run.x.clone_from(&self.kept[i]);
            self.at = i * self.every;
        }
        while self.at < k {
            let before = self.run.x.clone();
            self.run.iterate()?;
            self.at += 1;
            if self.moves.len() < self.at {
                self.moves.push(self.mean_move(&before));
            }
            if self.at.is_multiple_of(self.every) && self.kept.len() == self.at / self.every {
                self.kept.push(self.run.x.clone());
            }
        }
        self.run.write(world);
        Ok(Moved::redrawing(Redraw::Positions))
    }

    fn describe(&self) -> String {
        let s = self.run.summary(self.at as u32);
        format!(
            "iteration {} of {}: {} free vertices moved {:.3e} on average since the start",
            self.at, self.total, s.free, s.mean_move
        )
    }

    fn show(&self, _: &World, _: Option<ElementId>) -> StepShow {
        let free: Vec<usize> = (0..self.run.x.len())
            .filter(|&i| !self.run.held[i])
            .collect();
        let path = |i: usize| {
            let v = free[i];
            StepShape::Line(
                self.run.start[v].as_vec3(),
                self.run.x[v].as_vec3(),
                TOUCHED,
            )
        };
        StepShow {
            shapes: even_sample(free.len()).map(path).collect(),
            lists: vec![StepList {
                title: "mean move by iteration (green: each vertex's path since the start)".into(),
                lines: (0..self.moves.len())
                    .rev()
                    .map(|i| {
                        let shown = if i + 1 == self.at { "  ◀" } else { "" };
                        StepLine::text(format!("{:>3}: {:.3e}{shown}", i + 1, self.moves[i]))
                    })
                    .collect(),
            }],
            ..StepShow::default()
        }
    }

    fn finish(self: Box<Self>, _: &mut World, _: MeshId) -> Ended {
        let s = self.run.summary(self.at as u32);
        Ended::with(format!(
            "{} free vertices moved {:.3e} on average (stepped; kept at iteration {} of {})",
            s.free, s.mean_move, self.at, self.total
        ))
    }
}

/// One umbrella step of size `lambda` (negative for Taubin's μ) over the mesh's edges.
fn umbrella_step(t: &Connectivity, held: &[bool], x: &mut [DVec3], lambda: f64) {
    let before = x.to_vec();
    for v in t.vertices() {
        if held[v.index()] {
            continue;
        }
        let (mut sum, mut count) = (DVec3::ZERO, 0.0);
        for h in t.vertex_outgoing(v) {
            sum += before[t.to_vertex(h).index()];
            count += 1.0;
        }
        if count > 0.0 {
            let p = before[v.index()];
            x[v.index()] = p + lambda * (sum / count - p);
        }
    }
}

/// One explicit step with the normalised cotangent weights.
fn cotan_step(t: &Connectivity, held: &[bool], x: &mut [DVec3], lambda: f64) {
    let mut s = Surface::from_tables(t);
    s.positions.copy_from_slice(x);
    let n = x.len();
    let (mut sum, mut weight) = (vec![DVec3::ZERO; n], vec![0.0; n]);
    for (i, j, w) in cotan_edges(&s) {
        let (i, j) = (i as usize, j as usize);
        sum[i] += w * (x[j] - x[i]);
        sum[j] += w * (x[i] - x[j]);
        weight[i] += w;
        weight[j] += w;
    }
    for i in 0..n {
        if !held[i] && weight[i] > 0.0 {
            x[i] += lambda * sum[i] / weight[i];
        }
    }
}

/// One backward Euler step of mean-curvature flow: `(M − h L) x' = M x` over the free
/// vertices, the held ones moved to the right-hand side.
fn implicit_step(
    t: &Connectivity,
    held: &[bool],
    x: &mut [DVec3],
    lambda: f64,
) -> Result<(), Refusal> {
    let mut s = Surface::from_tables(t);
    s.positions.copy_from_slice(x);
    let n = x.len();
    let edges = cotan_edges(&s);
    let mean_length = if edges.is_empty() {
        0.0
    } else {
        edges
            .iter()
            .map(|&(i, j, _)| x[i as usize].distance(x[j as usize]))
            .sum::<f64>()
            / edges.len() as f64
    };
    let h = lambda * mean_length * mean_length;
    let area = mixed_areas(&s);
    // Free vertices get columns 0..free; held ones none.
    let mut column = vec![u32::MAX; n];
    let mut free = 0usize;
    // A vertex with no area (only on flat triangles, as a bisection's new vertex on a straight
    // edge) would make an empty row: it stays, like a held one.
    for i in 0..n {
        if !held[i] && area[i] > 0.0 {
            column[i] = free as u32;
            free += 1;
        }
    }
    if free == 0 {
        return Ok(());
    }
    let mut rhs = Mat::<f64>::zeros(free, 3);
    let mut diagonal = vec![0.0; free];
    let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(2 * edges.len() + free);
    for i in 0..n {
        if let Some(k) = column.get(i).copied().filter(|&k| k != u32::MAX) {
            let k = k as usize;
            diagonal[k] = area[i];
            for (c, value) in x[i].to_array().into_iter().enumerate() {
                rhs[(k, c)] = area[i] * value;
            }
        }
    }
    for &(i, j, w) in &edges {
        let (ci, cj) = (column[i as usize], column[j as usize]);
        // (M − hL): off-diagonal −h w, diagonal + h w for each edge at a free vertex.
        for (ca, b, cb) in [(ci, j, cj), (cj, i, ci)] {
            if ca == u32::MAX {
                continue;
            }
            diagonal[ca as usize] += h * w;
            if cb == u32::MAX {
                // A held neighbour: its term moves to the right-hand side.
                for (c, value) in x[b as usize].to_array().into_iter().enumerate() {
                    rhs[(ca as usize, c)] += h * w * value;
                }
            } else {
                triplets.push(Triplet::new(ca as usize, cb as usize, -h * w));
            }
        }
    }
    for (k, d) in diagonal.into_iter().enumerate() {
        triplets.push(Triplet::new(k, k, d));
    }
    let matrix = SparseColMat::<usize, f64>::try_new_from_triplets(free, free, &triplets)
        .map_err(|e| Refusal::BadParameter(format!("the smoothing system: {e:?}")))?;
    let llt = matrix.sp_cholesky(Side::Lower).map_err(|e| {
        Refusal::BadParameter(format!(
            "the smoothing system is not positive definite ({e:?}): degenerate triangles?"
        ))
    })?;
    llt.solve_in_place(rhs.as_mut());
    for i in 0..n {
        let k = column[i];
        if k != u32::MAX {
            let k = k as usize;
            let p = DVec3::new(rhs[(k, 0)], rhs[(k, 1)], rhs[(k, 2)]);
            if p.is_finite() {
                x[i] = p;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshMembers, MeshRef, build_mesh, shapes, validate};
    use crate::ops::local::testkit::positions;

    /// The step's method words are the methods' names, in order.
    #[test]
    fn the_declared_methods_are_the_methods() {
        let names: Vec<&str> = SmoothMethod::ALL.iter().map(|(_, n)| *n).collect();
        assert_eq!(names, METHODS);
    }

    #[test]
    fn a_planar_grid_is_a_fixed_point_of_every_method() {
        for &(method, _) in SmoothMethod::ALL {
            let mut world = World::new();
            let built = build_mesh(&mut world, &shapes::grid(6, 6), MeshInfo::default()).unwrap();
            let before = positions(&world, built.mesh);
            let params = SmoothParams {
                iterations: 3,
                ..SmoothParams::new(method)
            };
            smooth(&mut world, built.mesh, &params).unwrap();
            validate(&world, built.mesh).unwrap();
            for (a, b) in before.iter().zip(positions(&world, built.mesh)) {
                assert!(a.distance(b) < 1e-5, "{method:?}: {a} -> {b}");
            }
        }
    }

    #[test]
    fn a_vertex_on_a_straight_bisected_edge_does_not_stop_the_implicit_flow() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::grid(4, 4), MeshInfo::default()).unwrap();
        let m = MeshRef::new(&world);
        // An interior, axis-aligned edge: its midpoint has only flat fan triangles.
        let e = MeshMembers::collect(&world, built.mesh)
            .edges
            .into_iter()
            .find(|&e| {
                let (a, b) = m.edge_vertices(e);
                !m.is_boundary_edge(e) && (m.position(a).x == m.position(b).x)
            })
            .unwrap();
        crate::ops::local::bisect_edge(&mut world, e, 0.5).unwrap();
        let params = SmoothParams::new(SmoothMethod::Implicit);
        smooth(&mut world, built.mesh, &params).unwrap();
        validate(&world, built.mesh).unwrap();
    }

    #[test]
    fn held_vertices_stay_and_bad_steps_are_refused() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::icosphere(2), MeshInfo::default()).unwrap();
        let v = MeshMembers::collect(&world, built.mesh).vertices[3];
        let at = MeshRef::new(&world).position(v);
        let params = SmoothParams {
            held: vec![v],
            iterations: 4,
            ..SmoothParams::new(SmoothMethod::Implicit)
        };
        smooth(&mut world, built.mesh, &params).unwrap();
        assert_eq!(MeshRef::new(&world).position(v), at);
        let before = positions(&world, built.mesh);
        for step in [0.0, -1.0, f64::NAN, 1.5] {
            let bad = SmoothParams {
                step,
                ..SmoothParams::new(SmoothMethod::Uniform)
            };
            assert!(matches!(
                smooth(&mut world, built.mesh, &bad),
                Err(Refusal::BadParameter(_))
            ));
        }
        assert_eq!(positions(&world, built.mesh), before);
    }
}
