//! Wavefront OBJ, read with `tobj` and written here.
//!
//! `tobj` renumbers vertices in order of first use, drops unreferenced ones, splits the file
//! into models at `o`/`g`/`usemtl` (duplicating vertices shared across them) and rejects the
//! whole file for one out-of-range face. Pappus wants the file's own numbering (scripts name
//! vertices by it), every vertex (unreferenced ones are counted as repairs by the builder) and
//! one connected mesh. So a first pass here lists the `v` lines and each `f` line's vertex
//! numbers (the part before the first `/`; negative numbers count back from the last vertex
//! defined so far, positive ones may name a vertex defined later). Faces that name a missing
//! vertex, or have fewer than 3 corners, stay in the soup in file order (a missing vertex
//! becomes its 0-based number, or `u32::MAX` when that does not fit) for the builder to drop
//! and count. `tobj`'s first-use numbering is mapped back to the file's and checked against
//! the first pass.
//!
//! `tobj` reads the file as it stands on a second thread while the first pass runs (after it
//! while the other core warms memory, see [`crate::process_memory::warm`]), and that reading
//! serves when the file is one object of well-formed faces (most files: on the bunny the read
//! then takes about as long as `tobj` alone, not first pass + `tobj`). Otherwise the
//! well-formed faces alone are written out and handed to `tobj` as one model (grouping
//! statements left out). The first pass is the shorter of the two; while `tobj` finishes, it
//! faults in memory for the mesh about to be built ([`crate::process_memory::warm_while`]).
//!
//! Attributes, read in the same first pass: `vt u v` (a `w` is ignored) named by the corners
//! (`f v/vt`, `v/vt/vn`) become the soup's corner UVs; `vn` named by the corners (`v//vn`,
//! `v/vt/vn`) become vertex normals (a vertex whose corners name different normals takes their
//! normalised mean, and the soup's notes say how many did); `v x y z r g b` gives a vertex
//! colour (0–1 per channel, rounded to 8 bits: see [`crate::mesh::attributes`]). A corner that
//! names a `vt` or `vn` the file does not define (or number 0) is an error naming its line.
//!
//! Objects, groups, materials and smoothing groups (`o`, `g`, `usemtl`, `s`, and the `mtllib`
//! lines) become the soup's face groups ([`groups`]): every face keeps the names it was read
//! under, and the writer puts the statements back. The parts are merged into one mesh; the
//! `.mtl` files are referenced, never opened or rewritten.
//!
//! A line ending in `\` continues on the next. Ignored, and counted in the soup's notes: points
//! and lines, and any other statement; a vertex's `w` is ignored. A malformed `v`, `vt`, `vn`
//! or `f` line is an error naming its line.

mod groups;

use bevy::math::{Vec2, Vec3};
use std::borrow::Cow;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::sync::atomic::{AtomicBool, Ordering};

use super::corners::attach_corner_normals;
use super::skipped::Skipped;
use super::text::{Numbers, cap, check_text, lines};
use crate::io::error::ParseError;
use crate::mesh::soup::PolygonSoup;
use crate::process_memory;
use groups::{GroupReader, GroupWriter, writable_in_order};

/// The `f` lines, flat: each face's line and its corners as 0-based vertex numbers, not yet
/// range-checked ([`NO_VERTEX`] for a number that can name no vertex, such as `0`).
#[derive(Default)]
struct RawFaces {
    lines: Vec<usize>,
    /// Face `i`'s corners are `corners[starts[i]..starts[i + 1]]` (`starts` begins with 0).
    starts: Vec<usize>,
    corners: Vec<u64>,
}

/// Sets its flag when dropped.
struct SetOnDrop<'a>(&'a AtomicBool);

impl Drop for SetOnDrop<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Release);
    }
}

/// A corner number that names no vertex of any file.
const NO_VERTEX: u64 = u64::MAX;

impl RawFaces {
    /// Each face's line and corners, in file order.
    fn iter(&self) -> impl Iterator<Item = (usize, &[u64])> {
        self.lines
            .iter()
            .zip(self.starts.windows(2))
            .map(|(&line, s)| (line, &self.corners[s[0]..s[1]]))
    }

    /// Whether a face's corners are at least three, each naming one of `count` vertices.
    fn well_formed(corners: &[u64], count: u64) -> bool {
        corners.len() >= 3 && corners.iter().all(|&i| i < count)
    }
}

/// A corner's texture coordinate or normal reference, resolved to a 0-based number but not yet
/// range-checked (a positive number may name a `vt`/`vn` defined later).
#[derive(Clone, Copy)]
struct Reference {
    index: i64,
    /// The number as written.
    written: i64,
    line: usize,
}

/// The `vt`s or `vn`s each corner names, in file order: empty until a corner names one (most
/// files name none, and a list of nothing per corner would cost the bunny 13 MB), then
/// `None` for the corners before it and those that name none.
#[derive(Default)]
struct CornerReferences(Vec<Option<Reference>>);

impl CornerReferences {
    /// Records what corner number `corner` (counted over the whole file) names.
    fn push(&mut self, corner: usize, r: Option<Reference>) {
        if r.is_some() || !self.0.is_empty() {
            self.0.resize(corner, None);
            self.0.push(r);
        }
    }

    /// Whether any corner names one.
    fn any(&self) -> bool {
        !self.0.is_empty()
    }

    /// What each of `corners` corners names.
    fn each(&self, corners: usize) -> impl Iterator<Item = Option<Reference>> + '_ {
        self.0
            .iter()
            .copied()
            .chain(std::iter::repeat(None))
            .take(corners)
    }
}

/// The `vt`, `vn` and vertex colours of a file, and what each corner names.
#[derive(Default)]
struct Extras {
    uvs: Vec<Vec2>,
    normals: Vec<Vec3>,
    /// One per `v` line; `None` for a vertex given without a colour.
    colors: Vec<Option<[u8; 3]>>,
    any_color: bool,
    corner_uv: CornerReferences,
    corner_normal: CornerReferences,
    /// Statements read past, in order of first appearance.
    skipped: Skipped,
    /// Objects, groups, materials and smoothing groups.
    groups: GroupReader,
    /// The numbers read, and those mended on the way.
    numbers: Numbers,
}

/// What a statement the reader reads past is, for the note.
fn skipped_statement(keyword: &str) -> Cow<'static, str> {
    match keyword {
        "l" => "line element(s) (`l`)".into(),
        "p" => "point element(s) (`p`)".into(),
        other => format!("unknown statement(s) `{other}`").into(),
    }
}

/// An OBJ colour channel (a fraction of full intensity, 0–1) as a byte: rounded to the nearest
/// 1/255 and clamped (NaN gives 0). `c / 255` written in the shortest form reads back as `c`.
pub(super) fn channel(v: f32) -> u8 {
    (v * 255.0).round().clamp(0.0, 255.0) as u8
}

/// Parses a `v` line's tokens after the position: nothing, a `w`, or a colour `r g b`.
fn vertex_color<'a>(
    mut tokens: impl Iterator<Item = &'a str>,
    line: usize,
    numbers: &mut Numbers,
) -> Result<Option<[u8; 3]>, ParseError> {
    let (Some(r), Some(g), Some(b)) = (tokens.next(), tokens.next(), tokens.next()) else {
        return Ok(None);
    };
    let mut c = [0u8; 3];
    for ((slot, token), what) in c.iter_mut().zip([r, g, b]).zip(["red", "green", "blue"]) {
        *slot = channel(numbers.float(Some(token), line, what)?);
    }
    Ok(Some(c))
}

/// Parses a reference to a `vt` or `vn` (`what`) in corner `token`: 1-based, or negative and
/// relative to the `defined` ones so far.
fn reference(
    part: Option<&str>,
    token: &str,
    defined: usize,
    line: usize,
    what: &str,
) -> Result<Option<Reference>, ParseError> {
    let Some(part) = part.filter(|p| !p.is_empty()) else {
        return Ok(None);
    };
    let n: i64 = part.parse().map_err(|_| {
        ParseError::line(
            line,
            format!("`{token}`: `{part}` is not a {what} reference"),
        )
    })?;
    if n == 0 {
        return Err(ParseError::line(
            line,
            format!("`{token}` names {what} 0 (they are numbered from 1)"),
        ));
    }
    let index = if n < 0 { defined as i64 + n } else { n - 1 };
    Ok(Some(Reference {
        index,
        written: n,
        line,
    }))
}

/// Checks a corner's reference against the `count` defined in the whole file.
fn resolve(r: Reference, count: usize, what: &str) -> Result<usize, ParseError> {
    usize::try_from(r.index)
        .ok()
        .filter(|&i| i < count)
        .ok_or_else(|| {
            ParseError::line(
                r.line,
                format!(
                    "{what} {} does not exist (the file defines {count})",
                    r.written
                ),
            )
        })
}

/// Parses OBJ text.
pub fn read(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    check_text(bytes)?;
    let joined = join_continuations(bytes);
    let bytes: &[u8] = &joined;
    // `tobj` reads the file as it stands on a second thread while the first pass runs here,
    // unless the other core is warming memory for what follows (then after it, if at all).
    let (first, whole_file) = if process_memory::warming() {
        (first_pass(bytes), None)
    } else {
        let tobj_done = AtomicBool::new(false);
        std::thread::scope(|scope| {
            let tobj = std::thread::Builder::new()
                .name("tobj".into())
                .spawn_scoped(scope, || {
                    // Set however `tobj` ends, a panic included.
                    let _done = SetOnDrop(&tobj_done);
                    run_tobj(bytes)
                })
                .ok();
            let first = first_pass(bytes);
            // The first pass is the shorter: fault in the mesh's pages while `tobj` finishes.
            if let (Ok((positions, faces, _)), Some(_)) = (&first, &tobj) {
                // Rows: a vertex per position, a face per face, a halfedge per corner and an
                // edge per two; the repair's and the tables' arrays are about as many again
                // per corner.
                let rows = positions.len() + faces.lines.len() + faces.corners.len() * 5 / 2;
                let bytes = rows.saturating_mul(process_memory::BYTES_PER_ROW);
                process_memory::warm_while(bytes, || !tobj_done.load(Ordering::Acquire));
            }
            (first, tobj.and_then(|t| t.join().ok()))
        })
    };
    let (positions, faces, extras) = first?;

    let count = positions.len() as u64;
    let good = |corners: &[u64]| RawFaces::well_formed(corners, count);
    // The whole file's reading serves when every face is well formed and it is one object;
    // otherwise `tobj` reads the well-formed faces alone, as one object.
    let all_good = faces.iter().all(|(_, corners)| good(corners));
    let whole_file = all_good
        .then(|| whole_file.unwrap_or_else(|| run_tobj(bytes)))
        .and_then(Result::ok)
        .and_then(|models| faces_from_tobj(models, &positions, &faces, &good).ok());
    let parsed = match whole_file {
        Some(parsed) => parsed,
        None => parse_with_tobj(&positions, &faces, &good)?,
    };
    let mut soup = if all_good {
        // Every face is `tobj`'s, in file order: its lists become the soup's.
        let mut at = 0usize;
        let face_starts = std::iter::once(0)
            .chain(parsed.sizes.iter().map(|&size| {
                at += size as usize;
                at as u32
            }))
            .collect();
        PolygonSoup {
            positions,
            indices: parsed.indices,
            face_starts,
            ..PolygonSoup::default()
        }
    } else {
        // In file order, the well-formed faces as `tobj` read them and the others as written.
        let mut soup = PolygonSoup::with_capacity(0, faces.lines.len(), faces.corners.len());
        soup.positions = positions;
        let mut parsed = parsed.faces();
        let mut corners = Vec::new();
        for (line, face) in faces.iter() {
            if good(face) {
                let Some(next) = parsed.next() else {
                    return Err(ParseError::line(line, "tobj lost this face"));
                };
                soup.push_face(next);
            } else {
                corners.clear();
                corners.extend(face.iter().map(|&i| u32::try_from(i).unwrap_or(u32::MAX)));
                soup.push_face(&corners);
            }
        }
        soup
    };
    let skipped = extras.skipped.note();
    let mended = extras.numbers.note();
    attach_extras(&mut soup, extras)?;
    soup.notes.extend(mended);
    soup.notes.extend(skipped);
    Ok(soup)
}

/// The text with every line that ends in `\\` joined to the next (the format's continuation
/// lines, which `tobj` does not read), the newlines it removed put back after the joined line
/// so that later lines keep their numbers; borrowed as it is when there are none.
fn join_continuations(bytes: &[u8]) -> Cow<'_, [u8]> {
    let continued = |line: &[u8]| line.trim_ascii_end().ends_with(b"\\");
    if !bytes.contains(&b'\\') || !bytes.split(|&b| b == b'\n').any(continued) {
        return Cow::Borrowed(bytes);
    }
    let mut out = Vec::with_capacity(bytes.len());
    let mut pending = 0usize;
    for line in bytes.split(|&b| b == b'\n') {
        if continued(line) {
            let line = line.trim_ascii_end();
            out.extend_from_slice(&line[..line.len() - 1]);
            out.push(b' ');
            pending += 1;
        } else {
            out.extend_from_slice(line);
            out.extend(std::iter::repeat_n(b'\n', pending + 1));
            pending = 0;
        }
    }
    // `split` yields a last piece after a final newline: one newline too many.
    out.pop();
    Cow::Owned(out)
}

/// The first pass over OBJ text: the `v` lines, each `f` line's vertex numbers, and the
/// attributes (see the module doc).
fn first_pass(bytes: &[u8]) -> Result<(Vec<Vec3>, RawFaces, Extras), ParseError> {
    let mut positions = Vec::new();
    let mut faces = RawFaces::default();
    faces.starts.push(0);
    let mut extras = Extras::default();
    for (line, text) in lines(bytes) {
        let mut tokens = text.split_whitespace();
        match tokens.next() {
            Some("v") => {
                positions.push(extras.numbers.position(&mut tokens, line)?);
                let color = vertex_color(tokens, line, &mut extras.numbers)?;
                extras.any_color |= color.is_some();
                extras.colors.push(color);
            }
            Some("vt") => {
                let u = extras.numbers.float(tokens.next(), line, "u")?;
                // `v` is optional in the format (a 1-D texture): 0.
                let v = match tokens.next() {
                    Some(t) => extras.numbers.float(Some(t), line, "v")?,
                    None => 0.0,
                };
                extras.uvs.push(Vec2::new(u, v));
            }
            Some("vn") => extras
                .normals
                .push(extras.numbers.position(&mut tokens, line)?),
            Some("f") => {
                let defined = positions.len() as i64;
                for token in tokens {
                    let mut parts = token.split('/');
                    let number = parts.next().unwrap_or("");
                    let n: i64 = number.parse().map_err(|_| {
                        ParseError::line(line, format!("`{token}` is not a vertex reference"))
                    })?;
                    // 1-based, or negative: relative to the vertices defined so far.
                    let i = if n < 0 { defined + n } else { n - 1 };
                    let corner = faces.corners.len();
                    faces.corners.push(u64::try_from(i).unwrap_or(NO_VERTEX));
                    let uv = reference(
                        parts.next(),
                        token,
                        extras.uvs.len(),
                        line,
                        "texture coordinate",
                    )?;
                    let normal =
                        reference(parts.next(), token, extras.normals.len(), line, "normal")?;
                    extras.corner_uv.push(corner, uv);
                    extras.corner_normal.push(corner, normal);
                }
                faces.lines.push(line);
                faces.starts.push(faces.corners.len());
                extras.groups.face();
            }
            // `text` starts with the keyword: the rest of the line is its argument.
            Some(keyword) if extras.groups.statement(keyword, &text[keyword.len()..]) => {}
            Some(keyword) => extras.skipped.count(skipped_statement(keyword), 1),
            None => {}
        }
    }
    Ok((positions, faces, extras))
}

/// Puts the file's UVs, normals, colours and face groups on the soup: UVs per corner; a normal given per
/// corner becomes its vertex's normal (exactly, when every corner of the vertex names the same
/// one; the normalised mean of its corners' normals, with a note, when they differ); colours
/// per vertex (black, with a note, for a vertex given without one). A corner without a UV in a
/// file with UVs gets (0, 0), with a note.
fn attach_extras(soup: &mut PolygonSoup, extras: Extras) -> Result<(), ParseError> {
    let Extras {
        uvs,
        normals,
        colors,
        any_color,
        corner_uv,
        corner_normal,
        groups,
        ..
    } = extras;
    soup.face_groups = groups.finish();
    let corners = soup.indices.len();
    if corner_uv.any() {
        let mut missing = 0usize;
        let mut out = Vec::with_capacity(corners);
        for r in corner_uv.each(corners) {
            match r {
                Some(r) => out.push(uvs[resolve(r, uvs.len(), "texture coordinate")?]),
                None => {
                    missing += 1;
                    out.push(Vec2::ZERO);
                }
            }
        }
        if missing > 0 {
            soup.notes.push(format!(
                "{missing} face corner(s) name no texture coordinate: given (0, 0)"
            ));
        }
        soup.corner_uvs = Some(out);
    }
    if corner_normal.any() {
        let resolved = corner_normal
            .each(corners)
            .map(|r| {
                r.map(|r| resolve(r, normals.len(), "normal").map(|i| normals[i]))
                    .transpose()
            })
            .collect::<Result<Vec<_>, _>>()?;
        attach_corner_normals(soup, resolved.into_iter());
    }
    if any_color {
        let missing = colors.iter().filter(|c| c.is_none()).count();
        if missing > 0 {
            soup.notes.push(format!(
                "{missing} vertex(es) given without a colour in a file with colours: black"
            ));
        }
        soup.vertex_colors = Some(colors.into_iter().map(|c| c.unwrap_or([0; 3])).collect());
    }
    Ok(())
}

/// Faces in the file's numbering, as `tobj` read them: face `i` is the next `sizes[i]` of
/// `indices`.
struct TobjFaces {
    indices: Vec<u32>,
    sizes: Vec<u32>,
}

impl TobjFaces {
    /// Each face's corners, in order.
    fn faces(&self) -> impl Iterator<Item = &[u32]> {
        let mut at = 0usize;
        self.sizes.iter().map(move |&size| {
            let face = &self.indices[at..at + size as usize];
            at += size as usize;
            face
        })
    }
}

/// Runs `tobj` on the vertices and the well-formed faces, and returns those faces in the
/// file's numbering. Fails if `tobj` disagrees with the first pass (a bug, not a bad file).
fn parse_with_tobj(
    positions: &[Vec3],
    faces: &RawFaces,
    good: &dyn Fn(&[u64]) -> bool,
) -> Result<TobjFaces, ParseError> {
    let Some((first, _)) = faces.iter().find(|(_, corners)| good(corners)) else {
        return Ok(TobjFaces {
            indices: Vec::new(),
            sizes: Vec::new(),
        });
    };
    let disagree =
        |what: &str| ParseError::line(first, format!("tobj and Pappus disagree: {what}"));
    let mut text =
        String::with_capacity(cap(positions.len() * 24 + faces.lines.len() * 16, 1 << 30));
    for p in positions {
        let _ = writeln!(text, "v {} {} {}", p.x, p.y, p.z);
    }
    for (_, corners) in faces.iter().filter(|(_, corners)| good(corners)) {
        text.push('f');
        for &i in corners {
            let _ = write!(text, " {}", i + 1);
        }
        text.push('\n');
    }
    let models = run_tobj(text.as_bytes()).map_err(|e| disagree(&e.to_string()))?;
    faces_from_tobj(models, positions, faces, good).map_err(|what| disagree(&what))
}

/// `tobj`'s reading of OBJ `text` as Pappus asks for it: faces as written (not triangulated, not
/// reindexed), points and lines left out, no material file opened.
fn run_tobj(mut text: &[u8]) -> Result<Vec<tobj::Model>, tobj::LoadError> {
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: true,
        ignore_lines: true,
    };
    tobj::load_obj_buf(&mut text, &options, |_| {
        Ok((Vec::new(), Default::default()))
    })
    .map(|(models, _)| models)
}

/// The well-formed `faces` in the file's numbering, from `tobj`'s `models` of them. `tobj`
/// numbers vertices in order of first use, so its numbers map back through the order in which
/// the faces first name each vertex; its positions must be the first pass's, bit for bit.
/// Fails, saying what differs, unless `tobj` made exactly one model of exactly those faces.
fn faces_from_tobj(
    models: Vec<tobj::Model>,
    positions: &[Vec3],
    faces: &RawFaces,
    good: &dyn Fn(&[u64]) -> bool,
) -> Result<TobjFaces, String> {
    let count = models.len();
    let Ok([model]) = <[tobj::Model; 1]>::try_from(models) else {
        return Err(format!("{count} models"));
    };
    let mut first_use = Vec::new();
    let mut seen = vec![false; positions.len()];
    let mut well_formed = 0usize;
    for (_, corners) in faces.iter().filter(|(_, corners)| good(corners)) {
        well_formed += 1;
        for &i in corners {
            if !std::mem::replace(&mut seen[i as usize], true) {
                first_use.push(i as u32);
            }
        }
    }
    let mesh = model.mesh;
    let same = |a: f32, b: f32| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    let agrees = mesh.positions.len() == 3 * first_use.len()
        && first_use
            .iter()
            .zip(mesh.positions.chunks_exact(3))
            .all(|(&i, q)| {
                let p = positions[i as usize];
                same(p.x, q[0]) && same(p.y, q[1]) && same(p.z, q[2])
            });
    if !agrees {
        return Err("positions".into());
    }
    let mut indices = mesh.indices;
    for k in &mut indices {
        *k = *first_use.get(*k as usize).ok_or("indices")?;
    }
    // No sizes: every face is a triangle.
    let sizes = if mesh.face_arities.is_empty() {
        vec![3; indices.len() / 3]
    } else {
        mesh.face_arities
    };
    if sizes.iter().map(|&n| n as usize).sum::<usize>() != indices.len() {
        return Err("face sizes".into());
    }
    if sizes.len() != well_formed {
        return Err("face count".into());
    }
    Ok(TobjFaces { indices, sizes })
}

/// Writes OBJ text: `v` lines (shortest exact decimal form; `v x y z r g b` with colours, each
/// channel `c / 255`), `vt` lines when the soup has corner UVs (each distinct UV once, in order
/// of first use), `vn` lines when it has vertex normals (one per position, numbered as the
/// positions), then `f` lines (1-based; `v/vt`, `v//vn` or `v/vt/vn`) with the soup's face
/// groups as `mtllib`, `o`, `g`, `usemtl` and `s` statements ([`groups`]). Every number is
/// written in the shortest form that reads back to the same `f32`, so a file Pappus wrote reads
/// back bit for bit.
pub fn write(soup: &PolygonSoup) -> Vec<u8> {
    match soup
        .face_groups
        .as_ref()
        .filter(|g| g.fits(soup.face_count()) && !writable_in_order(g))
    {
        Some(groups) => write_in_order(&faces_by_group(soup, groups)),
        None => write_in_order(soup),
    }
}

/// The soup with its faces (and their corner UVs and groups) in order of group row, stably.
fn faces_by_group(soup: &PolygonSoup, groups: &crate::mesh::groups::FaceGroups) -> PolygonSoup {
    let mut order: Vec<usize> = (0..soup.face_count()).collect();
    order.sort_by_key(|&f| groups.of_face[f]);
    let mut out = PolygonSoup::with_capacity(0, order.len(), soup.indices.len());
    out.positions.clone_from(&soup.positions);
    out.vertex_normals.clone_from(&soup.vertex_normals);
    out.vertex_colors.clone_from(&soup.vertex_colors);
    out.vertex_quality.clone_from(&soup.vertex_quality);
    out.vertex_scalars.clone_from(&soup.vertex_scalars);
    let uvs = soup
        .corner_uvs
        .as_deref()
        .filter(|u| u.len() == soup.indices.len());
    let mut sorted_uvs = uvs.map(|u| Vec::with_capacity(u.len()));
    for &f in &order {
        out.push_face(soup.face(f));
        if let (Some(uvs), Some(out)) = (uvs, &mut sorted_uvs) {
            let (a, b) = (
                soup.face_starts[f] as usize,
                soup.face_starts[f + 1] as usize,
            );
            out.extend_from_slice(&uvs[a..b]);
        }
    }
    out.corner_uvs = sorted_uvs;
    out.face_groups = Some(crate::mesh::groups::FaceGroups {
        table: groups.table.clone(),
        of_face: order.iter().map(|&f| groups.of_face[f]).collect(),
    });
    out
}

/// [`fn@write`] with the faces in the soup's order.
fn write_in_order(soup: &PolygonSoup) -> Vec<u8> {
    let n = soup.positions.len();
    let normals = soup.vertex_normals.as_deref().filter(|v| v.len() == n);
    let colors = soup.vertex_colors.as_deref().filter(|v| v.len() == n);
    let uvs = soup
        .corner_uvs
        .as_deref()
        .filter(|u| u.len() == soup.indices.len());
    let mut out = String::with_capacity(n * 64 + soup.indices.len() * 16);
    out.push_str("# written by Pappus\n");
    let groups = soup
        .face_groups
        .as_ref()
        .filter(|g| g.fits(soup.face_count()));
    let mut statements = groups.map(|g| GroupWriter::new(g, &mut out));
    for (i, p) in soup.positions.iter().enumerate() {
        let _ = write!(out, "v {} {} {}", p.x, p.y, p.z);
        if let Some(colors) = colors {
            let [r, g, b] = colors[i].map(|c| f32::from(c) / 255.0);
            let _ = write!(out, " {r} {g} {b}");
        }
        out.push('\n');
    }
    // Each corner's `vt` number (1-based), identical UVs (bit for bit) sharing one.
    let corner_vt: Option<Vec<usize>> = uvs.map(|uvs| {
        let mut number: HashMap<[u32; 2], usize> = HashMap::new();
        uvs.iter()
            .map(|uv| {
                let key = uv.to_array().map(f32::to_bits);
                let next = number.len() + 1;
                *number.entry(key).or_insert_with(|| {
                    let _ = writeln!(out, "vt {} {}", uv.x, uv.y);
                    next
                })
            })
            .collect()
    });
    for n in normals.into_iter().flatten() {
        let _ = writeln!(out, "vn {} {} {}", n.x, n.y, n.z);
    }
    let mut corner = 0usize;
    for (f, face) in soup.faces().enumerate() {
        if let Some(w) = &mut statements {
            w.before_face(f, &mut out);
        }
        out.push('f');
        for &i in face {
            let i = u64::from(i) + 1;
            let vt = corner_vt.as_ref().map(|c| c[corner]);
            corner += 1;
            let _ = match (vt, normals) {
                (None, None) => write!(out, " {i}"),
                (Some(t), None) => write!(out, " {i}/{t}"),
                (None, Some(_)) => write!(out, " {i}//{i}"),
                (Some(t), Some(_)) => write!(out, " {i}/{t}/{i}"),
            };
        }
        out.push('\n');
    }
    out.into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Faces in the file's numbering.
    type Faces = Vec<Vec<u32>>;

    /// `tobj`'s reading of the whole file, where it serves, and its reading of the well-formed
    /// faces alone: `Some(both)`, or `None` where the whole file's reading is refused.
    fn both_readings(text: &[u8]) -> Option<(Faces, Faces)> {
        let (positions, faces, _) = first_pass(text).unwrap();
        let count = positions.len() as u64;
        let good = |corners: &[u64]| RawFaces::well_formed(corners, count);
        let listed = |read: TobjFaces| read.faces().map(<[u32]>::to_vec).collect();
        let alone = listed(parse_with_tobj(&positions, &faces, &good).unwrap());
        let models = run_tobj(text).ok()?;
        let whole = listed(faces_from_tobj(models, &positions, &faces, &good).ok()?);
        Some((whole, alone))
    }

    #[test]
    fn the_whole_files_reading_is_the_well_formed_faces_reading() {
        // Polygons, relative numbers, corners with UVs and normals, an unreferenced vertex,
        // vertex colours, points and lines.
        let text = b"v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 7 7 7 0 0 1\nv 1 1 0 1 1 1\nv 0 1 0 0 0 0\n\
            vt 0 0\nvn 0 0 1\nf -5/1/1 -4/1/1 -2//1 -1\nv 2 0 0 1 1 0\nf 2 4 6\np 1\nl 1 2\n\
            f 1/1 2/1 5/1\n";
        let (whole, alone) = both_readings(text).expect("one object, every face well formed");
        assert_eq!(whole, alone);
        assert_eq!(whole, [vec![0, 1, 3, 4], vec![1, 3, 5], vec![0, 1, 4]]);
        // The soup is the same either way: what `read` gives.
        let soup = read(text).unwrap();
        assert_eq!(soup.face_count(), 3);
        assert_eq!(soup.face(0), &[0, 1, 3, 4]);
    }

    #[test]
    fn the_whole_files_reading_is_refused_for_several_objects() {
        let text = b"o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\no b\nf 2 4 3\n";
        assert_eq!(
            both_readings(text),
            None,
            "two objects: the faces alone are read"
        );
        let soup = read(text).unwrap();
        assert_eq!(soup.face(1), &[1, 3, 2]);
    }

    #[test]
    fn vertex_normals_are_written_as_vn_with_matching_indices() {
        let mut soup = PolygonSoup::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0u32, 1, 2]]);
        soup.vertex_normals = Some(vec![Vec3::Z; 3]);
        let text = String::from_utf8(write(&soup)).unwrap();
        assert_eq!(text.matches("vn 0 0 1").count(), 3);
        assert!(text.contains("f 1//1 2//2 3//3"), "{text}");
        // It reads back as the same mesh.
        let back = read(text.as_bytes()).unwrap();
        assert_eq!(back.positions, soup.positions);
        assert_eq!(back.face(0), &[0, 1, 2]);
    }

    #[test]
    fn keeps_file_order_and_unreferenced_vertices() {
        let text = b"o first\nv 0 0 0\nv 9 9 9\nv 1 0 0\nv 0 1 0\nv 1 1 0\ng a\nusemtl red\nf 5 4 3\ng b\nf 1 3 4\n";
        let soup = read(text).unwrap();
        assert_eq!(soup.positions.len(), 5);
        assert_eq!(soup.positions[1], Vec3::splat(9.0));
        assert_eq!(soup.face_count(), 2);
        assert_eq!(soup.face(0), &[4, 3, 2]);
        assert_eq!(soup.face(1), &[0, 2, 3]);
    }

    #[test]
    fn reads_quads_and_relative_indices() {
        let text = b"mtllib none.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf -4/1/1 -3/1/1 -2//1 -1\nv 2 0 0\nf 2 -1 3\nf 1/1 2/1 3/1\n";
        let soup = read(text).unwrap();
        assert_eq!(soup.face_count(), 3);
        assert_eq!(soup.face(0), &[0, 1, 2, 3]);
        assert_eq!(soup.face(1), &[1, 4, 2]);
        assert_eq!(soup.face(2), &[0, 1, 2]);
    }

    #[test]
    fn faces_may_name_vertices_defined_later() {
        let soup = read(b"f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
        assert_eq!(soup.face(0), &[0, 1, 2]);
    }

    #[test]
    fn bad_faces_stay_in_place_for_the_builder_to_drop() {
        let text =
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\nf 1 2\nf 0 1 2\nf -9 1 2\nf 3 2 1\n";
        let soup = read(text).unwrap();
        assert_eq!(soup.face_count(), 6);
        assert_eq!(soup.face(0), &[0, 1, 2]);
        assert_eq!(soup.face(1), &[0, 1, 6]);
        assert_eq!(soup.face(2), &[0, 1]);
        assert_eq!(soup.face(3), &[u32::MAX, 0, 1]);
        assert_eq!(soup.face(4), &[u32::MAX, 0, 1]);
        assert_eq!(soup.face(5), &[2, 1, 0]);
    }

    #[test]
    fn odd_but_readable_text() {
        // A Latin-1 comment, CRLF line ends, a NaN coordinate, a `w`, a colour.
        let text = b"# caf\xe9\r\nv 0 0 0 1\r\nv NaN 0 0\r\nv 0 1 0 0.5 0.5 0.5\r\nf 1 2 3\r\n";
        let soup = read(text).unwrap();
        assert!(soup.positions[1].x.is_nan());
        assert_eq!(soup.face(0), &[0, 1, 2]);
        let empty = read(b"").unwrap();
        assert_eq!((empty.positions.len(), empty.face_count()), (0, 0));
    }

    #[test]
    fn continuation_lines_join_and_later_lines_keep_their_numbers() {
        let text = b"v 0 0 0\nv 1 \\\n 0 0\nv 0 1 0\nf 1 2 \\\r\n3\nv 1 2\n";
        let err = read(text).unwrap_err();
        assert_eq!(err.location, "line 7", "{err:?}");
        let soup = read(&text[..text.len() - 6]).unwrap();
        assert_eq!(soup.positions, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert_eq!(soup.face(0), &[0, 1, 2]);
    }

    #[test]
    fn statements_read_past_are_counted_in_the_notes() {
        let text = b"mtllib m.mtl\no a\ng x\nusemtl red\ns 1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvp 0.5\nf 1 2 3\nl 1 2\nl 2 3\np 1\ng y\n";
        let soup = read(text).unwrap();
        assert_eq!(soup.face_count(), 1);
        assert_eq!(
            soup.notes,
            vec![
                "skipped: 1 unknown statement(s) `vp`, 2 line element(s) (`l`), 1 point element(s) (`p`)"
            ]
        );
    }

    /// Two objects, groups, materials switched back and forth, smoothing, two libraries, and
    /// faces before any statement.
    const GROUPED: &[u8] = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n\
f 1 2 3\n\
mtllib a.mtl\nmtllib b c.mtl\no box\ng side top\nusemtl red\ns 1\nf 1 3 4\n\
usemtl blue\nf 2 5 6\nusemtl red\nf 2 6 3\n\
o lid\ng\ns off\nf 4 3 6\n";

    #[test]
    fn objects_groups_and_materials_are_kept_per_face() {
        let soup = read(GROUPED).unwrap();
        assert!(soup.notes.is_empty(), "{:?}", soup.notes);
        let groups = soup.face_groups.as_ref().unwrap();
        assert_eq!(groups.table.material_libraries, ["a.mtl", "b c.mtl"]);
        assert_eq!(groups.of_face, [0, 1, 2, 1, 3]);
        let names: Vec<String> = groups.table.groups.iter().map(|g| g.describe()).collect();
        assert_eq!(
            names,
            [
                "no group",
                "object box · group side top · material red · smoothing 1",
                "object box · group side top · material blue · smoothing 1",
                "object lid · group  · material red · smoothing off",
            ]
        );
    }

    #[test]
    fn statements_are_written_back_where_they_were() {
        let soup = read(GROUPED).unwrap();
        let written = String::from_utf8(write(&soup)).unwrap();
        let statements: Vec<&str> = written
            .lines()
            .filter(|l| !l.starts_with('v') && !l.starts_with('#'))
            .collect();
        assert_eq!(
            statements,
            [
                "mtllib a.mtl",
                "mtllib b c.mtl",
                "f 1 2 3",
                "o box",
                "g side top",
                "usemtl red",
                "s 1",
                "f 1 3 4",
                "usemtl blue",
                "f 2 5 6",
                "usemtl red",
                "f 2 6 3",
                "o lid",
                "g",
                "s off",
                "f 4 3 6",
            ]
        );
        let back = read(written.as_bytes()).unwrap();
        assert_eq!(back.face_groups, soup.face_groups);
        assert_eq!(back.indices, soup.indices);
    }

    #[test]
    fn a_face_that_would_unset_a_name_is_written_with_its_group() {
        let mut soup = read(GROUPED).unwrap();
        // As an edit could leave it: a face of the first (nameless) group made last.
        soup.push_face(&[5, 6, 3]);
        soup.face_groups.as_mut().unwrap().of_face.push(0);
        let back = read(&write(&soup)).unwrap();
        // Faces by group row, in their order within each: the red box faces together.
        assert_eq!(back.face(1), &[5, 6, 3]);
        assert_eq!(back.face(3), &[1, 5, 2]);
        assert_eq!(back.face_groups.unwrap().of_face, [0, 0, 1, 1, 2, 3]);
    }

    #[test]
    fn malformed_lines_name_the_line() {
        let cases: [(&[u8], &str, &str); 5] = [
            (b"v 0 0 0\nv 1 x 0\n", "line 2", "`x` is not a number (y)"),
            (
                b"v 0 0 0\n\n# c\nv 1 0\n",
                "line 4",
                "expected 3 coordinates, found 2",
            ),
            (
                b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 q\n",
                "line 4",
                "`q` is not a vertex reference",
            ),
            (
                b"v 0 0 0\nf 1 2.5 3\n",
                "line 2",
                "`2.5` is not a vertex reference",
            ),
            (
                b"v 0 0 0\nv\xff 1 0 0\0",
                "byte 16",
                "NUL byte: this is not a text file",
            ),
        ];
        for (text, location, message) in cases {
            let err = read(text).unwrap_err();
            assert_eq!(
                (err.location.as_str(), err.message.as_str()),
                (location, message)
            );
        }
    }

    #[test]
    fn a_swapped_exponent_sign_reads_as_its_authors_meant_in_every_statement() {
        let text = b"v 3.1+e2 0 0\nv 0 1-e1 0\nv 0 0 1\nvt 2.5-E1 0\nvt 0 0\nvt 1 1\n\
                     f 1/1 2/2 3/3\n";
        let soup = read(text).unwrap();
        assert_eq!(
            soup.positions,
            vec![
                Vec3::new(310.0, 0.0, 0.0),
                Vec3::new(0.0, 0.1, 0.0),
                Vec3::Z
            ]
        );
        assert_eq!(soup.corner_uvs.as_ref().unwrap()[0], Vec2::new(0.25, 0.0));
        assert_eq!(
            soup.notes,
            [
                "read 3 number(s) with the exponent's sign before its `e`, read as `e` then the \
              sign (the first `3.1+e2`, line 1)"
            ]
        );
        // What cannot be read one way only is still refused, naming its line.
        let err = read(b"v 0 0 0\nv 3.1+e2.5 0 0\n").unwrap_err();
        assert_eq!(
            (err.location.as_str(), err.message.as_str()),
            ("line 2", "`3.1+e2.5` is not a number (x)")
        );
    }
}
