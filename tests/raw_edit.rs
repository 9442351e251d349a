//! The checked low-level edit (`pappus::mesh::RawEdit`): a flip written by hand with it equals
//! the library's on a whole mesh and on the shared spot, and a broken edit is refused and
//! leaves the world exactly as it was, component for component.

mod common;
#[path = "common/hand_edits.rs"]
mod hand_edits;

use bevy::math::Vec3;
use bevy::prelude::{Entity, World};
use pappus::mesh::{EdgeId, ElementId, MeshMembers, MeshRef, RawEdit, RawEditError, Rule, shapes};
use pappus::ops::local::flip_edge;

/// The corner cycles of the faces beside `e`, each rotated to its smallest entity, sorted.
fn faces_beside(world: &World, e: EdgeId) -> Vec<Vec<Entity>> {
    let m = MeshRef::new(world);
    let h = m.edge_halfedge(e);
    let mut faces: Vec<Vec<Entity>> = [m.face(h), m.face(m.twin(h))]
        .into_iter()
        .flatten()
        .map(|f| {
            let mut cycle: Vec<Entity> = m.face_vertices(f).map(|v| v.0).collect();
            let start = (0..cycle.len()).min_by_key(|&i| cycle[i]).unwrap_or(0);
            cycle.rotate_left(start);
            cycle
        })
        .collect();
    faces.sort();
    faces
}

/// Flips every `stride`-th edge of `soup` by hand and with `flip_edge`, in two worlds built
/// alike: where the library flips, the hand-written flip commits and the faces beside the edge
/// are the same; both are flipped back before the next edge. Returns the flips compared.
fn compare_flips(soup: &pappus::mesh::PolygonSoup, stride: usize) -> usize {
    let (mut by_hand, built) = common::build(soup);
    let (mut library, _) = common::build(soup);
    let mesh = built.mesh;
    let edges = MeshMembers::collect(&by_hand, mesh).edges;
    let mut compared = 0;
    for &e in edges.iter().step_by(stride) {
        if MeshRef::new(&library).is_boundary_edge(e) || flip_edge(&mut library, e).is_err() {
            continue;
        }
        let mut edit = RawEdit::new(&mut by_hand, mesh);
        hand_edits::flip_by_hand(&mut edit, e).expect("the edge's elements are the mesh's");
        edit.commit().unwrap_or_else(|why| panic!("{e}: {why}"));
        assert_eq!(faces_beside(&by_hand, e), faces_beside(&library, e), "{e}");
        compared += 1;
        flip_edge(&mut library, e).expect("flips back");
        let mut edit = RawEdit::new(&mut by_hand, mesh);
        hand_edits::flip_by_hand(&mut edit, e).expect("the edge's elements are the mesh's");
        edit.commit().expect("flips back");
    }
    assert_eq!(
        common::elements(&by_hand, mesh),
        common::elements(&library, mesh)
    );
    compared
}

#[test]
fn a_flip_by_hand_is_the_librarys_on_every_edge_of_an_icosphere() {
    let soup = shapes::icosphere(2);
    assert_eq!(compare_flips(&soup, 1), 480);
}

#[test]
fn a_flip_by_hand_is_the_librarys_on_spot() {
    let Some(path) = common::model("spot.obj") else {
        return common::skip_because(
            "../shared/models/spot.obj",
            "a_flip_by_hand_is_the_librarys_on_spot",
        );
    };
    let (soup, _) = pappus::source::read_source(&path).expect("spot reads");
    // Every 13th edge: each commit checks the whole mesh, slow in this test build.
    assert!(compare_flips(&soup, 13) > 500);
}

#[test]
fn a_broken_edit_is_refused_naming_the_rule_and_leaves_the_world_as_it_was() {
    let (mut world, built) = common::build(&shapes::icosphere(1));
    let mesh = built.mesh;
    let before = common::snapshot(&mut world, mesh);
    let members = MeshMembers::collect(&world, mesh);
    let order = format!("{members:?}");
    let (h, other) = (members.halfedges[0], members.halfedges[7]);
    let mut edit = RawEdit::new(&mut world, mesh);
    let (e, a, _) = edit.new_edge();
    let v = edit.new_vertex(Vec3::ONE).unwrap();
    edit.set_to_vertex(a, v).unwrap();
    edit.set_position(members.vertices[3], Vec3::splat(9.0))
        .unwrap();
    edit.remove(members.faces[2]).unwrap();
    edit.set_next(h, other).unwrap();
    let Err(RawEditError::Invalid(invalid)) = edit.commit() else {
        panic!("a broken link commits");
    };
    assert!(
        matches!(invalid.rule, Rule::DanglingLink(_) | Rule::NextPrevDisagree),
        "{invalid}"
    );
    assert_eq!(common::snapshot(&mut world, mesh), before);
    // Even the storage order, which gives the rows of the flat tables and of Python's arrays.
    assert_eq!(format!("{:?}", MeshMembers::collect(&world, mesh)), order);
    assert!(world.get_entity(e.0).is_err() && world.get_entity(v.0).is_err());
    pappus::mesh::validate(&world, mesh).expect("the mesh is as it was");
}

#[test]
fn an_edit_dropped_without_a_commit_rolls_back() {
    let (mut world, built) = common::build(&shapes::icosphere(1));
    let mesh = built.mesh;
    let before = common::snapshot(&mut world, mesh);
    let members = MeshMembers::collect(&world, mesh);
    {
        let mut edit = RawEdit::new(&mut world, mesh);
        edit.set_twin(members.halfedges[0], members.halfedges[5])
            .unwrap();
        edit.new_face();
    }
    assert_eq!(common::snapshot(&mut world, mesh), before);
    let edit = RawEdit::new(&mut world, mesh);
    edit.rollback();
    assert_eq!(common::snapshot(&mut world, mesh), before);
}

#[test]
fn setters_refuse_what_is_not_an_element_of_this_mesh() {
    let (mut world, built) = common::build(&shapes::icosphere(1));
    let mesh = built.mesh;
    let other = pappus::mesh::build_mesh(&mut world, &shapes::tetrahedron(), Default::default())
        .unwrap()
        .mesh;
    let members = MeshMembers::collect(&world, mesh);
    let foreign = MeshMembers::collect(&world, other);
    let (h, v, f) = (members.halfedges[0], members.vertices[0], members.faces[0]);
    let mut edit = RawEdit::new(&mut world, mesh);
    let not_in = |x: ElementId| Err(RawEditError::NotInMesh(x));
    assert_eq!(
        edit.set_next(h, foreign.halfedges[0]),
        not_in(foreign.halfedges[0].into())
    );
    // A vertex where a halfedge belongs is not this mesh's halfedge.
    let v_as_h = pappus::mesh::HalfedgeId(v.0);
    assert_eq!(edit.set_twin(h, v_as_h), not_in(v_as_h.into()));
    assert!(matches!(
        edit.set_position(v, Vec3::NAN),
        Err(RawEditError::NotFinite(x, _)) if x == v.into()
    ));
    edit.remove(f).unwrap();
    assert_eq!(edit.set_face(h, Some(f)), not_in(f.into()));
    assert_eq!(edit.remove(f), not_in(f.into()));
    edit.rollback();
    pappus::mesh::validate(&world, mesh).expect("untouched");
}

/// The rules that count (two halfedges an edge, a face's loop all its halfedges), broken by
/// hand: each named, each rolled back.
#[test]
fn the_counting_rules_are_caught() {
    let (mut world, built) = common::build(&shapes::icosphere(1));
    let mesh = built.mesh;
    let m = MeshRef::new(&world);
    let members = MeshMembers::collect(&world, mesh);
    // Two edges' halfedge pairs on one edge, the other edge removed.
    let (e1, e2) = (members.edges[0], members.edges[40]);
    let (h, t) = (m.edge_halfedge(e2), m.twin(m.edge_halfedge(e2)));
    // The three halfedges of one face made another's, that face removed.
    let (f, g) = (members.faces[0], members.faces[30]);
    let loop_of_g: Vec<_> = m.face_halfedges(g).collect();
    let before = common::snapshot(&mut world, mesh);
    let mut edit = RawEdit::new(&mut world, mesh);
    edit.set_edge(h, e1).unwrap();
    edit.set_edge(t, e1).unwrap();
    edit.remove(e2).unwrap();
    let Err(RawEditError::Invalid(invalid)) = edit.commit() else {
        panic!("an edge of four halfedges commits");
    };
    assert_eq!(
        (invalid.element, invalid.rule),
        (e1.into(), Rule::EdgeNotTwoHalfedges)
    );
    let mut edit = RawEdit::new(&mut world, mesh);
    for &x in &loop_of_g {
        edit.set_face(x, Some(f)).unwrap();
    }
    edit.remove(g).unwrap();
    let Err(RawEditError::Invalid(invalid)) = edit.commit() else {
        panic!("a face claimed by six halfedges commits");
    };
    assert_eq!(
        (invalid.element, invalid.rule),
        (f.into(), Rule::FaceLoopIncomplete)
    );
    assert_eq!(common::snapshot(&mut world, mesh), before);
}

/// A small deterministic generator (xorshift64*).
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) % n.max(1) as u64) as usize
    }
}

/// Rewires the elements around a random edge at random, a few links at a time, and commits:
/// the commit's check of what the edit touched agrees with the whole mesh's check every time
/// (valid edits stand and leave a valid mesh; invalid ones leave the world as it was).
#[test]
fn the_edits_check_agrees_with_the_whole_meshs_on_random_rewiring() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let (mut valid, mut invalid) = (0, 0);
    for soup in [
        shapes::icosphere(1),
        shapes::grid(4, 4),
        shapes::quad_grid(3, 3),
    ] {
        let (mut world, built) = common::build(&soup);
        let mesh = built.mesh;
        for _ in 0..400 {
            let members = MeshMembers::collect(&world, mesh);
            let e = members.edges[rng.below(members.edges.len())];
            let m = MeshRef::new(&world);
            let h0 = m.edge_halfedge(e);
            let mut hs: Vec<_> = [h0, m.twin(h0)]
                .into_iter()
                .flat_map(|h| {
                    let mut around = vec![h, m.next(h), m.prev(h)];
                    around.extend([m.twin(m.next(h)), m.twin(m.prev(h))]);
                    around
                })
                .collect();
            hs.dedup();
            let vs: Vec<_> = hs.iter().map(|&h| m.to_vertex(h)).collect();
            let es: Vec<_> = hs.iter().map(|&h| m.edge(h)).collect();
            let fs: Vec<_> = hs.iter().filter_map(|&h| m.face(h)).collect();
            let interior = !m.is_boundary_edge(e);
            let mut removed = bevy::ecs::entity::EntityHashSet::default();
            let mut edit = RawEdit::new(&mut world, mesh);
            for i in 0..1 + rng.below(3) {
                let h = hs[rng.below(hs.len())];
                let g = hs[rng.below(hs.len())];
                let v = vs[rng.below(vs.len())];
                let ed = es[rng.below(es.len())];
                let f = fs.get(rng.below(fs.len().max(1))).copied();
                // Removed elements are no setter's argument: their refusals are ignored.
                let _ = match rng.below(11) {
                    0 => edit.set_next(h, g),
                    1 => edit.set_twin(h, g),
                    2 => edit.set_to_vertex(h, v),
                    3 => edit.set_edge(h, ed),
                    4 => edit.set_face(h, f.filter(|_| rng.below(3) > 0)),
                    5 => edit.set_vertex_halfedge(v, h),
                    6 => edit.set_edge_halfedge(ed, h),
                    7 => f.map_or(Ok(()), |f| edit.set_face_halfedge(f, h)),
                    8 => {
                        let x: ElementId = match rng.below(4) {
                            0 => h.into(),
                            1 => v.into(),
                            2 => ed.into(),
                            _ => f.map_or(ed.into(), Into::into),
                        };
                        let done = edit.remove(x);
                        if done.is_ok() {
                            removed.insert(x.entity());
                        }
                        done
                    }
                    // A flip by hand, on the mesh as it was (it reads the links it rewires).
                    9 if i == 0 && interior => hand_edits::flip_by_hand(&mut edit, e),
                    // Setting a link to what it is: valid.
                    _ => {
                        let next = MeshRef::new(edit.world()).try_halfedge(h).map(|x| x.next);
                        next.map_or(Ok(()), |n| edit.set_next(h, n))
                    }
                };
            }
            let whole = pappus::mesh::validate_without(edit.world(), mesh, &removed);
            let committed = edit.commit();
            assert_eq!(
                committed.is_ok(),
                whole.is_ok(),
                "{committed:?} / {whole:?}"
            );
            match committed {
                Ok(()) => {
                    pappus::mesh::validate(&world, mesh).unwrap();
                    valid += 1;
                }
                Err(_) => invalid += 1,
            }
        }
    }
    assert!(
        valid > 100 && invalid > 100,
        "{valid} valid, {invalid} invalid"
    );
}
