//! COLLADA (`.dae`, 1.4.1 and 1.5) reading, on `roxmltree`.
//!
//! The document is parsed whole into a read-only tree (`roxmltree`: no DOM mutation, no
//! allocation per text node beyond what entities need, ~2× faster than a DOM with owned
//! strings), then read in three steps: [`scene`] walks the visual scene and lists where each
//! geometry is placed (transforms composed, Y-up); [`geometry`] reads each placed geometry's
//! mesh once into a [`Part`]; the parts are appended here, each copy's
//! positions transformed (normals by the inverse transpose, and the winding reversed under a
//! mirroring transform so faces keep facing out).
//!
//! Several placed geometries become one mesh of several components: the editor holds one mesh
//! at a time, and the course scenes hold one mesh each beside a camera and a light. The notes
//! name the objects merged, and each face keeps its object (the node's name) and its material
//! (the one its primitive's symbol is bound to) as its face group, so a save to OBJ writes them
//! as `o` and `usemtl` lines. Per-corner normals and colours become per-vertex ones
//! ([`super::corners`]); UVs stay per corner.
//!
//! What is not read is said in the soup's notes: cameras, lights, materials' properties, images,
//! animations, skin weights (a skinned mesh is read in its bind pose), line primitives,
//! polygon holes, `<skew>` transforms, and geometries that are not meshes (splines, B-reps).
//! Pappus does not write COLLADA: `roxmltree` only reads, and glTF is the exchange format the
//! ecosystem has moved to.

mod geometry;
mod scene;
#[cfg(test)]
mod tests;
mod xml;

use roxmltree::{Document, Node, ParsingOptions};
use std::collections::HashMap;

use super::parts::{Part, assemble};
use super::skipped::Skipped;
use super::text::Numbers;
use crate::io::error::ParseError;
use crate::mesh::soup::PolygonSoup;
use xml::{Ids, child, children, line_of, reference};

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
    let materials = material_names(root, &ids);
    let placements: Vec<_> = scene
        .placements
        .iter()
        .map(|p| (p.geometry.id(), p.transform, p.name.as_str()))
        .collect();
    let (mut soup, parts) = assemble(&placements, |id| {
        let geometry = document.get_node(id);
        match geometry.and_then(|g| child(g, "mesh")) {
            Some(mesh) => geometry::read_mesh(mesh, &ids, &materials).map(Some),
            None => Ok(None),
        }
    })?;
    // The geometries in document order, then the scene (its library comes after theirs in
    // the files exporters write), so the note names the first mended number of the file.
    let mut numbers = Numbers::default();
    let mut read: Vec<_> = parts
        .iter()
        .filter_map(|(id, p)| Some((id, p.as_ref()?)))
        .collect();
    read.sort_unstable_by_key(|&(id, _)| id.get());
    for (_, part) in read {
        numbers.add(&part.numbers);
    }
    numbers.add(&scene.numbers);
    soup.notes.extend(numbers.note());
    soup.notes.extend(notes(root, &scene, &parts));
    Ok(soup)
}

/// The material each symbol a primitive may name stands for, by the scene's bindings
/// (`<instance_material symbol target>`): the material's `name`, else its id. A symbol bound to
/// different materials in different instances keeps its first binding.
fn material_names<'a>(root: Node<'a, '_>, ids: &Ids<'a, '_>) -> HashMap<&'a str, &'a str> {
    let mut names = HashMap::new();
    for binding in root
        .descendants()
        .filter(|n| n.has_tag_name("instance_material"))
    {
        let (Some(symbol), Some(target)) =
            (binding.attribute("symbol"), binding.attribute("target"))
        else {
            continue;
        };
        let id = reference(target);
        let name = ids.get(id).and_then(|m| m.attribute("name")).unwrap_or(id);
        names.entry(symbol).or_insert(name);
    }
    names
}

/// The sentence for the soup's notes on what was skipped.
fn notes(root: Node, scene: &scene::Scene, parts: &Parts) -> Option<String> {
    let mut skipped = Skipped::default();
    let library = |library: &'static str, element: &'static str| {
        children(root, library)
            .flat_map(move |l| children(l, element))
            .count()
    };
    skipped.count("camera(s)", library("library_cameras", "camera"));
    skipped.count("light(s)", library("library_lights", "light"));
    skipped.count(
        "material(s) (their names kept as face groups, not their properties)",
        library("library_materials", "material"),
    );
    skipped.count("image(s)", library("library_images", "image"));
    skipped.count("animation(s)", library("library_animations", "animation"));
    skipped.count(
        "skin or morph controller(s) (their mesh read in its bind pose)",
        scene.controlled,
    );
    for part in parts.values().flatten() {
        skipped.add(&part.skipped);
    }
    skipped.count("<skew> transform(s) (not applied)", scene.skews);
    skipped.count(
        "geometry(ies) that are not polygon meshes",
        parts.values().filter(|p| p.is_none()).count(),
    );
    skipped.note()
}
