//! Anderson acceleration of a fixed-point iteration `x ← G(x)` (Anderson 1965; in the form of
//! Walker & Ni, "Anderson Acceleration for Fixed-Point Iterations", SIAM J. Numer. Anal. 2011),
//! as Peng, Deng, Zhang & Zhang apply it to local–global geometry solvers ("Anderson
//! Acceleration for Geometry Optimization and Physics Simulation", SIGGRAPH 2018).
//!
//! With the residual `f_k = G(x_k) − x_k` and the last `m` differences `ΔF` of residuals and `ΔG`
//! of images, the next point is `G(x_k) − ΔG θ`, where `θ` minimises `‖f_k − ΔF θ‖`: the
//! combination of the recent steps that would have left the smallest residual. Each column of
//! `ΔF` (and its `ΔG`) is scaled to unit length, so the normal equations' matrix has a unit
//! diagonal; it is kept from one step to the next (one new row of dot products a step) and
//! solved by Cholesky with a small ridge.
//!
//! The accelerated point is a guess: it may raise the energy the iteration minimises. The
//! caller checks it and, when it is worse, takes the plain image `G(x_k)` and [`Anderson::reset`]s
//! (Peng et al.'s safeguard; [`super::Arap`] does so).

use bevy::math::DVec3;
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

/// How many recent steps the combination draws on (Peng et al. use 5 or 6 for ARAP).
pub const WINDOW: usize = 5;

/// Ridge added to the normal equations' unit diagonal, so nearly parallel steps stay solvable.
const RIDGE: f64 = 1e-10;

/// The recent steps of one fixed-point iteration (see the module doc). Its buffers are kept
/// from step to step: an iteration allocates nothing once the window is full.
#[derive(Default)]
pub struct Anderson {
    /// Whether `residual` and `image` hold the last iterate's.
    remembers: bool,
    /// The last iterate's residual `f = G(x) − x` and image `G(x)`.
    residual: Vec<DVec3>,
    image: Vec<DVec3>,
    /// Up to [`WINDOW`] columns `(ΔF, ΔG)`, a ring: the next one replaces `next`.
    steps: Vec<(Vec<DVec3>, Vec<DVec3>)>,
    next: usize,
    /// Each column's `1 / ‖ΔF‖`, by which it enters the normal equations.
    scale: [f64; WINDOW],
    /// `gram[i][j] = ΔF_i · ΔF_j`, unscaled.
    gram: [[f64; WINDOW]; WINDOW],
}

impl Anderson {
    /// Forgets every step: the next [`Anderson::accelerate`] returns nothing and starts anew
    /// (after the map `G` changed, or after a guess was refused).
    pub fn reset(&mut self) {
        self.remembers = false;
        self.steps.clear();
        self.next = 0;
    }

    /// Whether the last iterate is remembered, so that the next call can make a guess.
    pub fn remembers(&self) -> bool {
        self.remembers
    }

    /// Records the iterate `x` and its image `image = G(x)`, and writes the accelerated next
    /// point into `guess`: `false` (and `guess` left as it was) on the first call after a
    /// reset, or when the steps are degenerate (a zero step, or equations that do not factor),
    /// where the plain image is the next point.
    pub fn accelerate(&mut self, x: &[DVec3], image: &[DVec3], guess: &mut Vec<DVec3>) -> bool {
        if !self.remembers || self.residual.len() != x.len() {
            self.residual.clear();
            self.residual
                .extend(image.iter().zip(x).map(|(g, x)| *g - *x));
            self.image.clear();
            self.image.extend_from_slice(image);
            self.steps.clear();
            self.next = 0;
            self.remembers = true;
            return false;
        }
        if !self.add_step(x, image) || !self.combine(image, guess) {
            // A degenerate step: start anew from this iterate, which `add_step` recorded.
            self.steps.clear();
            self.next = 0;
            return false;
        }
        true
    }

    /// Adds the column `(f − f′, g − g′)` in place of the oldest, with its row of the normal
    /// equations, and records `f` and `g` as the last; `false` (no column added) if the step is
    /// zero or not finite.
    fn add_step(&mut self, x: &[DVec3], image: &[DVec3]) -> bool {
        let slot = self.next;
        if slot == self.steps.len() {
            self.steps
                .push((vec![DVec3::ZERO; x.len()], vec![DVec3::ZERO; x.len()]));
        }
        let (step_f, step_g) = &mut self.steps[slot];
        let mut length = 0.0;
        for i in 0..x.len() {
            let f = image[i] - x[i];
            step_f[i] = f - self.residual[i];
            step_g[i] = image[i] - self.image[i];
            self.residual[i] = f;
            self.image[i] = image[i];
            length += step_f[i].length_squared();
        }
        let length = length.sqrt();
        if !(length > 0.0 && length.is_finite()) {
            return false;
        }
        self.scale[slot] = length.recip();
        self.next = (slot + 1) % WINDOW;
        for j in 0..self.steps.len() {
            let d = dot(&self.steps[slot].0, &self.steps[j].0);
            self.gram[slot][j] = d;
            self.gram[j][slot] = d;
        }
        true
    }

    /// `guess = g − ΔG θ` with `θ` the least-squares combination of the columns for the last
    /// residual; `false` if the normal equations do not factor or the point is not finite.
    fn combine(&self, image: &[DVec3], guess: &mut Vec<DVec3>) -> bool {
        let columns = self.steps.len();
        let s = &self.scale;
        let normal = Mat::<f64>::from_fn(columns, columns, |i, j| {
            self.gram[i][j] * s[i] * s[j] + if i == j { RIDGE } else { 0.0 }
        });
        let rhs = Mat::<f64>::from_fn(columns, 1, |i, _| {
            dot(&self.steps[i].0, &self.residual) * s[i]
        });
        let Ok(cholesky) = normal.as_ref().llt(Side::Lower) else {
            return false;
        };
        let solved = cholesky.solve(&rhs);
        // θ for the scaled columns is s_i θ_i for the stored ones.
        let theta: Vec<f64> = (0..columns).map(|i| solved[(i, 0)] * s[i]).collect();
        guess.clear();
        guess.extend((0..image.len()).map(|k| {
            let mut p = image[k];
            for (t, (_, step_g)) in theta.iter().zip(&self.steps) {
                p -= step_g[k] * *t;
            }
            p
        }));
        guess.iter().all(|p| p.is_finite())
    }
}

/// `Σ a_i · b_i`.
fn dot(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a.dot(*b)).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `G(x) = A x + c` with `A` a contraction: the plain iteration converges linearly,
    /// Anderson's with a window as large as the dimension (here 3 = one `DVec3`) finds the
    /// fixed point in a few steps, exactly up to rounding.
    #[test]
    fn an_affine_map_is_solved_in_a_few_steps() {
        let a =
            bevy::math::DMat3::from_cols_array(&[0.9, 0.05, 0.0, -0.02, 0.8, 0.1, 0.0, 0.03, 0.95]);
        let c = DVec3::new(1.0, -2.0, 0.5);
        let fixed = (bevy::math::DMat3::IDENTITY - a).inverse() * c;
        let map = |x: &[DVec3]| vec![a * x[0] + c];
        let mut anderson = Anderson::default();
        let mut x = vec![DVec3::ZERO];
        let mut guess = Vec::new();
        for _ in 0..6 {
            let image = map(&x);
            x = if anderson.accelerate(&x, &image, &mut guess) {
                guess.clone()
            } else {
                image
            };
        }
        assert!((x[0] - fixed).length() < 1e-9, "{} vs {}", x[0], fixed);
        // The plain iteration after as many steps is still far off.
        let mut plain = vec![DVec3::ZERO];
        for _ in 0..6 {
            plain = map(&plain);
        }
        assert!((plain[0] - fixed).length() > 1.0);
    }

    #[test]
    fn the_first_step_after_a_reset_is_the_plain_image() {
        let mut anderson = Anderson::default();
        let x = vec![DVec3::ONE];
        let mut guess = Vec::new();
        assert!(!anderson.accelerate(&x, &[DVec3::X], &mut guess));
        assert!(anderson.remembers());
        anderson.reset();
        assert!(!anderson.remembers());
        assert!(!anderson.accelerate(&x, &[DVec3::X], &mut guess));
    }

    #[test]
    fn a_step_of_zero_gives_no_guess() {
        let mut anderson = Anderson::default();
        let x = vec![DVec3::ONE];
        let mut guess = Vec::new();
        anderson.accelerate(&x, &[DVec3::X], &mut guess);
        assert!(!anderson.accelerate(&x, &[DVec3::X], &mut guess));
        assert!(anderson.steps.is_empty());
        assert!(guess.is_empty());
    }
}
