use bevy::math::{Affine3A, DAffine3, DMat3, DVec3, Mat3, Vec3};
use bevy::prelude::World;

use super::*;
use crate::mesh::tables::extract;
use crate::mesh::{MeshMembers, MeshRef, build_mesh, shapes, validate};
use crate::ops::local::testkit::positions;

/// A regular `n × n` grid of unit cells, each split along its rising diagonal, with heights
/// `z(x, y)`: its cotangent Laplacian is the five-point stencil (the diagonals weigh 0).
fn grid_surface(n: u32, z: impl Fn(f64, f64) -> f64) -> Surface {
    let at = |i: u32, j: u32| j * (n + 1) + i;
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f64, j as f64);
            positions.push(DVec3::new(x, y, z(x, y)));
        }
    }
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    let boundary = (0..=n)
        .flat_map(|j| (0..=n).map(move |i| i == 0 || j == 0 || i == n || j == n))
        .collect();
    Surface {
        triangle_face: (0..triangles.len() as u32).collect(),
        positions,
        triangles,
        boundary,
    }
}

/// Vertices within `rings` rings of the grid's border.
fn border_rings(n: u32, rings: u32) -> Vec<bool> {
    (0..=n)
        .flat_map(|j| (0..=n).map(move |i| i.min(j).min(n - i).min(n - j) < rings))
        .collect()
}

#[test]
fn the_thin_plate_moves_a_flat_grid_affinely_under_an_affine_motion() {
    let n = 10;
    let surface = grid_surface(n, |_, _| 0.0);
    let held = border_rings(n, 2);
    let motion = DAffine3::from_mat3_translation(
        DMat3::from_cols(
            DVec3::new(1.2, 0.3, -0.4),
            DVec3::new(-0.2, 0.9, 0.5),
            DVec3::new(0.1, 0.2, 1.1),
        ),
        DVec3::new(3.0, -1.0, 2.0),
    );
    let targets: Vec<(u32, DVec3)> = (0..surface.positions.len() as u32)
        .filter(|&v| held[v as usize])
        .map(|v| (v, motion.transform_point3(surface.positions[v as usize])))
        .collect();
    let edges = cotan_edges(&surface);
    let x = ThinPlate::new(&surface, &edges, &held)
        .unwrap()
        .displace(&targets);
    for (v, p) in surface.positions.iter().enumerate() {
        let want = motion.transform_point3(*p);
        assert!(
            (x[v] - want).length() < 1e-9,
            "vertex {v}: {} vs {want}",
            x[v]
        );
    }
}

#[test]
fn the_thin_plate_reproduces_a_quadratic_bump_from_its_two_border_rings() {
    let n = 12;
    let bump = |x: f64, y: f64| 0.05 * ((x - 6.0).powi(2) + (y - 6.0).powi(2)) - 1.0;
    let flat = grid_surface(n, |_, _| 0.0);
    let held = border_rings(n, 2);
    let targets: Vec<(u32, DVec3)> = (0..flat.positions.len() as u32)
        .filter(|&v| held[v as usize])
        .map(|v| {
            let p = flat.positions[v as usize];
            (v, DVec3::new(p.x, p.y, bump(p.x, p.y)))
        })
        .collect();
    let edges = cotan_edges(&flat);
    let x = ThinPlate::new(&flat, &edges, &held)
        .unwrap()
        .displace(&targets);
    for (v, p) in flat.positions.iter().enumerate() {
        let want = DVec3::new(p.x, p.y, bump(p.x, p.y));
        assert!(
            (x[v] - want).length() < 1e-9,
            "vertex {v}: {} vs {want}",
            x[v]
        );
    }
}

/// The triangles of an icosphere, as a solve reads them.
fn sphere_surface(levels: u32) -> Surface {
    let mut world = World::new();
    let built = build_mesh(&mut world, &shapes::icosphere(levels), MeshInfo::default()).unwrap();
    Surface::from_tables(&extract(&world, built.mesh).tables)
}

#[test]
fn arap_moves_a_sphere_rigidly_when_its_held_cap_moves_rigidly() {
    // A sphere cannot bend without stretching (a flat sheet held at a few points could, at
    // almost no energy): the rigid motion is the one state of energy 0.
    let surface = sphere_surface(2);
    let held: Vec<bool> = surface.positions.iter().map(|p| p.y > 0.8).collect();
    let motion = DAffine3::from_mat3_translation(
        DMat3::from_axis_angle(DVec3::new(1.0, 2.0, 2.0).normalize(), 0.3),
        DVec3::new(0.5, -2.0, 1.0),
    );
    let mut arap = Arap::new(&surface, &held).unwrap();
    let cap = (0..surface.positions.len() as u32).filter(|&v| held[v as usize]);
    arap.place(cap.map(|v| (v, motion.transform_point3(surface.positions[v as usize]))));
    // ARAP converges linearly: 1000 iterations take the error under 1e-6.
    for _ in 0..1000 {
        arap.iterate();
    }
    for (p, q) in surface.positions.iter().zip(arap.positions()) {
        let want = motion.transform_point3(*p);
        assert!((*q - want).length() < 1e-6, "{q} vs {want}");
    }
    arap.fit_rotations();
    assert!(arap.energy() < 1e-10, "{}", arap.energy());
}

/// The side of [`lifted_grid`]'s grid, in edges.
const LIFTED_GRID: u32 = 12;

/// The column of [`lifted_grid`]'s row `v`.
fn lifted_grid_column(v: usize) -> u32 {
    v as u32 % (LIFTED_GRID + 1)
}

/// A flat 12 × 12 grid whose first two columns are anchors and whose last column, the handle,
/// is lifted by 4: its surface, the held rows and the handle's targets.
fn lifted_grid() -> (Surface, Vec<bool>, Vec<(u32, DVec3)>) {
    let n = LIFTED_GRID;
    let surface = grid_surface(n, |_, _| 0.0);
    let columns = lifted_grid_column;
    let held: Vec<bool> = (0..surface.positions.len())
        .map(|v| columns(v) < 2 || columns(v) > n - 2)
        .collect();
    let lift = DVec3::new(0.0, 0.0, 4.0);
    let targets: Vec<(u32, DVec3)> = (0..surface.positions.len() as u32)
        .filter(|&v| columns(v as usize) > n - 2)
        .map(|v| (v, surface.positions[v as usize] + lift))
        .collect();
    (surface, held, targets)
}

#[test]
fn arap_iterations_never_raise_the_energy_and_leave_held_vertices_where_placed() {
    let (surface, held, targets) = lifted_grid();
    let columns = lifted_grid_column;
    let mut arap = Arap::new(&surface, &held).unwrap();
    arap.place(targets.iter().copied());
    arap.fit_rotations();
    let mut energy = arap.energy();
    let start = energy;
    for _ in 0..20 {
        arap.iterate();
        arap.fit_rotations();
        let now = arap.energy();
        assert!(now <= energy * (1.0 + 1e-12), "{now} after {energy}");
        energy = now;
    }
    assert!(energy < 0.5 * start, "{start} -> {energy}");
    for (v, p) in targets {
        assert_eq!(arap.positions()[v as usize], p);
    }
    for v in (0..surface.positions.len()).filter(|&v| columns(v) < 2) {
        assert_eq!(arap.positions()[v], surface.positions[v]);
    }
}

/// Anderson acceleration (Peng et al. 2018): ten iterations from the same start end nearer the
/// minimum (its energy after 300 iterations) than ten plain local–global ones (each started
/// anew from the last result, which forgets the history), and a single iteration is the plain
/// one to the bit (no history to draw on).
#[test]
fn accelerated_iterations_end_lower_than_plain_ones() {
    let (surface, held, targets) = lifted_grid();
    let start = |arap: &mut Arap| arap.place(targets.iter().copied());
    let mut accelerated = Arap::new(&surface, &held).unwrap();
    start(&mut accelerated);
    let mut plain = Arap::new(&surface, &held).unwrap();
    start(&mut plain);
    accelerated.iterate();
    plain.iterate();
    assert_eq!(accelerated.positions(), plain.positions());
    for _ in 1..10 {
        accelerated.iterate();
        let last = plain.positions().to_vec();
        plain.start_from(&last);
        plain.iterate();
    }
    accelerated.fit_rotations();
    plain.fit_rotations();
    let (fast, slow) = (accelerated.energy(), plain.energy());
    for _ in 10..300 {
        accelerated.iterate();
    }
    accelerated.fit_rotations();
    let least = accelerated.energy();
    assert!(
        fast - least < 0.5 * (slow - least),
        "after 10: accelerated {fast}, plain {slow}; after 300 {least}"
    );
}

/// The energy the local step measures (expanded: `Σ w‖d‖² − 2 tr(Rᵀ A) + Σ w‖e‖²`) is the
/// spokes energy summed term by term, with the rotations it fitted.
#[test]
fn the_local_step_measures_the_spokes_energy() {
    let n = 8;
    let surface = grid_surface(n, |x, y| 0.1 * x * y);
    let held: Vec<bool> = (0..surface.positions.len())
        .map(|v| [0, n].contains(&(v as u32 % (n + 1))))
        .collect();
    let mut arap = Arap::new(&surface, &held).unwrap();
    arap.place((0..=n).map(|j| {
        let v = j * (n + 1) + n;
        (v, surface.positions[v as usize] + DVec3::new(1.0, 0.5, 2.0))
    }));
    for _ in 0..3 {
        arap.iterate();
    }
    arap.fit_rotations();
    let rotations: Vec<DMat3> = arap.rotations().map(DMat3::from_quat).collect();
    let (p, q) = (&surface.positions, arap.positions());
    let direct: f64 = cotan_edges(&surface)
        .iter()
        .map(|&(i, j, w)| {
            let (i, j) = (i as usize, j as usize);
            let spoke = |a: usize, b: usize| {
                ((q[a] - q[b]) - rotations[a] * (p[a] - p[b])).length_squared()
            };
            w * (spoke(i, j) + spoke(j, i))
        })
        .sum();
    assert!(direct > 1e-3);
    assert!(
        (arap.energy() - direct).abs() < 1e-12 * direct,
        "{} vs {direct}",
        arap.energy()
    );
}

#[test]
fn a_deformation_keeps_anchors_to_the_bit_and_lands_the_handle_where_it_was_sent() {
    for method in [DeformMethod::Arap, DeformMethod::Laplace] {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::icosphere(3), MeshInfo::default()).unwrap();
        let vertices = MeshMembers::collect(&world, built.mesh).vertices;
        let before = positions(&world, built.mesh);
        // Anchors: the lower cap; handle: the top cap, turned and lifted.
        let fixed: Vec<VertexId> = (0..vertices.len())
            .filter(|&i| before[i].y < -0.6)
            .map(|i| vertices[i])
            .collect();
        let handle: Vec<VertexId> = (0..vertices.len())
            .filter(|&i| before[i].y > 0.7)
            .map(|i| vertices[i])
            .collect();
        let motion =
            Affine3A::from_mat3_translation(Mat3::from_rotation_z(0.4), Vec3::new(0.2, 0.5, 0.0));
        let params = DeformParams {
            method,
            fixed: fixed.clone(),
            handle: handle.clone(),
            motion,
            iterations: 5,
        };
        let s = deform(&mut world, built.mesh, &params).unwrap();
        validate(&world, built.mesh).unwrap();
        let after = positions(&world, built.mesh);
        for i in 0..vertices.len() {
            if fixed.contains(&vertices[i]) {
                assert_eq!(after[i].to_array(), before[i].to_array());
            } else if handle.contains(&vertices[i]) {
                assert_eq!(after[i], motion.transform_point3(before[i]));
            }
        }
        assert_eq!(s.free, vertices.len() - fixed.len() - handle.len());
        if method == DeformMethod::Arap {
            assert!(s.energy < s.energy_before, "{s:?}");
        }
        // The middle moved toward the handle.
        let middle = (0..vertices.len())
            .find(|&i| before[i].y.abs() < 0.05)
            .unwrap();
        assert!(
            after[middle].y > before[middle].y,
            "{} -> {}",
            before[middle],
            after[middle]
        );
    }
}

#[test]
fn malformed_deformations_are_refused_and_change_nothing() {
    let mut world = World::new();
    let built = build_mesh(&mut world, &shapes::icosphere(2), MeshInfo::default()).unwrap();
    let vertices = MeshMembers::collect(&world, built.mesh).vertices;
    let before = positions(&world, built.mesh);
    let good = DeformParams {
        method: DeformMethod::Arap,
        fixed: vec![vertices[0]],
        handle: vec![vertices[5]],
        motion: Affine3A::from_translation(Vec3::X),
        iterations: 3,
    };
    let bad = [
        DeformParams {
            handle: Vec::new(),
            ..good.clone()
        },
        DeformParams {
            handle: vec![vertices[0]],
            ..good.clone()
        },
        DeformParams {
            iterations: 0,
            ..good.clone()
        },
        DeformParams {
            motion: Affine3A::from_translation(Vec3::NAN),
            ..good.clone()
        },
    ];
    for params in bad {
        let refusal = deform(&mut world, built.mesh, &params).unwrap_err();
        assert!(matches!(refusal, Refusal::BadParameter(_)), "{refusal}");
        assert_eq!(positions(&world, built.mesh), before);
    }
}

#[test]
fn fairing_a_raised_patch_of_a_plane_lays_it_flat_for_every_order() {
    for k in 1..=3 {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::grid(12, 12), MeshInfo::default()).unwrap();
        let vertices = MeshMembers::collect(&world, built.mesh).vertices;
        // Lift the middle (far from the border: the stencils stay inside).
        let middle: Vec<VertexId> = vertices
            .iter()
            .copied()
            .filter(|&v| {
                let p = MeshRef::new(&world).position(v);
                (p - Vec3::new(0.5, 0.5, 0.0)).abs().max_element() < 0.2
            })
            .collect();
        for &v in &middle {
            world.get_mut::<Position>(v.0).unwrap().0.z = 0.3;
        }
        let s = fair(
            &mut world,
            built.mesh,
            &FairParams {
                vertices: middle.clone(),
                k,
            },
        )
        .unwrap();
        validate(&world, built.mesh).unwrap();
        assert_eq!(s.free, middle.len());
        for &v in &middle {
            let z = MeshRef::new(&world).position(v).z;
            assert!(z.abs() < 1e-6, "k = {k}: z = {z}");
        }
    }
}

#[test]
fn a_part_with_nothing_held_stays_where_it_was() {
    let mut world = World::new();
    let mut soup = shapes::icosphere(1);
    let two = soup.positions.len() as u32;
    let other = shapes::icosphere(1);
    soup.positions.extend(
        other
            .positions
            .iter()
            .map(|p| *p + Vec3::new(5.0, 0.0, 0.0)),
    );
    for f in other.faces() {
        soup.push_face(&f.iter().map(|i| i + two).collect::<Vec<_>>());
    }
    let built = build_mesh(&mut world, &soup, MeshInfo::default()).unwrap();
    let vertices = MeshMembers::collect(&world, built.mesh).vertices;
    let before = positions(&world, built.mesh);
    let first = (0..vertices.len()).find(|&i| before[i].x < 2.0).unwrap();
    let params = DeformParams {
        method: DeformMethod::Arap,
        fixed: Vec::new(),
        handle: vec![vertices[first]],
        motion: Affine3A::from_translation(Vec3::Y),
        iterations: 2,
    };
    let s = deform(&mut world, built.mesh, &params).unwrap();
    assert_eq!(s.loose_parts, 1);
    let after = positions(&world, built.mesh);
    for i in 0..vertices.len() {
        if before[i].x > 2.0 {
            assert_eq!(after[i], before[i]);
        } else {
            assert!(after[i].y > before[i].y, "{} -> {}", before[i], after[i]);
        }
    }
}
