//! An operation written outside the crate, registered at run time: it becomes a `process` step,
//! a key in the editor's keymap and its panel, and an entry of the list Python's
//! `pappus.operations()` reads; one that would share a name and a kind, or a key, with a
//! registered operation is refused with both named. (Its own test binary: the registry is the
//! process's, and these tests add to it.)

mod common;

use bevy::prelude::World;
use pappus::edit::Step;
use pappus::mesh::ids::MeshId;
use pappus::mesh::shapes;
use pappus::mesh::tables::{Connectivity, VertexRow};
use pappus::ops::Refusal;
use pappus::ops::declaration::{Declaration, Names, Section};
use pappus::ops::geometry::Quantity;
use pappus::ops::geometry::quantity::{Given, Needs, QuantityDeclaration, VertexQuantity};
use pappus::ops::local::flip_edge;
use pappus::ops::operation::{Applied, EditContext, MeshOperation, Values};
use pappus::ops::registry::{self, register};

/// Pappus's flip under a declaration of its own, saying `verb to EDGE`: a student's edge
/// rotation as a lab would register it.
struct FlipAs(&'static Declaration, &'static str);

impl MeshOperation for FlipAs {
    fn declaration(&self) -> &'static Declaration {
        self.0
    }

    fn apply(
        &self,
        world: &mut World,
        _: MeshId,
        values: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        let e = values.edge()?;
        Applied::on_edge(world, e, |world| {
            let flipped = flip_edge(world, e)?;
            Ok((format!("{} to {flipped}", self.1), flipped.into()))
        })
    }
}

/// An operation that changes nothing, under a declaration that should be refused.
struct Idle(&'static Declaration);

impl MeshOperation for Idle {
    fn declaration(&self) -> &'static Declaration {
        self.0
    }

    fn apply(
        &self,
        _: &mut World,
        _: MeshId,
        _: Values<'_>,
        _: &mut EditContext<'_>,
    ) -> Result<Applied, Refusal> {
        Ok(Applied::whole("nothing".into()))
    }
}

/// A student's edge rotation, on a key of its own.
const SPIN: Declaration = Declaration::new("spin")
    .titled("Spin edge")
    .described("rotate the selected edge inside its two faces")
    .on_key("Alt+Y")
    .naming(Names::Edge)
    .in_section(Section::Local);

/// Another operation that claims `spin` on an edge.
const SECOND_SPIN: Declaration = Declaration::new("spin")
    .titled("Second spin")
    .naming(Names::Edge);

/// An operation on flip's key.
const ON_FLIPS_KEY: Declaration = Declaration::new("twirl")
    .titled("Twirl")
    .on_key("Alt+R")
    .naming(Names::Edge);

/// The number of edges from the nearest source: a quantity written outside the crate that
/// starts from vertices.
struct Hops;

const HOPS: QuantityDeclaration = QuantityDeclaration {
    name: "hops",
    label: "edges from the sources",
    colormap: pappus::colormap::ColorMap::Viridis,
    needs: Needs::Sources,
};

impl VertexQuantity for Hops {
    fn declaration(&self) -> &'static QuantityDeclaration {
        &HOPS
    }

    fn per_vertex(&self, t: &Connectivity, given: &Given<'_>) -> Vec<f64> {
        let mut hops = vec![f64::NAN; t.vertex_count()];
        let mut queue: std::collections::VecDeque<VertexRow> =
            given.sources.iter().copied().collect();
        for &s in given.sources {
            hops[s.index()] = 0.0;
        }
        while let Some(v) = queue.pop_front() {
            for h in t.vertex_outgoing(v) {
                let w = t.to_vertex(h);
                if hops[w.index()].is_nan() {
                    hops[w.index()] = hops[v.index()] + 1.0;
                    queue.push_back(w);
                }
            }
        }
        hops
    }
}

/// Registers [`Hops`] once for every test of this binary.
fn hops_registered() -> Quantity {
    static ONCE: std::sync::OnceLock<Quantity> = std::sync::OnceLock::new();
    *ONCE.get_or_init(|| registry::register_quantity(Hops).expect("hops is free"))
}

#[test]
fn an_outside_quantity_is_listed_and_a_second_of_its_name_is_refused() {
    let hops = hops_registered();
    assert_eq!(registry::quantity("HOPS"), Some(hops));
    assert_eq!(registry::quantities().last(), Some(&hops));
    let clash = registry::register_quantity(Hops).expect_err("refused");
    assert!(
        clash.to_string().contains("edges from the sources"),
        "{clash}"
    );
    // Built-in names are taken too.
    struct Mean;
    const MEAN: QuantityDeclaration = QuantityDeclaration {
        name: "mean",
        label: "my mean",
        colormap: pappus::colormap::ColorMap::Viridis,
        needs: Needs::Mesh,
    };
    impl VertexQuantity for Mean {
        fn declaration(&self) -> &'static QuantityDeclaration {
            &MEAN
        }
        fn per_vertex(&self, t: &Connectivity, _: &Given<'_>) -> Vec<f64> {
            vec![0.0; t.vertex_count()]
        }
    }
    let clash = registry::register_quantity(Mean)
        .expect_err("refused")
        .to_string();
    assert!(
        clash.contains("my mean") && clash.contains("mean curvature"),
        "{clash}"
    );
}

/// Registers `spin` (a [`FlipAs`]) once for every test of this binary.
fn spin_registered() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        register(FlipAs(&SPIN, "spun")).expect("spin is free");
    });
}

#[test]
fn an_outside_operation_is_a_step_that_runs_as_the_one_it_reproduces() {
    spin_registered();
    assert!(pappus::edit::step_syntax().contains("spin:A,B"));
    let names: Vec<&str> = registry::operations()
        .iter()
        .map(|op| op.declaration().name)
        .collect();
    assert_eq!(names.last(), Some(&"spin"));
    // `spin:0,1` on an icosphere gives the faces `flip:0,1` gives.
    let soup = shapes::icosphere(2);
    let faces_after = |step: &str| {
        let (mut world, built) = common::build(&soup);
        let step = Step::parse(step).unwrap();
        step.run(&mut world, built.mesh, &built.input_vertices)
            .unwrap();
        pappus::mesh::validate(&world, built.mesh).unwrap();
        common::canonical(&pappus::mesh::to_soup(&world, built.mesh))
    };
    let (a, b) = {
        let f = soup.faces().next().unwrap();
        (f[0], f[1])
    };
    let spun = faces_after(&format!("spin:{a},{b}"));
    assert_eq!(spun, faces_after(&format!("flip:{a},{b}")));
    assert_ne!(spun, common::canonical(&soup));
}

#[test]
fn a_second_operation_with_the_name_or_the_key_is_refused_naming_both() {
    spin_registered();
    let before = registry::operations().len();
    let clash = register(Idle(&SECOND_SPIN))
        .err()
        .expect("refused")
        .to_string();
    assert!(
        clash.contains("Second spin") && clash.contains("Spin edge"),
        "{clash}"
    );
    let clash = register(Idle(&ON_FLIPS_KEY))
        .err()
        .expect("refused")
        .to_string();
    assert!(
        clash.contains("Twirl") && clash.contains("\"Flip\"") && clash.contains("Alt+R"),
        "{clash}"
    );
    assert_eq!(registry::operations().len(), before);
}

#[cfg(feature = "editor")]
mod in_the_editor {
    use super::*;
    use bevy::input::ButtonState;
    use bevy::input::keyboard::{Key, KeyboardInput, NativeKey};
    use bevy::prelude::{App, Entity, KeyCode};
    use pappus::editor::AddOperation;
    use pappus::editor::input::shortcuts::{Action, shortcuts};
    use pappus::editor::session::requests::Request;
    use pappus::editor::session::selection::ActiveMesh;
    use pappus::mesh::ids::ElementId;

    fn key(app: &mut App, key_code: KeyCode, state: ButtonState) {
        app.world_mut().write_message(KeyboardInput {
            key_code,
            logical_key: Key::Unidentified(NativeKey::Unidentified),
            state,
            text: None,
            repeat: false,
            window: Entity::PLACEHOLDER,
        });
        app.update();
    }

    #[test]
    fn an_added_operation_has_its_key_and_runs_on_the_selection() {
        let mut app = common::headless_editor();
        app.add_operation(FlipAs(&MIRROR, "mirrored"));
        assert!(
            shortcuts().any(|s| s.action == Action::Operation("mirror-edge") && s.keys == "Alt+J")
        );
        common::send(&mut app, Request::Open("shape:icosphere".into()));
        let mesh = app.world().resource::<ActiveMesh>().0.unwrap();
        let members = pappus::mesh::MeshMembers::collect(app.world(), mesh);
        let e = members.edges[0];
        common::send(&mut app, Request::Select(Some(ElementId::Edge(e))));
        key(&mut app, KeyCode::AltLeft, ButtonState::Pressed);
        key(&mut app, KeyCode::KeyJ, ButtonState::Pressed);
        key(&mut app, KeyCode::KeyJ, ButtonState::Released);
        key(&mut app, KeyCode::AltLeft, ButtonState::Released);
        let outcome = common::last_outcome(&app);
        assert!(outcome.request.starts_with("mirror edge"), "{outcome:?}");
        assert!(
            outcome.result.as_ref().unwrap().starts_with("mirrored to"),
            "{outcome:?}"
        );
    }

    #[test]
    fn the_editor_colours_by_an_outside_quantity_from_the_selection() {
        use pappus::editor::view::colouring::{ColorBy, VertexValues};
        let hops = hops_registered();
        let mut app = common::headless_editor();
        common::send(&mut app, Request::Open("shape:icosphere".into()));
        let mesh = app.world().resource::<ActiveMesh>().0.unwrap();
        app.world_mut().resource_mut::<ColorBy>().0 = Some(hops);
        let m = pappus::mesh::MeshMembers::collect(app.world(), mesh);
        for &v in &m.vertices[..2] {
            common::send(&mut app, Request::Select(Some(ElementId::Vertex(v))));
            app.update();
            let values = app.world().get::<VertexValues>(mesh.0).expect("coloured");
            let hops_of = |v: pappus::mesh::VertexId| values.values[&v.0];
            assert_eq!(hops_of(v), 0.0);
            let r = pappus::mesh::MeshRef::new(app.world());
            for h in r.vertex_outgoing(v) {
                assert_eq!(hops_of(r.to_vertex(h)), 1.0);
            }
            assert!(values.values.values().all(|x| x.is_finite()));
        }
    }

    #[test]
    #[should_panic(expected = "G")]
    fn an_operation_on_a_key_of_the_editor_is_refused_at_start() {
        let mut app = common::headless_editor();
        app.add_operation(Idle(&ON_GRAB));
    }

    /// Flip again, under a name and on a key of its own (the other tests of this binary may
    /// have registered `spin` already).
    const MIRROR: Declaration = Declaration::new("mirror-edge")
        .titled("Mirror edge")
        .on_key("Alt+J")
        .naming(Names::Edge)
        .in_section(Section::Local);

    /// An operation on the editor's own grab key.
    const ON_GRAB: Declaration = Declaration::new("grab-something")
        .titled("Grab something")
        .on_key("G")
        .naming(Names::Mesh);
}
