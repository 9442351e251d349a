//! The real editor in a window (Xvfb + Mesa's software Vulkan): select an edge, flip it with its
//! shortcut, and check the screenshots. Skipped, with a notice, where `xvfb-run` is missing;
//! under `CI=true` that is a failure.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

fn decode(path: &Path) -> (u32, u32, Vec<u8>) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    let channels = info.color_type.samples();
    // Keep RGB only.
    let rgb = buf
        .chunks(channels)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    (info.width, info.height, rgb)
}

fn distinct_colours(rgb: &[u8]) -> usize {
    let mut set = std::collections::HashSet::new();
    for p in rgb.chunks(3) {
        set.insert([p[0], p[1], p[2]]);
    }
    set.len()
}

/// Whether `xvfb-run` is installed; without it `test` skips (a failure under CI).
fn xvfb_is_here(test: &str) -> bool {
    let here = Command::new("xvfb-run").arg("--help").output().is_ok();
    if !here {
        common::skip_because("xvfb-run", test);
    }
    here
}

/// An empty folder `name` in the tests' scratch space (emptied if a run left it).
fn fresh_folder(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn flip_through_its_shortcut_changes_the_picture() {
    if !xvfb_is_here("the windowed screenshot test") {
        return;
    }
    let dir = fresh_folder("screenshot");
    let (before, after) = (dir.join("before.png"), dir.join("after.png"));
    // The icosphere's input vertices 0 and 11 share an interior edge (a face of the icosahedron).
    // 30 frames first: under load, the first frames can come before the pipelines are ready.
    let script = format!(
        "wait:30;select-edge:0,11;wait:3;shot:{};key:Alt+R;wait:4;shot:{};exit",
        before.display(),
        after.display()
    );
    let output = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x700x24"])
        .arg(env!("CARGO_BIN_EXE_pappus"))
        .arg("shape:icosahedron")
        .env("PAPPUS_SCRIPT", &script)
        .output()
        .expect("runs the editor");
    let log = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "editor failed: {log}");
    assert!(
        log.contains("flip e"),
        "the shortcut reached the editor: {log}"
    );
    assert!(
        log.contains(": flipped to e"),
        "the flip was applied: {log}"
    );
    let (w, h, a) = decode(&before);
    let (w2, h2, b) = decode(&after);
    assert_eq!((w, h), (w2, h2));
    assert!(w >= 640 && h >= 480, "{w}x{h}");
    assert!(distinct_colours(&a) > 50, "the first screenshot is blank");
    // Compare the viewport only (right of the side panel, above the status line), so text in
    // the panels cannot pass for a change of the mesh.
    let changed = (0..h as usize - 40)
        .flat_map(|y| (360..w as usize).map(move |x| (y * w as usize + x) * 3))
        .filter(|&i| a[i..i + 3] != b[i..i + 3])
        .count();
    assert!(
        changed > 100,
        "the flip changed only {changed} viewport pixels"
    );
}

#[test]
fn a_box_selection_extrudes_through_the_keys_with_a_typed_height() {
    if !xvfb_is_here("the windowed extrusion test") {
        return;
    }
    // Face mode, a box over the torus's right side, E, 0.3 typed, Enter.
    let script = "wait:30;key:3;box:0.70,0.30,0.80,0.55;wait:3;key:Escape;wait:2;\
                  key:E;wait:3;key:0;key:.;key:3;wait:2;key:Enter;wait:3;exit";
    let output = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x700x24"])
        .arg(env!("CARGO_BIN_EXE_pappus"))
        .arg("shape:torus")
        .env("PAPPUS_SCRIPT", script)
        .output()
        .expect("runs the editor");
    let log = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "editor failed: {log}");
    let selected = log
        .split("faces selected")
        .next()
        .and_then(|s| s.rsplit(": ").next())
        .and_then(|n| n.trim().parse::<usize>().ok())
        .unwrap_or(0);
    assert!(selected > 0, "the box selected faces: {log}");
    assert!(
        log.contains(&format!("{selected} faces lifted on")),
        "the selected faces were extruded: {log}"
    );
    assert!(
        log.contains("vertices moved"),
        "the typed height moved the top: {log}"
    );
}

/// Crash recovery end to end: an editor that flips an edge and is then killed with SIGKILL
/// (no chance to save or clean up) leaves a recovery file, and `pappus recover --latest`
/// gives back the flipped mesh.
#[test]
fn an_editor_killed_after_an_edit_leaves_its_work_to_recover() {
    if !xvfb_is_here("the windowed recovery test") {
        return;
    }
    let dir = fresh_folder("killed");
    let state = dir.join("state");
    let recoveries = state.join("pappus/recovery");
    // Flip the edge between input vertices 0 and 11, then stay open (the script waits on).
    let mut editor = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x700x24"])
        .arg(env!("CARGO_BIN_EXE_pappus"))
        .arg("shape:icosahedron")
        .env(
            "PAPPUS_SCRIPT",
            "wait:30;select-edge:0,11;wait:3;key:Alt+R;wait:100000",
        )
        .env("XDG_STATE_HOME", &state)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("runs the editor");
    let start = std::time::Instant::now();
    let found = loop {
        if let Some(r) = pappus::recovery::list(&recoveries).into_iter().next() {
            break r;
        }
        if start.elapsed().as_secs() > 90 || editor.try_wait().unwrap().is_some() {
            let _ = editor.kill();
            panic!("no recovery file appeared");
        }
        std::thread::sleep(std::time::Duration::from_millis(200));
    };
    // SIGKILL: the editor gets no chance to do anything more.
    let killed = Command::new("kill")
        .args(["-9", &found.info.pid.to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    editor.wait().unwrap();
    assert_eq!(found.info.name, "icosahedron");
    let recovered = dir.join("recovered.obj");
    let output = Command::new(env!("CARGO_BIN_EXE_pappus"))
        .args(["recover", "--latest", "-o"])
        .arg(&recovered)
        .env("XDG_STATE_HOME", &state)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let expected = dir.join("expected.obj");
    let output = Command::new(env!("CARGO_BIN_EXE_pappus"))
        .args(["process", "shape:icosahedron", "-o"])
        .arg(&expected)
        .arg("flip:0,11")
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let read = |p: &Path| pappus::io::read(p).unwrap();
    assert_eq!(
        common::canonical(&read(&recovered)),
        common::canonical(&read(&expected)),
        "the recovered mesh is the flipped one"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
