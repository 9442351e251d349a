//! Curvature and smoothing on real and procedural meshes: Gauss–Bonnet holds exactly on every
//! shared model, and Taubin's filter keeps a noisy sphere's volume where the umbrella shrinks it.

mod common;

use common::build;
use pappus::mesh::tables::extract;
use pappus::mesh::{MeshId, mesh_stats, shapes, validate};
use pappus::ops::geometry::{Surface, curvature};
use pappus::ops::named::Named;
use pappus::ops::smooth::{SmoothMethod, SmoothParams, smooth};
use std::f64::consts::PI;

#[test]
fn gauss_bonnet_holds_on_every_shared_model() {
    let Some(dir) = common::models_dir() else {
        return;
    };
    let mut checked = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "obj") {
            continue;
        }
        let (world, built) = build(&pappus::io::read(&path).unwrap());
        let chi = mesh_stats(&world, built.mesh).euler_characteristic as f64;
        let c = curvature(&Surface::from_tables(&extract(&world, built.mesh).tables));
        // Inside the defect is Gaussian curvature, on the boundary the turning of the boundary
        // curve (π − Σθ): the two add up to 2πχ exactly, closed or not.
        let total: f64 = c.angle_defect.iter().sum();
        let name = path.file_name().unwrap().to_string_lossy();
        assert!(
            (total - 2.0 * PI * chi).abs() < 1e-7 * (1.0 + chi.abs()) * 2.0 * PI,
            "{name}: Σ defects {total} against 2πχ = {}",
            2.0 * PI * chi
        );
        checked += 1;
    }
    assert!(checked >= 9, "checked {checked} models");
}

/// The volume a closed mesh encloses (the divergence theorem over its fanned triangles).
fn volume(world: &bevy::prelude::World, mesh: MeshId) -> f64 {
    let s = Surface::from_tables(&extract(world, mesh).tables);
    (0..s.triangles.len())
        .map(|t| {
            let [a, b, c] = s.corners(t);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

/// The unit icosphere with every vertex pushed along its radius by up to ±2 % (a fixed
/// pseudo-random pattern).
fn noisy_sphere() -> pappus::mesh::PolygonSoup {
    let mut soup = shapes::icosphere(4);
    let mut state = 0x2545_f491_4f6c_dd1du64;
    for p in &mut soup.positions {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let noise = (state % 2001) as f32 / 1000.0 - 1.0;
        *p *= 1.0 + 0.02 * noise;
    }
    soup
}

#[test]
fn taubin_keeps_a_noisy_spheres_volume_where_the_umbrella_shrinks_it() {
    let mut changes = Vec::new();
    for method in [SmoothMethod::Uniform, SmoothMethod::Taubin] {
        let (mut world, built) = build(&noisy_sphere());
        let before = volume(&world, built.mesh);
        let params = SmoothParams {
            iterations: 10,
            ..SmoothParams::new(method)
        };
        smooth(&mut world, built.mesh, &params).unwrap();
        validate(&world, built.mesh).unwrap();
        let change = volume(&world, built.mesh) / before - 1.0;
        println!("{method:?}: volume changed by {:.3} %", 100.0 * change);
        changes.push(change);
    }
    assert!(changes[0] < -0.02, "the umbrella shrinks: {}", changes[0]);
    assert!(changes[1].abs() < 0.01, "Taubin keeps it: {}", changes[1]);
}

#[test]
fn every_smoothing_takes_noise_off_a_sphere() {
    // The spread of the radii falls under each method (the boundary-free sphere moves freely).
    let spread = |world: &bevy::prelude::World, mesh: MeshId| {
        let s = Surface::from_tables(&extract(world, mesh).tables);
        let radii: Vec<f64> = s.positions.iter().map(|p| p.length()).collect();
        let mean = radii.iter().sum::<f64>() / radii.len() as f64;
        (radii.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / radii.len() as f64).sqrt() / mean
    };
    for &(method, _) in SmoothMethod::ALL {
        let (mut world, built) = build(&noisy_sphere());
        let before = spread(&world, built.mesh);
        let params = SmoothParams {
            iterations: 5,
            ..SmoothParams::new(method)
        };
        smooth(&mut world, built.mesh, &params).unwrap();
        let after = spread(&world, built.mesh);
        assert!(
            after < before / 2.0,
            "{method:?}: spread {before} -> {after}"
        );
    }
}
