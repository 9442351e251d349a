//! The real editor in a window (Xvfb + Mesa's software Vulkan): select an edge, flip it with its
//! shortcut, and check the screenshots. Skipped, with a notice, where `xvfb-run` is missing.

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

#[test]
fn flip_through_its_shortcut_changes_the_picture() {
    if Command::new("xvfb-run").arg("--help").output().is_err() {
        println!("NOTICE: xvfb-run is not installed; skipping the windowed screenshot test");
        return;
    }
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("screenshot");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let (before, after) = (dir.join("before.png"), dir.join("after.png"));
    // The icosphere's input vertices 0 and 11 share an interior edge (a face of the icosahedron).
    let script = format!(
        "wait:10;select-edge:0,11;wait:3;shot:{};key:Alt+R;wait:4;shot:{};exit",
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
    if Command::new("xvfb-run").arg("--help").output().is_err() {
        println!("NOTICE: xvfb-run is not installed; skipping the windowed extrusion test");
        return;
    }
    // Face mode, a box over the torus's right side, E, 0.3 typed, Enter.
    let script = "wait:10;key:3;box:0.70,0.30,0.80,0.55;wait:3;key:Escape;wait:2;\
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
