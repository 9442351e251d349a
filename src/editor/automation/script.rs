//! Scripted runs of the real editor, for screenshots and the windowed test.
//!
//! `PAPPUS_SCRIPT` holds steps separated by `;`, run one after another, each once the previous
//! is done; the first waits one frame (for the file named on the command line to be asked
//! for) and no step starts while a file is being read:
//!
//! | step | meaning |
//! |---|---|
//! | `wait:N` | let N frames pass |
//! | `key:NAME` | press and release a key through the same input path as a person (`key:R`, `key:3`, `key:.`, `key:Period`, `key:Enter`, `key:Escape`, `key:Delete`, `key:Backspace`, `key:Minus`, `key:Equal`, `key:F9`, `key:Right`, `key:Left`, `key:End`, `key:PageUp`, `key:PageDown`); `key:Shift+S`, `key:Ctrl+T`, `key:Alt+M` hold a modifier |
//! | `select-edge:A,B` | select the edge between the input file's vertices A and B (0-based) |
//! | `select-vertex:A` | select the input file's vertex A |
//! | `select-face:N` | select the input file's face N (0-based) |
//! | `select:ID` | select an element by id (`f12v0`) |
//! | `select-…:+…` | any of the four with `+` before its argument adds to the selection instead (`select-face:+3`) |
//! | `box:X0,Y0,X1,Y1` | box select the rectangle between these fractions of the window (0–1, from the top left), as B and a drag would; the box stays drawn until the next `key:Escape` |
//! | `uv-select:U,V` | select the face whose UV polygon holds (U, V), as a click in the UV view does (`uv-select:0.5,0.5`) |
//! | `open:PATH` | open a file (or `shape:NAME`) as Ctrl+O would |
//! | `lod:FACES` | move the level-of-detail slider (after a simplification) |
//! | `step:N`, `step:back:N`, `step:to:K`, `step:end`, `step:finish`, `step:cancel` | move the stepped run in progress (start one with `key:F9;key:Shift+S`) |
//! | `orbit:YAW,PITCH` | turn the camera about what it looks at by these degrees (`orbit:180,-60` looks from behind and below) |
//! | `zoom:F` | multiply the camera's distance to what it looks at by F (`zoom:0.5` comes twice as close) |
//! | `colour:NAME` | colour the mesh by a quantity (`colour:mean`, names as `process --quantity`; `colour:none`) |
//! | `shot:PATH` | save a screenshot of the window to PATH (PNG) and wait until it is written |
//! | `measure:N` | let N frames pass and log their mean and longest frame time |
//! | `exit` | quit |
//!
//! Example: `PAPPUS_SCRIPT='wait:5;select-edge:0,1;shot:before.png;key:Alt+R;wait:3;shot:after.png;exit'`.

use bevy::input::ButtonState;
use bevy::input::keyboard::{Key, KeyboardInput};
use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, save_to_disk};
use bevy::window::PrimaryWindow;
use std::path::PathBuf;

use crate::mesh::ids::{ElementId, parse_element};
use crate::mesh::topology::MeshRef;

use crate::edit::Edit;
use crate::ops::geometry::Quantity;

use crate::editor::input::key_names::chord;
use crate::editor::session::requests::Request;
use crate::editor::session::requests::{SelectionEdit, StepMove};
use crate::editor::session::selection::ActiveMesh;

/// One scripted step (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub enum ScriptStep {
    /// Let frames pass.
    Wait(u32),
    /// Press and release a key, holding a modifier (Shift or Control) if given.
    Key(Option<KeyCode>, KeyCode),
    /// Select an element, alone or (`add`) added to the selection.
    Select {
        /// The element.
        target: Target,
        /// Whether it joins the selection rather than replacing it.
        add: bool,
    },
    /// Box select between two corners, as fractions of the window.
    Box(Vec2, Vec2),
    /// Select the face at a point of the UV layout.
    UvSelect(f32, f32),
    /// Open a file.
    Open(PathBuf),
    /// Move the level-of-detail slider.
    Lod(usize),
    /// Move the stepped run.
    Step(StepMove),
    /// Multiply the camera's distance to its focus (below 1: closer).
    Zoom(f32),
    /// Turn the camera about its focus by these degrees (yaw, pitch).
    Orbit(f32, f32),
    /// Colour by a quantity (or by nothing).
    Colour(Option<Quantity>),
    /// Save a screenshot.
    Shot(PathBuf),
    /// Measure the mean frame time over N frames.
    Measure(u32),
    /// Quit.
    Exit,
}

/// An element a script selects: by the input file's numbering (a freshly opened mesh lists
/// its vertices and faces in file order) or by id.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// The edge between two input vertices.
    Edge(u32, u32),
    /// An input vertex.
    Vertex(u32),
    /// An input face.
    Face(u32),
    /// An element by id.
    Id(ElementId),
}

impl Target {
    /// Reads a `select…` step's argument (`+` already taken off).
    fn parse(step: &str, arg: &str) -> Option<Target> {
        let number = |x: &str| x.trim().parse().ok();
        match step {
            "select-edge" => {
                let (a, b) = arg.split_once(',')?;
                Some(Target::Edge(number(a)?, number(b)?))
            }
            "select-vertex" => number(arg).map(Target::Vertex),
            "select-face" => number(arg).map(Target::Face),
            "select" => parse_element(arg.trim()).map(Target::Id),
            _ => None,
        }
    }

    /// The element in the active mesh, or a warning naming what is missing.
    fn find(self, world: &World) -> Result<ElementId, String> {
        match self {
            Target::Edge(a, b) => input_edge(world, a, b)
                .ok_or_else(|| format!("no edge between input vertices {a} and {b}")),
            Target::Vertex(a) => input_element::<crate::mesh::Vertex>(world, a)
                .map(|v| ElementId::Vertex(crate::mesh::VertexId(v)))
                .ok_or_else(|| format!("no input vertex {a}")),
            Target::Face(n) => input_element::<crate::mesh::Face>(world, n)
                .map(|f| ElementId::Face(crate::mesh::FaceId(f)))
                .ok_or_else(|| format!("no input face {n}")),
            Target::Id(x) => Ok(x),
        }
    }
}

/// The steps still to run.
#[derive(Resource, Debug, Default)]
pub struct Script {
    steps: std::collections::VecDeque<ScriptStep>,
    waiting: u32,
    shots_pending: usize,
    measuring: Option<(u32, std::time::Instant)>,
    /// The process's CPU time when the measurement began.
    measuring_cpu: Option<f64>,
    /// While measuring: when this frame's script run began, and the longest frame so far (ms).
    frame_clock: Option<(std::time::Instant, f64)>,
    /// Keys to release at the next step (so a held modifier is seen with its key).
    release: Vec<KeyCode>,
}

/// Screenshots requested by the script that are not yet on disk.
#[derive(Resource, Debug, Default, Clone)]
pub struct PendingShots(pub std::sync::Arc<std::sync::atomic::AtomicUsize>);

impl Script {
    /// Whether steps, waits or screenshots are still to come (the editor then draws every
    /// frame instead of waiting for input).
    pub fn is_running(&self) -> bool {
        !self.steps.is_empty()
            || self.waiting > 0
            || self.shots_pending > 0
            || self.measuring.is_some()
            || !self.release.is_empty()
    }

    /// Parses a script (see the module doc).
    ///
    /// # Errors
    /// The step that could not be read.
    pub fn parse(text: &str) -> Result<Script, String> {
        let mut steps = std::collections::VecDeque::new();
        for raw in text.split(';').map(str::trim).filter(|s| !s.is_empty()) {
            let (name, arg) = raw.split_once(':').unwrap_or((raw, ""));
            let bad = || format!("bad script step `{raw}`");
            steps.push_back(match name {
                "wait" => ScriptStep::Wait(arg.parse().map_err(|_| bad())?),
                "measure" => ScriptStep::Measure(arg.parse().map_err(|_| bad())?),
                // A key, read as the keymap reads declared keys, with at most one modifier.
                "key" => {
                    let c = chord(arg).ok_or_else(bad)?;
                    let held: Vec<KeyCode> = [
                        (c.shift, KeyCode::ShiftLeft),
                        (c.ctrl, KeyCode::ControlLeft),
                        (c.alt, KeyCode::AltLeft),
                    ]
                    .into_iter()
                    .filter_map(|(held, k)| held.then_some(k))
                    .collect();
                    match held.as_slice() {
                        [] => ScriptStep::Key(None, c.key),
                        [modifier] => ScriptStep::Key(Some(*modifier), c.key),
                        _ => return Err(bad()),
                    }
                }
                "select" | "select-edge" | "select-vertex" | "select-face" => {
                    let (add, arg) = match arg.trim().strip_prefix('+') {
                        Some(rest) => (true, rest),
                        None => (false, arg),
                    };
                    let target = Target::parse(name, arg).ok_or_else(bad)?;
                    ScriptStep::Select { target, add }
                }
                "box" => {
                    let v: Vec<f32> = arg
                        .split(',')
                        .map(|x| {
                            x.trim()
                                .parse()
                                .ok()
                                .filter(|x: &f32| (0.0..=1.0).contains(x))
                        })
                        .collect::<Option<_>>()
                        .ok_or_else(bad)?;
                    match v[..] {
                        [x0, y0, x1, y1] => ScriptStep::Box(Vec2::new(x0, y0), Vec2::new(x1, y1)),
                        _ => return Err(bad()),
                    }
                }
                "uv-select" => {
                    let (u, v) = arg.split_once(',').ok_or_else(bad)?;
                    ScriptStep::UvSelect(
                        u.trim().parse().map_err(|_| bad())?,
                        v.trim().parse().map_err(|_| bad())?,
                    )
                }
                "shot" => ScriptStep::Shot(PathBuf::from(arg)),
                "open" => ScriptStep::Open(PathBuf::from(arg)),
                "lod" => ScriptStep::Lod(arg.parse().map_err(|_| bad())?),
                "step" => ScriptStep::Step(match arg.split_once(':') {
                    Some(("back", n)) => StepMove::Back(n.parse().map_err(|_| bad())?),
                    Some(("to", k)) => StepMove::To(k.parse().map_err(|_| bad())?),
                    None if arg == "end" => StepMove::Forward(usize::MAX),
                    None if arg == "finish" => StepMove::Finish,
                    None if arg == "cancel" => StepMove::Cancel,
                    None => StepMove::Forward(arg.parse().map_err(|_| bad())?),
                    Some(_) => return Err(bad()),
                }),
                "orbit" => {
                    let (yaw, pitch) = arg.split_once(',').ok_or_else(bad)?;
                    ScriptStep::Orbit(
                        yaw.trim().parse().map_err(|_| bad())?,
                        pitch.trim().parse().map_err(|_| bad())?,
                    )
                }
                "zoom" => ScriptStep::Zoom(
                    arg.parse()
                        .ok()
                        .filter(|f: &f32| *f > 0.0 && f.is_finite())
                        .ok_or_else(bad)?,
                ),
                "colour" if arg == "none" => ScriptStep::Colour(None),
                "colour" => {
                    ScriptStep::Colour(Some(crate::ops::registry::quantity(arg).ok_or_else(bad)?))
                }
                "exit" => ScriptStep::Exit,
                _ => return Err(bad()),
            });
        }
        Ok(Script {
            steps,
            // The first frame's requests (the file to open) are applied after the script's
            // first run: wait for them.
            waiting: 1,
            shots_pending: 0,
            measuring: None,
            measuring_cpu: None,
            frame_clock: None,
            release: Vec::new(),
        })
    }
}

/// Runs the script a step at a time (in the `Input` set, so pressed keys are seen this frame).
pub fn run_script(world: &mut World) {
    let Some(mut script) = world.remove_resource::<Script>() else {
        return;
    };
    if let Some((last, longest)) = script.frame_clock {
        let now = std::time::Instant::now();
        let frame = (now - last).as_secs_f64() * 1000.0;
        script.frame_clock = Some((now, longest.max(frame)));
    }
    let pending = world.resource::<PendingShots>().0.clone();
    for key in std::mem::take(&mut script.release) {
        send_key(world, key, ButtonState::Released);
    }
    loop {
        if script.waiting > 0 {
            script.waiting -= 1;
            break;
        }
        if let Some((frames, start)) = script.measuring.take() {
            let longest = script.frame_clock.take().map_or(0.0, |(_, l)| l);
            log_measurement(world, frames, start, longest, script.measuring_cpu);
        }
        if script.shots_pending > 0 && pending.load(std::sync::atomic::Ordering::SeqCst) > 0 {
            break;
        }
        script.shots_pending = 0;
        if crate::editor::pipeline::opening::busy(world).is_some() {
            break;
        }
        let Some(step) = script.steps.pop_front() else {
            break;
        };
        if !run_step(world, &mut script, step, &pending) {
            break;
        }
    }
    world.insert_resource(script);
}

/// Logs the mean and the longest frame time (and the process's CPU time a frame) of a
/// `measure:N` step.
fn log_measurement(
    world: &mut World,
    frames: u32,
    start: std::time::Instant,
    longest: f64,
    cpu_then: Option<f64>,
) {
    let ms = start.elapsed().as_secs_f64() * 1000.0 / f64::from(frames.max(1));
    bevy::log::info!(
        "measure: mean frame time {ms:.1} ms over {frames} frames (the longest {longest:.1} ms)"
    );
    if let (Some(now), Some(then)) = (super::frame_stats::process_cpu_ms(), cpu_then) {
        let cpu = (now - then) / f64::from(frames.max(1));
        bevy::log::info!("measure: process CPU {cpu:.1} ms a frame (all threads)");
    }
    super::frame_stats::log_breakdown(world);
}

/// Selects `element` for a script step (alone, or added to the selection), or warns with
/// what is missing.
fn script_select(world: &mut World, element: Result<ElementId, String>, add: bool) {
    match element {
        Ok(x) if add => {
            world.write_message(Request::Selection(SelectionEdit::Add(vec![x])));
        }
        Ok(x) => {
            world.write_message(Request::Select(Some(x)));
        }
        Err(missing) => bevy::log::warn!("script: {missing}"),
    }
}

/// Runs one step; `false` when the script yields the rest of the frame (a screenshot, exit).
fn run_step(
    world: &mut World,
    script: &mut Script,
    step: ScriptStep,
    pending: &std::sync::Arc<std::sync::atomic::AtomicUsize>,
) -> bool {
    match step {
        ScriptStep::Wait(n) => script.waiting = n,
        ScriptStep::Measure(n) => {
            script.waiting = n;
            script.measuring = Some((n, std::time::Instant::now()));
            script.frame_clock = Some((std::time::Instant::now(), 0.0));
            script.measuring_cpu = super::frame_stats::process_cpu_ms();
            super::frame_stats::clear_history(world);
        }
        ScriptStep::Key(modifier, key) => {
            // This frame: the modifier and the key go down; next step: both come up.
            for k in modifier.into_iter().chain([key]) {
                send_key(world, k, ButtonState::Pressed);
            }
            script.release = modifier.into_iter().chain([key]).collect();
            script.waiting = 2;
        }
        ScriptStep::Select { target, add } => {
            let element = target.find(world);
            script_select(world, element, add);
            script.waiting = 1;
        }
        ScriptStep::UvSelect(u, v) => {
            let layout = world.resource::<crate::editor::panels::uv_view::UvLayout>();
            let face = crate::editor::panels::uv_view::face_at(layout, Vec2::new(u, v))
                .map(ElementId::Face)
                .ok_or_else(|| format!("no face at UV ({u}, {v})"));
            script_select(world, face, false);
            script.waiting = 1;
        }
        ScriptStep::Lod(faces) => {
            let refine = crate::ops::decimate::Refine::to(Some(faces));
            world.write_message(Request::Edit(Edit::Operation(refine)));
            script.waiting = 2;
        }
        ScriptStep::Step(movement) => {
            world.write_message(Request::Step(movement));
            script.waiting = 2;
        }
        ScriptStep::Orbit(yaw, pitch) => {
            crate::editor::view::scene::move_orbit(world, |orbit| {
                orbit.yaw += yaw.to_radians();
                orbit.pitch = (orbit.pitch + pitch.to_radians()).clamp(-1.55, 1.55);
            });
            script.waiting = 1;
        }
        ScriptStep::Zoom(factor) => {
            crate::editor::view::scene::move_orbit(world, |orbit| orbit.radius *= factor);
            script.waiting = 1;
        }
        ScriptStep::Colour(quantity) => {
            world
                .resource_mut::<crate::editor::view::colouring::ColorBy>()
                .0 = quantity;
            script.waiting = 2;
        }
        ScriptStep::Open(path) => {
            world.write_message(Request::Open(path));
            script.waiting = 2;
        }
        ScriptStep::Box(from, to) => {
            let size = world
                .query_filtered::<&Window, With<PrimaryWindow>>()
                .iter(world)
                .next()
                .map(|w| Vec2::new(w.width(), w.height()))
                .unwrap_or(Vec2::ONE);
            let (a, b) = (from * size, to * size);
            let elements = crate::editor::gestures::box_select::elements_in(world, a, b);
            *world.resource_mut::<crate::editor::gestures::box_select::BoxSelect>() =
                crate::editor::gestures::box_select::BoxSelect {
                    armed: true,
                    drag: Some((a, b)),
                };
            world.write_message(Request::Selection(SelectionEdit::Replace(elements)));
            script.waiting = 2;
        }
        ScriptStep::Shot(path) => {
            pending.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
            let counter = pending.clone();
            let mut save = save_to_disk(path);
            world.spawn(Screenshot::primary_window()).observe(
                move |captured: On<bevy::render::view::screenshot::ScreenshotCaptured>| {
                    save(captured);
                    counter.fetch_sub(1, std::sync::atomic::Ordering::SeqCst);
                },
            );
            script.shots_pending = 1;
            return false;
        }
        ScriptStep::Exit => {
            world.write_message(AppExit::Success);
            return false;
        }
    }
    true
}

fn send_key(world: &mut World, key: KeyCode, state: ButtonState) {
    let window = world
        .query_filtered::<Entity, With<PrimaryWindow>>()
        .iter(world)
        .next()
        .unwrap_or(Entity::PLACEHOLDER);
    world.write_message(KeyboardInput {
        key_code: key,
        logical_key: Key::Unidentified(bevy::input::keyboard::NativeKey::Unidentified),
        state,
        text: None,
        repeat: false,
        window,
    });
}

/// The element of kind `K` at `index` in the input file: a freshly built mesh lists its
/// vertices and faces in file order, so the index is the position in that list.
fn input_element<K: bevy::prelude::Component>(world: &World, index: u32) -> Option<Entity> {
    let mesh = world.resource::<ActiveMesh>().0?;
    crate::mesh::members::of_kind::<K, _>(world, mesh, |e| e)
        .get(index as usize)
        .copied()
}

/// The edge between the input file's vertices `a` and `b`.
fn input_edge(world: &World, a: u32, b: u32) -> Option<ElementId> {
    let va = crate::mesh::VertexId(input_element::<crate::mesh::Vertex>(world, a)?);
    let vb = crate::mesh::VertexId(input_element::<crate::mesh::Vertex>(world, b)?);
    let m = MeshRef::new(world);
    m.find_halfedge(va, vb).map(|h| ElementId::Edge(m.edge(h)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scripted_keys_and_uv_clicks_parse() {
        let script = Script::parse("uv-select:0.25, 0.5").unwrap();
        assert_eq!(script.steps[0], ScriptStep::UvSelect(0.25, 0.5));
        assert!(Script::parse("uv-select:0.25").is_err());
        let script = Script::parse("select-edge:0, 5;select-face:+3;select:+f12v0").unwrap();
        let picks: Vec<ScriptStep> = script.steps.into_iter().collect();
        assert_eq!(
            picks,
            vec![
                ScriptStep::Select {
                    target: Target::Edge(0, 5),
                    add: false
                },
                ScriptStep::Select {
                    target: Target::Face(3),
                    add: true
                },
                ScriptStep::Select {
                    target: Target::Id(parse_element("f12v0").unwrap()),
                    add: true
                },
            ]
        );
        assert!(Script::parse("select-face:x").is_err());
        let script = Script::parse("key:M;key:Ctrl+Z;key:Ctrl+Y").unwrap();
        let keys: Vec<ScriptStep> = script.steps.into_iter().collect();
        assert_eq!(
            keys,
            vec![
                ScriptStep::Key(None, KeyCode::KeyM),
                ScriptStep::Key(Some(KeyCode::ControlLeft), KeyCode::KeyZ),
                ScriptStep::Key(Some(KeyCode::ControlLeft), KeyCode::KeyY),
            ]
        );
        // One modifier at most, and only the three the keymap knows.
        for bad in ["key:Ctrl+Shift+S", "key:Hyper+S", "key:Shift+", "key:MM"] {
            assert!(Script::parse(bad).is_err(), "{bad}");
        }
    }
}
