//! One COLLADA `<geometry>`'s `<mesh>` read into a [`Part`]: its positions and its polygons,
//! with the normals, texture coordinates and colours its corners name.
//!
//! A `<mesh>` holds `<source>`s (a `<float_array>` read through an `<accessor>`'s count,
//! stride and offset), one `<vertices>` (the `POSITION` source, and any per-vertex `NORMAL`,
//! `TEXCOORD`, `COLOR`), and primitives whose `<p>` lists every corner as a tuple of indices,
//! one per input `offset` (COLLADA 1.4.1 §4.2, 1.5 §5): `<triangles>`, `<polylist>` (a
//! `<vcount>` per polygon), `<polygons>` (a `<p>` per polygon; a `<ph>`'s `<h>` holes are
//! dropped and counted), `<trifans>` and `<tristrips>` (a `<p>` per fan or strip, turned into
//! triangles as [`crate::io::strips`] says; a strip's degenerate triangles, its way of turning
//! corners, are left out). `<lines>` and
//! `<linestrips>` hold no faces and are counted.
//!
//! Of several `TEXCOORD` inputs, set 0 (or the lowest set) is read. Every position of the
//! `POSITION` source is kept in order, used or not (as Blender counts them); a corner naming a
//! position that does not exist gets `u32::MAX`, which the builder drops with its face.

use bevy::math::{Vec2, Vec3};
use roxmltree::Node;
use std::collections::HashMap;

use super::xml::{Ids, child, children, line_of, reference};
use crate::io::error::ParseError;
use crate::io::obj::channel;
use crate::io::parts::{NO_POSITION, Part};
use crate::io::strips::strip_triangles;
use crate::io::text::Numbers;
use crate::mesh::groups::Group;

/// A `<source>`'s numbers and how to read items from them.
struct Source {
    values: Vec<f32>,
    count: usize,
    stride: usize,
    offset: usize,
}

impl Source {
    /// Item `i`'s first `N` components, if it exists.
    fn item<const N: usize>(&self, i: u32) -> Option<[f32; N]> {
        let i = i as usize;
        if i >= self.count {
            return None;
        }
        let start = self.offset.checked_add(i.checked_mul(self.stride)?)?;
        let values = self.values.get(start..start.checked_add(N)?)?;
        values.try_into().ok()
    }
}

/// What a corner of a primitive reads, and from where in its index tuple.
#[derive(Clone, Copy)]
enum Reads {
    Normal,
    Uv,
    Color,
}

/// An input of a primitive (or of `<vertices>`): which value, its source, its tuple offset.
struct Input<'s> {
    reads: Reads,
    source: &'s Source,
    offset: usize,
}

/// Reads a `<geometry>` element's mesh; each primitive's faces in the group of the material its
/// `material` symbol is bound to (`materials`: symbol → name).
///
/// # Errors
/// A missing `<mesh>` is not an error (the caller checks); a malformed number, a reference to
/// an element that does not exist, or a `<vertices>` without `POSITION` is, naming its line.
pub(super) fn read_mesh(
    mesh: Node,
    ids: &Ids,
    materials: &HashMap<&str, &str>,
) -> Result<Part, ParseError> {
    let mut sources = HashMap::new();
    let mut numbers = Numbers::default();
    for node in children(mesh, "source") {
        if let Some(id) = node.attribute("id") {
            sources.insert(id, read_source(node, &mut numbers)?);
        }
    }
    let source = |node: Node, url: &str| -> Result<&Source, ParseError> {
        let id = reference(url);
        sources.get(id).ok_or_else(|| {
            let what = match ids.get(id) {
                Some(_) => "is not a <source> of this mesh",
                None => "does not exist",
            };
            ParseError::line(line_of(node), format!("source `{url}` {what}"))
        })
    };
    let vertices = child(mesh, "vertices")
        .ok_or_else(|| ParseError::line(line_of(mesh), "<mesh> without <vertices>"))?;
    let mut positions = None;
    let mut per_vertex = Vec::new();
    for input in children(vertices, "input") {
        let url = input.attribute("source").unwrap_or_default();
        match input.attribute("semantic") {
            Some("POSITION") => positions = Some(source(input, url)?),
            Some(semantic) => {
                if let Some(reads) = reads(semantic) {
                    per_vertex.push(Input {
                        reads,
                        source: source(input, url)?,
                        offset: 0,
                    });
                }
            }
            None => {}
        }
    }
    let positions = positions.ok_or_else(|| {
        ParseError::line(line_of(vertices), "<vertices> without a POSITION input")
    })?;
    let mut part = Part::new();
    part.numbers = numbers;
    part.positions = (0..=u32::MAX)
        .map_while(|i| positions.item::<3>(i).map(Vec3::from_array))
        .collect();
    for primitive in mesh.children().filter(Node::is_element) {
        let name = primitive.tag_name().name();
        if matches!(name, "lines" | "linestrips") {
            part.skipped.count("line primitive(s)", 1);
            continue;
        }
        if !matches!(
            name,
            "triangles" | "polylist" | "polygons" | "trifans" | "tristrips"
        ) {
            continue;
        }
        let mut layout = Layout {
            stride: 1,
            vertex: None,
            inputs: Vec::new(),
            per_vertex: &per_vertex,
        };
        let mut texcoord_set = u32::MAX;
        for input in children(primitive, "input") {
            let offset = number::<usize>(input, "offset")?.unwrap_or(0);
            layout.stride = layout.stride.max(offset.saturating_add(1));
            let semantic = input.attribute("semantic").unwrap_or_default();
            if semantic == "VERTEX" {
                layout.vertex = Some(offset);
                continue;
            }
            let Some(reads) = reads(semantic) else {
                continue;
            };
            if let Reads::Uv = reads {
                // Set 0, or the lowest set given.
                let set = number::<u32>(input, "set")?.unwrap_or(0);
                if set >= texcoord_set {
                    continue;
                }
                texcoord_set = set;
                layout.inputs.retain(|i| !matches!(i.reads, Reads::Uv));
            }
            let url = input.attribute("source").unwrap_or_default();
            layout.inputs.push(Input {
                reads,
                source: source(input, url)?,
                offset,
            });
        }
        if layout.vertex.is_none() {
            return Err(ParseError::line(
                line_of(primitive),
                format!("<{name}> without a VERTEX input"),
            ));
        }
        // The material the primitive's symbol is bound to, else the symbol itself.
        let material = primitive
            .attribute("material")
            .map(|symbol| materials.get(symbol).copied().unwrap_or(symbol).to_owned());
        part.use_group(Group {
            material,
            ..Group::default()
        });
        read_primitive(primitive, &layout, &mut part)?;
    }
    Ok(part)
}

/// What a per-corner input semantic reads; `None` for those Pappus does not read (tangents,
/// binormals, a second UV set's `TEXBINORMAL`, …).
fn reads(semantic: &str) -> Option<Reads> {
    match semantic {
        "NORMAL" => Some(Reads::Normal),
        "TEXCOORD" => Some(Reads::Uv),
        "COLOR" => Some(Reads::Color),
        _ => None,
    }
}

/// How one primitive's index tuples are laid out.
struct Layout<'a, 's> {
    /// Indices per corner.
    stride: usize,
    /// The tuple offset of the `VERTEX` index.
    vertex: Option<usize>,
    /// The primitive's own per-corner inputs.
    inputs: Vec<Input<'s>>,
    /// `<vertices>`' own inputs, read at the vertex index.
    per_vertex: &'a [Input<'s>],
}

/// Reads one primitive's faces into `part`.
fn read_primitive(primitive: Node, layout: &Layout, part: &mut Part) -> Result<(), ParseError> {
    let stride = layout.stride;
    match primitive.tag_name().name() {
        "triangles" | "polylist" => {
            let Some(p) = child(primitive, "p") else {
                return Ok(());
            };
            let indices = integers(p)?;
            let corners = indices.len() / stride;
            let sizes: Vec<usize> = match child(primitive, "vcount") {
                Some(vcount) if primitive.has_tag_name("polylist") => {
                    integers(vcount)?.into_iter().map(|n| n as usize).collect()
                }
                _ => vec![3; corners / 3],
            };
            let mut start = 0usize;
            for (k, &size) in sizes.iter().enumerate() {
                let end = start.saturating_add(size);
                if end > corners {
                    part.skipped
                        .count("incomplete face(s) at the end of a <p>", sizes.len() - k);
                    break;
                }
                let face: Vec<&[u32]> = (start..end)
                    .map(|c| &indices[c * stride..(c + 1) * stride])
                    .collect();
                push_face(part, layout, &face);
                start = end;
            }
            if primitive.has_tag_name("triangles") && !corners.is_multiple_of(3) {
                part.skipped
                    .count("incomplete face(s) at the end of a <p>", 1);
            }
        }
        "polygons" | "trifans" | "tristrips" => {
            for entry in primitive.children().filter(Node::is_element) {
                let p = match entry.tag_name().name() {
                    "p" => entry,
                    "ph" => {
                        part.skipped
                            .count("polygon hole(s)", children(entry, "h").count());
                        match child(entry, "p") {
                            Some(p) => p,
                            None => continue,
                        }
                    }
                    _ => continue,
                };
                let indices = integers(p)?;
                let corners: Vec<&[u32]> = indices.chunks_exact(stride).collect();
                match primitive.tag_name().name() {
                    "polygons" => push_face(part, layout, &corners),
                    "trifans" => {
                        for i in 1..corners.len().saturating_sub(1) {
                            push_triangle(part, layout, [corners[0], corners[i], corners[i + 1]]);
                        }
                    }
                    _ => {
                        let vertex = layout.vertex.unwrap_or(0);
                        for triangle in strip_triangles(&corners, |t| t[vertex]) {
                            push_face(part, layout, &triangle);
                        }
                    }
                }
            }
        }
        _ => {}
    }
    Ok(())
}

/// Pushes a fan's triangle, unless two of its corners are one position (no face).
fn push_triangle(part: &mut Part, layout: &Layout, corners: [&[u32]; 3]) {
    let vertex = layout.vertex.unwrap_or(0);
    let [a, b, c] = corners.map(|t| t[vertex]);
    if a != b && b != c && a != c {
        push_face(part, layout, &corners);
    }
}

/// Pushes one face: each corner's position index and the values its inputs name.
fn push_face(part: &mut Part, layout: &Layout, corners: &[&[u32]]) {
    let vertex_offset = layout.vertex.unwrap_or(0);
    let count = part.positions.len();
    for tuple in corners {
        let vertex = tuple[vertex_offset];
        let (mut normal, mut uv, mut color) = (None, None, None);
        let vertex_inputs = layout.per_vertex.iter().map(|i| (i, vertex));
        let corner_inputs = layout.inputs.iter().map(|i| (i, tuple[i.offset]));
        for (input, index) in vertex_inputs.chain(corner_inputs) {
            match input.reads {
                Reads::Normal => normal = input.source.item::<3>(index).map(Vec3::from_array),
                Reads::Uv => uv = input.source.item::<2>(index).map(Vec2::from_array),
                Reads::Color => {
                    color = input
                        .source
                        .item::<3>(index)
                        .map(|c| Vec3::from_array(c.map(|v| f32::from(channel(v)))));
                }
            }
        }
        let index = if (vertex as usize) < count {
            vertex
        } else {
            NO_POSITION
        };
        part.push_corner(index, normal, uv, color);
    }
    part.end_face();
}

/// Reads a `<source>`: its `<float_array>` and its accessor's count, stride and offset.
fn read_source(source: Node, numbers: &mut Numbers) -> Result<Source, ParseError> {
    let values = match child(source, "float_array") {
        Some(array) => floats(array, numbers)?,
        None => Vec::new(),
    };
    let accessor = child(source, "technique_common").and_then(|t| child(t, "accessor"));
    let (stride, offset, count) = match accessor {
        Some(a) => {
            let stride = number::<usize>(a, "stride")?.unwrap_or(1).max(1);
            let offset = number::<usize>(a, "offset")?.unwrap_or(0);
            let count = number::<usize>(a, "count")?.unwrap_or(values.len() / stride);
            (stride, offset, count)
        }
        None => (3, 0, values.len() / 3),
    };
    Ok(Source {
        values,
        count,
        stride,
        offset,
    })
}

/// An attribute as a number, `None` when absent.
fn number<T: std::str::FromStr>(node: Node, name: &str) -> Result<Option<T>, ParseError> {
    node.attribute(name)
        .map(|text| {
            text.trim().parse::<T>().map_err(|_| {
                ParseError::line(
                    line_of(node),
                    format!("{name}=\"{text}\" is not a non-negative integer"),
                )
            })
        })
        .transpose()
}

/// An element's text as whitespace-separated floats, read by the text formats' one grammar
/// ([`Numbers`]: a decimal comma, as exporters under a European locale write, is read and
/// counted; COLLADA's arrays separate their numbers by whitespace alone).
pub(super) fn floats(node: Node, numbers: &mut Numbers) -> Result<Vec<f32>, ParseError> {
    let line = line_of(node);
    let text = node.text().unwrap_or_default();
    text.split_ascii_whitespace()
        .map(|t| {
            numbers
                .parse::<f32>(t, line)
                .ok_or_else(|| ParseError::line(line, format!("`{t}` is not a number")))
        })
        .collect()
}

/// An element's text as whitespace-separated non-negative integers; a token that does not
/// parse is an error naming the element's line.
fn integers(node: Node) -> Result<Vec<u32>, ParseError> {
    let text = node.text().unwrap_or_default();
    text.split_ascii_whitespace()
        .map(|t| {
            t.parse::<u32>().map_err(|_| {
                ParseError::line(
                    line_of(node),
                    format!("`{t}` is not an index (a non-negative integer)"),
                )
            })
        })
        .collect()
}
