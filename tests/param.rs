//! Parameterization on the shared models (`../shared/models`): the bunny above its median
//! height (`bunny-disk.obj`, one boundary loop, 34k faces) and the whole Stanford bunny (5
//! holes), with every method. Tutte's theorem: uniform and mean-value weights give no flipped
//! triangle; harmonic weights may, and their figure is printed. Skipped with a notice where the
//! folder is absent.

mod common;

use bevy::prelude::World;
use pappus::mesh::tables::{Connectivity, extract};
use pappus::mesh::{MeshInfo, build_mesh};
use pappus::ops::param::{ParamMethod, ParamParams, Parameterization, parameterize};

fn tables(name: &str) -> Option<Connectivity> {
    let path = common::model(name)?;
    let soup = pappus::io::read(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    let mut world = World::new();
    let built = build_mesh(&mut world, &soup, MeshInfo::default()).expect("builds");
    Some(extract(&world, built.mesh).tables)
}

fn run(name: &str, t: &Connectivity, method: ParamMethod) -> Parameterization {
    let p = parameterize(t, &ParamParams::new(method)).unwrap_or_else(|e| panic!("{name}: {e}"));
    let r = &p.report;
    println!(
        "{name} {method}: {} triangles, {} flipped, angle distortion {:.3}°, conformal energy \
         {:.4}, area distortion {:.3}, {} loops ({} filled), {} in {:.1} ms (total {:.1} ms)",
        r.triangles,
        r.flipped,
        r.angle_distortion_deg,
        r.conformal_energy,
        r.area_distortion,
        r.boundary_loops,
        r.filled_holes,
        r.solver.name(),
        r.solve_ms,
        r.total_ms
    );
    for h in t.halfedges() {
        let uv = p.uv[h.index()];
        assert_eq!(t.is_boundary(h), uv.x.is_nan(), "{name} {method}");
        if !t.is_boundary(h) {
            assert!(uv.min_element() >= -1e-6 && uv.max_element() <= 1.0 + 1e-6);
        }
    }
    p
}

/// LSCM's measured flips on bunny-disk: 0 (the conformal energy is convex and the bunny's
/// triangles are well shaped); a small allowance for the solver's rounding on slivers.
const LSCM_FLIP_ALLOWANCE: usize = 2;

#[test]
fn bunny_disk_every_method() {
    let Some(t) = tables("bunny-disk.obj") else {
        return;
    };
    for method in [ParamMethod::Uniform, ParamMethod::MeanValue] {
        let p = run("bunny-disk", &t, method);
        assert_eq!(p.report.flipped, 0, "{method}: Tutte's theorem");
        assert_eq!(p.report.boundary_loops, 1);
        assert!(p.vertex_uvs(&t).is_some());
    }
    let harmonic = run("bunny-disk", &t, ParamMethod::Harmonic);
    assert!(harmonic.report.triangles > 30_000);
    assert!(harmonic.report.angle_distortion_deg.is_finite());
    let lscm = run("bunny-disk", &t, ParamMethod::Lscm);
    assert!(
        lscm.report.flipped <= LSCM_FLIP_ALLOWANCE,
        "{:?}",
        lscm.report
    );
    // LSCM is the most conformal of the four.
    assert!(lscm.report.conformal_energy <= harmonic.report.conformal_energy);
}

#[test]
fn the_bunny_with_five_holes_keeps_its_holes_out_of_the_layout() {
    let Some(t) = tables("stanford-bunny.obj") else {
        return;
    };
    for method in [ParamMethod::Uniform, ParamMethod::MeanValue] {
        let p = run("stanford-bunny", &t, method);
        assert_eq!(p.report.boundary_loops, 5);
        assert_eq!(p.report.filled_holes, 4);
        assert_eq!(
            p.report.flipped, 0,
            "{method}: Tutte's theorem with the holes filled"
        );
    }
    let harmonic = run("stanford-bunny", &t, ParamMethod::Harmonic);
    assert!(harmonic.report.angle_distortion_deg.is_finite());
    let lscm = run("stanford-bunny", &t, ParamMethod::Lscm);
    assert_eq!(lscm.report.filled_holes, 0);
}
