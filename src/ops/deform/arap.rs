//! As-rigid-as-possible surface deformation (Sorkine & Alexa, "As-Rigid-As-Possible Surface
//! Modeling", SGP 2007), with the "spokes" energy and cotangent weights:
//!
//! `E(p′, R) = Σ_i Σ_{j ∈ N(i)} w_ij ‖(p′_i − p′_j) − R_i (p_i − p_j)‖²`
//!
//! minimised by alternating two steps, each of which cannot raise `E`:
//! - **local**: each vertex's rotation `R_i`, the rotation closest to
//!   `Σ_j w_ij (p′_i − p′_j)(p_i − p_j)ᵀ` ([`super::rotation`], warm-started from the last
//!   one), vertices split over the cores;
//! - **global**: the positions, from the linear system `L p′ = b`,
//!   `b_i = Σ_j (w_ij / 2)(R_i + R_j)(p_i − p_j)`, with `L` the cotangent stiffness matrix. `L`
//!   does not change while the held vertices stay the same, so its free block is factored once
//!   ([`HeldSystem`]) and each iteration is three triangular solves.
//!
//! Each iteration is sped up by Anderson acceleration ([`super::anderson`]; Peng et al. 2018): the
//! next positions are the recent global steps' best combination rather than the last one alone.
//! That guess is checked by the next local step, which measures its energy anyway: when it is
//! higher than that of the positions the last iteration started from, the plain global step's
//! result is taken instead and the history forgotten, so the energy never rises. Moving the
//! held vertices changes the iteration's map and forgets the history too (a handle dragged a
//! little each frame runs plain iterations).
//!
//! The held vertices (anchors and handle) sit where they are placed; an iteration moves only the
//! others. [`Arap`] keeps the factor, the rotations and the positions between calls, so the
//! editor can run one iteration a frame while a handle is dragged, starting from the last
//! frame's result.

use bevy::math::{DMat3, DQuat, DVec3};

use crate::ops::Refusal;
use crate::ops::geometry::{Surface, cotan_edges};
use crate::ops::parallel::in_parallel;

use super::anderson::Anderson;
use super::rotation::closest_rotation;
use super::system::{HeldSystem, k_harmonic};

/// An as-rigid-as-possible deformation in progress (see the module doc).
pub struct Arap {
    /// Each vertex's one-ring in `ring[start[i]..start[i + 1]]`: (neighbour, cotangent weight).
    start: Vec<u32>,
    ring: Vec<(u32, f64)>,
    /// Each one-ring entry's weighted rest spoke `w_ij (p_i − p_j)`, beside `ring`.
    spokes: Vec<DVec3>,
    /// Each vertex's `Σ_j w_ij ‖p_i − p_j‖²` (its energy's rest term).
    rest_terms: Vec<f64>,
    system: HeldSystem,
    /// Each vertex's rotation and its part of the energy, from the last local step.
    local: Vec<LocalFit>,
    current: Vec<DVec3>,
    /// Whether `local` holds the fit of `current`: `Some(true)` with its energy measured.
    fitted: Option<bool>,
    /// Whether [`Arap::iterate`]'s local step measures the energy too (it costs a tenth of an
    /// iteration or more; [`Arap::fit_rotations`] always does).
    measuring: bool,
    /// The recent global steps over the free vertices, for the accelerated guess.
    anderson: Anderson,
    /// The last global step's result, the plain next positions.
    image: Vec<DVec3>,
    /// The global step's right-hand side, and the rotations as matrices for it.
    rhs: Vec<DVec3>,
    matrices: Vec<DMat3>,
    /// The free rows of `current` and `image`, and the guess, gathered for [`Anderson`].
    free_rows: [Vec<DVec3>; 3],
    /// While `current` is an accelerated guess not checked yet (`image` then holds the plain
    /// global step's result to fall back to): the energy of the positions that iteration
    /// started from.
    guess: Option<f64>,
}

/// One vertex's result of the local step.
#[derive(Clone, Copy, Debug)]
struct LocalFit {
    /// The rotation closest to its one-ring's covariance.
    rotation: DQuat,
    /// `Σ_j w_ij ‖(p′_i − p′_j) − R_i (p_i − p_j)‖²` for the positions it was fitted to.
    energy: f64,
}

impl Arap {
    /// Prepares the deformation of `surface` (its positions the rest pose) with the vertices
    /// where `held` is set held: builds the one-rings and factors the system. The deformed
    /// positions start at the rest pose.
    ///
    /// # Refusals
    /// As [`HeldSystem::new`]: nothing free, or a part of the mesh with nothing held.
    pub fn new(surface: &Surface, held: &[bool]) -> Result<Self, Refusal> {
        let n = surface.vertex_count();
        let edges = cotan_edges(surface);
        let system = HeldSystem::new(&k_harmonic(n, &edges, &[], 1), held)?;
        let mut count = vec![0u32; n + 1];
        for &(i, j, _) in &edges {
            count[i as usize + 1] += 1;
            count[j as usize + 1] += 1;
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let start = count.clone();
        let mut ring = vec![(0u32, 0.0); 2 * edges.len()];
        let mut fill = count;
        for &(i, j, w) in &edges {
            ring[fill[i as usize] as usize] = (j, w);
            fill[i as usize] += 1;
            ring[fill[j as usize] as usize] = (i, w);
            fill[j as usize] += 1;
        }
        let rest = &surface.positions;
        let mut spokes = vec![DVec3::ZERO; ring.len()];
        let mut rest_terms = vec![0.0; n];
        for i in 0..n {
            for k in start[i] as usize..start[i + 1] as usize {
                let (j, w) = ring[k];
                let e = rest[i] - rest[j as usize];
                spokes[k] = e * w;
                rest_terms[i] += w * e.length_squared();
            }
        }
        Ok(Self {
            start,
            ring,
            spokes,
            rest_terms,
            system,
            local: vec![
                LocalFit {
                    rotation: DQuat::IDENTITY,
                    energy: 0.0,
                };
                n
            ],
            current: surface.positions.clone(),
            fitted: None,
            measuring: false,
            anderson: Anderson::default(),
            image: Vec::new(),
            rhs: Vec::new(),
            matrices: Vec::new(),
            free_rows: Default::default(),
            guess: None,
        })
    }

    /// The deformed positions, by vertex row: after [`Arap::iterate`], possibly an accelerated
    /// guess whose energy [`Arap::settle`] has not checked yet.
    pub fn positions(&self) -> &[DVec3] {
        &self.current
    }

    /// Each vertex's rotation from the last local step.
    pub fn rotations(&self) -> impl ExactSizeIterator<Item = DQuat> + '_ {
        self.local.iter().map(|fit| fit.rotation)
    }

    /// Puts held vertices where they go (rows that are not held are ignored: only the solve
    /// places them). A held vertex that moves starts the acceleration anew.
    pub fn place(&mut self, targets: impl IntoIterator<Item = (u32, DVec3)>) {
        let mut moved = false;
        for (v, p) in targets {
            let at = &mut self.current[v as usize];
            if self.system.is_held(v) && *at != p {
                *at = p;
                moved = true;
            }
        }
        if moved {
            self.restart();
        }
    }

    /// Starts the next iteration from these positions (the last frame's result, or a better
    /// guess); the held vertices keep where [`Arap::place`] put them.
    pub fn start_from(&mut self, positions: &[DVec3]) {
        for (v, p) in positions.iter().enumerate() {
            if !self.system.is_held(v as u32) {
                self.current[v] = *p;
            }
        }
        self.restart();
    }

    /// Forgets the fit, the acceleration's history and any unchecked guess: the positions
    /// changed from outside the iteration.
    fn restart(&mut self) {
        self.fitted = None;
        self.anderson.reset();
        self.guess = None;
    }

    /// Makes each [`Arap::iterate`] measure the energy of the positions it starts from.
    pub fn measure_each_iteration(&mut self, on: bool) {
        self.measuring = on;
    }

    /// Whether each [`Arap::iterate`] measures the energy.
    pub fn measures_each_iteration(&self) -> bool {
        self.measuring
    }

    /// One local step (unless the current positions are fitted already) and one global step,
    /// accelerated (see the module doc).
    pub fn iterate(&mut self) {
        // The energy serves as the next guess's reference once the history holds a step.
        let measure = self.measuring || self.anderson.remembers();
        self.fit(measure);
        self.right_hand_side();
        self.image.clone_from(&self.current);
        self.system.solve(Some(&self.rhs), &mut self.image);
        self.fitted = None;
        let free = self.system.free();
        let [x, image, guess] = &mut self.free_rows;
        x.clear();
        x.extend(free.iter().map(|&v| self.current[v as usize]));
        image.clear();
        image.extend(free.iter().map(|&v| self.image[v as usize]));
        if self.anderson.accelerate(x, image, guess) {
            for (&v, p) in free.iter().zip(guess.iter()) {
                self.current[v as usize] = *p;
            }
            // The local fits are still those of the positions this iteration started from.
            self.guess = Some(self.energy());
        } else {
            std::mem::swap(&mut self.current, &mut self.image);
        }
    }

    /// Checks an accelerated guess left by [`Arap::iterate`] (its local step, which the next
    /// iteration then reuses): a guess of higher energy than the positions its iteration
    /// started from is replaced by the plain global step's result. Afterwards
    /// [`Arap::positions`] are final; without a guess this does nothing.
    pub fn settle(&mut self) {
        if self.guess.is_some() {
            self.fit(true);
        }
    }

    /// The local step: each vertex's best rotation for the current positions, and with it the
    /// energy of the current positions ([`Arap::energy`]).
    pub fn fit_rotations(&mut self) {
        self.fit(true);
    }

    /// The local step for the current positions, unless done already (measured if `measure`);
    /// an unchecked guess is checked, and refused if it raised the energy.
    fn fit(&mut self, measure: bool) {
        let checking = self.guess.is_some();
        if self.fitted == Some(true) || (self.fitted == Some(false) && !measure && !checking) {
            return;
        }
        self.local_step(measure || checking);
        self.fitted = Some(measure || checking);
        if let Some(start_energy) = self.guess.take()
            && self.energy() > start_energy
        {
            self.current.clone_from(&self.image);
            self.anderson.reset();
            self.local_step(true);
            self.fitted = Some(true);
        }
    }

    fn local_step(&mut self, measure: bool) {
        let (current, start, ring, spokes) = (&self.current, &self.start, &self.ring, &self.spokes);
        let rest_terms = &self.rest_terms;
        in_parallel(&mut self.local, |i, fit| {
            let ci = current[i];
            let mut a = DMat3::ZERO;
            let mut deformed_term = 0.0;
            for k in start[i] as usize..start[i + 1] as usize {
                let (e, (j, w)) = (spokes[k], ring[k]);
                let d = ci - current[j as usize];
                a += DMat3::from_cols(d * e.x, d * e.y, d * e.z);
                if measure {
                    deformed_term += w * d.length_squared();
                }
            }
            fit.rotation = closest_rotation(&a, fit.rotation);
            if !measure {
                return;
            }
            // Σ w ‖d − R e‖² = Σ w ‖d‖² − 2 tr(Rᵀ A) + Σ w ‖e‖², with A = Σ d (w e)ᵀ.
            let r = DMat3::from_quat(fit.rotation);
            let score = r.x_axis.dot(a.x_axis) + r.y_axis.dot(a.y_axis) + r.z_axis.dot(a.z_axis);
            fit.energy = deformed_term - 2.0 * score + rest_terms[i];
        });
    }

    /// The global step's right-hand side `b_i = Σ_j (w_ij / 2)(R_i + R_j)(p_i − p_j)`, into
    /// `rhs` (each rotation as a matrix into `matrices` first).
    fn right_hand_side(&mut self) {
        let (local, start, ring, spokes) = (&self.local, &self.start, &self.ring, &self.spokes);
        self.matrices.resize(local.len(), DMat3::IDENTITY);
        in_parallel(&mut self.matrices, |i, m| {
            *m = DMat3::from_quat(local[i].rotation);
        });
        let matrices = &self.matrices;
        self.rhs.resize(local.len(), DVec3::ZERO);
        in_parallel(&mut self.rhs, |i, b| {
            let mut sum = DVec3::ZERO;
            for k in start[i] as usize..start[i + 1] as usize {
                let j = ring[k].0 as usize;
                sum += (matrices[i] + matrices[j]) * spokes[k];
            }
            *b = sum * 0.5;
        });
    }

    /// The energy `E` of the positions the last measuring local step fitted its rotations to,
    /// with those rotations: the energy of those positions alone (each rotation is the best for
    /// them). After [`Arap::fit_rotations`] or [`Arap::settle`], the current positions' energy;
    /// after a measured [`Arap::iterate`], that of the positions the iteration started from.
    pub fn energy(&self) -> f64 {
        self.local.iter().map(|fit| fit.energy).sum()
    }
}
