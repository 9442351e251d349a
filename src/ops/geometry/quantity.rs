//! The quantities a mesh can be coloured by or exported with: one value per vertex, by table
//! row.
//!
//! Curvatures come from [`mod@super::curvature`]; valence counts a vertex's edges; the smallest
//! angle is the smallest corner angle, in degrees, of the faces around the vertex (where thin
//! triangles are); the edge length is the mean length of the vertex's edges.

use bevy::ecs::world::WorldId;

use crate::colormap::ColorMap;
use crate::mesh::change::Remap;
use crate::mesh::tables::{Connectivity, FaceRow, VertexRow};
use crate::mesh::{FaceId, VertexId};

use super::closest::Reference;
use super::curvature::scalar_curvature;
use super::surface::Surface;

/// What a quantity is computed from beside the mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Needs {
    /// The mesh alone.
    Mesh,
    /// Another surface to measure to ([`Given::other`]): the mesh before the last whole-mesh
    /// edit in the editor, the input on the command line, `to=` from Python.
    Other,
    /// Source vertices ([`Given::sources`]): the selection in the editor, `NAME:A/B` on the
    /// command line, `sources=` from Python.
    Sources,
}

/// What a quantity declares about itself: its name on the command line and in Python, its
/// label in the panel and the legend, its colour map, and what it needs beside the mesh.
#[derive(Clone, Copy, Debug)]
pub struct QuantityDeclaration {
    /// Its name (`mean`, `geodesic`): unique among the registered quantities.
    pub name: &'static str,
    /// Its name in the panel and the legend ("mean curvature").
    pub label: &'static str,
    /// The colour map that shows it: diverging for signed quantities.
    pub colormap: ColorMap,
    /// What it needs beside the mesh.
    pub needs: Needs,
}

/// What a quantity is given beside the mesh's tables.
#[derive(Clone, Copy, Default)]
pub struct Given<'a> {
    /// The surface a [`Needs::Other`] quantity measures to.
    pub other: Option<&'a Reference>,
    /// The source vertices of a [`Needs::Sources`] quantity, by row.
    pub sources: &'a [VertexRow],
    /// The vertex at each row, for a quantity whose values are kept on the vertices rather
    /// than computed ([`super::stored::StoredQuantity`]); empty where the caller has no
    /// entities (such a quantity is then NaN everywhere).
    pub vertices: &'a [VertexId],
    /// The face at each row, likewise for a quantity kept on the faces.
    pub faces: &'a [FaceId],
}

/// A value per vertex of a mesh: what the editor colours by, `process --quantity` writes and
/// Python's `Mesh.quantity` returns. Pappus's own are [`Quantity::BUILT_IN`]; another crate's
/// join them through [`crate::ops::registry::register_quantity`].
pub trait VertexQuantity: Sync + 'static {
    /// What it declares.
    fn declaration(&self) -> &'static QuantityDeclaration;

    /// Its value at every vertex of the mesh in `t`, by row. Where it cannot be computed (no
    /// other surface or no source given where it needs one) the values are NaN; it never
    /// panics on a valid mesh.
    fn per_vertex(&self, t: &Connectivity, given: &Given<'_>) -> Vec<f64>;

    /// Its value at every face, by row, for a quantity that lives on the faces (the editor
    /// then colours each face flat); `None`, the default, for one that lives on the vertices.
    /// Such a quantity's [`VertexQuantity::per_vertex`] is still what the command line and
    /// Python read.
    fn per_face(&self, _t: &Connectivity, _given: &Given<'_>) -> Option<Vec<f64>> {
        None
    }

    /// An undo or redo in `world` brought elements back under new entities (`map`: from the
    /// entity each had to the one that stands for it now). A quantity that keeps values by
    /// entity of that world ([`super::stored::StoredQuantity`]) gives them to the new entities;
    /// the default, for one computed from the mesh, does nothing.
    fn follow(&self, _world: WorldId, _map: &Remap) {}

    /// An edit in `world` rewrote the faces in place (subdivision: only vertex ids survive
    /// it), so a face entity now names another face. A quantity that keeps values by face
    /// entity of that world forgets them rather than draw them on the wrong faces, and says
    /// whether it had any; the default, for one computed from the mesh, does nothing.
    fn faces_renumbered(&self, _world: WorldId) -> bool {
        false
    }
}

/// A registered quantity, by reference: cheap to copy, compared by name.
#[derive(Clone, Copy)]
pub struct Quantity(pub &'static dyn VertexQuantity);

impl PartialEq for Quantity {
    fn eq(&self, other: &Self) -> bool {
        self.name() == other.name()
    }
}

impl Eq for Quantity {}

impl std::hash::Hash for Quantity {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.name().hash(state);
    }
}

impl std::fmt::Debug for Quantity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Quantity({})", self.name())
    }
}

impl Quantity {
    /// Mean curvature `H`.
    pub const MEAN: Quantity = Quantity(&BuiltIn(Kind::Mean));
    /// Gaussian curvature `K` (angle defect over area).
    pub const GAUSSIAN: Quantity = Quantity(&BuiltIn(Kind::Gaussian));
    /// The angle defect (integrated Gaussian curvature).
    pub const ANGLE_DEFECT: Quantity = Quantity(&BuiltIn(Kind::AngleDefect));
    /// The larger principal curvature.
    pub const MAX_CURVATURE: Quantity = Quantity(&BuiltIn(Kind::MaxCurvature));
    /// The smaller principal curvature.
    pub const MIN_CURVATURE: Quantity = Quantity(&BuiltIn(Kind::MinCurvature));
    /// The number of edges at the vertex.
    pub const VALENCE: Quantity = Quantity(&BuiltIn(Kind::Valence));
    /// The smallest corner angle (degrees) of the faces around the vertex.
    pub const MIN_ANGLE: Quantity = Quantity(&BuiltIn(Kind::MinAngle));
    /// The mean length of the vertex's edges.
    pub const EDGE_LENGTH: Quantity = Quantity(&BuiltIn(Kind::EdgeLength));
    /// The distance from the vertex to another surface: the mesh before the last whole-mesh
    /// edit in the editor, the input on the command line (MeshLab's Hausdorff colouring).
    pub const DISTANCE: Quantity = Quantity(&BuiltIn(Kind::Distance));

    /// Pappus's own quantities, in the order the panel lists them.
    pub const BUILT_IN: &[Quantity] = &[
        Quantity::MEAN,
        Quantity::GAUSSIAN,
        Quantity::ANGLE_DEFECT,
        Quantity::MAX_CURVATURE,
        Quantity::MIN_CURVATURE,
        Quantity::VALENCE,
        Quantity::MIN_ANGLE,
        Quantity::EDGE_LENGTH,
        Quantity::DISTANCE,
    ];

    /// Its name on the command line and in Python.
    pub fn name(self) -> &'static str {
        self.0.declaration().name
    }

    /// Its name in the panel and the legend.
    pub fn label(self) -> &'static str {
        self.0.declaration().label
    }

    /// The colour map that shows it.
    pub fn colormap(self) -> ColorMap {
        self.0.declaration().colormap
    }

    /// What it needs beside the mesh.
    pub fn needs(self) -> Needs {
        self.0.declaration().needs
    }

    /// Its value at every vertex of the mesh in `t`, by row (NaN where it cannot be computed:
    /// see [`VertexQuantity::per_vertex`]).
    pub fn per_vertex(self, t: &Connectivity, given: &Given<'_>) -> Vec<f64> {
        self.0.per_vertex(t, given)
    }

    /// Its value at every face by row, for a quantity on the faces (see
    /// [`VertexQuantity::per_face`]).
    pub fn per_face(self, t: &Connectivity, given: &Given<'_>) -> Option<Vec<f64>> {
        self.0.per_face(t, given)
    }
}

/// Pappus's own quantities.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Mean,
    Gaussian,
    AngleDefect,
    MaxCurvature,
    MinCurvature,
    Valence,
    MinAngle,
    EdgeLength,
    Distance,
}

/// One of Pappus's own quantities.
struct BuiltIn(Kind);

/// Declares a built-in quantity.
const fn declared(
    name: &'static str,
    label: &'static str,
    needs: Needs,
    signed: bool,
) -> QuantityDeclaration {
    QuantityDeclaration {
        name,
        label,
        colormap: if signed {
            ColorMap::Diverging
        } else {
            ColorMap::Viridis
        },
        needs,
    }
}

impl VertexQuantity for BuiltIn {
    fn declaration(&self) -> &'static QuantityDeclaration {
        use Needs::{Mesh, Other};
        const MEAN: QuantityDeclaration = declared("mean", "mean curvature", Mesh, true);
        const GAUSSIAN: QuantityDeclaration =
            declared("gaussian", "Gaussian curvature", Mesh, true);
        const DEFECT: QuantityDeclaration = declared("angle-defect", "angle defect", Mesh, true);
        const MAX: QuantityDeclaration =
            declared("max-curvature", "max principal curvature", Mesh, true);
        const MIN: QuantityDeclaration =
            declared("min-curvature", "min principal curvature", Mesh, true);
        const VALENCE: QuantityDeclaration = declared("valence", "valence", Mesh, false);
        const MIN_ANGLE: QuantityDeclaration =
            declared("min-angle", "smallest corner angle (°)", Mesh, false);
        const EDGE_LENGTH: QuantityDeclaration =
            declared("edge-length", "edge length", Mesh, false);
        const DISTANCE: QuantityDeclaration =
            declared("distance", "distance to the mesh before", Other, false);
        match self.0 {
            Kind::Mean => &MEAN,
            Kind::Gaussian => &GAUSSIAN,
            Kind::AngleDefect => &DEFECT,
            Kind::MaxCurvature => &MAX,
            Kind::MinCurvature => &MIN,
            Kind::Valence => &VALENCE,
            Kind::MinAngle => &MIN_ANGLE,
            Kind::EdgeLength => &EDGE_LENGTH,
            Kind::Distance => &DISTANCE,
        }
    }

    fn per_vertex(&self, t: &Connectivity, given: &Given<'_>) -> Vec<f64> {
        self.0.per_vertex(t, given.other)
    }
}

impl Kind {
    /// Its value at every vertex of the mesh in `t`, by row. The distance measures to `other`
    /// (NaN everywhere without one); the others ignore it.
    fn per_vertex(self, t: &Connectivity, other: Option<&Reference>) -> Vec<f64> {
        let curvature_of = || scalar_curvature(&Surface::from_tables(t));
        match self {
            Kind::Mean => curvature_of().mean,
            Kind::Gaussian => curvature_of().gaussian,
            Kind::AngleDefect => curvature_of().angle_defect,
            Kind::MaxCurvature => curvature_of().max,
            Kind::MinCurvature => curvature_of().min,
            Kind::Distance => t
                .positions
                .iter()
                .map(|&p| other.map_or(f64::NAN, |r| f64::from(p.distance(r.closest(p)))))
                .collect(),
            Kind::Valence => t
                .vertices()
                .map(|v| t.vertex_outgoing(v).count() as f64)
                .collect(),
            Kind::EdgeLength => t
                .vertices()
                .map(|v| {
                    let p = t.position(v);
                    let (sum, n) = t.vertex_outgoing(v).fold((0.0, 0.0), |(s, n), h| {
                        (
                            s + f64::from(p.distance(t.position(t.to_vertex(h)))),
                            n + 1.0,
                        )
                    });
                    if n > 0.0 { sum / n } else { 0.0 }
                })
                .collect(),
            Kind::MinAngle => {
                let mut smallest = vec![f64::INFINITY; t.vertex_count()];
                for f in t.faces() {
                    let least = corner_angles_deg(t, f)
                        .into_iter()
                        .filter(|a| a.is_finite())
                        .fold(f64::INFINITY, f64::min);
                    for h in t.face_halfedges(f) {
                        let v = t.to_vertex(h).index();
                        smallest[v] = smallest[v].min(least);
                    }
                }
                smallest
                    .into_iter()
                    .map(|a| if a.is_finite() { a } else { 0.0 })
                    .collect()
            }
        }
    }
}

/// The corner angles of face `f` in degrees, one per corner in the face's order (NaN at a
/// corner with a zero-length side).
pub fn corner_angles_deg(t: &Connectivity, f: FaceRow) -> Vec<f64> {
    let corners: Vec<_> = t
        .face_halfedges(f)
        .map(|h| t.position(t.to_vertex(h)).as_dvec3())
        .collect();
    let k = corners.len();
    (0..k)
        .map(|i| {
            let (p, a, b) = (corners[i], corners[(i + k - 1) % k], corners[(i + 1) % k]);
            (a - p).angle_between(b - p).to_degrees()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tables::extract;
    use crate::mesh::{MeshInfo, build_mesh, shapes};
    use bevy::prelude::World;

    #[test]
    fn exact_values_on_a_cube_and_names_round_trip() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::cube(), MeshInfo::default()).unwrap();
        let t = extract(&world, built.mesh).tables;
        assert!(
            Quantity::VALENCE
                .per_vertex(&t, &Given::default())
                .iter()
                .all(|&v| v == 3.0)
        );
        assert!(
            Quantity::MIN_ANGLE
                .per_vertex(&t, &Given::default())
                .iter()
                .all(|&a| (a - 90.0).abs() < 1e-9)
        );
        // Three right angles at each corner: the defect is π/2.
        for d in Quantity::ANGLE_DEFECT.per_vertex(&t, &Given::default()) {
            assert!((d - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        }
        let side = 2.0 * f64::from(shapes::cube().positions[0].x.abs());
        for l in Quantity::EDGE_LENGTH.per_vertex(&t, &Given::default()) {
            assert!((l - side).abs() < 1e-6, "{l}");
        }
        // Distances to the plane z = 0 are the corners' heights.
        let plane = Reference::from_triangles(vec![[
            bevy::math::Vec3::new(-10.0, -10.0, 0.0),
            bevy::math::Vec3::new(10.0, -10.0, 0.0),
            bevy::math::Vec3::new(0.0, 10.0, 0.0),
        ]]);
        let d = Quantity::DISTANCE.per_vertex(
            &t,
            &Given {
                other: Some(&plane),
                ..Given::default()
            },
        );
        for (d, p) in d.iter().zip(&t.positions) {
            assert_eq!(*d, f64::from(p.z.abs()));
        }
        assert!(
            Quantity::DISTANCE
                .per_vertex(&t, &Given::default())
                .iter()
                .all(|d| d.is_nan())
        );
        let names: Vec<&str> = Quantity::BUILT_IN.iter().map(|q| q.name()).collect();
        assert_eq!(
            names,
            [
                "mean",
                "gaussian",
                "angle-defect",
                "max-curvature",
                "min-curvature",
                "valence",
                "min-angle",
                "edge-length",
                "distance"
            ]
        );
        assert_eq!(Quantity::DISTANCE.needs(), Needs::Other);
        assert_eq!(Quantity::MEAN.colormap(), ColorMap::Diverging);
        assert_eq!(Quantity::VALENCE.colormap(), ColorMap::Viridis);
    }
}
