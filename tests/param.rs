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
        "{name} {method}: {} triangles, {} flipped, {} degenerate, angle distortion {:.3}°, conformal energy \
         {:.4}, area distortion {:.3}, {} loops ({} filled), {} in {:.1} ms (total {:.1} ms)",
        r.triangles,
        r.flipped,
        r.degenerate,
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

/// The faces of `soup` whose centroid lies above the median height (y), as a soup of their own:
/// the connected piece of the face with the highest centroid (faces joined by a shared side).
fn slice_above_median(soup: &pappus::mesh::PolygonSoup) -> pappus::mesh::PolygonSoup {
    let face = |f: usize| {
        let (a, b) = (
            soup.face_starts[f] as usize,
            soup.face_starts[f + 1] as usize,
        );
        &soup.indices[a..b]
    };
    let faces = soup.face_starts.len() - 1;
    let centroid_y = |f: usize| {
        let c = face(f);
        c.iter().map(|&i| soup.positions[i as usize].y).sum::<f32>() / c.len() as f32
    };
    let mut heights: Vec<f32> = (0..faces).map(centroid_y).collect();
    heights.sort_by(f32::total_cmp);
    let median = heights[faces / 2];
    let above: Vec<usize> = (0..faces).filter(|&f| centroid_y(f) > median).collect();
    // Faces by side, to walk the piece.
    let mut by_side: std::collections::HashMap<(u32, u32), Vec<usize>> = Default::default();
    for &f in &above {
        let c = face(f);
        for k in 0..c.len() {
            let (a, b) = (c[k], c[(k + 1) % c.len()]);
            by_side.entry((a.min(b), a.max(b))).or_default().push(f);
        }
    }
    let seed = *above
        .iter()
        .max_by(|&&a, &&b| centroid_y(a).total_cmp(&centroid_y(b)))
        .expect("faces above the median");
    let mut piece = std::collections::BTreeSet::from([seed]);
    let mut stack = vec![seed];
    while let Some(f) = stack.pop() {
        let c = face(f);
        for k in 0..c.len() {
            let (a, b) = (c[k], c[(k + 1) % c.len()]);
            for &g in &by_side[&(a.min(b), a.max(b))] {
                if piece.insert(g) {
                    stack.push(g);
                }
            }
        }
    }
    let kept: Vec<Vec<u32>> = piece.into_iter().map(|f| face(f).to_vec()).collect();
    pappus::mesh::PolygonSoup::from_faces(soup.positions.clone(), &kept)
}

#[test]
fn disks_cut_from_other_models_and_closed_ones_cut_automatically_never_flip_with_tutte() {
    for name in ["spot.obj", "homer.obj", "fandisk.obj", "beast.obj"] {
        let Some(path) = common::model(name) else {
            return;
        };
        let soup = pappus::io::read(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        // The top half as a piece of its own (it may have several boundary loops: the longest
        // is the outer one, the others are filled for the solve); and the whole closed model,
        // cut open along the shortest path between two far-apart vertices.
        for (label, soup) in [("top half", slice_above_median(&soup)), ("closed", soup)] {
            let mut world = World::new();
            let built = build_mesh(&mut world, &soup, MeshInfo::default()).expect("builds");
            let t = extract(&world, built.mesh).tables;
            let name = format!("{name} {label}");
            for method in [ParamMethod::Uniform, ParamMethod::MeanValue] {
                let p = run(&name, &t, method);
                assert_eq!(p.report.flipped, 0, "{name} {method}: Tutte's theorem");
                if label == "closed" {
                    assert!(p.report.auto_seam_edges > 0, "{name}: cut automatically");
                }
            }
            let harmonic = run(&name, &t, ParamMethod::Harmonic);
            assert!(harmonic.report.angle_distortion_deg.is_finite());
        }
    }
}
