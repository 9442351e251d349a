//! The editor's logic without a window: shortcuts become requests, requests are applied (or
//! refused with a reason), navigation walks the relations, and a change rebuilds the render
//! copy exactly once. Picking is checked from a ray cast at a known triangle.

mod common;

use bevy::input::ButtonState;
use bevy::input::keyboard::{Key, KeyboardInput, NativeKey};
use bevy::prelude::*;
use pappus::edit::Edit;
use pappus::editor::gestures::picking::pick_in_face;
use pappus::editor::session::requests::{EditOutcome, OutcomeLog, Request};
use pappus::editor::session::selection::{ActiveMesh, SelectMode, Selection};
use pappus::editor::view::render_sync::{RenderOf, RenderStats, TriangleFaces};
use pappus::mesh::ids::ElementId;
use pappus::mesh::{MeshRef, validate};

fn app() -> App {
    common::headless_editor()
}

fn open(app: &mut App, source: &str) {
    app.world_mut().write_message(Request::Open(source.into()));
    app.update();
    let log = app.world().resource::<OutcomeLog>();
    assert!(
        log.entries.last().unwrap().result.is_ok(),
        "{:?}",
        log.entries.last()
    );
}

fn key_event(key: KeyCode, state: ButtonState) -> KeyboardInput {
    KeyboardInput {
        key_code: key,
        logical_key: Key::Unidentified(NativeKey::Unidentified),
        state,
        text: None,
        repeat: false,
        window: Entity::PLACEHOLDER,
    }
}

fn press(app: &mut App, key: KeyCode) {
    for state in [ButtonState::Pressed, ButtonState::Released] {
        app.world_mut().write_message(key_event(key, state));
        app.update();
    }
}

/// Presses `key` while `modifier` is held.
fn press_with(app: &mut App, modifier: KeyCode, key: KeyCode) {
    app.world_mut()
        .write_message(key_event(modifier, ButtonState::Pressed));
    app.update();
    press(app, key);
    app.world_mut()
        .write_message(key_event(modifier, ButtonState::Released));
    app.update();
}

fn last_outcome(app: &App) -> EditOutcome {
    common::last_outcome(app)
}

fn selection(app: &App) -> Option<ElementId> {
    app.world().resource::<Selection>().element
}

fn mesh(app: &App) -> pappus::mesh::MeshId {
    app.world().resource::<ActiveMesh>().0.unwrap()
}

/// An interior edge of the active mesh.
fn some_interior_edge(app: &App) -> pappus::mesh::EdgeId {
    let world = app.world();
    let m = MeshRef::new(world);
    let members = pappus::mesh::MeshMembers::collect(world, mesh(app));
    members
        .edges
        .into_iter()
        .find(|&e| !m.is_boundary_edge(e))
        .unwrap()
}

#[test]
fn opening_a_shape_builds_and_renders_it_once() {
    let mut app = app();
    open(&mut app, "shape:icosphere");
    validate(app.world(), mesh(&app)).unwrap();
    assert_eq!(app.world().resource::<RenderStats>().rebuilds, 1);
    // Frames without changes rebuild nothing.
    app.update();
    app.update();
    assert_eq!(app.world().resource::<RenderStats>().rebuilds, 1);
    let faces = app
        .world_mut()
        .query::<&TriangleFaces>()
        .single(app.world())
        .unwrap()
        .0
        .len();
    assert_eq!(faces, 1280);
}

#[test]
fn a_change_triggers_exactly_one_rebuild() {
    let mut app = app();
    open(&mut app, "shape:cube");
    let before = app.world().resource::<RenderStats>().rebuilds;
    app.world_mut()
        .write_message(Request::Edit(Edit::registered("triangulate").unwrap()));
    app.update();
    assert!(last_outcome(&app).result.is_ok());
    assert_eq!(app.world().resource::<RenderStats>().rebuilds, before + 1);
    app.update();
    assert_eq!(app.world().resource::<RenderStats>().rebuilds, before + 1);
    let tris = app.world().resource::<RenderStats>().last_triangles;
    assert_eq!(tris, 12);
}

#[test]
fn navigation_keys_walk_the_relations() {
    let mut app = app();
    open(&mut app, "shape:torus");
    let e = some_interior_edge(&app);
    app.world_mut()
        .write_message(Request::Select(Some(ElementId::Edge(e))));
    app.update();
    press(&mut app, KeyCode::KeyH);
    let Some(ElementId::Halfedge(h)) = selection(&app) else {
        panic!("H selects the edge's halfedge, got {:?}", selection(&app));
    };
    let (twin, next, prev, tip, face) = {
        let m = MeshRef::new(app.world());
        (
            m.twin(h),
            m.next(h),
            m.prev(h),
            m.to_vertex(h),
            m.face(h).unwrap(),
        )
    };
    press(&mut app, KeyCode::KeyT);
    assert_eq!(selection(&app), Some(ElementId::Halfedge(twin)));
    press(&mut app, KeyCode::KeyT);
    press(&mut app, KeyCode::KeyN);
    assert_eq!(selection(&app), Some(ElementId::Halfedge(next)));
    press(&mut app, KeyCode::KeyP);
    press(&mut app, KeyCode::KeyP);
    assert_eq!(selection(&app), Some(ElementId::Halfedge(prev)));
    press(&mut app, KeyCode::KeyN);
    press(&mut app, KeyCode::KeyF);
    assert_eq!(selection(&app), Some(ElementId::Face(face)));
    app.world_mut()
        .write_message(Request::Select(Some(ElementId::Halfedge(h))));
    app.update();
    press(&mut app, KeyCode::KeyV);
    assert_eq!(selection(&app), Some(ElementId::Vertex(tip)));
    // E goes to the edge from a halfedge (as in Scotty3D); from anything else it extrudes.
    app.world_mut()
        .write_message(Request::Select(Some(ElementId::Halfedge(h))));
    app.update();
    press(&mut app, KeyCode::KeyE);
    assert!(matches!(selection(&app), Some(ElementId::Edge(_))));
    press(&mut app, KeyCode::Escape);
    assert_eq!(selection(&app), None);
}

#[test]
fn mode_keys_change_what_a_click_selects() {
    let mut app = app();
    for (key, mode) in [
        (KeyCode::Digit1, SelectMode::Vertex),
        (KeyCode::Digit2, SelectMode::Edge),
        (KeyCode::Digit3, SelectMode::Face),
        (KeyCode::Digit4, SelectMode::Halfedge),
        (KeyCode::Backquote, SelectMode::Auto),
    ] {
        press(&mut app, key);
        assert_eq!(*app.world().resource::<SelectMode>(), mode);
    }
}

#[test]
fn operation_keys_without_an_edge_are_refused_with_a_reason() {
    let mut app = app();
    open(&mut app, "shape:torus");
    for (modifier, key, why) in [
        (
            Some(KeyCode::AltLeft),
            KeyCode::KeyR,
            "select an edge (or halfedge) first",
        ),
        (
            Some(KeyCode::AltLeft),
            KeyCode::KeyS,
            "select an edge (or halfedge) first",
        ),
        (None, KeyCode::KeyK, "select an edge (or halfedge) first"),
        (
            None,
            KeyCode::KeyC,
            "select an edge (or halfedge) or a face first",
        ),
        (
            None,
            KeyCode::KeyD,
            "select an edge (or halfedge) or a vertex first",
        ),
        (None, KeyCode::KeyE, "select faces (mode 3) first"),
        (None, KeyCode::KeyX, "select elements first"),
        (None, KeyCode::KeyG, "select something to transform first"),
    ] {
        match modifier {
            Some(m) => press_with(&mut app, m, key),
            None => press(&mut app, key),
        }
        let outcome = last_outcome(&app);
        assert_eq!(outcome.result.unwrap_err().to_string(), why, "{key:?}");
    }
}

/// (V, E, F) of the active mesh.
fn counts(app: &App) -> (usize, usize, usize) {
    let s = pappus::mesh::mesh_stats(app.world(), mesh(app));
    (s.vertices, s.edges, s.faces)
}

#[test]
fn each_operation_key_applies_its_operation() {
    let mut app = app();
    open(&mut app, "shape:icosphere");
    let m = mesh(&app);
    // Local edits on the selected edge: each changes the counts as its formula says, and the
    // selection moves to what it made.
    let mut quad = None;
    for (alt, key, verb, (dv, de, df)) in [
        (true, KeyCode::KeyR, "flip", (0, 0, 0)),
        (true, KeyCode::KeyS, "split", (1, 3, 2)),
        (false, KeyCode::KeyC, "collapse", (-1, -3, -2)),
        (false, KeyCode::KeyD, "dissolve", (0, -1, -1)),
        (false, KeyCode::KeyK, "bisect", (1, 1, 0)),
    ] {
        let e = some_interior_edge(&app);
        let ends = MeshRef::new(app.world()).edge_vertices(e);
        app.world_mut()
            .write_message(Request::Select(Some(ElementId::Edge(e))));
        app.update();
        let (v, ed, f) = counts(&app);
        match alt {
            true => press_with(&mut app, KeyCode::AltLeft, key),
            false => press(&mut app, key),
        }
        let outcome = last_outcome(&app);
        assert_eq!(outcome.request, format!("{verb} {}", ElementId::Edge(e)));
        assert!(outcome.result.is_ok(), "{outcome:?}");
        let expected = (
            v.checked_add_signed(dv).unwrap(),
            ed.checked_add_signed(de).unwrap(),
            f.checked_add_signed(df).unwrap(),
        );
        assert_eq!(counts(&app), expected, "{verb}");
        let world = app.world();
        let m = MeshRef::new(world);
        match (verb, selection(&app)) {
            // The flipped edge joins the two vertices opposite the old one.
            ("flip", Some(ElementId::Edge(flipped))) => {
                let (a, b) = m.edge_vertices(flipped);
                assert!(![a, b].contains(&ends.0) && ![a, b].contains(&ends.1));
            }
            ("split", Some(ElementId::Vertex(new))) => assert_eq!(m.valence(new), 4),
            ("bisect", Some(ElementId::Vertex(new))) => assert_eq!(m.valence(new), 2),
            ("collapse", Some(ElementId::Vertex(kept))) => {
                assert!([ends.0, ends.1].contains(&kept));
            }
            ("dissolve", Some(ElementId::Face(merged))) => {
                assert_eq!(m.face_degree(merged), 4);
                quad = Some(merged);
            }
            (_, other) => panic!("{verb} selected {other:?}"),
        }
        validate(world, mesh(&app)).unwrap();
    }
    // J cuts the polygon the dissolve made (a quad, a pentagon if the bisection was beside it).
    let h = MeshRef::new(app.world()).face_halfedge(quad.expect("the dissolve selected its face"));
    app.world_mut()
        .write_message(Request::Select(Some(ElementId::Halfedge(h))));
    app.update();
    let (v, e, f) = counts(&app);
    press(&mut app, KeyCode::KeyJ);
    assert!(
        last_outcome(&app).result.is_ok(),
        "{:?}",
        last_outcome(&app)
    );
    assert_eq!(counts(&app), (v, e + 1, f + 1));
    // The bisection left polygons (Ctrl+T is tested on its own below).
    app.world_mut()
        .write_message(Request::Edit(Edit::registered("triangulate").unwrap()));
    app.update();
    // Whole-mesh edits: Loop quadruples the triangles, Catmull–Clark makes a quad of every
    // corner, M remeshes to a valid triangle mesh, each recorded as one undo step.
    let (v, e, f) = counts(&app);
    press(&mut app, KeyCode::KeyL);
    assert_eq!(counts(&app), (v + e, 2 * e + 3 * f, 4 * f));
    press(&mut app, KeyCode::KeyM);
    assert!(last_outcome(&app).request.starts_with("remesh"));
    assert!(
        last_outcome(&app).result.is_ok(),
        "{:?}",
        last_outcome(&app)
    );
    let s = pappus::mesh::mesh_stats(app.world(), m);
    assert_eq!(s.face_sizes.keys().copied().collect::<Vec<_>>(), [3]);
    assert_eq!(s.euler_characteristic, 2);
    let (v, e, f) = counts(&app);
    press(&mut app, KeyCode::KeyQ);
    assert_eq!(counts(&app), (v + e + f, 2 * e + 3 * f, 3 * f));
    press(&mut app, KeyCode::KeyM);
    assert!(
        last_outcome(&app).result.is_err(),
        "remeshing quads is refused"
    );
    // O smooths the quads in place: the counts stay.
    let before = counts(&app);
    press(&mut app, KeyCode::KeyO);
    assert!(last_outcome(&app).request.starts_with("smooth"));
    assert!(
        last_outcome(&app).result.is_ok(),
        "{:?}",
        last_outcome(&app)
    );
    assert_eq!(counts(&app), before);
    let history = app
        .world()
        .resource::<pappus::editor::session::history::UndoHistory>()
        .undo_entries()
        .len();
    assert_eq!(history, 11, "one undo step per applied edit");
    validate(app.world(), m).unwrap();
}

#[test]
fn triangulate_key_needs_ctrl_and_applies() {
    let mut app = app();
    open(&mut app, "shape:cube");
    app.world_mut()
        .resource_mut::<ButtonInput<KeyCode>>()
        .press(KeyCode::ControlLeft);
    app.world_mut().write_message(KeyboardInput {
        key_code: KeyCode::ControlLeft,
        logical_key: Key::Control,
        state: ButtonState::Pressed,
        text: None,
        repeat: false,
        window: Entity::PLACEHOLDER,
    });
    press(&mut app, KeyCode::KeyT);
    let outcome = last_outcome(&app);
    assert!(outcome.request.starts_with("triangulate"), "{outcome:?}");
    let s = pappus::mesh::mesh_stats(app.world(), mesh(&app));
    assert_eq!((s.faces, s.face_sizes.get(&3).copied()), (12, Some(12)));
}

/// Alt+N turns every face round (Blender's Flip Normals): the counts stay, each face's normal
/// points the other way; Shift+N (Recalculate Outside) turns the inside-out cube back; Alt+C
/// (a key only the normalize operation's declaration names) centres and fits it; and undo
/// walks it all back.
#[test]
fn reverse_key_turns_every_face_round_and_undoes() {
    let mut app = app();
    open(&mut app, "shape:cube");
    let m = mesh(&app);
    let normals = |app: &App| -> Vec<Vec3> {
        let world = app.world();
        let r = MeshRef::new(world);
        pappus::mesh::MeshMembers::collect(world, m)
            .faces
            .iter()
            .map(|&f| r.face_area_vector(f))
            .collect()
    };
    let undo_steps = |app: &App| {
        app.world()
            .resource::<pappus::editor::session::history::UndoHistory>()
            .undo_entries()
            .len()
    };
    let (before, counts_before, steps_before) = (normals(&app), counts(&app), undo_steps(&app));
    press_with(&mut app, KeyCode::AltLeft, KeyCode::KeyN);
    let outcome = last_outcome(&app);
    assert_eq!(outcome.request, "reverse orientation");
    assert_eq!(outcome.result.ok().as_deref(), Some("6 faces turned round"));
    assert_eq!(counts(&app), counts_before);
    for (now, then) in normals(&app).iter().zip(&before) {
        assert!((*now + *then).length() < 1e-6, "{now} {then}");
    }
    validate(app.world(), m).unwrap();
    // Shift+N turns the inside-out cube back outward: the same links, so the same normals.
    press_with(&mut app, KeyCode::ShiftLeft, KeyCode::KeyN);
    let outcome = last_outcome(&app);
    assert_eq!(outcome.request, "orient outside");
    assert_eq!(
        outcome.result.ok().as_deref(),
        Some("1 of 1 part turned outward (6 faces turned round)")
    );
    assert_eq!(normals(&app), before);
    press_with(&mut app, KeyCode::ShiftLeft, KeyCode::KeyN);
    assert_eq!(
        last_outcome(&app).result.ok().as_deref(),
        Some("no part faces inward (1 part)")
    );
    // Alt+C, declared by the normalize operation alone: the box centred, its longest side 1.
    press_with(&mut app, KeyCode::AltLeft, KeyCode::KeyC);
    let outcome = last_outcome(&app);
    assert_eq!(outcome.request, "normalize (size 1)");
    assert!(outcome.result.as_ref().unwrap().starts_with("centred"));
    let (lo, hi) = {
        let r = MeshRef::new(app.world());
        pappus::mesh::MeshMembers::collect(app.world(), m)
            .vertices
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(r.position(v)), hi.max(r.position(v)))
            })
    };
    assert!(((lo + hi) / 2.0).length() < 1e-6 && ((hi - lo).max_element() - 1.0).abs() < 1e-6);
    for _ in steps_before..undo_steps(&app) {
        app.world_mut().write_message(Request::Undo);
        app.update();
    }
    assert_eq!(normals(&app), before);
}

#[test]
fn stale_and_bad_requests_are_refused_and_change_nothing() {
    let mut app = app();
    open(&mut app, "shape:cube");
    let stale = ElementId::Vertex(pappus::mesh::VertexId(
        Entity::from_raw_u32(999_999).unwrap(),
    ));
    app.world_mut().write_message(Request::Select(Some(stale)));
    app.update();
    assert!(last_outcome(&app).result.is_err());
    assert_eq!(selection(&app), None);
    app.world_mut()
        .write_message(Request::Open("/nonexistent/mesh.obj".into()));
    app.update();
    assert!(last_outcome(&app).result.is_err());
    // The cube is still there.
    assert_eq!(pappus::mesh::mesh_stats(app.world(), mesh(&app)).faces, 6);
}

#[test]
fn picking_maps_a_triangle_hit_to_the_right_element() {
    let mut app = app();
    open(&mut app, "shape:quad-grid");
    let world = app.world_mut();
    let (render, faces) = world
        .query::<(&RenderOf, &TriangleFaces)>()
        .single(world)
        .map(|(r, t)| (*r, t.0.clone()))
        .unwrap();
    let _ = render;
    // Quads are fanned into two triangles; both map back to the same quad.
    assert_eq!(faces.len(), 200);
    assert_eq!(faces[0], faces[1]);
    let face = faces[0];
    let m = MeshRef::new(app.world());
    // A top-down orthographic view: x, y scaled to pixels.
    let to_screen = |p: Vec3| Some(Vec2::new(p.x * 1000.0, p.y * 1000.0));
    let corners: Vec<_> = m.face_vertices(face).collect();
    let p0 = m.position(corners[0]);
    let centre = m.face_centroid(face);
    let screen = |p: Vec3| Vec2::new(p.x * 1000.0, p.y * 1000.0);
    // Near a corner: that vertex.
    let near_corner = screen(p0.lerp(centre, 0.05));
    assert_eq!(
        pick_in_face(&m, face, near_corner, SelectMode::Auto, to_screen),
        ElementId::Vertex(corners[0])
    );
    // Near the middle of a side: that edge.
    let side_mid = (m.position(corners[0]) + m.position(corners[1])) / 2.0;
    let picked = pick_in_face(
        &m,
        face,
        screen(side_mid.lerp(centre, 0.05)),
        SelectMode::Auto,
        to_screen,
    );
    let expected = m.edge(m.find_halfedge(corners[0], corners[1]).unwrap());
    assert_eq!(picked, ElementId::Edge(expected));
    // Near the fan diagonal, in the middle of the quad: the quad, not a phantom edge.
    let diagonal_mid = (m.position(corners[0]) + m.position(corners[2])) / 2.0;
    assert_eq!(
        pick_in_face(&m, face, screen(diagonal_mid), SelectMode::Auto, to_screen),
        ElementId::Face(face)
    );
    // Modes force the kind.
    assert_eq!(
        pick_in_face(&m, face, screen(diagonal_mid), SelectMode::Face, to_screen),
        ElementId::Face(face)
    );
    assert!(matches!(
        pick_in_face(
            &m,
            face,
            screen(diagonal_mid),
            SelectMode::Vertex,
            to_screen
        ),
        ElementId::Vertex(_)
    ));
    assert!(matches!(
        pick_in_face(&m, face, screen(centre), SelectMode::Halfedge, to_screen),
        ElementId::Halfedge(h) if m.face(h) == Some(face)
    ));
}

#[test]
fn a_ray_cast_at_a_known_triangle_finds_its_face() {
    use bevy::ecs::system::RunSystemOnce;
    use bevy::picking::mesh_picking::ray_cast::{
        MeshRayCast, MeshRayCastSettings, RayCastVisibility,
    };
    let mut app = app();
    app.add_plugins(TransformPlugin);
    app.update();
    open(&mut app, "shape:quad-grid");
    // Bounds are normally computed by the camera plugin; add them for the headless cast.
    let render = app
        .world_mut()
        .query_filtered::<Entity, With<RenderOf>>()
        .single(app.world())
        .unwrap();
    let handle = app.world().get::<Mesh3d>(render).unwrap().0.clone();
    let aabb = {
        use bevy::camera::primitives::MeshAabb;
        app.world()
            .resource::<Assets<Mesh>>()
            .get(&handle)
            .unwrap()
            .compute_aabb()
            .unwrap()
    };
    app.world_mut().entity_mut(render).insert(aabb);
    app.update();
    // Straight down onto the point (0.25, 0.35): grid cell (2, 3) of the 10×10 grid.
    let hit = app
        .world_mut()
        .run_system_once(|mut ray_cast: MeshRayCast| {
            let ray = Ray3d::new(Vec3::new(0.25, 0.35, 5.0), Dir3::NEG_Z);
            let settings = MeshRayCastSettings::default().with_visibility(RayCastVisibility::Any);
            ray_cast
                .cast_ray(ray, &settings)
                .first()
                .map(|(e, h)| (*e, h.triangle_index))
        })
        .unwrap();
    let (entity, triangle) = hit.expect("the ray hits the grid");
    assert_eq!(entity, render);
    let face = app.world().get::<TriangleFaces>(render).unwrap().0[triangle.unwrap()];
    let m = MeshRef::new(app.world());
    let c = m.face_centroid(face);
    assert!(
        (c.x - 0.25).abs() < 1e-5 && (c.y - 0.35).abs() < 1e-5,
        "centroid {c}"
    );
}

/// Every live face is drawn by exactly one chunk, once per triangle it fans into.
fn assert_every_face_drawn_once(app: &mut App) {
    let drawn: Vec<pappus::mesh::FaceId> = app
        .world_mut()
        .query::<&TriangleFaces>()
        .iter(app.world())
        .flat_map(|t| t.0.iter().copied())
        .collect();
    let members = pappus::mesh::MeshMembers::collect(app.world(), mesh(app));
    let m = MeshRef::new(app.world());
    let expected: usize = members.faces.iter().map(|&f| m.face_degree(f) - 2).sum();
    assert_eq!(drawn.len(), expected);
    let mut distinct = drawn.clone();
    distinct.sort();
    distinct.dedup();
    assert_eq!(distinct.len(), members.faces.len());
}

#[test]
fn local_edits_redraw_only_the_chunks_they_touch() {
    use pappus::editor::view::render_sync::CHUNK_FACES;
    let mut app = app();
    open(&mut app, "shape:icosphere:6");
    let chunks = app
        .world_mut()
        .query::<&TriangleFaces>()
        .iter(app.world())
        .count();
    assert_eq!(chunks, 81920usize.div_ceil(CHUNK_FACES));
    assert_every_face_drawn_once(&mut app);
    for name in ["flip", "split", "collapse", "dissolve"] {
        let e = some_interior_edge(&app);
        let before = app.world().resource::<RenderStats>().rebuilds;
        app.world_mut()
            .write_message(Request::Edit(Edit::local(name, e)));
        app.update();
        assert!(
            last_outcome(&app).result.is_ok(),
            "{:?}",
            last_outcome(&app)
        );
        let stats = app.world().resource::<RenderStats>();
        assert_eq!(stats.rebuilds, before + 1);
        // At most the chunks of a few neighbouring faces were redrawn, never the whole sphere.
        assert!(
            stats.last_triangles <= 2 * 2 * CHUNK_FACES,
            "{}",
            stats.last_triangles
        );
        assert_every_face_drawn_once(&mut app);
    }
}

#[test]
fn a_chunk_left_without_faces_draws_no_mesh() {
    use pappus::editor::session::requests::SelectionEdit;
    use pappus::editor::view::render_sync::{ChunkFaces, RenderChunks};
    let mut app = app();
    // 17 000 faces: a full chunk and one of 616.
    open(&mut app, "shape:torus:170:100");
    let chunks = |app: &App| {
        let chunks = app.world().get::<RenderChunks>(mesh(app).0).unwrap();
        chunks.chunks.clone()
    };
    let drawn = chunks(&app);
    assert_eq!(drawn.len(), 2);
    let faces = &app.world().get::<ChunkFaces>(drawn[1]).unwrap().0;
    let faces: Vec<ElementId> = faces.iter().map(|&f| ElementId::Face(f)).collect();
    press(&mut app, KeyCode::Digit3);
    app.world_mut()
        .write_message(Request::Selection(SelectionEdit::Replace(faces)));
    app.update();
    press(&mut app, KeyCode::KeyX);
    let outcome = last_outcome(&app);
    assert!(outcome.result.is_ok(), "{outcome:?}");
    // The same chunks: the emptied one has nothing to draw and no mesh asset.
    assert_eq!(chunks(&app), drawn);
    let world = app.world();
    assert!(world.get::<TriangleFaces>(drawn[1]).unwrap().0.is_empty());
    assert!(world.get::<Mesh3d>(drawn[1]).is_none());
    assert!(world.get::<Mesh3d>(drawn[0]).is_some());
    assert_every_face_drawn_once(&mut app);
}

#[test]
fn a_change_of_looks_redraws_the_mesh_and_keeps_what_changed_its_chunks() {
    use pappus::editor::view::render_sync::RenderChunks;
    let mut app = app();
    open(&mut app, "shape:icosphere");
    let changes = |app: &App| {
        app.world()
            .get::<RenderChunks>(mesh(app).0)
            .unwrap()
            .changes
    };
    let opened = changes(&app);
    assert_eq!(opened.whole, 1);
    let smooth = |app: &mut App| {
        let chunk = app.world().get::<RenderChunks>(mesh(app).0).unwrap().chunks[0];
        let handle = app.world().get::<Mesh3d>(chunk).unwrap().0.clone();
        let meshes = app.world().resource::<Assets<Mesh>>();
        meshes
            .get(&handle)
            .unwrap()
            .attribute(Mesh::ATTRIBUTE_NORMAL)
            .is_some()
    };
    assert!(!smooth(&mut app));
    // Smooth shading: drawn anew with normals, the chunks' record of changes as it was.
    press(&mut app, KeyCode::KeyZ);
    assert_eq!(app.world().resource::<RenderStats>().rebuilds, 2);
    assert!(smooth(&mut app));
    assert_eq!(changes(&app), opened);
    // A local edit in the same frame as a change of looks: one redraw, of the whole.
    let e = some_interior_edge(&app);
    app.world_mut()
        .write_message(Request::Edit(Edit::local("flip", e)));
    app.world_mut()
        .write_message(key_event(KeyCode::KeyZ, ButtonState::Pressed));
    app.update();
    assert!(
        last_outcome(&app).result.is_ok(),
        "{:?}",
        last_outcome(&app)
    );
    assert!(!smooth(&mut app));
    assert_eq!(app.world().resource::<RenderStats>().rebuilds, 3);
    assert_eq!((changes(&app).whole, changes(&app).drawn), (3, 3));
    app.world_mut()
        .write_message(key_event(KeyCode::KeyZ, ButtonState::Released));
    app.update();
    // An edit redrawn whole is a change of the whole.
    app.world_mut()
        .write_message(Request::Edit(Edit::registered("loop").unwrap()));
    app.update();
    assert!(
        last_outcome(&app).result.is_ok(),
        "{:?}",
        last_outcome(&app)
    );
    let rebuilds = app.world().resource::<RenderStats>().rebuilds;
    assert_eq!(changes(&app).whole, rebuilds);
}

/// A move of most of the mesh (an ARAP frame) keeps the chunks and their triangles and
/// refreshes their positions; a topological edit in the same frame is drawn too.
#[test]
fn a_move_of_most_of_the_mesh_refreshes_positions_in_the_chunks_it_has() {
    use pappus::editor::view::render_data::ChunkVertices;
    let mut app = app();
    open(&mut app, "shape:icosphere:6");
    let chunk_entities = |app: &mut App| -> Vec<Entity> {
        let mut e: Vec<Entity> = app
            .world_mut()
            .query_filtered::<Entity, With<TriangleFaces>>()
            .iter(app.world())
            .collect();
        e.sort();
        e
    };
    let before = chunk_entities(&mut app);
    let vertices = pappus::mesh::MeshMembers::collect(app.world(), mesh(&app)).vertices;
    let moves: Vec<_> = {
        let m = MeshRef::new(app.world());
        vertices.iter().map(|&v| (v, m.position(v) * 2.0)).collect()
    };
    app.world_mut()
        .write_message(Request::Edit(Edit::Move(moves)));
    app.update();
    assert!(last_outcome(&app).result.is_ok());
    assert_eq!(chunk_entities(&mut app), before, "the same chunks");
    assert_every_face_drawn_once(&mut app);
    // Every render vertex is where its mesh vertex now is.
    let drawn: Vec<(Vec<[f32; 3]>, Vec<pappus::mesh::VertexId>)> = app
        .world_mut()
        .query::<(&Mesh3d, &ChunkVertices)>()
        .iter(app.world())
        .map(|(handle, vertices)| {
            let meshes = app.world().resource::<Assets<Mesh>>();
            let positions = meshes
                .get(&handle.0)
                .unwrap()
                .attribute(Mesh::ATTRIBUTE_POSITION)
                .unwrap()
                .as_float3()
                .unwrap()
                .to_vec();
            (positions, vertices.0.clone())
        })
        .collect();
    let m = MeshRef::new(app.world());
    for (positions, vertices) in drawn {
        for (p, v) in positions.iter().zip(vertices) {
            assert_eq!(*p, m.position(v).to_array());
        }
    }
    // A flip and a move of everything in one frame: both drawn.
    let e = some_interior_edge(&app);
    let moves: Vec<_> = {
        let m = MeshRef::new(app.world());
        vertices.iter().map(|&v| (v, m.position(v) * 0.5)).collect()
    };
    app.world_mut()
        .write_message(Request::Edit(Edit::local("flip", e)));
    app.world_mut()
        .write_message(Request::Edit(Edit::Move(moves)));
    app.update();
    assert_every_face_drawn_once(&mut app);
}

#[test]
fn dragging_the_selected_vertex_moves_it_in_the_view_plane() {
    use bevy::input::mouse::{MouseButton, MouseButtonInput};
    use bevy::window::PrimaryWindow;
    use pappus::editor::EditorSystems;
    use pappus::editor::gestures::drag::{VertexDrag, drive_vertex_drag};
    // Looking straight down -z at the unit quad grid in the z = 0 plane.
    let mut app = app_with_camera();
    app.init_resource::<VertexDrag>();
    app.add_systems(Update, drive_vertex_drag.in_set(EditorSystems::Input));
    app.update();
    open(&mut app, "shape:quad-grid");
    let vertices = pappus::mesh::MeshMembers::collect(app.world(), mesh(&app)).vertices;
    let v = vertices[5 * 11 + 5]; // (0.5, 0.5)
    app.world_mut()
        .write_message(Request::Select(Some(ElementId::Vertex(v))));
    app.update();
    let start = MeshRef::new(app.world()).position(v);
    let (camera, transform) = app
        .world_mut()
        .query::<(&Camera, &GlobalTransform)>()
        .single(app.world())
        .map(|(c, t)| (c.clone(), *t))
        .unwrap();
    let on_screen = camera.world_to_viewport(&transform, start).unwrap();
    let window = app
        .world_mut()
        .query_filtered::<Entity, With<PrimaryWindow>>()
        .single(app.world())
        .unwrap();
    let cursor = |app: &mut App, p: Vec2| {
        app.world_mut()
            .get_mut::<Window>(window)
            .unwrap()
            .set_cursor_position(Some(p));
    };
    cursor(&mut app, on_screen);
    app.world_mut().write_message(MouseButtonInput {
        button: MouseButton::Left,
        state: ButtonState::Pressed,
        window,
    });
    app.update();
    cursor(&mut app, on_screen + Vec2::new(40.0, 0.0));
    app.update();
    app.update();
    app.world_mut().write_message(MouseButtonInput {
        button: MouseButton::Left,
        state: ButtonState::Released,
        window,
    });
    app.update();
    let end = MeshRef::new(app.world()).position(v);
    assert!(end.x > start.x + 0.01, "{start} → {end}");
    assert!(
        (end.y - start.y).abs() < 1e-4 && end.z.abs() < 1e-4,
        "{start} → {end}"
    );
    validate(app.world(), mesh(&app)).unwrap();
    // Moving the pointer after the release moves nothing.
    cursor(&mut app, on_screen + Vec2::new(80.0, 0.0));
    app.update();
    assert_eq!(MeshRef::new(app.world()).position(v), end);
}

/// The editor's logic with a camera looking down at the z = 0 plane (a gesture needs one).
fn app_with_camera() -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        bevy::input::InputPlugin,
        WindowPlugin::default(),
        AssetPlugin::default(),
        bevy::image::ImagePlugin::default(),
        bevy::mesh::MeshPlugin,
        bevy::camera::CameraPlugin,
        bevy::render::camera::CameraPlugin,
        TransformPlugin,
        pappus::editor::EditorLogicPlugin,
    ));
    app.init_resource::<bevy::render::texture::ManualTextureViews>();
    app.world_mut().spawn((
        Camera3d::default(),
        Transform::from_xyz(0.5, 0.5, 2.0).looking_at(Vec3::new(0.5, 0.5, 0.0), Vec3::Y),
    ));
    app.update();
    app.update();
    app
}

#[test]
fn a_proportional_move_takes_each_vertex_by_its_falloff() {
    use pappus::editor::session::panel_state::UiState;
    use pappus::ops::deform::{Falloff, Proportional};
    use pappus::ops::named::Named;
    let radius = 0.35;
    for &(falloff, name) in Falloff::ALL {
        let mut app = app_with_camera();
        open(&mut app, "shape:quad-grid");
        let vertices = pappus::mesh::MeshMembers::collect(app.world(), mesh(&app)).vertices;
        let centre = vertices[5 * 11 + 5]; // (0.5, 0.5)
        let before: Vec<Vec3> = {
            let m = MeshRef::new(app.world());
            vertices.iter().map(|&v| m.position(v)).collect()
        };
        app.world_mut()
            .write_message(Request::Select(Some(ElementId::Vertex(centre))));
        app.update();
        app.world_mut().resource_mut::<UiState>().proportional = Proportional {
            enabled: true,
            falloff,
            radius,
            connected: false,
        };
        // G, 0.1 typed (along X), Enter.
        for key in [
            KeyCode::KeyG,
            KeyCode::Digit0,
            KeyCode::Period,
            KeyCode::Digit1,
            KeyCode::Enter,
        ] {
            press(&mut app, key);
        }
        let m = MeshRef::new(app.world());
        let pivot = before[5 * 11 + 5];
        for (i, &v) in vertices.iter().enumerate() {
            let d = before[i].distance(pivot);
            let w = if v == centre {
                1.0
            } else {
                falloff.weight(d, radius)
            };
            let want = before[i] + Vec3::X * 0.1 * w;
            let got = m.position(v);
            assert!(
                (got - want).length() < 1e-6,
                "{name}: vertex {i} at {d}: {got} vs {want}"
            );
        }
        // Some vertex beside the centre moved, one past the radius did not.
        assert!(
            m.position(vertices[5 * 11 + 6]) != before[5 * 11 + 6],
            "{name}"
        );
        assert_eq!(m.position(vertices[0]), before[0]);
        let undo = app
            .world()
            .resource::<pappus::editor::session::history::UndoHistory>()
            .undo_entries()
            .len();
        assert_eq!(undo, 1, "{name}: one undo step");
    }
}

#[test]
fn a_move_of_a_handle_with_anchors_marked_deforms_the_mesh_in_one_undo_step() {
    let mut app = app_with_camera();
    // The left column holds; the right column is the handle, lifted 0.1 along Z.
    let (vertices, before) = grid_with_anchors_and_handle(&mut app);
    lift_handle(&mut app);
    let r = MeshRef::new(app.world());
    for (i, &v) in vertices.iter().enumerate() {
        let p = r.position(v);
        if before[i].x == 0.0 {
            assert_eq!(p, before[i], "anchor {i}");
        } else if before[i].x == 1.0 {
            assert_eq!(p, before[i] + Vec3::Z * 0.1, "handle {i}");
        } else {
            assert!(p.z > 0.0 && p.z < 0.1, "vertex {i} at {}: {p}", before[i]);
        }
    }
    // Higher toward the handle.
    let at = |x: f32, y: f32| {
        let i = (0..vertices.len())
            .find(|&i| (before[i] - Vec3::new(x, y, 0.0)).length() < 1e-6)
            .unwrap();
        r.position(vertices[i]).z
    };
    assert!(at(0.3, 0.5) < at(0.7, 0.5));
    let undo = app
        .world()
        .resource::<pappus::editor::session::history::UndoHistory>()
        .undo_entries()
        .len();
    assert_eq!(undo, 1, "one undo step");
    // The panel's row: the iterations run (one a frame, ten more on Enter) and the energy.
    let progress = app
        .world()
        .resource::<pappus::editor::gestures::handle_deform::Anchors>()
        .progress
        .expect("an ARAP gesture reports its progress");
    assert!(progress.iterations > pappus::editor::gestures::handle_deform::FINAL_ITERATIONS);
    assert!(progress.energy.is_finite() && progress.energy > 0.0);
    press_with(&mut app, KeyCode::ControlLeft, KeyCode::KeyZ);
    let r = MeshRef::new(app.world());
    for (i, &v) in vertices.iter().enumerate() {
        assert_eq!(r.position(v), before[i]);
    }
}

/// `G`, `Z`, 0.1 typed, Enter: the selection moved 0.1 along Z.
fn lift_handle(app: &mut App) {
    for key in [
        KeyCode::KeyG,
        KeyCode::KeyZ,
        KeyCode::Digit0,
        KeyCode::Period,
        KeyCode::Digit1,
        KeyCode::Enter,
    ] {
        press(app, key);
    }
}

/// The quad grid opened with its left column as anchors and its right column selected (the
/// handle); the vertices and their rest positions.
fn grid_with_anchors_and_handle(app: &mut App) -> (Vec<pappus::mesh::VertexId>, Vec<Vec3>) {
    use pappus::editor::session::requests::SelectionEdit;
    open(app, "shape:quad-grid");
    let vertices = pappus::mesh::MeshMembers::collect(app.world(), mesh(app)).vertices;
    let before: Vec<Vec3> = {
        let r = MeshRef::new(app.world());
        vertices.iter().map(|&v| r.position(v)).collect()
    };
    let column = |x: f32| -> Vec<ElementId> {
        (0..vertices.len())
            .filter(|&i| (before[i].x - x).abs() < 1e-6)
            .map(|i| ElementId::Vertex(vertices[i]))
            .collect()
    };
    app.world_mut()
        .write_message(Request::from(SelectionEdit::Replace(column(0.0))));
    app.update();
    press_with(app, KeyCode::ShiftLeft, KeyCode::KeyA);
    let anchored = last_outcome(app).result.unwrap();
    assert!(anchored.starts_with("11 anchor vertices"), "{anchored}");
    app.world_mut()
        .write_message(Request::from(SelectionEdit::Replace(column(1.0))));
    app.update();
    (vertices, before)
}

#[test]
fn in_step_mode_an_arap_handle_drag_steps_an_iteration_at_a_time_and_ends_as_the_deformation() {
    use pappus::editor::gestures::handle_deform::STEPPED_ITERATIONS;
    use pappus::editor::pipeline::stepping::Stepping;
    use pappus::ops::deform::DeformSteps;
    use pappus::ops::deform::{DeformMethod, DeformParams};
    let mut app = app_with_camera();
    let (vertices, before) = grid_with_anchors_and_handle(&mut app);
    let positions = |app: &App| -> Vec<Vec3> {
        let r = MeshRef::new(app.world());
        vertices.iter().map(|&v| r.position(v)).collect()
    };
    press(&mut app, KeyCode::F9);
    lift_handle(&mut app);
    app.update();
    let run_at = |app: &App| {
        let run = app
            .world()
            .resource::<Stepping>()
            .run
            .as_ref()
            .expect("a run");
        (run.steps.at(), run.steps.made())
    };
    // Iteration 0: the gesture's move taken back, the handle placed, the rest as it was.
    assert_eq!(run_at(&app), (0, STEPPED_ITERATIONS as usize));
    let undo = |app: &App| {
        app.world()
            .resource::<pappus::editor::session::history::UndoHistory>()
            .undo_entries()
            .len()
    };
    assert_eq!(undo(&app), 0, "the gesture's move was taken back");
    let at_start = positions(&app);
    for (i, p) in at_start.iter().enumerate() {
        let expected = match before[i].x == 1.0 {
            true => before[i] + Vec3::Z * 0.1,
            false => before[i],
        };
        assert_eq!(*p, expected, "vertex {i} at iteration 0");
    }
    // Three steps: each an iteration, the energy falling, each free vertex's rotation drawn.
    for _ in 0..3 {
        press(&mut app, KeyCode::ArrowRight);
    }
    assert_eq!(run_at(&app).0, 3);
    let (energies, at_three, frames) = {
        let run = app.world().resource::<Stepping>().run.as_ref().unwrap();
        let d = run
            .steps
            .downcast_ref::<DeformSteps>()
            .expect("a deformation run");
        let energies: Vec<f64> = d.iterations.iter().map(|i| i.energy).collect();
        (
            energies,
            d.iterations[3].positions.clone(),
            d.frames().count(),
        )
    };
    assert_eq!(energies.len(), 4);
    assert!(energies.windows(2).all(|w| w[1] <= w[0]), "{energies:?}");
    let free = vertices.len() - 2 * 11;
    assert_eq!(frames, free, "a rotation for every free vertex");
    let drawn = app
        .world()
        .resource::<pappus::editor::gestures::overlay::Overlay>()
        .shapes
        .iter()
        .filter(|s| matches!(s, pappus::editor::gestures::overlay::Shape::Line(_, _, c) if pappus::editor::gestures::overlay::AXIS_COLORS.contains(c)))
        .count();
    assert_eq!(drawn, 3 * free, "three axes a frame");
    let after_three = positions(&app);
    assert!(at_three.iter().all(|p| after_three.contains(p)));
    // Back one and forward again: iteration 3 exactly as it was.
    press(&mut app, KeyCode::ArrowLeft);
    assert_eq!(run_at(&app).0, 2);
    assert_ne!(positions(&app), after_three);
    press(&mut app, KeyCode::ArrowRight);
    assert_eq!(positions(&app), after_three);
    // Kept: one undo entry, the mesh the unstepped deformation of three iterations gives.
    press(&mut app, KeyCode::Enter);
    assert!(app.world().resource::<Stepping>().run.is_none());
    assert_eq!(undo(&app), 1);
    let mut whole = app_with_camera();
    let (vertices_whole, _) = grid_with_anchors_and_handle(&mut whole);
    let column = |x: f32| -> Vec<pappus::mesh::VertexId> {
        (0..vertices_whole.len())
            .filter(|&i| (before[i].x - x).abs() < 1e-6)
            .map(|i| vertices_whole[i])
            .collect()
    };
    whole
        .world_mut()
        .write_message(Request::Edit(Edit::Deform(DeformParams {
            method: DeformMethod::Arap,
            fixed: column(0.0),
            handle: column(1.0),
            motion: bevy::math::Affine3A::from_translation(Vec3::Z * 0.1),
            iterations: 3,
        })));
    whole.update();
    let r = MeshRef::new(whole.world());
    let unstepped: Vec<Vec3> = vertices_whole.iter().map(|&v| r.position(v)).collect();
    assert_eq!(
        unstepped, after_three,
        "stepped to 3 = deformed with 3 iterations"
    );
    press_with(&mut app, KeyCode::ControlLeft, KeyCode::KeyZ);
    assert_eq!(positions(&app), before);
}

#[test]
fn hole_and_fairing_keys_fill_and_fair() {
    let mut app = app();
    open(&mut app, "shape:grid-with-holes:2");
    let m = mesh(&app);
    let boundary = {
        let world = app.world();
        let r = MeshRef::new(world);
        pappus::mesh::MeshMembers::collect(world, m)
            .edges
            .into_iter()
            .find(|&e| r.is_boundary_edge(e))
            .unwrap()
    };
    // Alt+F: one hole, faired triangles.
    app.world_mut()
        .write_message(Request::Select(Some(ElementId::Edge(boundary))));
    app.update();
    let loops = pappus::mesh::mesh_stats(app.world(), m).boundary_loops;
    press_with(&mut app, KeyCode::AltLeft, KeyCode::KeyF);
    let outcome = last_outcome(&app);
    assert!(outcome.request.ends_with("(fair)"), "{outcome:?}");
    assert!(outcome.result.is_ok(), "{outcome:?}");
    assert_eq!(
        pappus::mesh::mesh_stats(app.world(), m).boundary_loops,
        loops - 1
    );
    // Shift+F: every other hole, faired (the editor's default).
    press_with(&mut app, KeyCode::ShiftLeft, KeyCode::KeyF);
    let outcome = last_outcome(&app);
    assert_eq!(outcome.request, "fill all holes (fair)");
    assert!(outcome.result.is_ok(), "{outcome:?}");
    let stats = pappus::mesh::mesh_stats(app.world(), m);
    assert!(stats.closed && stats.euler_characteristic == 2, "{stats:?}");
    // Shift+O: fair the selected vertex.
    let v = pappus::mesh::MeshMembers::collect(app.world(), m).vertices[5];
    app.world_mut()
        .write_message(Request::Select(Some(ElementId::Vertex(v))));
    app.update();
    press_with(&mut app, KeyCode::ShiftLeft, KeyCode::KeyO);
    let outcome = last_outcome(&app);
    assert_eq!(outcome.request, format!("fair {v} (k 2)"));
    assert!(outcome.result.is_ok(), "{outcome:?}");
    validate(app.world(), m).unwrap();
}

#[test]
fn shift_s_simplifies_to_the_panel_ratio() {
    let mut app = app();
    open(&mut app, "shape:icosphere");
    app.world_mut().write_message(KeyboardInput {
        key_code: KeyCode::ShiftLeft,
        logical_key: Key::Shift,
        state: ButtonState::Pressed,
        text: None,
        repeat: false,
        window: Entity::PLACEHOLDER,
    });
    app.update();
    press(&mut app, KeyCode::KeyS);
    let outcome = last_outcome(&app);
    assert!(outcome.request.starts_with("simplify"), "{outcome:?}");
    assert!(outcome.result.unwrap().starts_with("1280 -> 640 faces"));
    validate(app.world(), mesh(&app)).unwrap();
}

#[test]
fn level_of_detail_and_vertex_split_follow_the_simplification() {
    use pappus::ops::simplification_history::SimplificationHistory as History;
    let mut app = app();
    open(&mut app, "shape:icosphere");
    let m = mesh(&app);
    app.world_mut()
        .write_message(Request::Edit(Edit::invoked("simplify:0.25").unwrap()));
    app.update();
    assert!(
        last_outcome(&app)
            .result
            .unwrap()
            .starts_with("1280 -> 320 faces")
    );
    // The slider's request: half way up.
    app.world_mut().write_message(Request::Edit(Edit::Operation(
        pappus::ops::decimate::Refine::to(Some(640)),
    )));
    app.update();
    assert!(
        last_outcome(&app)
            .result
            .as_ref()
            .unwrap()
            .ends_with("640 faces")
    );
    assert_eq!(pappus::mesh::mesh_stats(app.world(), m).faces, 640);
    // Splitting a vertex back: only the one the last applied collapse kept.
    let next = {
        let pm = History::of(app.world(), m).unwrap();
        pm.next_split_vertex().unwrap()
    };
    let other = pappus::mesh::MeshMembers::collect(app.world(), m)
        .vertices
        .into_iter()
        .find(|&v| v != next)
        .unwrap();
    app.world_mut()
        .write_message(Request::Edit(Edit::local("vertex-split", other)));
    app.update();
    let refusal = last_outcome(&app).result.unwrap_err().to_string();
    assert!(refusal.contains(&next.to_string()), "{refusal}");
    app.world_mut()
        .write_message(Request::Edit(Edit::local("vertex-split", next)));
    app.update();
    assert!(
        last_outcome(&app).result.is_ok(),
        "{:?}",
        last_outcome(&app)
    );
    assert_eq!(pappus::mesh::mesh_stats(app.world(), m).faces, 642);
    validate(app.world(), m).unwrap();
    // Any other edit ends the history.
    let e = some_interior_edge(&app);
    app.world_mut()
        .write_message(Request::Edit(Edit::local("flip", e)));
    app.update();
    app.world_mut().write_message(Request::Edit(Edit::Operation(
        pappus::ops::decimate::Refine::to(Some(1280)),
    )));
    app.update();
    assert!(last_outcome(&app).result.is_err());
}

#[test]
fn a_save_that_would_drop_the_beasts_uvs_asks_first() {
    let Some(beast) = common::model("beast.obj") else {
        return;
    };
    let mut app = app();
    open(&mut app, beast.to_str().unwrap());
    let target = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("beast-no-uv.off");
    let _ = std::fs::remove_file(&target);
    let save = |app: &mut App| {
        app.world_mut()
            .write_message(Request::Save(Some(target.clone())));
        app.update();
    };
    save(&mut app);
    let asked = last_outcome(&app).result.unwrap_err().to_string();
    assert!(
        asked.contains("beast-no-uv.off: UVs dropped (OFF cannot hold it)"),
        "{asked}"
    );
    assert!(!target.exists(), "nothing is written before the answer");
    app.world_mut()
        .write_message(Request::ConfirmDiscard(false));
    app.update();
    assert!(!target.exists());
    save(&mut app);
    app.world_mut().write_message(Request::ConfirmDiscard(true));
    app.update();
    let saved = last_outcome(&app).result.unwrap();
    assert!(saved.contains("UVs dropped"), "{saved}");
    assert_eq!(pappus::io::read(&target).unwrap().face_count(), 32364);
    // PLY holds the UVs: no question.
    app.world_mut()
        .write_message(Request::Save(Some(target.with_extension("ply"))));
    app.update();
    assert!(last_outcome(&app).result.is_ok());
}

#[test]
fn a_file_dropped_on_the_window_opens() {
    let Some(cube) = common::model("course/cube.dae") else {
        return;
    };
    let mut app = app();
    open(&mut app, "shape:torus");
    app.world_mut()
        .write_message(bevy::window::FileDragAndDrop::DroppedFile {
            window: Entity::PLACEHOLDER,
            path_buf: cube,
        });
    app.update();
    let opened = last_outcome(&app).result.unwrap();
    assert!(opened.contains("cube.dae"), "{opened}");
    assert_eq!(counts(&app), (8, 18, 12));
}

/// A large file (here any: the threshold set to 0) is read on another thread: the window
/// keeps going, edits wait, and the file replaces the mesh when ready, as one undo step; a
/// cancelled read leaves the mesh as it was.
#[test]
fn a_large_file_opens_in_the_background_and_can_be_cancelled() {
    use pappus::editor::pipeline::jobs::JobSettings;
    use pappus::editor::pipeline::opening::Opening;
    let Some(spot) = common::model("spot.obj") else {
        return;
    };
    let mut app = app();
    open(&mut app, "shape:torus");
    let torus = counts(&app);
    app.world_mut().resource_mut::<JobSettings>().min_open_bytes = 0;
    let reading = |app: &App| app.world().resource::<Opening>().0.is_some();
    // Cancelled: the torus stays.
    open(&mut app, spot.to_str().unwrap());
    assert!(reading(&app));
    app.world_mut().write_message(Request::CancelJob);
    app.update();
    assert!(!reading(&app));
    assert_eq!(counts(&app), torus);
    // Read to the end.
    open(&mut app, spot.to_str().unwrap());
    let started = last_outcome(&app).result.unwrap();
    assert!(started.contains("reading in the background"), "{started}");
    let e = some_interior_edge(&app);
    app.world_mut()
        .write_message(Request::Edit(Edit::local("flip", e)));
    app.update();
    if reading(&app) {
        let refused = last_outcome(&app).result.unwrap_err().to_string();
        assert!(refused.contains("open spot.obj"), "{refused}");
    }
    update_until(&mut app, |app| !reading(app));
    // The open's outcome: when the reading ended in the flip's frame, the flip (of an edge of
    // the torus, gone by then) was refused after it.
    let log = &app.world().resource::<OutcomeLog>().entries;
    let opened = log
        .iter()
        .rev()
        .find(|o| o.request.starts_with("open"))
        .expect("the open's outcome")
        .result
        .clone()
        .unwrap();
    assert!(opened.contains("2930 vertices, 5856 faces"), "{opened}");
    assert_eq!(counts(&app), (2930, 8784, 5856));
    app.world_mut().write_message(Request::Undo);
    app.update();
    assert_eq!(counts(&app), torus, "one undo brings the torus back");
}

/// A large mesh's panel figures are read a slice a frame and counted on a thread (the last ones
/// shown meanwhile), and its validity is checked when the panel asks.
#[test]
fn a_large_meshs_figures_are_counted_apart_and_its_validity_when_asked() {
    use pappus::editor::panels::{state::InspectorView, ui::snapshot};
    use pappus::editor::pipeline::jobs::JobSettings;
    let mut app = app();
    app.init_resource::<InspectorView>()
        .add_systems(Update, snapshot.in_set(pappus::editor::EditorSystems::Ui));
    app.world_mut()
        .resource_mut::<JobSettings>()
        .min_faces_figures_apart = 100;
    open(&mut app, "shape:icosphere");
    let view = |app: &App| {
        app.world()
            .resource::<InspectorView>()
            .mesh
            .clone()
            .unwrap()
    };
    update_until(&mut app, |app| {
        let shown = view(app);
        shown.stats.is_some() && !shown.counting
    });
    let shown = view(&app);
    let stats = shown.stats.unwrap();
    assert_eq!(stats, pappus::mesh::mesh_stats(app.world(), mesh(&app)));
    assert_eq!((stats.faces, stats.euler_characteristic), (1280, 2));
    assert!(shown.validation.is_none(), "not checked unasked");
    assert!(
        !app.world()
            .resource::<InspectorView>()
            .histograms
            .is_empty()
    );
    app.world_mut()
        .resource_mut::<pappus::editor::session::panel_state::UiState>()
        .check_validity = true;
    app.update();
    assert_eq!(view(&app).validation, Some(Ok(())));
}

/// A change of looks redraws the mesh and leaves the panel's figures standing (on the bunny a
/// count is 150 ms of a frame); showing a quantity counts them again with its histogram, and so
/// does an edit.
#[test]
fn a_change_of_looks_leaves_the_panels_figures_standing() {
    use pappus::editor::panels::{state::InspectorView, ui::snapshot};
    use pappus::editor::view::colouring::ColorBy;
    use pappus::ops::geometry::Quantity;
    let mut app = app();
    app.init_resource::<InspectorView>()
        .add_systems(Update, snapshot.in_set(pappus::editor::EditorSystems::Ui));
    open(&mut app, "shape:icosphere");
    let view = |app: &App| app.world().resource::<InspectorView>().clone();
    update_until(&mut app, |app| {
        view(app).mesh.is_some_and(|m| m.stats.is_some())
    });
    let counted = view(&app).figures_key;
    let histograms = view(&app).histograms.len();
    let rebuilds = app.world().resource::<RenderStats>().rebuilds;
    press(&mut app, KeyCode::KeyZ);
    press(&mut app, KeyCode::KeyZ);
    for _ in 0..3 {
        app.update();
    }
    let stats = app.world().resource::<RenderStats>();
    assert_eq!(stats.rebuilds, rebuilds + 2, "redrawn each time");
    assert_eq!(view(&app).figures_key, counted, "not counted again");
    // A quantity shown: its histogram joins the others.
    app.world_mut().resource_mut::<ColorBy>().0 = Some(Quantity::VALENCE);
    update_until(&mut app, |app| view(app).histograms.len() == histograms + 1);
    let coloured = view(&app).figures_key;
    assert_ne!(coloured, counted);
    // An edit: counted again.
    let e = some_interior_edge(&app);
    app.world_mut()
        .write_message(Request::Edit(Edit::local("flip", e)));
    update_until(&mut app, |app| view(app).figures_key != coloured);
}

#[test]
fn unsaved_changes_are_not_lost_to_an_open() {
    let mut app = app();
    open(&mut app, "shape:torus");
    // Unchanged: another file opens straight away.
    open(&mut app, "shape:icosphere");
    let e = some_interior_edge(&app);
    app.world_mut()
        .write_message(Request::Edit(Edit::local("flip", e)));
    app.update();
    assert!(last_outcome(&app).result.is_ok());
    let edited = mesh(&app);
    // Changed: opening asks first and leaves the mesh alone.
    app.world_mut()
        .write_message(Request::Open("shape:cube".into()));
    app.update();
    assert!(
        last_outcome(&app)
            .result
            .unwrap_err()
            .to_string()
            .contains("unsaved changes")
    );
    assert_eq!(mesh(&app), edited);
    // "Cancel" keeps it; asking again and "Discard" opens the cube.
    app.world_mut()
        .write_message(Request::ConfirmDiscard(false));
    app.update();
    assert_eq!(mesh(&app), edited);
    app.world_mut()
        .write_message(Request::Open("shape:cube".into()));
    app.world_mut().write_message(Request::ConfirmDiscard(true));
    app.update();
    assert_eq!(pappus::mesh::mesh_stats(app.world(), mesh(&app)).faces, 6);
    // Saving clears the mark: edit, save, open without a question.
    let path = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("saved-cube.off");
    app.world_mut()
        .write_message(Request::Edit(Edit::registered("triangulate").unwrap()));
    app.world_mut()
        .write_message(Request::Save(Some(path.clone())));
    app.world_mut()
        .write_message(Request::Open("shape:tetrahedron".into()));
    app.update();
    assert!(
        last_outcome(&app).result.is_ok(),
        "{:?}",
        last_outcome(&app)
    );
    assert_eq!(pappus::mesh::mesh_stats(app.world(), mesh(&app)).faces, 4);
    assert!(path.exists());
}

#[test]
fn colouring_by_a_quantity_paints_the_render_copy_and_goes_away() {
    use pappus::editor::view::colouring::{ColorBy, VertexValues};
    use pappus::ops::geometry::Quantity;
    let mut app = app();
    open(&mut app, "shape:icosphere");
    let has_colours = |app: &mut App| {
        let meshes: Vec<Handle<Mesh>> = app
            .world_mut()
            .query_filtered::<&Mesh3d, With<RenderOf>>()
            .iter(app.world())
            .map(|m| m.0.clone())
            .collect();
        let assets = app.world().resource::<Assets<Mesh>>();
        meshes.iter().all(|h| {
            assets
                .get(h)
                .unwrap()
                .attribute(Mesh::ATTRIBUTE_COLOR)
                .is_some()
        })
    };
    assert!(!has_colours(&mut app));
    app.world_mut().resource_mut::<ColorBy>().0 = Some(Quantity::MEAN);
    app.update();
    let values = app.world().get::<VertexValues>(mesh(&app).0).unwrap();
    assert_eq!(values.values.len(), 642);
    assert!(values.values.values().all(|h| (h - 1.0).abs() < 0.01));
    // A local edit recomputes the values and keeps the range the legend shows.
    let range = values.range;
    assert!(has_colours(&mut app));
    let e = some_interior_edge(&app);
    app.world_mut()
        .write_message(Request::Edit(Edit::local("flip", e)));
    app.update();
    assert_eq!(
        app.world().get::<VertexValues>(mesh(&app).0).unwrap().range,
        range
    );
    assert!(has_colours(&mut app));
    app.world_mut().resource_mut::<ColorBy>().0 = None;
    app.update();
    assert!(app.world().get::<VertexValues>(mesh(&app).0).is_none());
    assert!(!has_colours(&mut app));
}

#[test]
fn the_distance_colouring_measures_against_the_mesh_before_a_whole_mesh_edit() {
    use pappus::editor::view::colouring::{ColorBy, VertexValues};
    use pappus::ops::geometry::Quantity;
    let mut app = app();
    open(&mut app, "shape:icosphere");
    app.world_mut().resource_mut::<ColorBy>().0 = Some(Quantity::DISTANCE);
    app.update();
    // No whole-mesh edit yet: nothing to measure against (grey).
    let values = app.world().get::<VertexValues>(mesh(&app).0).unwrap();
    assert!(values.values.values().all(|d| d.is_nan()));
    app.world_mut()
        .write_message(Request::Edit(Edit::invoked("simplify:0.25").unwrap()));
    app.update();
    let values = app.world().get::<VertexValues>(mesh(&app).0).unwrap();
    let most = values.values.values().copied().fold(0.0, f64::max);
    assert!(values.values.values().all(|d| d.is_finite() && *d >= 0.0));
    // Collapses moved vertices off the sphere, never far (a unit sphere of 1280 faces).
    assert!(most > 1e-4 && most < 0.05, "{most}");
}

#[test]
fn smoothing_as_a_job_holds_the_vertex_the_editor_named() {
    use pappus::editor::pipeline::jobs::{JobSettings, Jobs};
    let mut app = app();
    app.world_mut().resource_mut::<JobSettings>().min_faces = 100;
    open(&mut app, "shape:icosphere");
    let members = pappus::mesh::MeshMembers::collect(app.world(), mesh(&app));
    let (held, free) = (members.vertices[7], members.vertices[8]);
    let at = |app: &App, v| MeshRef::new(app.world()).position(v);
    let (held_at, free_at) = (at(&app, held), at(&app, free));
    let smooth = Edit::local_on("smooth", [held], &[0.0, 3.0]);
    app.world_mut().write_message(Request::Edit(smooth));
    app.update();
    assert!(app.world().resource::<Jobs>().running.is_some() || last_outcome(&app).result.is_ok());
    update_until(&mut app, |app| {
        app.world().resource::<Jobs>().running.is_none()
    });
    assert!(
        last_outcome(&app).result.is_ok(),
        "{:?}",
        last_outcome(&app)
    );
    assert_eq!(at(&app, held), held_at, "the held vertex stayed");
    assert_ne!(at(&app, free), free_at, "the others moved");
}

/// A job's commit follows the whole selected set through its rows, not the active element
/// alone: a smoothing (run on a copy of the mesh) keeps every selected element; a Loop
/// subdivision (run on the tables) keeps the selected vertices, whose ids it keeps.
#[test]
fn a_job_keeps_the_selected_set() {
    use pappus::editor::pipeline::jobs::{JobSettings, Jobs};
    let mut app = app();
    app.world_mut().resource_mut::<JobSettings>().min_faces = 100;
    open(&mut app, "shape:icosphere");
    let members = pappus::mesh::MeshMembers::collect(app.world(), mesh(&app));
    let mut chosen: Vec<ElementId> = members.vertices[3..9]
        .iter()
        .map(|&v| ElementId::Vertex(v))
        .collect();
    chosen.push(ElementId::Face(members.faces[5]));
    chosen.push(ElementId::Vertex(members.vertices[20]));
    let run = |app: &mut App, edit: Edit| {
        app.world_mut().write_message(Request::Edit(edit));
        app.update();
        assert!(
            app.world().resource::<Jobs>().running.is_some(),
            "runs as a job"
        );
        update_until(app, |app| app.world().resource::<Jobs>().running.is_none());
        assert!(last_outcome(app).result.is_ok(), "{:?}", last_outcome(app));
    };
    let select = |app: &mut App| {
        let mut selection = app.world_mut().resource_mut::<Selection>();
        selection.select_only(None);
        selection.extend(chosen.iter().copied());
    };
    select(&mut app);
    run(&mut app, Edit::registered("smooth").unwrap());
    let selection = app.world().resource::<Selection>();
    assert_eq!(selection.len(), chosen.len(), "{:?}", selection.elements());
    assert_eq!(selection.element, chosen.last().copied());
    let m = MeshRef::new(app.world());
    assert!(
        selection
            .elements()
            .iter()
            .all(|&x| pappus::editor::session::selection::exists(&m, x))
    );
    select(&mut app);
    run(&mut app, Edit::registered("loop").unwrap());
    let selection = app.world().resource::<Selection>();
    let vertices: Vec<ElementId> = chosen
        .iter()
        .copied()
        .filter(|x| matches!(x, ElementId::Vertex(_)))
        .collect();
    assert_eq!(
        selection.elements(),
        vertices,
        "the vertices keep their ids"
    );
    assert_eq!(selection.element, chosen.last().copied());
}

/// Whether every render chunk of the active mesh has texture coordinates.
fn renders_uvs(app: &mut App) -> bool {
    let meshes: Vec<Handle<Mesh>> = app
        .world_mut()
        .query_filtered::<&Mesh3d, With<RenderOf>>()
        .iter(app.world())
        .map(|m| m.0.clone())
        .collect();
    let assets = app.world().resource::<Assets<Mesh>>();
    !meshes.is_empty()
        && meshes.iter().all(|h| {
            assets
                .get(h)
                .unwrap()
                .attribute(Mesh::ATTRIBUTE_UV_0)
                .is_some()
        })
}

#[test]
fn shift_u_parameterizes_as_a_job_draws_a_checker_and_undo_removes_the_uvs() {
    use pappus::editor::panels::uv_view::UvLayout;
    use pappus::editor::pipeline::jobs::{JobSettings, Jobs};
    use pappus::editor::view::render_sync::ViewSettings;
    use pappus::mesh::attributes::MeshAttributes;
    let mut app = app();
    app.world_mut().resource_mut::<JobSettings>().min_faces = 100;
    open(&mut app, "shape:icosphere");
    assert!(!MeshAttributes::of(app.world(), mesh(&app)).uv);
    assert!(!renders_uvs(&mut app));
    // Shift+U: the panel's method (mean-value, circle); the closed sphere is cut automatically.
    app.world_mut()
        .resource_mut::<ButtonInput<KeyCode>>()
        .press(KeyCode::ShiftLeft);
    app.world_mut().write_message(KeyboardInput {
        key_code: KeyCode::ShiftLeft,
        logical_key: Key::Shift,
        state: ButtonState::Pressed,
        text: None,
        repeat: false,
        window: Entity::PLACEHOLDER,
    });
    press(&mut app, KeyCode::KeyU);
    while app.world().resource::<Jobs>().running.is_some() {
        std::thread::sleep(std::time::Duration::from_millis(2));
        app.update();
    }
    let outcome = last_outcome(&app);
    assert!(
        outcome
            .request
            .starts_with("parameterize (mean-value, circle)"),
        "{outcome:?}"
    );
    let summary = outcome.result.clone().unwrap();
    assert!(summary.contains("flip"), "{summary}");
    let m = mesh(&app);
    assert!(MeshAttributes::of(app.world(), m).uv);
    validate(app.world(), m).unwrap();
    // The checkerboard (on by default) gives the render copy UVs; a seam splits render vertices.
    assert!(renders_uvs(&mut app));
    let vertices: usize = {
        let handles: Vec<Handle<Mesh>> = app
            .world_mut()
            .query_filtered::<&Mesh3d, With<RenderOf>>()
            .iter(app.world())
            .map(|h| h.0.clone())
            .collect();
        let assets = app.world().resource::<Assets<Mesh>>();
        handles
            .iter()
            .map(|h| assets.get(h).unwrap().count_vertices())
            .sum()
    };
    assert!(vertices > 642, "the cut's corners are split: {vertices}");
    // The UV view opened by itself and holds the layout; clicking a face's UV centroid picks it.
    assert!(
        app.world()
            .resource::<pappus::editor::session::panel_state::UiState>()
            .uv_view
    );
    {
        let layout = app.world().resource::<UvLayout>();
        assert_eq!(layout.faces.len(), 1280);
        assert!(!layout.seams.is_empty());
        let centroid = layout.face_corners(5).iter().copied().sum::<Vec2>() / 3.0;
        assert_eq!(
            pappus::editor::panels::uv_view::face_at(layout, centroid),
            Some(layout.faces[5])
        );
    }
    // Checker off: no UVs drawn; on again: back.
    app.world_mut().resource_mut::<ViewSettings>().checker = false;
    app.world_mut()
        .entity_mut(m.0)
        .insert(pappus::editor::session::selection::MeshDirty);
    app.update();
    assert!(!renders_uvs(&mut app));
    app.world_mut().resource_mut::<ViewSettings>().checker = true;
    app.world_mut()
        .entity_mut(m.0)
        .insert(pappus::editor::session::selection::MeshDirty);
    app.update();
    assert!(renders_uvs(&mut app));
    // Undo takes the UVs away, from the mesh, the render copy and the UV view.
    app.world_mut().write_message(Request::Undo);
    app.update();
    let m = mesh(&app);
    assert!(!MeshAttributes::of(app.world(), m).uv);
    assert!(!renders_uvs(&mut app));
    assert!(app.world().resource::<UvLayout>().is_empty());
}

/// A folder of its own for a test's recovery files.
fn recovery_folder(test: &str) -> std::path::PathBuf {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("recovery-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Updates `app` until `done` holds (a thread's write lands between frames), for at most 10 s.
fn update_until(app: &mut App, done: impl Fn(&App) -> bool) {
    let start = std::time::Instant::now();
    while !done(app) {
        assert!(start.elapsed().as_secs() < 10, "timed out");
        std::thread::sleep(std::time::Duration::from_millis(5));
        app.update();
    }
}

/// Autosave: an edit writes the unsaved mesh to a recovery file once the editor is idle (here
/// at once), which gives the mesh back bit for bit; a save removes it.
#[test]
fn an_idle_editor_keeps_its_unsaved_mesh_in_a_recovery_file_until_it_is_saved() {
    use pappus::editor::pipeline::recovery::Autosave;
    let dir = recovery_folder("autosave");
    let mut app = app();
    let mut autosave = Autosave::into_folder(Some(dir.clone()));
    autosave.idle = std::time::Duration::ZERO;
    app.insert_resource(autosave);
    open(&mut app, "shape:icosphere:1");
    app.update();
    assert!(
        pappus::recovery::list(&dir).is_empty(),
        "nothing unsaved yet"
    );
    let e = some_interior_edge(&app);
    app.world_mut()
        .write_message(Request::Edit(Edit::local("flip", e)));
    update_until(&mut app, |app| {
        app.world().resource::<Autosave>().written.is_some()
    });
    let found = pappus::recovery::list(&dir);
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].info.name, "icosphere:1");
    assert_eq!(found[0].info.source, None);
    let kept = found[0].read().unwrap();
    let now = pappus::mesh::to_soup(app.world(), mesh(&app));
    assert_eq!(
        (kept.positions.clone(), kept.indices.clone()),
        (now.positions, now.indices)
    );
    // Saved: the recovery goes.
    let saved = dir.join("saved.obj");
    app.world_mut()
        .write_message(Request::Save(Some(saved.clone())));
    update_until(&mut app, |_| pappus::recovery::list(&dir).is_empty());
    assert!(saved.is_file());
    // Edited again, then quit with "discard changes": the recovery goes too.
    let e = some_interior_edge(&app);
    app.world_mut()
        .write_message(Request::Edit(Edit::local("flip", e)));
    update_until(&mut app, |_| !pappus::recovery::list(&dir).is_empty());
    app.world_mut()
        .resource_mut::<pappus::editor::session::requests::ConfirmDiscard>()
        .0 = Some(pappus::editor::session::requests::PendingDiscard::Quit);
    app.world_mut().write_message(Request::ConfirmDiscard(true));
    app.update();
    assert!(
        pappus::recovery::list(&dir).is_empty(),
        "discarded on purpose"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// At start the newest recovery newer than its source is offered; restoring opens its mesh as
/// unsaved work on the source file, and the recovery is removed.
#[test]
fn a_recovery_newer_than_its_source_is_offered_at_start_and_restores() {
    use pappus::editor::pipeline::recovery::{Autosave, RecoveryOffer};
    use pappus::editor::session::requests::RecoveryAnswer;
    use pappus::editor::session::state::is_modified;
    let dir = recovery_folder("offer");
    std::fs::create_dir_all(&dir).unwrap();
    let source = dir.join("torus.obj");
    std::fs::write(&source, b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let soup = pappus::mesh::shapes::torus(6, 4);
    let info = pappus::recovery::RecoveryInfo {
        source: Some(source.clone()),
        name: "torus.obj".into(),
        saved_at: pappus::recovery::now() + 5.0,
        pid: u32::MAX,
        vertices: soup.positions.len(),
        faces: soup.face_count(),
    };
    pappus::recovery::write(&dir, "torus.obj-1-2", &soup, &info).unwrap();
    // An older one, and one older than its source, are not the one offered.
    let stale = pappus::recovery::RecoveryInfo {
        saved_at: 1000.0,
        ..info.clone()
    };
    pappus::recovery::write(&dir, "torus.obj-1-1", &soup, &stale).unwrap();
    let mut app = pappus::editor::headless_app();
    app.insert_resource(Autosave::into_folder(Some(dir.clone())));
    app.update();
    let offered = app
        .world()
        .resource::<RecoveryOffer>()
        .0
        .clone()
        .expect("an offer");
    assert_eq!(offered.name, "torus.obj-1-2");
    app.world_mut()
        .write_message(Request::Recover(RecoveryAnswer::Restore));
    app.update();
    assert!(
        last_outcome(&app).result.is_ok(),
        "{:?}",
        last_outcome(&app)
    );
    let mesh = mesh(&app);
    let restored = pappus::mesh::to_soup(app.world(), mesh);
    assert_eq!(restored.positions, soup.positions);
    assert_eq!(restored.indices, soup.indices);
    let info_now = app.world().get::<pappus::mesh::MeshInfo>(mesh.0).unwrap();
    assert_eq!(info_now.path.as_deref(), Some(source.as_path()));
    assert!(is_modified(app.world(), mesh), "restored work is unsaved");
    let left: Vec<String> = pappus::recovery::list(&dir)
        .into_iter()
        .map(|r| r.name)
        .collect();
    assert_eq!(left, ["torus.obj-1-1"], "the restored recovery is gone");
    assert!(app.world().resource::<RecoveryOffer>().0.is_none());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A Loop the memory budget refuses leaves the mesh as it was, in a job as at once.
#[test]
fn a_subdivision_past_the_memory_budget_is_refused_and_changes_nothing() {
    use pappus::editor::pipeline::jobs::{JobSettings, Jobs};
    for min_faces in [usize::MAX, 100] {
        let mut app = app();
        app.world_mut().resource_mut::<JobSettings>().min_faces = min_faces;
        open(&mut app, "shape:icosphere:5");
        let before = pappus::mesh::to_soup(app.world(), mesh(&app));
        app.world_mut()
            .write_message(Request::Edit(Edit::invoked("loop:8").unwrap()));
        app.update();
        update_until(&mut app, |app| {
            app.world().resource::<Jobs>().running.is_none()
        });
        let outcome = last_outcome(&app);
        let why = outcome.result.expect_err("refused").to_string();
        assert!(
            why.contains("Loop ×8 would make 1342 M faces, about ")
                && why.contains("the budget is"),
            "{why}"
        );
        let after = pappus::mesh::to_soup(app.world(), mesh(&app));
        assert_eq!(after, before, "the mesh is as it was");
    }
}

#[test]
fn a_shown_mesh_colours_by_the_scripts_array_and_goes_back_with_its_selection() {
    use pappus::editor::automation::show::{GivenArray, ShowPlugin, ShowRequest};
    use pappus::editor::view::colouring::{ColorBy, VertexValues};
    let folder = std::env::temp_dir().join(format!("pappus-shown-{}", std::process::id()));
    let mut app = app();
    // Each vertex's value is its input number; a name Pappus has is registered apart.
    let height = GivenArray {
        name: "show-test-height".into(),
        on_faces: false,
        values: (0..642).map(f64::from).collect(),
    };
    let valence = GivenArray {
        name: "valence".into(),
        on_faces: false,
        values: vec![0.0; 642],
    };
    let face_rows = GivenArray {
        name: "show-test-face-rows".into(),
        on_faces: true,
        values: (0..1280).map(f64::from).collect(),
    };
    app.add_plugins(ShowPlugin {
        request: ShowRequest {
            mesh: "shape:icosphere".into(),
            name: Some("a script's sphere".into()),
            quantities: vec![height, valence, face_rows],
            hand_back: folder.clone(),
        },
    });
    open(&mut app, "shape:icosphere");
    app.update();
    let shown = app.world().resource::<ColorBy>().0.unwrap();
    assert_eq!(shown.name(), "show-test-height");
    let info = app
        .world()
        .get::<pappus::mesh::MeshInfo>(mesh(&app).0)
        .unwrap();
    assert_eq!(info.name, "a script's sphere");
    assert!(pappus::ops::registry::quantity("valence-script").is_some());
    let vertices = pappus::mesh::members::of_kind::<pappus::mesh::Vertex, _>(
        app.world(),
        mesh(&app),
        pappus::mesh::VertexId,
    );
    let values = app.world().get::<VertexValues>(mesh(&app).0).unwrap();
    for (i, v) in vertices.iter().enumerate() {
        assert_eq!(values.values[&v.0], i as f64);
    }
    assert!(!values.on_faces);
    // An array on the faces: each face one colour, its corners render vertices of their own.
    let on_faces = pappus::ops::registry::quantity("show-test-face-rows").unwrap();
    app.world_mut().resource_mut::<ColorBy>().0 = Some(on_faces);
    app.update();
    let faces = pappus::mesh::members::of_kind::<pappus::mesh::Face, _>(
        app.world(),
        mesh(&app),
        pappus::mesh::FaceId,
    );
    let values = app.world().get::<VertexValues>(mesh(&app).0).unwrap();
    assert!(values.on_faces);
    for (i, f) in faces.iter().enumerate() {
        assert_eq!(values.values[&f.0], i as f64);
    }
    let drawn: usize = app
        .world_mut()
        .query_filtered::<&Mesh3d, With<RenderOf>>()
        .iter(app.world())
        .map(|m| m.0.clone())
        .collect::<Vec<_>>()
        .iter()
        .map(|h| {
            let asset = app.world().resource::<Assets<Mesh>>().get(h).unwrap();
            assert!(asset.attribute(Mesh::ATTRIBUTE_COLOR).is_some());
            asset.count_vertices()
        })
        .sum();
    assert_eq!(drawn, 3 * 1280);
    app.world_mut().resource_mut::<ColorBy>().0 = Some(shown);
    // Nothing edited: the answer says so, with the selection by kind as rows.
    let edge = some_interior_edge(&app);
    let face = pappus::mesh::MeshMembers::collect(app.world(), mesh(&app)).faces[7];
    {
        let mut selection = app.world_mut().resource_mut::<Selection>();
        selection.select_only(Some(ElementId::Edge(edge)));
        selection.add(ElementId::Face(face));
    }
    pappus::editor::automation::show::hand_back(app.world_mut(), &folder).unwrap();
    let answer: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(folder.join("answer.json")).unwrap())
            .unwrap();
    assert_eq!(answer["edited"], false);
    let (a, b) = MeshRef::new(app.world()).edge_vertices(edge);
    let row = |v: pappus::mesh::VertexId| vertices.iter().position(|&w| w == v).unwrap();
    assert_eq!(
        answer["selection"]["edges"],
        serde_json::json!([[row(a), row(b)]])
    );
    assert_eq!(answer["selection"]["faces"], serde_json::json!([7]));
    assert_eq!(answer["selection"]["vertices"], serde_json::json!([]));
    // A flip, then the window closes: the mesh goes back edited, the same size, as a PLY.
    app.world_mut()
        .write_message(Request::Edit(Edit::local("flip", edge)));
    app.update();
    app.world_mut().write_message(AppExit::Success);
    app.update();
    let answer: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(folder.join("answer.json")).unwrap())
            .unwrap();
    assert_eq!(answer["edited"], true);
    assert_eq!(answer["notes"], serde_json::json!([]));
    let back = pappus::io::read(&folder.join("mesh.ply")).unwrap();
    assert_eq!((back.positions.len(), back.face_count()), (642, 1280));
    std::fs::remove_dir_all(&folder).unwrap();
}

/// A script's arrays are kept by entity: an undo that brings a collapsed vertex and its faces
/// back under new entities gives them their values again, and so does a redo of an undone
/// split.
#[test]
fn a_shown_array_keeps_its_values_through_undo_and_redo() {
    use pappus::editor::automation::show::{GivenArray, ShowPlugin, ShowRequest};
    use pappus::editor::view::colouring::{ColorBy, VertexValues};
    let folder = std::env::temp_dir().join(format!("pappus-undone-{}", std::process::id()));
    let mut app = app();
    let arrays = [
        ("show-undo-vertices", false, 642),
        ("show-undo-faces", true, 1280),
    ];
    app.add_plugins(ShowPlugin {
        request: ShowRequest {
            mesh: "shape:icosphere".into(),
            name: None,
            quantities: arrays
                .iter()
                .map(|&(name, on_faces, n)| GivenArray {
                    name: name.into(),
                    on_faces,
                    values: (0..n).map(f64::from).collect(),
                })
                .collect(),
            hand_back: folder.clone(),
        },
    });
    open(&mut app, "shape:icosphere");
    app.update();
    // Every element of the mesh has a value in both arrays (none is NaN).
    let all_valued = |app: &mut App| {
        arrays.iter().all(|&(name, on_faces, _)| {
            let q = pappus::ops::registry::quantity(name).unwrap();
            app.world_mut().resource_mut::<ColorBy>().0 = Some(q);
            app.update();
            let values = app.world().get::<VertexValues>(mesh(app).0).unwrap();
            let members = pappus::mesh::MeshMembers::collect(app.world(), mesh(app));
            let entities: Vec<Entity> = match on_faces {
                false => members.vertices.iter().map(|v| v.0).collect(),
                true => members.faces.iter().map(|f| f.0).collect(),
            };
            entities
                .iter()
                .all(|e| values.values.get(e).is_some_and(|x| !x.is_nan()))
        })
    };
    assert!(all_valued(&mut app));
    let edge = some_interior_edge(&app);
    app.world_mut()
        .write_message(Request::Edit(Edit::local("collapse", edge)));
    app.update();
    app.world_mut().write_message(Request::Undo);
    app.update();
    assert!(all_valued(&mut app), "after undoing a collapse");
    let edge = some_interior_edge(&app);
    app.world_mut()
        .write_message(Request::Edit(Edit::local("flip", edge)));
    app.update();
    app.world_mut().write_message(Request::Undo);
    app.update();
    app.world_mut().write_message(Request::Redo);
    app.update();
    assert!(all_valued(&mut app), "after redoing a flip");
    // The hand-back names each vertex's row in the mesh shown, through the undo; a vertex a
    // split makes has none.
    // (Vertex sources, face sources), each sorted.
    let sources = |app: &mut App| -> [Vec<i64>; 2] {
        pappus::editor::automation::show::hand_back(app.world_mut(), &folder).unwrap();
        let text = std::fs::read_to_string(folder.join("answer.json")).unwrap();
        let answer: serde_json::Value = serde_json::from_str(&text).unwrap();
        ["vertex_sources", "face_sources"].map(|kind| {
            let mut sources: Vec<i64> = serde_json::from_value(answer[kind].clone()).unwrap();
            sources.sort_unstable();
            sources
        })
    };
    let all = |n: i64| (0..n).collect::<Vec<i64>>();
    assert_eq!(sources(&mut app), [all(642), all(1280)]);
    let edge = some_interior_edge(&app);
    app.world_mut()
        .write_message(Request::Edit(Edit::local("split", edge)));
    app.update();
    // The split's two new faces have none either (the other two halves keep their faces').
    let [vertices, faces] = sources(&mut app);
    assert_eq!(vertices, [vec![-1], all(642)].concat());
    assert_eq!((faces[..2].to_vec(), faces.len()), (vec![-1, -1], 1282));
    assert!(faces[2..].windows(2).all(|w| w[0] < w[1]) && faces[2] >= 0);
    // Subdivision rewrites the faces in place: the array on faces is forgotten (drawn grey,
    // never on faces it was not given for), the one on vertices kept on the old vertices.
    app.world_mut()
        .write_message(Request::Edit(Edit::registered("loop").unwrap()));
    app.update();
    update_until(&mut app, |app| {
        use pappus::editor::pipeline::jobs::Jobs;
        app.world().resource::<Jobs>().running.is_none()
    });
    let summary = last_outcome(&app).result.clone().unwrap();
    // (Another test's arrays may be registered in this process too.)
    let said = summary.contains("show-undo-faces") && summary.contains("forgotten: the faces");
    assert!(said, "{summary}");
    let q = pappus::ops::registry::quantity("show-undo-faces").unwrap();
    app.world_mut().resource_mut::<ColorBy>().0 = Some(q);
    app.update();
    let values = app.world().get::<VertexValues>(mesh(&app).0).unwrap();
    assert!(values.values.values().all(|x| x.is_nan()));
    // No face has an origin after it either; the old vertices keep theirs.
    let [vertices, faces] = sources(&mut app);
    assert!(faces.iter().all(|&row| row == -1) && faces.len() == 4 * 1282);
    assert_eq!(vertices[vertices.len() - 642..], all(642));
    let _ = std::fs::remove_dir_all(&folder);
}
