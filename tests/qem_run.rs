//! A QEM simplification stepped collapse by collapse ([`QemRun`], on entities): stepped to the
//! end it makes the unstepped run's mesh (on flat tables; to the entity) and history records
//! (to the bit), on regular meshes, on boundaries and sharp folds run to the last legal
//! collapse, and on a mesh edited first (its storage order no longer its entity order); moved
//! back along its history and forward again it has the same mesh at every step and the same
//! end; the next collapse it shows is the one it makes; a run whose mesh was edited while it
//! waited refuses to go on. Each with the distance check too
//! ([`SimplifyParams::distance_weight`]), which queues edges again as it measures them, and
//! with the fit to the input at the end ([`SimplifyParams::fit_to_input`]), which the
//! stepped run makes when it is finished.

mod common;

use bevy::math::Vec3;
use bevy::prelude::World;
use common::{build, canonical, elements};
use pappus::mesh::shapes::{
    grid_with_holes, icosphere, slab_with_holes, torus, triangle_fan, triangulate_fans,
};
use pappus::mesh::soup::PolygonSoup;
use pappus::mesh::{MeshId, MeshRef, to_soup};
use pappus::ops::Refusal;
use pappus::ops::progressive::{ProgressiveMesh, SlotIndex, SlotRecord};
use pappus::ops::simplify::{QemRun, SimplifyParams};

/// The mesh up to relabeling: faces as cycles of positions, bitwise.
fn shape(world: &World, mesh: MeshId) -> Vec<Vec<common::Key>> {
    canonical(&to_soup(world, mesh))
}

/// A torus whose vertices are moved off it by a fixed pseudo-random amount along the radius,
/// up to a tenth of the tube's: bumps that the distance check weighs.
fn bumpy_torus() -> PolygonSoup {
    let mut soup = triangulate_fans(&torus(24, 12));
    let mut state = 11u32;
    for p in &mut soup.positions {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        let bump = (state >> 8) as f32 / (1u32 << 24) as f32 * 0.1;
        let around = Vec3::new(p.x, p.y, 0.0).normalize_or_zero();
        *p += (*p - around).normalize_or_zero() * bump;
    }
    soup
}

/// `params` with the distance check on ([`SimplifyParams::distance_weight`]).
fn with_distance(params: SimplifyParams) -> SimplifyParams {
    SimplifyParams {
        distance_weight: 8.0,
        ..params
    }
}

/// `params` with the fit to the input at the end ([`SimplifyParams::fit_to_input`]).
fn with_fit(params: SimplifyParams) -> SimplifyParams {
    SimplifyParams {
        fit_to_input: true,
        ..params
    }
}

/// The meshes every test runs on: regular ones, where many edges cost the same and the
/// order of ties decides, one with boundaries and holes, and some with the distance check,
/// which queues edges again as it measures them, or the fit at the end.
fn inputs() -> Vec<(&'static str, PolygonSoup, SimplifyParams)> {
    vec![
        (
            "bumpy torus, fit",
            bumpy_torus(),
            with_fit(SimplifyParams::ratio(0.15)),
        ),
        (
            "holes, distance, fit",
            triangulate_fans(&grid_with_holes(3)),
            with_fit(with_distance(SimplifyParams::ratio(0.25))),
        ),
        (
            "icosphere, distance",
            icosphere(3),
            with_distance(SimplifyParams::ratio(0.1)),
        ),
        (
            "bumpy torus, distance",
            bumpy_torus(),
            with_distance(SimplifyParams::ratio(0.15)),
        ),
        (
            "holes, distance",
            triangulate_fans(&grid_with_holes(3)),
            with_distance(SimplifyParams::ratio(0.25)),
        ),
        ("icosphere", icosphere(3), SimplifyParams::ratio(0.1)),
        (
            "torus",
            triangulate_fans(&torus(24, 12)),
            SimplifyParams::ratio(0.2),
        ),
        (
            "holes",
            triangulate_fans(&grid_with_holes(3)),
            SimplifyParams::ratio(0.25),
        ),
    ]
}

fn record_bits(r: &SlotRecord) -> impl PartialEq + std::fmt::Debug {
    let p = |v: Vec3| v.to_array().map(f32::to_bits);
    (
        (r.kept, r.removed, r.left, r.right, r.faces),
        [r.merged_position, r.kept_position, r.removed_position].map(p),
    )
}

/// Steps `run` `n` times at the coarsest level, recording into `pm`; returns how many it made.
fn step(world: &mut World, run: &mut QemRun, pm: &mut ProgressiveMesh, n: usize) -> usize {
    run.reattach(world, pm.slots()).expect("the run goes on");
    let index = SlotIndex::of(pm);
    let mut made = 0;
    while made < n {
        let Some(next) = run.peek(world, |_| {}) else {
            break;
        };
        let result = run.collapse_next(world, |_| {}).expect("peek promised one");
        assert_eq!((result.kept, result.removed), (next.kept, next.removed));
        assert!(MeshRef::new(world).try_edge(next.queued.edge).is_none());
        pm.push(world, &index, &result);
        made += 1;
    }
    made
}

/// The stepped run's end as the editor's step mode makes it: the fit to the input, if the run
/// was asked for one, and the history settled on the fitted mesh.
fn finish(world: &mut World, run: &QemRun, pm: &mut ProgressiveMesh) {
    if run.fit_to_input(world, &pm.never_kept()) {
        pm.settle_coarsest(world);
    }
}

/// Simplifies `soup` (after `edit`) unstepped and stepped, and holds the two to the same mesh,
/// element for element, and the same records, bit for bit.
fn assert_stepped_matches_unstepped(
    name: &str,
    soup: &PolygonSoup,
    params: &SimplifyParams,
    edit: impl Fn(&mut World, MeshId),
) {
    let (mut whole, built) = build(soup);
    edit(&mut whole, built.mesh);
    let (expected, summary) = ProgressiveMesh::simplify(&mut whole, built.mesh, params).unwrap();
    let (mut world, built) = build(soup);
    let mesh = built.mesh;
    edit(&mut world, mesh);
    let mut run = QemRun::start(&world, mesh, params).unwrap();
    let mut pm = ProgressiveMesh::start(&world, mesh, run.faces());
    // Uneven strides, as a user pressing 1, 10 and 100 would.
    for stride in [1, 10, 100, 1, 7].into_iter().cycle() {
        if step(&mut world, &mut run, &mut pm, stride) < stride {
            break;
        }
    }
    finish(&mut world, &run, &mut pm);
    assert_eq!(run.summary(), summary, "{name}");
    assert!(
        elements(&world, mesh) == elements(&whole, built.mesh),
        "{name}: the stepped mesh differs"
    );
    assert_eq!(pm.records.len(), expected.records.len(), "{name}");
    for (a, b) in pm.records.iter().zip(&expected.records) {
        assert_eq!(record_bits(a), record_bits(b), "{name}");
    }
    assert_eq!(pm.slots(), expected.slots(), "{name}");
    pappus::mesh::validate(&world, mesh).unwrap();
    pappus::mesh::validate(&whole, built.mesh).unwrap();
}

#[test]
fn stepping_to_the_end_makes_the_unstepped_runs_mesh_and_records() {
    for (name, soup, params) in inputs() {
        assert_stepped_matches_unstepped(name, &soup, &params, |_, _| {});
    }
}

#[test]
fn both_runs_refuse_alike_down_to_the_last_legal_collapse() {
    // Every collapse until none is allowed: boundary loops of three, lone triangles, wings
    // left with too few edges, the link condition, sharp folds (the slab's rims).
    let to_the_end = SimplifyParams::faces(0);
    let meshes = [
        ("slab", triangulate_fans(&slab_with_holes(2))),
        ("holes", triangulate_fans(&grid_with_holes(2))),
        ("open fan", triangle_fan(9, false)),
        ("closed fan", triangle_fan(9, true)),
    ];
    for (name, soup) in meshes {
        assert_stepped_matches_unstepped(name, &soup, &to_the_end, |_, _| {});
        let to_the_end = with_distance(to_the_end);
        assert_stepped_matches_unstepped(name, &soup, &to_the_end, |_, _| {});
    }
}

#[test]
fn both_runs_agree_on_a_mesh_edited_first() {
    // Collapses free entities and splits reuse them: the mesh's storage order is then no
    // longer its entity order, which the unstepped run's rows follow and its ties do not.
    let edit = |world: &mut World, mesh: MeshId| {
        for round in 0..12 {
            let members = pappus::mesh::MeshMembers::collect(world, mesh);
            let e = members.edges[(round * 37) % members.edges.len()];
            if round % 2 == 0 {
                let _ = pappus::ops::local::collapse_edge(world, e, Default::default());
            } else {
                let _ = pappus::ops::local::split_edge_midpoint(world, e);
            }
        }
    };
    assert_stepped_matches_unstepped("edited", &icosphere(3), &SimplifyParams::ratio(0.2), edit);
    let params = with_distance(SimplifyParams::ratio(0.2));
    assert_stepped_matches_unstepped("edited, distance", &bumpy_torus(), &params, edit);
}

#[test]
fn scrubbing_back_and_forth_gives_the_same_mesh_at_every_step_and_the_same_end() {
    for (name, soup, params) in inputs() {
        let (mut whole, reference) = build(&soup);
        let end = ProgressiveMesh::simplify(&mut whole, reference.mesh, &params).unwrap();
        let (mut world, built) = build(&soup);
        let mesh = built.mesh;
        let mut run = QemRun::start(&world, mesh, &params).unwrap();
        let mut pm = ProgressiveMesh::start(&world, mesh, run.faces());
        let mut at_step = vec![shape(&world, mesh)];

        // Go forward in strides, keeping the shape at each stop; after each stride go back
        // to an earlier stop (a long way: the bulk refine, which renumbers everything) and
        // forward again, checking the shapes on the way.
        for (round, stride) in [40, 3, 25, 60].into_iter().cycle().enumerate() {
            if step(&mut world, &mut run, &mut pm, stride) == 0 {
                break;
            }

            at_step.push(shape(&world, mesh));
            let back = round % at_step.len();
            run.detach();
            let faces = pm.full_faces
                - pm.records[..pm.records.len() - stride.min(pm.records.len())]
                    .iter()
                    .map(|r| r.faces)
                    .sum::<usize>();
            pm.go_to_faces(&mut world, if back == 0 { usize::MAX } else { faces })
                .unwrap();
            if back == 0 {
                assert_eq!(shape(&world, mesh), at_step[0], "{name}: the full level");
            }
            pm.go_to_faces(&mut world, 0).unwrap();
            assert_eq!(
                shape(&world, mesh),
                *at_step.last().unwrap(),
                "{name}: back at the run's front"
            );
            pappus::mesh::validate(&world, mesh).unwrap();
        }
        finish(&mut world, &run, &mut pm);
        assert_eq!(run.summary(), end.1, "{name}");
        assert_eq!(shape(&world, mesh), shape(&whole, reference.mesh), "{name}");
    }
}

#[test]
fn a_fitted_history_goes_back_to_the_full_mesh_and_forth_to_the_fitted_one() {
    let soup = bumpy_torus();
    let (mut world, built) = build(&soup);
    let mesh = built.mesh;
    let full = shape(&world, mesh);
    let params = SimplifyParams::ratio(0.15);
    let (mut unfitted, plain) = build(&soup);
    ProgressiveMesh::simplify(&mut unfitted, plain.mesh, &params).unwrap();
    let (mut pm, _) = ProgressiveMesh::simplify(&mut world, mesh, &with_fit(params)).unwrap();
    let fitted = shape(&world, mesh);
    assert_ne!(
        fitted,
        shape(&unfitted, plain.mesh),
        "the fit moved nothing"
    );
    pm.go_to_faces(&mut world, usize::MAX).unwrap();
    assert_eq!(shape(&world, mesh), full);
    pm.go_to_faces(&mut world, 0).unwrap();
    assert_eq!(shape(&world, mesh), fitted);
    pappus::mesh::validate(&world, mesh).unwrap();
}

#[test]
fn the_candidates_are_the_queue_cheapest_first_and_peek_is_the_first_allowed() {
    let (mut world, built) = build(&triangulate_fans(&torus(16, 8)));
    let mut run = QemRun::start(&world, built.mesh, &SimplifyParams::ratio(0.5)).unwrap();
    let queued = run.queued();
    let first = run.candidates(12);
    assert_eq!(first.len(), 12);
    assert!(first.windows(2).all(|w| w[0].cost <= w[1].cost));
    let mut refused = Vec::new();
    let next = run.peek(&world, |r| refused.push(r)).unwrap();
    // Refused edges leave the queue; the next one stays counted.
    assert_eq!(run.queued(), queued - refused.len());
    assert_eq!(first[refused.len()], next.queued);
    assert_eq!(run.candidates(1)[0], next.queued);
    let result = run.collapse_next(&mut world, |_| unreachable!()).unwrap();
    assert_eq!(result.kept, next.kept);
    assert_eq!(
        MeshRef::new(&world).position(result.kept),
        next.queued.position
    );
}

#[test]
fn a_run_whose_mesh_was_edited_while_it_waited_refuses_to_go_on() {
    let (mut world, built) = build(&icosphere(2));
    let params = SimplifyParams::ratio(0.5);
    let mut run = QemRun::start(&world, built.mesh, &params).unwrap();
    let mut pm = ProgressiveMesh::start(&world, built.mesh, run.faces());
    step(&mut world, &mut run, &mut pm, 5);
    run.detach();
    let queued = run.candidates(3)[2].edge;
    pappus::ops::local::collapse_edge(&mut world, queued, Default::default()).unwrap();
    let refusal = run.reattach(&world, pm.slots()).unwrap_err();
    assert!(
        matches!(refusal, Refusal::HistoryMismatch(ref why) if why.contains("is gone")),
        "{refusal}"
    );
    // Still detached: it refuses again rather than going on.
    assert!(run.reattach(&world, pm.slots()).is_err());
}
