//! The quantities a mesh can be coloured by or exported with: one value per vertex, by table
//! row.
//!
//! Curvatures come from [`super::curvature`]; valence counts a vertex's edges; the smallest
//! angle is the smallest corner angle, in degrees, of the faces around the vertex (where thin
//! triangles are); the edge length is the mean length of the vertex's edges.

use crate::colormap::ColorMap;
use crate::mesh::tables::{Connectivity, FaceRow};
use crate::ops::named::Named;

use super::closest::Reference;
use super::curvature::scalar_curvature;
use super::surface::Surface;

/// A per-vertex quantity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// Mean curvature `H`.
    Mean,
    /// Gaussian curvature `K` (angle defect over area).
    Gaussian,
    /// The angle defect (integrated Gaussian curvature).
    AngleDefect,
    /// The larger principal curvature.
    MaxCurvature,
    /// The smaller principal curvature.
    MinCurvature,
    /// The number of edges at the vertex.
    Valence,
    /// The smallest corner angle (degrees) of the faces around the vertex.
    MinAngle,
    /// The mean length of the vertex's edges.
    EdgeLength,
    /// The distance from the vertex to another surface: the mesh before the last whole-mesh
    /// edit in the editor, the input on the command line (MeshLab's Hausdorff colouring).
    Distance,
}

impl Named for Quantity {
    /// Every quantity, with its name on the command line.
    const ALL: &'static [(Self, &'static str)] = &[
        (Quantity::Mean, "mean"),
        (Quantity::Gaussian, "gaussian"),
        (Quantity::AngleDefect, "angle-defect"),
        (Quantity::MaxCurvature, "max-curvature"),
        (Quantity::MinCurvature, "min-curvature"),
        (Quantity::Valence, "valence"),
        (Quantity::MinAngle, "min-angle"),
        (Quantity::EdgeLength, "edge-length"),
        (Quantity::Distance, "distance"),
    ];
}

impl Quantity {
    /// Its name in the panel and the legend.
    pub fn label(self) -> &'static str {
        match self {
            Quantity::Mean => "mean curvature",
            Quantity::Gaussian => "Gaussian curvature",
            Quantity::AngleDefect => "angle defect",
            Quantity::MaxCurvature => "max principal curvature",
            Quantity::MinCurvature => "min principal curvature",
            Quantity::Valence => "valence",
            Quantity::MinAngle => "smallest corner angle (°)",
            Quantity::EdgeLength => "edge length",
            Quantity::Distance => "distance to the mesh before",
        }
    }

    /// The colour map that shows it: diverging for signed quantities.
    pub fn colormap(self) -> ColorMap {
        match self {
            Quantity::Valence | Quantity::MinAngle | Quantity::EdgeLength | Quantity::Distance => {
                ColorMap::Viridis
            }
            _ => ColorMap::Diverging,
        }
    }

    /// Its value at every vertex of the mesh in `t`, by row. [`Quantity::Distance`] measures to
    /// `other` (NaN everywhere without one); the others ignore it.
    pub fn per_vertex(self, t: &Connectivity, other: Option<&Reference>) -> Vec<f64> {
        let curvature_of = || scalar_curvature(&Surface::from_tables(t));
        match self {
            Quantity::Mean => curvature_of().mean,
            Quantity::Gaussian => curvature_of().gaussian,
            Quantity::AngleDefect => curvature_of().angle_defect,
            Quantity::MaxCurvature => curvature_of().max,
            Quantity::MinCurvature => curvature_of().min,
            Quantity::Distance => t
                .positions
                .iter()
                .map(|&p| other.map_or(f64::NAN, |r| f64::from(p.distance(r.closest(p)))))
                .collect(),
            Quantity::Valence => t
                .vertices()
                .map(|v| t.vertex_outgoing(v).count() as f64)
                .collect(),
            Quantity::EdgeLength => t
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
            Quantity::MinAngle => {
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
            Quantity::Valence
                .per_vertex(&t, None)
                .iter()
                .all(|&v| v == 3.0)
        );
        assert!(
            Quantity::MinAngle
                .per_vertex(&t, None)
                .iter()
                .all(|&a| (a - 90.0).abs() < 1e-9)
        );
        // Three right angles at each corner: the defect is π/2.
        for d in Quantity::AngleDefect.per_vertex(&t, None) {
            assert!((d - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        }
        let side = 2.0 * f64::from(shapes::cube().positions[0].x.abs());
        for l in Quantity::EdgeLength.per_vertex(&t, None) {
            assert!((l - side).abs() < 1e-6, "{l}");
        }
        // Distances to the plane z = 0 are the corners' heights.
        let plane = Reference::from_triangles(vec![[
            bevy::math::Vec3::new(-10.0, -10.0, 0.0),
            bevy::math::Vec3::new(10.0, -10.0, 0.0),
            bevy::math::Vec3::new(0.0, 10.0, 0.0),
        ]]);
        let d = Quantity::Distance.per_vertex(&t, Some(&plane));
        for (d, p) in d.iter().zip(&t.positions) {
            assert_eq!(*d, f64::from(p.z.abs()));
        }
        assert!(
            Quantity::Distance
                .per_vertex(&t, None)
                .iter()
                .all(|d| d.is_nan())
        );
        for &(q, name) in Quantity::ALL {
            assert_eq!(Quantity::from_name(name), Some(q));
            assert_eq!(q.name(), name);
        }
    }
}
