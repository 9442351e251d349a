//! Helpers shared by the integration tests.
#![allow(dead_code)]

use bevy::math::Vec3;
#[cfg(feature = "editor")]
use bevy::prelude::App;
use bevy::prelude::World;
use pappus::mesh::{BuiltMesh, MeshInfo, PolygonSoup, build_mesh, validate};
use std::path::PathBuf;

/// Builds `soup` into a fresh world and checks that the result validates.
pub fn build(soup: &PolygonSoup) -> (World, BuiltMesh) {
    let mut world = World::new();
    let built = build_mesh(&mut world, soup, MeshInfo::default()).expect("builds");
    if let Err(e) = validate(&world, built.mesh) {
        panic!("freshly built mesh is invalid: {e}");
    }
    (world, built)
}

/// Every vertex (id, position bits) and face (id, its corners' ids from its halfedge), sorted
/// by id: equal for two meshes only when they are the same to the entity and the bit.
#[derive(Debug, PartialEq)]
pub struct Elements {
    vertices: Vec<(u64, [u32; 3])>,
    faces: Vec<(u64, Vec<u64>)>,
}

/// `mesh`'s [`Elements`].
pub fn elements(world: &World, mesh: pappus::mesh::MeshId) -> Elements {
    let members = pappus::mesh::MeshMembers::collect(world, mesh);
    let m = pappus::mesh::MeshRef::new(world);
    let mut vertices: Vec<_> = members
        .vertices
        .iter()
        .map(|&v| (v.0.to_bits(), m.position(v).to_array().map(f32::to_bits)))
        .collect();
    let mut faces: Vec<_> = members
        .faces
        .iter()
        .map(|&f| {
            let corners = m.face_vertices(f).map(|v| v.0.to_bits()).collect();
            (f.0.to_bits(), corners)
        })
        .collect();
    vertices.sort_unstable();
    faces.sort_unstable();
    Elements { vertices, faces }
}

/// One entity's element components.
type Components = (
    bevy::prelude::Entity,
    Option<pappus::mesh::Halfedge>,
    Option<pappus::mesh::Vertex>,
    Option<pappus::mesh::Position>,
    Option<pappus::mesh::Edge>,
    Option<pappus::mesh::Face>,
    Option<pappus::mesh::InMesh>,
);

/// Every element component of `mesh`'s entities, and how many entities the world holds.
#[derive(Debug, PartialEq)]
pub struct Snapshot {
    entities: usize,
    rows: Vec<Components>,
}

/// `mesh`'s [`Snapshot`]: equal before and after an edit only where the world holds exactly
/// what it held.
pub fn snapshot(world: &mut World, mesh: pappus::mesh::MeshId) -> Snapshot {
    let members = pappus::mesh::MeshMembers::collect(world, mesh);
    let mut rows: Vec<_> = members
        .entities()
        .map(|e| {
            (
                e,
                world.get::<pappus::mesh::Halfedge>(e).copied(),
                world.get::<pappus::mesh::Vertex>(e).copied(),
                world.get::<pappus::mesh::Position>(e).copied(),
                world.get::<pappus::mesh::Edge>(e).copied(),
                world.get::<pappus::mesh::Face>(e).copied(),
                world.get::<pappus::mesh::InMesh>(e).copied(),
            )
        })
        .collect();
    rows.sort_by_key(|r| r.0);
    let entities = world.query::<bevy::prelude::Entity>().iter(world).count();
    Snapshot { entities, rows }
}

/// Whether a test whose fixture is missing must fail rather than skip: under CI (`CI=true`,
/// as `.ci/run` runs), where a green run must have run every test.
pub fn skipping_is_failure() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true" || v == "1")
}

/// A test cannot run because `missing` is absent: under CI that is a failure (a panic that
/// names it); elsewhere a notice, also appended to the file `$PAPPUS_SKIPPED` names (where
/// `.ci/run` collects them to say which tests skipped).
pub fn skip_because(missing: &str, test: &str) {
    if skipping_is_failure() {
        panic!("{missing} is absent, and under CI=true a test may not pass by skipping ({test})");
    }
    println!("NOTICE: {missing} is absent; skipping {test}");
    if let Some(log) = std::env::var_os("PAPPUS_SKIPPED") {
        use std::io::Write as _;
        if let Ok(mut f) = std::fs::OpenOptions::new()
            .append(true)
            .create(true)
            .open(log)
        {
            let _ = writeln!(f, "{test}: {missing} is absent");
        }
    }
}

/// The shared test models folder (`../shared/models` beside the repository), if present;
/// absent, the test skips ([`skip_because`]: a failure under CI).
pub fn models_dir() -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/models");
    if dir.is_dir() {
        Some(dir)
    } else {
        let test = std::thread::current()
            .name()
            .unwrap_or("a test on the shared models")
            .to_string();
        skip_because("../shared/models", &test);
        None
    }
}

/// The path of one shared model, if the folder is present.
pub fn model(name: &str) -> Option<PathBuf> {
    models_dir().map(|d| d.join(name))
}

/// A position as exact bits.
pub type Key = [u32; 3];

/// Faces as cycles of positions (bitwise), each rotated to start at its smallest corner,
/// sorted: two meshes with the same canonical form are the same up to relabeling
/// (orientation kept).
pub fn canonical(soup: &PolygonSoup) -> Vec<Vec<Key>> {
    let key = |p: Vec3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let mut faces: Vec<Vec<Key>> = soup
        .faces()
        .map(|f| {
            let keys: Vec<Key> = f.iter().map(|&i| key(soup.positions[i as usize])).collect();
            let start = (0..keys.len()).min_by_key(|&i| keys[i]).unwrap();
            keys[start..]
                .iter()
                .chain(&keys[..start])
                .copied()
                .collect()
        })
        .collect();
    faces.sort();
    faces
}

#[cfg(feature = "editor")]
/// The editor's logic without a window (`MinimalPlugins`, input, assets, meshes), updated once.
pub fn headless_editor() -> App {
    let mut app = pappus::editor::headless_app();
    app.update();
    app
}

#[cfg(feature = "editor")]
/// The editor's last outcome (the request's label and what became of it).
pub fn last_outcome(app: &App) -> pappus::editor::session::requests::EditOutcome {
    app.world()
        .resource::<pappus::editor::session::requests::OutcomeLog>()
        .entries
        .last()
        .expect("an outcome")
        .clone()
}

#[cfg(feature = "editor")]
/// Writes `request` and lets the editor run one update.
pub fn send(app: &mut App, request: impl Into<pappus::editor::session::requests::Request>) {
    app.world_mut().write_message(request.into());
    app.update();
}

#[cfg(feature = "editor")]
/// A key going down or up, through the same input path as a person's, and one update.
pub fn key(app: &mut App, key: bevy::prelude::KeyCode, state: bevy::input::ButtonState) {
    use bevy::input::keyboard::{Key, KeyboardInput, NativeKey};
    app.world_mut().write_message(KeyboardInput {
        key_code: key,
        logical_key: Key::Unidentified(NativeKey::Unidentified),
        state,
        text: None,
        repeat: false,
        window: bevy::prelude::Entity::PLACEHOLDER,
    });
    app.update();
}

#[cfg(feature = "editor")]
/// Presses and releases `k`, holding `modifier` if given.
pub fn press(app: &mut App, modifier: Option<bevy::prelude::KeyCode>, k: bevy::prelude::KeyCode) {
    use bevy::input::ButtonState;
    if let Some(m) = modifier {
        key(app, m, ButtonState::Pressed);
    }
    key(app, k, ButtonState::Pressed);
    key(app, k, ButtonState::Released);
    if let Some(m) = modifier {
        key(app, m, ButtonState::Released);
    }
}

#[cfg(feature = "editor")]
/// The summary of the editor's last outcome; panics, naming the request, if it was declined.
pub fn last_ok(app: &App) -> String {
    let last = last_outcome(app);
    match last.result {
        Ok(summary) => summary,
        Err(why) => panic!("{} was declined: {why}", last.request),
    }
}

/// Runs `edit` on `mesh` as the command line does (no undo history, no progress); its summary.
///
/// # Panics
/// If the edit is refused.
pub fn run_edit(
    world: &mut World,
    mesh: pappus::mesh::MeshId,
    edit: &pappus::edit::Edit,
) -> String {
    let mut context = pappus::edit::EditContext {
        progress: &mut |_| true,
    };
    edit.run(world, mesh, &mut context)
        .expect("applied")
        .summary
}

/// A proptest strategy for a parameter along an edge, in [0.05, 0.95) in steps of 1/1000.
///
/// Drawn as an integer and scaled: proptest 1.12's `Range<f32>` sampler can fail its own
/// assertion (`self.low - result < initial.step`) on some seeds, which failed a CI run.
pub fn edge_fraction() -> impl proptest::strategy::Strategy<Value = f32> {
    use proptest::strategy::Strategy;
    (50u16..950).prop_map(|thousandths| f32::from(thousandths) / 1000.0)
}

/// The cases a property test runs when `PAPPUS_PROPTEST_CASES` does not say: enough for every
/// edit kind to come up on every shape in each run; `benches/proptest_long.sh` runs 1 024.
pub const PROPTEST_CASES: u32 = 64;

/// The property tests' configuration: `PAPPUS_PROPTEST_CASES` cases (default
/// [`PROPTEST_CASES`]), and a failing case saved beside its test's source
/// (`tests/NAME.proptest-regressions`, to be committed) and replayed first by every later run.
pub fn proptest_config() -> proptest::test_runner::Config {
    let cases = std::env::var("PAPPUS_PROPTEST_CASES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(PROPTEST_CASES);
    proptest::test_runner::Config {
        cases,
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::WithSource("proptest-regressions"),
        )),
        ..proptest::test_runner::Config::default()
    }
}
