//! COLLADA (`.dae`, 1.4.1 and 1.5) reading, on `roxmltree`.
//!
//! The document is parsed whole into a read-only tree (`roxmltree`: no DOM mutation, no
//! allocation per text node beyond what entities need, ~2× faster than a DOM with owned
//! strings), then read in three steps: [`scene`] walks the visual scene and lists where each
//! geometry is placed (transforms composed, Y-up); [`geometry`] reads each placed geometry's
//! mesh once into a [`Part`](geometry::Part); the parts are appended here, each copy's
//! positions transformed (normals by the inverse transpose, and the winding reversed under a
//! mirroring transform so faces keep facing out).
//!
//! Several placed geometries become one mesh of several components: the editor holds one mesh
//! at a time, and the course scenes hold one mesh each beside a camera and a light. The notes
//! name the objects merged. Per-corner normals and colours become per-vertex ones
//! ([`super::corners`]); UVs stay per corner.
//!
//! What is not read is said in the soup's notes: cameras, lights, materials, images,
//! animations, skin weights (a skinned mesh is read in its bind pose), line primitives,
//! polygon holes, `<skew>` transforms, and geometries that are not meshes (splines, B-reps).
//! Pappus does not write COLLADA: `roxmltree` only reads, and glTF is the exchange format the
//! ecosystem has moved to.

mod geometry;
mod scene;
#[cfg(test)]
mod tests;

use bevy::math::{Mat3, Mat4, Vec2, Vec3};
use roxmltree::{Document, Node, ParsingOptions};
use std::collections::HashMap;

use super::ParseError;
use super::corners::{differing_normals_note, mean_normal, per_vertex};
use crate::memory_budget;
use crate::mesh::soup::PolygonSoup;
use geometry::{NO_POSITION, Part, Skipped};

/// Every element with an `id`, by id.
type Ids<'a, 'input> = HashMap<&'a str, Node<'a, 'input>>;

/// Each placed `<geometry>`'s mesh, read once (`None`: not a polygon mesh).
type Parts = HashMap<roxmltree::NodeId, Option<Part>>;

/// Reads a COLLADA document.
///
/// # Errors
/// Text that is not UTF-8 or not well-formed XML, a root that is not `<COLLADA>`, a number
/// that does not parse, a reference to an element that does not exist, or a scene too large
/// for the memory budget; each names its line.
pub fn read(bytes: &[u8]) -> Result<PolygonSoup, ParseError> {
    let text = std::str::from_utf8(bytes)
        .map_err(|e| ParseError::byte(e.valid_up_to(), "not UTF-8 text (a COLLADA file is XML)"))?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let options = ParsingOptions {
        allow_dtd: true,
        ..ParsingOptions::default()
    };
    let document = Document::parse_with_options(text, options)
        .map_err(|e| ParseError::line(e.pos().row as usize, e.to_string()))?;
    let root = document.root_element();
    if !root.has_tag_name("COLLADA") {
        return Err(ParseError::line(
            line_of(root),
            format!(
                "<{}> is not a COLLADA document (expected <COLLADA>)",
                root.tag_name().name()
            ),
        ));
    }
    let ids: Ids = root
        .descendants()
        .filter_map(|n| Some((n.attribute("id")?, n)))
        .collect();
    let scene = scene::walk(root, &ids)?;
    let mut parts = Parts::new();
    for placement in &scene.placements {
        if let std::collections::hash_map::Entry::Vacant(entry) =
            parts.entry(placement.geometry.id())
        {
            let part = match child(placement.geometry, "mesh") {
                Some(mesh) => Some(geometry::read_mesh(mesh, &ids)?),
                None => None,
            };
            entry.insert(part);
        }
    }
    check_budget(&scene, &parts)?;
    let mut merged = Merged::default();
    let mut names = Vec::new();
    for placement in &scene.placements {
        if let Some(Some(part)) = parts.get(&placement.geometry.id()) {
            merged.append(part, placement.transform);
            names.push(placement.name.as_str());
        }
    }
    let mut soup = merged.into_soup();
    soup.notes.extend(notes(root, &scene, &parts, &names));
    Ok(soup)
}

/// Refuses a scene whose copies would not fit the memory budget (instances multiply).
fn check_budget(scene: &scene::Scene, parts: &Parts) -> Result<(), ParseError> {
    let (mut faces, mut rows) = (0u64, 0u64);
    for placement in &scene.placements {
        if let Some(Some(part)) = parts.get(&placement.geometry.id()) {
            let part_faces = part.face_starts.len().saturating_sub(1) as u64;
            faces = faces.saturating_add(part_faces);
            // Vertices, a halfedge a corner, half an edge a corner, and the faces.
            let corners = part.indices.len() as u64;
            rows = rows
                .saturating_add(part.positions.len() as u64 + corners + corners / 2 + part_faces);
        }
    }
    memory_budget::check(&memory_budget::Estimate {
        what: format!("the scene's {} placed mesh(es)", scene.placements.len()),
        faces,
        rows,
        instead: "open a scene that places fewer copies",
    })
    .map_err(|refusal| ParseError::line(1, refusal.to_string()).unsupported())
}

/// The parts appended one after another, per-corner values kept until the end.
#[derive(Default)]
struct Merged {
    soup: PolygonSoup,
    normals: Option<Vec<Option<Vec3>>>,
    uvs: Option<Vec<Option<Vec2>>>,
    colors: Option<Vec<Option<Vec3>>>,
}

impl Merged {
    /// Appends a copy of `part` placed by `transform`.
    fn append(&mut self, part: &Part, transform: Mat4) {
        let base = self.soup.positions.len() as u32;
        let corners_before = self.soup.indices.len();
        let identity = transform == Mat4::IDENTITY;
        // The identity is skipped, not applied: 1·x + 0·y would turn −0 into +0.
        self.soup.positions.extend(part.positions.iter().map(|&p| {
            if identity {
                p
            } else {
                transform.transform_point3(p)
            }
        }));
        let normal_matrix = Mat3::from_mat4(transform).inverse().transpose();
        let normal_matrix = if normal_matrix.is_finite() {
            normal_matrix
        } else {
            Mat3::IDENTITY
        };
        let mirrored = transform.determinant() < 0.0;
        let order = |start: usize, end: usize| -> Vec<usize> {
            if mirrored {
                (start..end).rev().collect()
            } else {
                (start..end).collect()
            }
        };
        start_list(&mut self.normals, corners_before, &part.normals);
        start_list(&mut self.uvs, corners_before, &part.uvs);
        start_list(&mut self.colors, corners_before, &part.colors);
        for face in part.face_starts.windows(2) {
            let corners = order(face[0] as usize, face[1] as usize);
            let face_indices: Vec<u32> = corners
                .iter()
                .map(|&k| match part.indices[k] {
                    NO_POSITION => NO_POSITION,
                    v => base + v,
                })
                .collect();
            self.soup.push_face(&face_indices);
            for &k in &corners {
                if let Some(list) = &mut self.normals {
                    list.push(corner(&part.normals, k).map(|n: Vec3| {
                        if identity {
                            n
                        } else {
                            (normal_matrix * n).normalize_or_zero()
                        }
                    }));
                }
                if let Some(list) = &mut self.uvs {
                    list.push(corner(&part.uvs, k));
                }
                if let Some(list) = &mut self.colors {
                    list.push(corner(&part.colors, k));
                }
            }
        }
    }

    /// The soup, per-corner normals and colours gathered per vertex.
    fn into_soup(self) -> PolygonSoup {
        let Merged {
            mut soup,
            normals,
            uvs,
            colors,
        } = self;
        let n = soup.positions.len();
        if let Some(normals) = normals {
            let gathered = per_vertex(&soup.indices, n, normals.into_iter(), mean_normal);
            if gathered.differing > 0 {
                soup.notes.push(differing_normals_note(gathered.differing));
            }
            soup.vertex_normals = Some(
                gathered
                    .values
                    .into_iter()
                    .map(|v| v.unwrap_or(Vec3::ZERO))
                    .collect(),
            );
        }
        if let Some(uvs) = uvs {
            let missing = uvs.iter().filter(|u| u.is_none()).count();
            if missing > 0 {
                soup.notes.push(format!(
                    "{missing} face corner(s) have no texture coordinate: given (0, 0)"
                ));
            }
            soup.corner_uvs = Some(uvs.into_iter().map(|u| u.unwrap_or(Vec2::ZERO)).collect());
        }
        if let Some(colors) = colors {
            let gathered = per_vertex(&soup.indices, n, colors.into_iter(), |sum, count| {
                sum / count as f32
            });
            if gathered.differing > 0 {
                soup.notes.push(format!(
                    "{} vertex(es) had different colours at different corners: each takes their mean",
                    gathered.differing
                ));
            }
            soup.vertex_colors = Some(
                gathered
                    .values
                    .into_iter()
                    .map(|c| c.map_or([0; 3], |c| c.round().to_array().map(|v| v as u8)))
                    .collect(),
            );
        }
        soup
    }
}

/// Corner `k`'s value in a part's per-corner list, if it has one.
fn corner<T: Copy>(list: &Option<Vec<Option<T>>>, k: usize) -> Option<T> {
    list.as_ref().and_then(|l| l.get(k).copied().flatten())
}

/// Starts a merged per-corner list (`None` for the `before` corners already merged) when the
/// first part that has its values comes.
fn start_list<T: Copy>(
    list: &mut Option<Vec<Option<T>>>,
    before: usize,
    part: &Option<Vec<Option<T>>>,
) {
    if list.is_none() && part.is_some() {
        *list = Some(vec![None; before]);
    }
}

/// The sentences for the soup's notes: the objects merged, and what was skipped.
fn notes(root: Node, scene: &scene::Scene, parts: &Parts, names: &[&str]) -> Vec<String> {
    let mut skipped_in_parts = Skipped::default();
    for part in parts.values().flatten() {
        skipped_in_parts.add(part.skipped);
    }
    let not_meshes = parts.values().filter(|p| p.is_none()).count();
    let mut notes = Vec::new();
    if names.len() > 1 {
        let shown: Vec<&str> = names.iter().take(5).copied().collect();
        let more = if names.len() > 5 { ", …" } else { "" };
        notes.push(format!(
            "{} objects ({}{more}) read as one mesh of several parts",
            names.len(),
            shown.join(", ")
        ));
    }
    let mut skipped = Vec::new();
    let library = |library: &'static str, element: &'static str| {
        children(root, library)
            .flat_map(move |l| children(l, element))
            .count()
    };
    for (count, what) in [
        (library("library_cameras", "camera"), "camera(s)"),
        (library("library_lights", "light"), "light(s)"),
        (library("library_materials", "material"), "material(s)"),
        (library("library_images", "image"), "image(s)"),
        (library("library_animations", "animation"), "animation(s)"),
        (
            scene.controlled,
            "skin or morph controller(s) (their mesh read in its bind pose)",
        ),
        (skipped_in_parts.line_primitives, "line primitive(s)"),
        (skipped_in_parts.holes, "polygon hole(s)"),
        (
            skipped_in_parts.incomplete_faces,
            "incomplete face(s) at the end of a <p>",
        ),
        (scene.skews, "<skew> transform(s) (not applied)"),
        (not_meshes, "geometry(ies) that are not polygon meshes"),
    ] {
        if count > 0 {
            skipped.push(format!("{count} {what}"));
        }
    }
    if !skipped.is_empty() {
        notes.push(format!("skipped: {}", skipped.join(", ")));
    }
    notes
}

/// The first child element with this tag name.
fn child<'a, 'input>(node: Node<'a, 'input>, name: &str) -> Option<Node<'a, 'input>> {
    node.children().find(|c| c.has_tag_name(name))
}

/// The child elements with this tag name.
fn children<'a, 'input>(
    node: Node<'a, 'input>,
    name: &'static str,
) -> impl Iterator<Item = Node<'a, 'input>> {
    node.children().filter(move |c| c.has_tag_name(name))
}

/// The 1-based line an element starts on.
fn line_of(node: Node) -> usize {
    node.document().text_pos_at(node.range().start).row as usize
}

/// The id a `#id` URL names (a URL without `#` is taken as the id itself).
fn reference(url: &str) -> &str {
    url.strip_prefix('#').unwrap_or(url)
}
