//! Clicking and hovering: from a pointer position to a vertex, edge, halfedge or face.
//!
//! Bevy's `MeshPickingPlugin` finds the render entity under the pointer and raises
//! `Pointer<Click>` / `Pointer<Move>`. Its hit carries no triangle index, so the observers here
//! re-cast the ray with [`MeshRayCast`] (from the pointer's own position: the event's hit can be
//! a frame old) to get the triangle, and write a [`PickRequest`]. The exclusive
//! [`resolve_picks`] then maps the triangle to its face through [`TriangleFaces`] and chooses
//! among the face's *real* corners and sides by distance on screen — a fan diagonal of a
//! polygon is not an edge, so clicking near one selects the polygon.

use bevy::picking::events::{Click, Move, Out, Pointer};
use bevy::picking::mesh_picking::ray_cast::{MeshRayCast, MeshRayCastSettings};
use bevy::picking::pointer::PointerButton;
use bevy::prelude::*;

use crate::mesh::ids::{ElementId, FaceId, HalfedgeId};
use crate::mesh::topology::MeshRef;

use crate::editor::session::requests::Request;
use crate::editor::session::requests::SelectionEdit;
use crate::editor::session::selection::{Hover, SelectMode};
use crate::editor::view::render_sync::{RenderOf, TriangleFaces};

/// Screen distance (pixels) within which a click picks a vertex in auto mode.
pub const VERTEX_RADIUS_PX: f32 = 12.0;
/// Screen distance (pixels) within which a click picks an edge in auto mode.
pub const EDGE_RADIUS_PX: f32 = 7.0;

/// A ray hit on a render mesh, waiting to be turned into an element.
#[derive(Message, Debug, Clone, Copy, PartialEq)]
pub struct PickRequest {
    /// The render entity that was hit.
    pub render: Entity,
    /// The triangle of its render mesh.
    pub triangle: usize,
    /// The pointer position in the viewport, pixels.
    pub cursor: Vec2,
    /// The camera that saw it.
    pub camera: Entity,
    /// Select (a click), or only hover.
    pub select: bool,
}

/// What else a click depends on: the modifiers held, the transform and the box select under way.
type ClickContext<'w> = (
    Option<Res<'w, ButtonInput<KeyCode>>>,
    Option<ResMut<'w, super::transform::Gestures>>,
    Option<Res<'w, super::box_select::BoxSelect>>,
);

/// Re-casts a click's ray to find the triangle and writes a selecting [`PickRequest`].
pub fn on_click(
    click: On<Pointer<Click>>,
    renders: Query<(), With<RenderOf>>,
    cameras: Query<(&Camera, &GlobalTransform)>,
    mut ray_cast: MeshRayCast,
    mut picks: MessageWriter<PickRequest>,
    mut requests: MessageWriter<Request>,
    (keys, gestures, box_select): ClickContext<'_>,
) {
    if click.event.button != PointerButton::Primary {
        return;
    }
    // A click that confirms a transform (or the release of one that did) or ends a box selects
    // nothing: the gesture or the box has the pointer.
    if let Some(mut gestures) = gestures
        && (std::mem::take(&mut gestures.swallow_click) || gestures.active.is_some())
    {
        return;
    }
    if box_select.is_some_and(|b| b.armed) {
        return;
    }
    let target = click.entity;
    if renders.get(target).is_err() {
        return;
    }
    let cursor = click.pointer_location.position;
    match cast(
        &cameras,
        &mut ray_cast,
        click.event.hit.camera,
        target,
        cursor,
    ) {
        Some(triangle) => {
            picks.write(PickRequest {
                render: target,
                triangle,
                cursor,
                camera: click.event.hit.camera,
                select: true,
            });
        }
        // A click on the background selects nothing, unless Shift adds to the selection.
        None if !held(&keys, Modifier::Shift) => {
            requests.write(Request::Select(None));
        }
        None => {}
    }
}

/// Re-casts the pointer's ray as it moves over a mesh, for the hover highlight.
pub fn on_move(
    moved: On<Pointer<Move>>,
    renders: Query<(), With<RenderOf>>,
    cameras: Query<(&Camera, &GlobalTransform)>,
    mut ray_cast: MeshRayCast,
    mut picks: MessageWriter<PickRequest>,
) {
    let target = moved.entity;
    if renders.get(target).is_err() {
        return;
    }
    let cursor = moved.pointer_location.position;
    if let Some(triangle) = cast(
        &cameras,
        &mut ray_cast,
        moved.event.hit.camera,
        target,
        cursor,
    ) {
        picks.write(PickRequest {
            render: target,
            triangle,
            cursor,
            camera: moved.event.hit.camera,
            select: false,
        });
    }
}

/// Clears the hover highlight when the pointer leaves a mesh.
pub fn on_out(out: On<Pointer<Out>>, renders: Query<(), With<RenderOf>>, mut hover: ResMut<Hover>) {
    if renders.get(out.entity).is_ok() {
        hover.element = None;
    }
}

fn cast(
    cameras: &Query<(&Camera, &GlobalTransform)>,
    ray_cast: &mut MeshRayCast,
    camera: Entity,
    target: Entity,
    cursor: Vec2,
) -> Option<usize> {
    let (camera, transform) = cameras.get(camera).ok()?;
    let ray = camera.viewport_to_world(transform, cursor).ok()?;
    let only_target = |e: Entity| e == target;
    let settings = MeshRayCastSettings::default().with_filter(&only_target);
    ray_cast
        .cast_ray(ray, &settings)
        .first()
        .and_then(|(_, hit)| hit.triangle_index)
}

/// Turns pick requests into selections (clicks) or the hover highlight (moves).
pub fn resolve_picks(
    world: &mut World,
    mut cursor: Local<bevy::ecs::message::MessageCursor<PickRequest>>,
) {
    let picks: Vec<PickRequest> = cursor
        .read(world.resource::<Messages<PickRequest>>())
        .copied()
        .collect();
    let keys = world.get_resource::<ButtonInput<KeyCode>>();
    let (shift, ctrl, alt) = (
        held(&keys, Modifier::Shift),
        held(&keys, Modifier::Ctrl),
        held(&keys, Modifier::Alt),
    );
    for pick in picks {
        // Alt+click picks an edge whatever the mode: the loop (or, with Ctrl, the ring) through it.
        let mode = match pick.select && alt {
            true => SelectMode::Edge,
            false => *world.resource::<SelectMode>(),
        };
        let Some(element) = resolve(world, &pick, mode) else {
            continue;
        };
        let request = match (element, pick.select) {
            (_, false) => {
                world.resource_mut::<Hover>().element = Some(element);
                continue;
            }
            (ElementId::Edge(e), true) if alt && ctrl => SelectionEdit::Ring(e, shift).into(),
            (ElementId::Edge(e), true) if alt => SelectionEdit::Loop(e, shift).into(),
            (x, true) if shift => SelectionEdit::Toggle(x).into(),
            (x, true) => Request::Select(Some(x)),
        };
        world.write_message(request);
    }
}

/// A modifier key, either side.
#[derive(Clone, Copy)]
enum Modifier {
    Shift,
    Ctrl,
    Alt,
}

/// Whether `modifier` is held (never, without a keyboard).
fn held(
    keys: &Option<impl std::ops::Deref<Target = ButtonInput<KeyCode>>>,
    modifier: Modifier,
) -> bool {
    let pair = match modifier {
        Modifier::Shift => [KeyCode::ShiftLeft, KeyCode::ShiftRight],
        Modifier::Ctrl => [KeyCode::ControlLeft, KeyCode::ControlRight],
        Modifier::Alt => [KeyCode::AltLeft, KeyCode::AltRight],
    };
    keys.as_ref().is_some_and(|k| k.any_pressed(pair))
}

fn resolve(world: &mut World, pick: &PickRequest, mode: SelectMode) -> Option<ElementId> {
    let face = *world
        .get::<TriangleFaces>(pick.render)?
        .0
        .get(pick.triangle)?;
    let (camera, transform) = world
        .query::<(&Camera, &GlobalTransform)>()
        .get(world, pick.camera)
        .ok()
        .map(|(c, t)| (c.clone(), *t))?;
    let to_screen = |p: Vec3| camera.world_to_viewport(&transform, p).ok();
    let m = MeshRef::new(world);
    m.try_face(face)?;
    Some(pick_in_face(&m, face, pick.cursor, mode, to_screen))
}

/// Chooses the element of face `f` that a click at `cursor` means, given how points project to
/// the screen. Only the face's real corners and sides are candidates.
pub fn pick_in_face(
    m: &MeshRef<'_>,
    f: FaceId,
    cursor: Vec2,
    mode: SelectMode,
    to_screen: impl Fn(Vec3) -> Option<Vec2>,
) -> ElementId {
    let mut nearest_vertex = None;
    let mut nearest_side: Option<(f32, HalfedgeId)> = None;
    for h in m.face_halfedges(f) {
        let (a, b) = (m.from_vertex(h), m.to_vertex(h));
        let (Some(pa), Some(pb)) = (to_screen(m.position(a)), to_screen(m.position(b))) else {
            continue;
        };
        let dv = pb.distance(cursor);
        if nearest_vertex.is_none_or(|(d, _)| dv < d) {
            nearest_vertex = Some((dv, b));
        }
        let de = segment_distance(cursor, pa, pb);
        if nearest_side.is_none_or(|(d, _)| de < d) {
            nearest_side = Some((de, h));
        }
    }
    let face = ElementId::Face(f);
    match mode {
        SelectMode::Face => face,
        SelectMode::Vertex => nearest_vertex.map_or(face, |(_, v)| ElementId::Vertex(v)),
        SelectMode::Edge => nearest_side.map_or(face, |(_, h)| ElementId::Edge(m.edge(h))),
        SelectMode::Halfedge => nearest_side.map_or(face, |(_, h)| ElementId::Halfedge(h)),
        SelectMode::Auto => match (nearest_vertex, nearest_side) {
            (Some((d, v)), _) if d <= VERTEX_RADIUS_PX => ElementId::Vertex(v),
            (_, Some((d, h))) if d <= EDGE_RADIUS_PX => ElementId::Edge(m.edge(h)),
            _ => face,
        },
    }
}

/// Distance from `p` to the segment `a`–`b`.
pub fn segment_distance(p: Vec2, a: Vec2, b: Vec2) -> f32 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + ab * t)
}
