//! Moving, rotating and scaling the selection, and dragging an extrusion's or an inset's
//! distance: Blender's modal transforms (G, R, S; E and I then move).
//!
//! A [`Gesture`] starts from the selection's vertices (the corners of every selected element)
//! about their centroid, the pivot. While it lasts, the pointer drives it without a button
//! held; X, Y or Z constrain it to that world axis (again: free); digits, `.` and `-` type an
//! exact value (a distance, degrees, a factor); Enter or a left click confirms; Esc cancels. Each
//! frame in which the positions change writes one [`Edit::Move`]; the frames of one
//! gesture merge into one undo step ([`UndoHistory::begin_gesture`]). Cancelling takes back
//! every undo step the gesture made ([`Request::Retract`]): its moves, and the extrusion or
//! inset it followed.
//!
//! - **Grab**: the pivot follows the pointer in the plane through it that faces the camera; a
//!   constraint keeps the axis's part of the motion.
//! - **Rotate**: by the angle the pointer turns about the pivot on screen, about the view axis
//!   (or the constraint's, signed so that the mesh turns with the pointer).
//! - **Scale**: by the ratio of the pointer's distances from the pivot on screen, now and at
//!   the start; a constraint scales along that axis only.
//! - **Extrude / Inset**: each vertex moves along its own direction (the region's normal at it;
//!   towards its face's centroid) by one amount: the pointer's travel along the mean direction
//!   for an extrusion, the fraction by which the pointer came closer to the pivot for an inset.
//!
//! **Proportional editing** (Alt+O; its settings come with the gesture's start): a move, rotation or
//! scale also takes the unselected vertices within the radius, each by its falloff weight `w`
//! ([`crate::ops::deform::Falloff`]): moved by `w` times the motion, turned by `w` times the
//! angle, scaled by `1 + w (factor − 1)`. `PageUp` / `PageDown` or the wheel change the radius while
//! the gesture runs (drawn as a circle about the pivot); the vertices a larger radius reaches
//! join the gesture where they are ([`super::proportional`]).
//!
//! **Handle deformation** (with [`Anchors`] marked, Shift+A): a move, rotation or scale of the
//! selection (the handle) deforms the rest of the mesh, the anchors held
//! ([`crate::ops::deform::LiveDeform`]): the system is factored when the gesture starts, each
//! frame runs one as-rigid-as-possible iteration from the last frame's result (or the one
//! thin-plate solve), and confirming runs [`FINAL_ITERATIONS`] more ([`super::handle_deform`]). In step mode (F9) an
//! as-rigid-as-possible gesture moves the handle alone, and confirming it takes the move back
//! and starts a stepped run of the same deformation ([`Edit::Deform`], [`STEPPED_ITERATIONS`](super::handle_deform::STEPPED_ITERATIONS)
//! iterations), to be watched an iteration at a time ([`crate::editor::pipeline::stepping`]).

use bevy::input::mouse::MouseButton;
use bevy::math::Affine3A;
use bevy::math::primitives::InfinitePlane3d;
use bevy::prelude::*;
use bevy::window::PrimaryWindow;

use bevy::ecs::entity::EntityHashMap;

use crate::edit::Edit;
use crate::mesh::ids::VertexId;
use crate::mesh::topology::MeshRef;
use crate::ops::deform::{DeformMethod, LiveDeform, Proportional};
use crate::ops::local::extrude_directions;

use super::handle_deform::{
    Anchors, DeformProgress, FINAL_ITERATIONS, handle_deformation, stepped_deformation,
};
use super::proportional::{Follow, gather};
use super::typed_value::typed_char;
use crate::editor::pipeline::stepping::Stepping;
use crate::editor::session::history::UndoHistory;
use crate::editor::session::requests::Request;
use crate::editor::session::selection::Selection;

/// What a gesture does with the pointer.
#[derive(Clone, Debug, PartialEq)]
pub enum GestureKind {
    /// Move (G).
    Grab,
    /// Rotate (R).
    Rotate,
    /// Scale (S).
    Scale,
    /// Push each vertex along its direction by one distance (after an extrusion).
    Extrude(Vec<Vec3>),
    /// Pull each vertex towards its face's centroid by one fraction (after an inset): its
    /// direction is the whole way there.
    Inset(Vec<Vec3>),
}

impl GestureKind {
    /// Its name in the status line.
    pub fn name(&self) -> &'static str {
        match self {
            GestureKind::Grab => "move",
            GestureKind::Rotate => "rotate",
            GestureKind::Scale => "scale",
            GestureKind::Extrude(_) => "extrude",
            GestureKind::Inset(_) => "inset",
        }
    }
}

/// One transform under way.
#[derive(Debug)]
pub struct Gesture {
    /// What it does.
    pub kind: GestureKind,
    /// The world axis it is held to (0, 1, 2: X, Y, Z), if any.
    pub axis: Option<usize>,
    /// The value typed so far.
    pub typed: String,
    /// The vertices and where they were when it started.
    pub start: Vec<(VertexId, Vec3)>,
    /// The centroid of the start positions.
    pub pivot: Vec3,
    /// The pointer when it started.
    pub cursor: Vec2,
    /// The history's mark before the edit it follows ([`UndoHistory::mark`]): cancelling takes
    /// back every entry from it on (the edit's and the gesture's own).
    pub undo_mark: u64,
    /// The value the pointer (or the typing) gives now, for the status line.
    pub value: f32,
    /// Proportional editing's reach, when it is on for this gesture.
    pub follow: Option<Follow>,
    /// The handle deformation, when anchors are marked.
    pub deform: Option<Box<LiveDeform>>,
    /// Confirmed by Enter with a last edit under way: the gesture ends next frame, once that
    /// edit has joined its undo step.
    pub closing: bool,
    /// A handle deformation in step mode: the handle moves alone, and confirming starts a
    /// stepped run.
    pub stepped: bool,
    /// The handle's motion now (a move, rotation or scale; for a stepped deformation).
    pub motion: Option<Affine3A>,
}

/// The gesture under way, and the one to start once the edit it follows has applied.
#[derive(Resource, Default, Debug)]
pub struct Gestures {
    /// The gesture under way.
    pub active: Option<Gesture>,
    /// An extrusion or inset asked for: its gesture starts next frame if the edit applied.
    pub after_edit: Option<FollowUp>,
    /// A left click that confirmed a gesture: its release must not select.
    pub swallow_click: bool,
    /// A gesture had the keyboard this frame (the shortcuts stay quiet).
    pub keys_taken: bool,
}

/// A gesture to start after an edit (an extrusion or an inset) has applied.
#[derive(Clone, Debug)]
pub struct FollowUp {
    /// The edit's label (its outcome is looked up by it).
    pub label: String,
    /// Which gesture.
    pub inset: bool,
    /// The history's mark before the edit.
    pub undo_mark: u64,
}

impl Gestures {
    /// The status line while a gesture runs.
    pub fn hint(&self) -> Option<String> {
        let g = self.active.as_ref()?;
        let axis = g.axis.map_or(String::new(), |a| {
            let along = match g.kind {
                GestureKind::Rotate => "about",
                _ => "along",
            };
            format!(" {along} {}", ["X", "Y", "Z"][a])
        });
        let value = match (&g.kind, g.typed.is_empty()) {
            (_, false) => format!("{}|", g.typed),
            (GestureKind::Rotate, true) => format!("{:.1}°", g.value),
            (_, true) => format!("{:.4}", g.value),
        };
        let radius = g.follow.as_ref().map_or(String::new(), |f| {
            format!(
                ", proportional {} r {:.4} (PageUp/PageDown)",
                crate::ops::named::Named::name(f.settings.falloff),
                f.settings.radius
            )
        });
        let deform = g.deform.as_ref().map_or(String::new(), |d| {
            DeformProgress::of(d).map_or(", deforming".into(), |p| format!(", deforming ({p})"))
        });
        Some(format!(
            "{}{axis}: {value}{radius}{deform}   (X/Y/Z constrain, type a value, Enter or click confirms, Esc cancels)",
            g.kind.name()
        ))
    }
}

/// Starts a gesture on the selection's vertices; `false` (nothing started) if nothing is
/// selected. `undo_mark`: the history's mark to take back to on Esc (by default, now's).
/// `proportional`: proportional editing's settings, when it is on (a move, rotation or scale
/// then takes the vertices around along). Without a pointer over the window (a script), the
/// pointer is taken to be at the pivot's right, so typed values still work.
pub fn start(
    world: &mut World,
    kind: GestureKind,
    undo_mark: Option<u64>,
    proportional: Option<Proportional>,
) -> bool {
    let vertices = selected_vertices(world);
    if vertices.is_empty() {
        return false;
    }
    let m = MeshRef::new(world);
    let start: Vec<(VertexId, Vec3)> = vertices.iter().map(|&v| (v, m.position(v))).collect();
    let pivot = start.iter().map(|(_, p)| *p).sum::<Vec3>() / start.len() as f32;
    let cursor = cursor(world)
        .or_else(|| {
            let (camera, eye) = camera(world)?;
            Some(camera.world_to_viewport(&eye, pivot).ok()? + Vec2::new(100.0, 0.0))
        })
        .unwrap_or(Vec2::ZERO);
    let takes_along = matches!(
        kind,
        GestureKind::Grab | GestureKind::Rotate | GestureKind::Scale
    );
    let follow = proportional
        .filter(|p| p.enabled && takes_along)
        .map(|settings| Follow {
            settings,
            selected: start.len(),
            distances: Vec::new(),
            gathered: 0.0,
        });
    let deform = match handle_deformation(world, &start).map(|d| d.filter(|_| takes_along)) {
        Ok(deform) => deform,
        Err(refusal) => {
            let label = format!("{} (handle deformation)", kind.name());
            crate::editor::session::finish::report(world, label, Err(refusal.into()), 0.0);
            return false;
        }
    };
    let follow = follow.filter(|_| deform.is_none());
    let stepped = deform.is_some()
        && world.get_resource::<Stepping>().is_some_and(|s| s.enabled)
        && world
            .get_resource::<Anchors>()
            .is_some_and(|a| a.method == DeformMethod::Arap);
    let mut history = world.resource_mut::<UndoHistory>();
    let undo_mark = undo_mark.unwrap_or(history.mark());
    history.begin_gesture();
    let mut gesture = Gesture {
        kind,
        axis: None,
        typed: String::new(),
        start,
        pivot,
        cursor,
        undo_mark,
        value: 0.0,
        follow,
        deform,
        closing: false,
        stepped,
        motion: None,
    };
    if let Some(follow) = gesture.follow.as_mut() {
        gather(world, follow, &mut gesture.start);
    }
    world.resource_mut::<Gestures>().active = Some(gesture);
    true
}

/// The corners of every selected element, each once, in selection order.
pub fn selected_vertices(world: &World) -> Vec<VertexId> {
    let m = MeshRef::new(world);
    let mut seen = bevy::ecs::entity::EntityHashSet::default();
    let mut out = Vec::new();
    for &x in world.resource::<Selection>().elements() {
        if !crate::editor::session::selection::exists(&m, x) {
            continue;
        }
        let corners = crate::editor::session::select_many::corners(&m, x);
        out.extend(corners.into_iter().filter(|v| seen.insert(v.0)));
    }
    out
}

fn cursor(world: &mut World) -> Option<Vec2> {
    world
        .query_filtered::<&Window, With<PrimaryWindow>>()
        .iter(world)
        .next()
        .and_then(Window::cursor_position)
}

fn camera(world: &mut World) -> Option<(Camera, GlobalTransform)> {
    world
        .query_filtered::<(&Camera, &GlobalTransform), With<Camera3d>>()
        .iter(world)
        .find(|(c, _)| c.is_active)
        .map(|(c, t)| (c.clone(), *t))
}

/// Runs the gesture under way (the `Input` set, before the shortcuts, which it silences):
/// keys, pointer, and one move per frame in which the positions change.
pub fn drive_gesture(world: &mut World) {
    start_follow_up(world);
    let held = world
        .get_resource::<ButtonInput<MouseButton>>()
        .is_some_and(|b| b.pressed(MouseButton::Left));
    let mut gestures = world.resource_mut::<Gestures>();
    // The confirming click's release has been seen by picking by now (it runs first).
    if !held {
        gestures.swallow_click = false;
    }
    gestures.keys_taken = gestures.active.is_some();
    let Some(mut g) = gestures.active.take() else {
        return;
    };
    if g.closing {
        return end(world, false);
    }
    let keys = world.resource::<ButtonInput<KeyCode>>();
    let pressed: Vec<KeyCode> = keys.get_just_pressed().copied().collect();
    let clicked = world
        .get_resource::<ButtonInput<MouseButton>>()
        .is_some_and(|b| b.just_pressed(MouseButton::Left));
    for key in pressed {
        match key {
            KeyCode::Escape => {
                world.resource_mut::<UndoHistory>().end_gesture();
                world.write_message(Request::Retract(g.undo_mark));
                return;
            }
            KeyCode::Enter | KeyCode::NumpadEnter if g.stepped => {
                return hand_to_step_mode(world, g, false);
            }
            KeyCode::Enter | KeyCode::NumpadEnter => {
                if g.deform.is_some()
                    && let Some(moves) = positions(world, &mut g, FINAL_ITERATIONS)
                {
                    world.write_message(Request::Edit(Edit::Move(moves)));
                    g.closing = true;
                    world.resource_mut::<Gestures>().active = Some(g);
                    return;
                }
                return end(world, false);
            }
            KeyCode::KeyX | KeyCode::KeyY | KeyCode::KeyZ => {
                let a = match key {
                    KeyCode::KeyX => 0,
                    KeyCode::KeyY => 1,
                    _ => 2,
                };
                g.axis = if g.axis == Some(a) { None } else { Some(a) };
            }
            KeyCode::Backspace => {
                g.typed.pop();
            }
            KeyCode::PageUp => resize(&mut g, 1.25),
            KeyCode::PageDown => resize(&mut g, 0.8),
            _ => {
                if let Some(c) = typed_char(key) {
                    g.typed.push(c);
                }
            }
        }
    }
    let wheel = world
        .get_resource::<bevy::input::mouse::AccumulatedMouseScroll>()
        .map_or(0.0, |s| s.delta.y);
    if wheel != 0.0 {
        resize(&mut g, 1.1f32.powf(wheel.clamp(-3.0, 3.0)));
    }
    if let Some(follow) = g.follow.as_mut() {
        gather(world, follow, &mut g.start);
    }
    if clicked && g.stepped {
        return hand_to_step_mode(world, g, true);
    }
    if clicked {
        // Apply this frame's position, then stop.
        if let Some(moves) = positions(world, &mut g, FINAL_ITERATIONS) {
            world.write_message(Request::Edit(Edit::Move(moves)));
        }
        return end(world, true);
    }
    let iterations = u32::from(!g.stepped);
    if let Some(moves) = positions(world, &mut g, iterations) {
        let m = MeshRef::new(world);
        let changed = moves
            .iter()
            .any(|&(v, p)| m.try_position(v).is_some_and(|q| q != p));
        if changed {
            world.write_message(Request::Edit(Edit::Move(moves)));
        }
    }
    world.resource_mut::<Gestures>().active = Some(g);
}

/// Ends a stepped handle deformation's gesture: takes its move back and asks for a stepped run
/// of the deformation it showed (from the mesh as it was before the gesture).
fn hand_to_step_mode(world: &mut World, mut g: Gesture, by_click: bool) {
    let _ = positions(world, &mut g, 0);
    end(world, by_click);
    world.write_message(Request::Retract(g.undo_mark));
    if let Some(motion) = g.motion {
        let handle: Vec<VertexId> = g.start.iter().map(|(v, _)| *v).collect();
        let run = stepped_deformation(world, handle, motion);
        world.write_message(Request::StartStepped(run));
    }
}

/// Scales the proportional radius (when the gesture has one).
fn resize(g: &mut Gesture, factor: f32) {
    if let Some(f) = g.follow.as_mut() {
        f.resize(factor);
    }
}

fn end(world: &mut World, by_click: bool) {
    world.resource_mut::<UndoHistory>().end_gesture();
    let mut gestures = world.resource_mut::<Gestures>();
    gestures.active = None;
    gestures.swallow_click = by_click;
}

/// Starts the gesture an extrusion or inset asked for, once its outcome is in.
fn start_follow_up(world: &mut World) {
    let Some(follow) = world.resource_mut::<Gestures>().after_edit.take() else {
        return;
    };
    let applied = world
        .resource::<crate::editor::session::requests::OutcomeLog>()
        .entries
        .last()
        .is_some_and(|o| o.request == follow.label && o.result.is_ok());
    if !applied {
        return;
    }
    let kind = match follow.inset {
        false => GestureKind::Extrude(Vec::new()),
        true => GestureKind::Inset(Vec::new()),
    };
    if start(world, kind, Some(follow.undo_mark), None) {
        let directions = directions(world, follow.inset);
        if let Some(GestureKind::Extrude(d) | GestureKind::Inset(d)) = world
            .resource_mut::<Gestures>()
            .active
            .as_mut()
            .map(|g| &mut g.kind)
        {
            *d = directions;
        }
    }
}

/// Each gesture vertex's direction: the extrusion's own ([`extrude_directions`]: moving by a
/// distance along them is the extrusion by that distance, bit for bit), or the inset's (the way
/// to its face's centroid). One pass over the selected faces.
fn directions(world: &World, inset: bool) -> Vec<Vec3> {
    let faces = crate::editor::session::selection::selected_faces(world);
    let m = MeshRef::new(world);
    let towards: EntityHashMap<Vec3> = match inset {
        false => extrude_directions(world, &faces)
            .into_iter()
            .map(|(v, d)| (v.0, d))
            .collect(),
        true => faces
            .iter()
            .flat_map(|&f| {
                let c = m.face_centroid(f);
                m.face_vertices(f).map(move |v| (v.0, c - m.position(v)))
            })
            .collect(),
    };
    let start = &world
        .resource::<Gestures>()
        .active
        .as_ref()
        .expect("started")
        .start;
    start
        .iter()
        .map(|(v, _)| towards.get(&v.0).copied().unwrap_or(Vec3::ZERO))
        .collect()
}

/// Where the gesture puts its vertices now (`None` without a pointer or camera), running
/// `iterations` ARAP iterations of a handle deformation. Sets `g.value`.
fn positions(world: &mut World, g: &mut Gesture, iterations: u32) -> Option<Vec<(VertexId, Vec3)>> {
    let typed: Option<f32> = g.typed.parse().ok().filter(|x: &f32| x.is_finite());
    let (camera, eye) = camera(world)?;
    let now = cursor(world).unwrap_or(g.cursor);
    let on_screen = |p: Vec3| camera.world_to_viewport(&eye, p).ok();
    let on_plane = |c: Vec2| {
        let ray = camera.viewport_to_world(&eye, c).ok()?;
        ray.plane_intersection_point(g.pivot, InfinitePlane3d::new(eye.forward()))
    };
    let axis = g.axis.map(|a| Vec3::AXES[a]);
    let pivot_px = on_screen(g.pivot)?;
    let transform: Box<dyn Fn(usize, Vec3, f32) -> Vec3> = match &g.kind {
        GestureKind::Grab => {
            let pointer = on_plane(now)? - on_plane(g.cursor)?;
            let delta = match (typed, axis) {
                (Some(x), a) => a.unwrap_or(Vec3::X) * x,
                (None, Some(a)) => a * pointer.dot(a),
                (None, None) => pointer,
            };
            g.value = delta.length();
            g.motion = Some(Affine3A::from_translation(delta));
            Box::new(move |_, p, w| p + delta * w)
        }
        GestureKind::Rotate => {
            let (a, b) = (g.cursor - pivot_px, now - pivot_px);
            let turned = a.perp_dot(b).atan2(a.dot(b));
            let forward = *eye.forward();
            let (about, angle) = match axis {
                // The turn is seen along the view: an axis pointing away turns with it.
                Some(x) => (x, turned * if x.dot(forward) < 0.0 { -1.0 } else { 1.0 }),
                None => (forward, turned),
            };
            let angle = typed.map_or(angle, f32::to_radians);
            g.value = angle.to_degrees();
            let pivot = g.pivot;
            g.motion = Some(about_pivot(
                pivot,
                Affine3A::from_quat(Quat::from_axis_angle(about, angle)),
            ));
            Box::new(move |_, p, w| pivot + Quat::from_axis_angle(about, angle * w) * (p - pivot))
        }
        GestureKind::Scale => {
            let from = (g.cursor - pivot_px).length().max(1.0);
            let factor = typed.unwrap_or((now - pivot_px).length() / from);
            g.value = factor;
            let pivot = g.pivot;
            let scale = axis.map_or(Vec3::splat(factor), |a| Vec3::ONE + a * (factor - 1.0));
            g.motion = Some(about_pivot(pivot, Affine3A::from_scale(scale)));
            Box::new(move |_, p, w| {
                let d = p - pivot;
                // The selection (w = 1) scales by the factor itself, to the bit.
                let factor = if w == 1.0 {
                    factor
                } else {
                    1.0 + (factor - 1.0) * w
                };
                match axis {
                    Some(a) => p + a * d.dot(a) * (factor - 1.0),
                    None => pivot + d * factor,
                }
            })
        }
        GestureKind::Extrude(dirs) => {
            let mean = dirs.iter().sum::<Vec3>().normalize_or(Vec3::Z);
            let distance = typed.unwrap_or_else(|| {
                (on_plane(now).unwrap_or(g.pivot) - on_plane(g.cursor).unwrap_or(g.pivot)).dot(mean)
            });
            g.value = distance;
            let dirs = dirs.clone();
            Box::new(move |i, p, _| p + dirs[i] * distance)
        }
        GestureKind::Inset(dirs) => {
            let from = (g.cursor - pivot_px).length().max(1.0);
            let closer = (1.0 - (now - pivot_px).length() / from).clamp(0.0, 0.95);
            let fraction = typed.map_or(closer, |x| x.clamp(0.0, 0.95));
            g.value = fraction;
            let dirs = dirs.clone();
            Box::new(move |i, p, _| p + dirs[i] * fraction)
        }
    };
    let m = MeshRef::new(world);
    let moves: Vec<(VertexId, Vec3)> = g
        .start
        .iter()
        .enumerate()
        .filter_map(|(i, &(v, p))| {
            let w = g.follow.as_ref().map_or(1.0, |f| f.weight(i));
            // A follower out of reach that is where it started is left out of the edit.
            let idle = w == 0.0 && m.try_position(v) == Some(p);
            (!idle).then(|| (v, transform(i, p, w)))
        })
        .collect();
    match g.deform.as_mut() {
        Some(live) => {
            let targets: Vec<Vec3> = moves.iter().map(|(_, p)| *p).collect();
            // A frame whose solve is not finite moves nothing; without an iteration only the
            // handle moves (the rest is where it was).
            let moves = live.solve(&targets, iterations).ok().map(|mut moves| {
                if iterations == 0 {
                    moves.truncate(targets.len());
                }
                moves
            });
            if let Some(mut anchors) = world.get_resource_mut::<Anchors>() {
                anchors.progress = DeformProgress::of(live);
            }
            moves
        }
        None => Some(moves),
    }
}

/// `transform` about `pivot`: the pivot stays.
fn about_pivot(pivot: Vec3, transform: Affine3A) -> Affine3A {
    Affine3A::from_translation(pivot) * transform * Affine3A::from_translation(-pivot)
}
