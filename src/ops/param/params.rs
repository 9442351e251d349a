//! The parameters of a parameterization and its refusals: [`ParamMethod`], [`BoundaryShape`]
//! (each with its command-line name, [`FromStr`] and back), [`ParamParams`] with its defaults,
//! and [`ParamError`]. The leaf of this folder: every other file here uses it, it uses none.

use std::fmt;
use std::str::FromStr;

use thiserror::Error;

use crate::ops::named::Named;

use crate::mesh::tables::EdgeRow;

/// Which mapping computes the layout.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ParamMethod {
    /// Tutte's barycentric mapping, uniform weights (`1/n_i`). Fixed boundary, never flips.
    Uniform,
    /// Floater's mean-value weights. Fixed boundary, never flips, reproduces planar meshes. The
    /// default: bijective and shape-aware.
    #[default]
    MeanValue,
    /// Harmonic (cotangent) weights. Fixed boundary; may flip beside obtuse triangles.
    Harmonic,
    /// Least-squares conformal maps. Free boundary, two pinned vertices.
    Lscm,
}

impl Named for ParamMethod {
    /// Every method, with its name on the command line (`param:NAME`).
    const ALL: &'static [(Self, &'static str)] = &[
        (ParamMethod::Uniform, "uniform"),
        (ParamMethod::MeanValue, "mean-value"),
        (ParamMethod::Harmonic, "harmonic"),
        (ParamMethod::Lscm, "lscm"),
    ];
}

impl ParamMethod {
    /// Whether the boundary is fixed on a convex shape (every method but LSCM).
    pub fn fixed_boundary(self) -> bool {
        self != ParamMethod::Lscm
    }
}

/// Where a fixed boundary goes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BoundaryShape {
    /// The unit circle, by arc length. The default: strictly convex, so no flat triangles.
    #[default]
    Circle,
    /// The unit square, by arc length, corners at the vertices nearest the quarter lengths.
    Square,
}

impl Named for BoundaryShape {
    /// Every shape, with its name on the command line (`param:METHOD:NAME`).
    const ALL: &'static [(Self, &'static str)] = &[
        (BoundaryShape::Circle, "circle"),
        (BoundaryShape::Square, "square"),
    ];
}

/// A name that is no method or boundary shape; the text lists the names there are.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
#[error("unknown {kind} `{name}` (expected one of: {expected})")]
pub struct UnknownName {
    /// What was being named ("parameterization method", "boundary shape").
    pub kind: &'static str,
    /// The name given.
    pub name: String,
    /// The names there are, `|`-separated.
    pub expected: String,
}

fn parse_name<T: Named>(kind: &'static str, s: &str) -> Result<T, UnknownName> {
    T::from_name(s).ok_or_else(|| UnknownName {
        kind,
        name: s.to_string(),
        expected: T::names(),
    })
}

impl FromStr for ParamMethod {
    type Err = UnknownName;

    /// `uniform`, `mean-value`, `harmonic` or `lscm` (any case).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_name("parameterization method", s)
    }
}

impl FromStr for BoundaryShape {
    type Err = UnknownName;

    /// `circle` or `square` (any case).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_name("boundary shape", s)
    }
}

impl fmt::Display for ParamMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl fmt::Display for BoundaryShape {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// How to parameterize. The same struct serves the command line, the editor and the tests.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParamParams {
    /// The mapping. Default [`ParamMethod::MeanValue`].
    pub method: ParamMethod,
    /// Where a fixed boundary goes (ignored by LSCM). Default [`BoundaryShape::Circle`].
    pub boundary: BoundaryShape,
    /// Edges to cut along (rows of the tables parameterized). Boundary edges and repeats are
    /// ignored. Default none.
    pub seams: Vec<EdgeRow>,
    /// Cut a closed genus-0 mesh automatically (when the seams leave it closed). Default true.
    pub auto_cut: bool,
}

impl ParamParams {
    /// `method` with the default boundary (circle), no seams, automatic cut on.
    pub fn new(method: ParamMethod) -> Self {
        Self {
            method,
            boundary: BoundaryShape::default(),
            seams: Vec::new(),
            auto_cut: true,
        }
    }
}

impl Default for ParamParams {
    fn default() -> Self {
        Self::new(ParamMethod::default())
    }
}

/// Why a mesh was not parameterized. Expected outcomes, shown to the user; the text says how to
/// fix it where it can be fixed.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
pub enum ParamError {
    /// The mesh has no face.
    #[error("the mesh has no faces to parameterize")]
    NoFaces,
    /// A seam names an edge row the tables do not have.
    #[error("seam edge row {edge} does not exist (the mesh has {edges} edges)")]
    SeamOutOfRange {
        /// The row given.
        edge: u32,
        /// How many edges there are.
        edges: usize,
    },
    /// The mesh (cut along its seams) is in several pieces.
    #[error(
        "the mesh is in {components} separate pieces: parameterize one at a time (separate them) \
         or remove the seams that cut a piece off"
    )]
    Components {
        /// How many.
        components: usize,
    },
    /// The mesh cut along its seams is not a disk.
    #[error(
        "the mesh cut along {seams} seam edges is not a disk: genus {genus}, {loops} boundary \
         loops; {}",
        not_a_disk_fix(*genus, *loops)
    )]
    NotADisk {
        /// Its genus (handles) after cutting.
        genus: usize,
        /// Its boundary loops after cutting.
        loops: usize,
        /// The seam edges cut (given and automatic).
        seams: usize,
    },
    /// The outer boundary loop is too short for the shape.
    #[error("the outer boundary has {vertices} vertices; the shape needs at least {needed}")]
    BoundaryTooShort {
        /// Its vertices.
        vertices: usize,
        /// How many the boundary shape needs.
        needed: usize,
    },
    /// The sparse solve failed (the text says how).
    #[error("the parameterization solve failed: {0}")]
    Solve(String),
}

/// How to open a mesh that is not a disk.
fn not_a_disk_fix(genus: usize, loops: usize) -> String {
    if genus > 0 {
        format!(
            "mark seams that cut through every handle (at least {} closed seam loops, e.g. around \
             each handle and along it)",
            2 * genus
        )
    } else if loops == 0 {
        "the mesh is closed: mark seam edges (a path of edges) or allow the automatic cut".into()
    } else {
        "mark seam edges so that it opens into one piece".into()
    }
}
