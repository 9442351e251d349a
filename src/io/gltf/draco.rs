//! `KHR_draco_mesh_compression`: a primitive whose indices and attributes are one Draco stream
//! in a buffer view, decoded by [`draco_core`] (a pure-Rust port of Google's Draco decoder,
//! byte-exact with Draco 1.5.7; every bitstream version, sequential and Edgebreaker, standard
//! and valence, so what Blender, gltf-transform and gltfpack write).
//!
//! The extension names the buffer view and, for each attribute it compresses, the unique id
//! of its attribute in the stream. The primitive's accessors keep their types and counts but
//! need no data: a file that requires the extension has none, one that only uses it may keep an
//! uncompressed copy, which is then not read. The stream decodes to the primitive's vertices (in
//! Draco's order, which is not the accessors' order) and its triangles; an attribute the
//! extension does not name is read from its accessor as usual. Values come out as floats: the
//! stream's quantisation and octahedral normals are undone by the decoder, and a normalised
//! integer attribute (colours) is scaled as glTF §3.11 says.
//!
//! The decode runs under the decoder's default limits (a stream of more than 256 M points or
//! 2 GiB of values is refused), and a panic inside the decoder is caught and reported as a
//! broken stream: a third-party decoder must not take the editor's unsaved mesh down with it.

use draco_core::{DataType, DecoderBuffer, Mesh, MeshDecoder};
use gltf::mesh::Mode;

use super::buffers::Buffers;

/// The extension's name.
pub(super) const EXTENSION: &str = "KHR_draco_mesh_compression";

/// A primitive's decoded Draco stream and which of its attributes the extension maps to which
/// of the stream's.
pub(super) struct Decoded {
    mesh: Mesh,
    /// (glTF attribute semantic, the stream's unique attribute id).
    attributes: Vec<(String, u32)>,
}

/// Decodes `primitive`'s Draco stream; `None` for a primitive without the extension.
///
/// # Errors
/// The extension's object malformed or naming a buffer view that does not exist or cannot be
/// read, a primitive not drawn as triangles, or a stream the decoder refuses (named).
pub(super) fn decode(
    primitive: &gltf::Primitive,
    document: &gltf::Document,
    buffers: &Buffers,
) -> Result<Option<Decoded>, String> {
    let Some(extension) = primitive.extension_value(EXTENSION) else {
        return Ok(None);
    };
    let malformed = |what: &str| format!("{EXTENSION} of a primitive: {what}");
    let view = extension
        .get("bufferView")
        .and_then(serde_json::Value::as_u64)
        .ok_or_else(|| malformed("no `bufferView` number"))?;
    let attributes = extension
        .get("attributes")
        .and_then(serde_json::Value::as_object)
        .ok_or_else(|| malformed("no `attributes` object"))?
        .iter()
        .map(|(semantic, id)| {
            let id = id.as_u64().and_then(|id| u32::try_from(id).ok());
            id.map(|id| (semantic.clone(), id))
                .ok_or_else(|| malformed(&format!("the id of `{semantic}` is not a number")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    if primitive.mode() != Mode::Triangles {
        return Err(malformed(
            "a Draco stream holds triangles, the primitive is not drawn as TRIANGLES",
        ));
    }
    let bytes = usize::try_from(view)
        .ok()
        .and_then(|view| document.views().nth(view))
        .and_then(|view| buffers.view(&view))
        .ok_or_else(|| {
            malformed(&format!(
                "buffer view {view} does not exist or lies outside its buffer"
            ))
        })?;
    let decoded = std::panic::catch_unwind(|| {
        let mut mesh = Mesh::new();
        MeshDecoder::new()
            .decode(&mut DecoderBuffer::new(bytes), &mut mesh)
            .map(|()| mesh)
    });
    let mesh =
        match decoded {
            Ok(Ok(mesh)) => mesh,
            Ok(Err(error)) => {
                return Err(format!(
                    "a Draco-compressed primitive cannot be decoded: {error}"
                ));
            }
            Err(_) => return Err(
                "a Draco-compressed primitive cannot be decoded: the decoder failed on its stream"
                    .into(),
            ),
        };
    Ok(Some(Decoded { mesh, attributes }))
}

impl Decoded {
    /// Whether the extension compresses the attribute `semantic` (`POSITION`, `TEXCOORD_0`, …).
    pub fn has(&self, semantic: &gltf::Semantic) -> bool {
        self.id(semantic).is_some()
    }

    /// The stream's points: the primitive's vertices.
    pub fn points(&self) -> usize {
        self.mesh.num_points()
    }

    /// Every point's value of the compressed attribute `semantic` as `N` floats (components it
    /// lacks read as 0, extra ones dropped), a normalised integer scaled to [0, 1] or [−1, 1];
    /// `None` when the extension does not compress it.
    ///
    /// # Errors
    /// The extension names an id the stream has no attribute for.
    pub fn floats<const N: usize>(
        &self,
        semantic: &gltf::Semantic,
    ) -> Result<Option<Vec<[f32; N]>>, String> {
        let Some(id) = self.id(semantic) else {
            return Ok(None);
        };
        let attribute = self.mesh.attribute_by_unique_id(id).ok_or_else(|| {
            let name = semantic.to_string();
            format!("{EXTENSION}: `{name}` names attribute {id}, which the stream lacks")
        })?;
        let largest = match attribute.data_type() {
            DataType::Int8 => f32::from(i8::MAX),
            DataType::Uint8 => f32::from(u8::MAX),
            DataType::Int16 => f32::from(i16::MAX),
            DataType::Uint16 => f32::from(u16::MAX),
            _ => 1.0,
        };
        // glTF's colours are normalised whenever they are integers.
        let normalized = attribute.normalized() || matches!(semantic, gltf::Semantic::Colors(_));
        let scale = |c: f32| super::values::scaled(c, normalized, largest);
        let values = attribute.read_f32s(self.points(), N);
        let (items, _) = values.as_chunks::<N>();
        Ok(Some(items.iter().map(|item| item.map(scale)).collect()))
    }

    /// The triangles' corners, three a triangle, as point numbers.
    pub fn triangles(&self) -> Vec<u32> {
        self.mesh
            .faces()
            .iter()
            .flat_map(|face| face.map(|point| point.0))
            .collect()
    }

    fn id(&self, semantic: &gltf::Semantic) -> Option<u32> {
        let name = semantic.to_string();
        self.attributes
            .iter()
            .find(|(s, _)| *s == name)
            .map(|&(_, id)| id)
    }
}

#[cfg(test)]
mod tests {
    //! Draco streams written here by `draco-core`'s encoder (a dev-dependency), on each of its
    //! connectivity coders, wrapped in documents as exporters write them: the surface read back
    //! is the encoded one, vertex for vertex and face for face.
    use bevy::math::Vec3;
    use draco_core::{
        DataType, EncoderBuffer, EncoderOptions, FaceIndex, GeometryAttributeType, MeshEncoder,
        PointAttribute, PointIndex,
    };
    use serde_json::json;

    use super::super::read;
    use crate::mesh::soup::PolygonSoup;

    /// The stream's attribute ids, not their positions in its list: a reader must look
    /// attributes up by the id the extension names.
    const POSITION_ID: u32 = 7;
    const NORMAL_ID: u32 = 3;
    const COLOUR_ID: u32 = 5;

    /// `soup` (triangles) as a Draco stream with positions, normals and u8 colours, encoded
    /// at `speed` (10: sequential, 5–9: Edgebreaker, below 5: Edgebreaker valence), positions
    /// quantised to `bits` (0: lossless).
    fn stream(soup: &PolygonSoup, speed: i32, bits: i32) -> Vec<u8> {
        let n = soup.positions.len();
        let mut mesh = draco_core::Mesh::new();
        let colour = |p: Vec3| (p * 100.0 + 120.0).to_array().map(|c| c as u8);
        let mut add = |kind, id, data_type, values: Vec<u8>| {
            let mut attribute = PointAttribute::new();
            attribute.init(kind, 3, data_type, kind == GeometryAttributeType::Color, n);
            attribute.buffer_mut().write(0, &values);
            attribute.set_unique_id(id);
            mesh.add_attribute_preserve_unique_id(attribute)
        };
        let floats = |v: &[Vec3]| {
            v.iter()
                .flat_map(|p| p.to_array())
                .flat_map(f32::to_le_bytes)
                .collect()
        };
        let normals: Vec<Vec3> = soup.positions.iter().map(|p| p.normalize()).collect();
        let position = add(
            GeometryAttributeType::Position,
            POSITION_ID,
            DataType::Float32,
            floats(&soup.positions),
        );
        add(
            GeometryAttributeType::Normal,
            NORMAL_ID,
            DataType::Float32,
            floats(&normals),
        );
        let colours = soup.positions.iter().flat_map(|&p| colour(p)).collect();
        add(
            GeometryAttributeType::Color,
            COLOUR_ID,
            DataType::Uint8,
            colours,
        );
        mesh.set_num_faces(soup.face_count());
        for (f, face) in soup.faces().enumerate() {
            mesh.set_face(
                FaceIndex(f as u32),
                [face[0], face[1], face[2]].map(PointIndex),
            );
        }
        let mut options = EncoderOptions::new();
        options.set_global_int("encoding_speed", speed);
        options.set_global_int("decoding_speed", speed);
        if bits > 0 {
            options.set_attribute_int(position, "quantization_bits", bits);
        }
        let mut encoder = MeshEncoder::new();
        encoder.set_mesh(mesh);
        let mut out = EncoderBuffer::new();
        encoder.encode(&options, &mut out).unwrap();
        out.data().to_vec()
    }

    /// A document of one primitive compressed as `stream`, the extension `required` (its
    /// accessors without data) or only used (with `fallback`'s uncompressed positions and
    /// indices), `extension` edited at top-level keys.
    fn document(
        stream: &[u8],
        soup: &PolygonSoup,
        fallback: Option<&PolygonSoup>,
        extension: serde_json::Value,
    ) -> Vec<u8> {
        let counts = (soup.positions.len(), soup.face_count());
        let (min, max) = soup
            .positions
            .iter()
            .fold((Vec3::MAX, Vec3::MIN), |(min, max), &p| {
                (min.min(p), max.max(p))
            });
        let mut bytes = stream.to_vec();
        let mut views = vec![json!({"buffer": 0, "byteOffset": 0, "byteLength": bytes.len()})];
        let mut position = json!({
            "componentType": 5126, "count": counts.0, "type": "VEC3",
            "min": min.to_array(), "max": max.to_array()
        });
        let mut indices = json!({"componentType": 5125, "count": counts.1 * 3, "type": "SCALAR"});
        if let Some(soup) = fallback {
            bytes.resize(bytes.len().next_multiple_of(4), 0);
            for (accessor, data) in [
                (
                    &mut position,
                    soup.positions
                        .iter()
                        .flat_map(|p| p.to_array())
                        .flat_map(f32::to_le_bytes)
                        .collect::<Vec<u8>>(),
                ),
                (
                    &mut indices,
                    soup.indices.iter().flat_map(|i| i.to_le_bytes()).collect(),
                ),
            ] {
                views.push(
                    json!({"buffer": 0, "byteOffset": bytes.len(), "byteLength": data.len()}),
                );
                accessor["bufferView"] = json!(views.len() - 1);
                bytes.extend(data);
            }
        }
        let mut compression = json!({
            "bufferView": 0,
            "attributes": {"POSITION": POSITION_ID, "NORMAL": NORMAL_ID, "COLOR_0": COLOUR_ID}
        });
        for (key, value) in extension.as_object().unwrap() {
            compression[key] = value.clone();
        }
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::Engine::encode(&base64::engine::general_purpose::STANDARD, &bytes)
        );
        let mut document = json!({
            "asset": {"version": "2.0"},
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{
                "attributes": {"POSITION": 0, "NORMAL": 2, "COLOR_0": 3},
                "indices": 1,
                "mode": 4,
                "extensions": {super::EXTENSION: compression}
            }]}],
            "buffers": [{"byteLength": bytes.len(), "uri": uri}],
            "bufferViews": views,
            "accessors": [
                position,
                indices,
                {"componentType": 5126, "count": counts.0, "type": "VEC3"},
                {"componentType": 5121, "normalized": true, "count": counts.0, "type": "VEC3"}
            ],
            "extensionsUsed": [super::EXTENSION]
        });
        if fallback.is_none() {
            document["extensionsRequired"] = json!([super::EXTENSION]);
        }
        serde_json::to_vec(&document).unwrap()
    }

    /// Each face of `back` as the faces of `soup` it matches, corner by corner to the nearest
    /// vertex of `soup` (a rotation of its corners, orientation kept), sorted.
    fn faces_as(back: &PolygonSoup, soup: &PolygonSoup, tolerance: f32) -> Vec<[u32; 3]> {
        let nearest = |p: Vec3| {
            let (i, q) = soup
                .positions
                .iter()
                .enumerate()
                .min_by(|a, b| a.1.distance(p).total_cmp(&b.1.distance(p)))
                .unwrap();
            assert!(
                q.distance(p) <= tolerance,
                "{p} is {} from {q}",
                q.distance(p)
            );
            i as u32
        };
        let mut faces: Vec<[u32; 3]> = back
            .faces()
            .map(|f| {
                let mut face = [f[0], f[1], f[2]].map(|v| nearest(back.positions[v as usize]));
                let first = (0..3).min_by_key(|&k| face[k]).unwrap();
                face.rotate_left(first);
                face
            })
            .collect();
        faces.sort_unstable();
        faces
    }

    fn sorted_faces(soup: &PolygonSoup) -> Vec<[u32; 3]> {
        faces_as(soup, soup, 0.0)
    }

    #[test]
    fn every_connectivity_coder_reads_back_the_encoded_surface() {
        let soup = crate::mesh::shapes::icosphere(2);
        let (v, f) = (soup.positions.len(), soup.face_count());
        assert_eq!((v, f), (162, 320));
        // Sequential, Edgebreaker standard, Edgebreaker valence; lossless and quantised.
        for (speed, bits, tolerance) in [(10, 0, 0.0), (10, 14, 1e-4), (5, 14, 1e-4), (0, 11, 1e-3)]
        {
            let bytes = document(&stream(&soup, speed, bits), &soup, None, json!({}));
            let back = read(&bytes, None).unwrap();
            let case = format!("speed {speed}, {bits} bits");
            assert_eq!((back.positions.len(), back.face_count()), (v, f), "{case}");
            assert_eq!(
                faces_as(&back, &soup, tolerance),
                sorted_faces(&soup),
                "{case}"
            );
            assert!(back.notes.is_empty(), "{case}: {:?}", back.notes);
            for (i, &p) in back.positions.iter().enumerate() {
                let normal = back.vertex_normals.as_ref().unwrap()[i];
                assert!(
                    normal.distance(p.normalize()) < 0.02,
                    "{case}: normal {normal} at {p}"
                );
            }
            // Colours were u8, normalised: read back as the bytes they were (from the positions
            // as read, which sit within the quantisation of the encoded ones).
            let colours = back.vertex_colors.as_ref().unwrap();
            for (c, p) in colours.iter().zip(&back.positions) {
                let expected = (*p * 100.0 + 120.0).to_array();
                for k in 0..3 {
                    assert!(
                        (f32::from(c[k]) - expected[k]).abs() <= 1.01,
                        "{case}: {c:?} at {p}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_used_extension_is_read_from_the_stream_not_the_fallback() {
        let soup = crate::mesh::shapes::icosphere(1);
        // The fallback is a different surface (moved by one): what is read is the stream's.
        let mut moved = soup.clone();
        moved.positions.iter_mut().for_each(|p| *p += Vec3::ONE);
        let bytes = document(&stream(&soup, 7, 0), &soup, Some(&moved), json!({}));
        let back = read(&bytes, None).unwrap();
        assert_eq!(faces_as(&back, &soup, 0.0), sorted_faces(&soup));
    }

    #[test]
    fn broken_streams_and_extensions_are_refused_naming_the_cause() {
        let soup = crate::mesh::shapes::icosphere(1);
        let good = stream(&soup, 10, 0);
        let refused = |bytes: &[u8]| read(bytes, None).unwrap_err().message;
        let decode = "a Draco-compressed primitive cannot be decoded: ";
        for broken in [
            &good[..good.len() / 2],
            &good[..5],
            b"DRACO\x09\x09\x01\0\0\0\0",
        ] {
            let message = refused(&document(broken, &soup, None, json!({})));
            assert!(message.starts_with(decode), "{message}");
        }
        let mut flipped = good.clone();
        for b in flipped.iter_mut().skip(12).step_by(7) {
            *b ^= 0x5a;
        }
        // Garbled bytes are an error or some surface, never a panic.
        let _ = read(&document(&flipped, &soup, None, json!({})), None);
        for (edit, message) in [
            (
                json!({"bufferView": 9}),
                "buffer view 9 does not exist or lies outside its buffer",
            ),
            (json!({"bufferView": "0"}), "no `bufferView` number"),
            (json!({"attributes": [0]}), "no `attributes` object"),
            (
                json!({"attributes": {"POSITION": -1}}),
                "the id of `POSITION` is not a number",
            ),
        ] {
            let bytes = document(&good, &soup, None, edit);
            assert_eq!(
                refused(&bytes),
                format!("{} of a primitive: {message}", super::EXTENSION)
            );
        }
        let bytes = document(&good, &soup, None, json!({"attributes": {"POSITION": 40}}));
        assert_eq!(
            refused(&bytes),
            format!(
                "{}: `POSITION` names attribute 40, which the stream lacks",
                super::EXTENSION
            )
        );
        // Drawn as anything but triangles.
        let mut value: serde_json::Value =
            serde_json::from_slice(&document(&good, &soup, None, json!({}))).unwrap();
        value["meshes"][0]["primitives"][0]["mode"] = json!(5);
        let message = refused(&serde_json::to_vec(&value).unwrap());
        assert!(
            message.ends_with("the primitive is not drawn as TRIANGLES"),
            "{message}"
        );
        // An accessor without data outside a compressed primitive is still refused.
        value["meshes"][0]["primitives"][0]["mode"] = json!(4);
        value["meshes"][0]["primitives"][0]["extensions"] = json!({});
        let message = refused(&serde_json::to_vec(&value).unwrap());
        assert!(
            message.starts_with("invalid glTF: accessors[0].bufferView: Missing data"),
            "{message}"
        );
    }
}
