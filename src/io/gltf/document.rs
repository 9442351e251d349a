//! A glTF file's document: parsed, its version and required extensions checked, and validated
//! by the `gltf` crate with what Pappus tolerates taken out.
//!
//! What is refused is refused by name with what to do (glTF 1.0, meshopt-compressed buffers, an
//! unknown required extension), never with a decoder's error about a JSON type.
//! `KHR_mesh_quantization` is read ([`super::values`]), and so is `KHR_draco_mesh_compression`
//! ([`super::draco`]: its accessors need no data, which validation would otherwise refuse). What
//! is tolerated is said in the notes:
//! - a required extension that concerns only how the surface looks (materials, textures,
//!   lights, the 1.0-era `KHR_technique_webgl`): Pappus reads no material's properties, so the
//!   geometry is what it would be with the extension understood (the spec lets a reader refuse
//!   a file that requires an extension it does not know; it does not make one refuse an
//!   extension it knows to be irrelevant);
//! - a `POSITION` accessor without its `min` and `max`: the spec requires them, exporters omit
//!   them, and Pappus reads the positions themselves (the bounds are only a hint to a renderer).

use gltf::json::validation::{Error as Invalid, Validate};
use gltf::json::{Path as JsonPath, Root};

use crate::io::error::ParseError;

/// The document, the `.glb`'s binary chunk, and the notes on what was tolerated.
pub(super) struct Parsed {
    pub document: gltf::Document,
    pub blob: Option<Vec<u8>>,
    pub notes: Vec<String>,
}

/// Required extensions that change the geometry's encoding, which Pappus does not decode, and
/// what to do about each.
const UNDECODED: [(&str, &str); 1] = [(
    "EXT_meshopt_compression",
    "meshopt-compressed buffers are not supported: re-export without meshopt compression",
)];

/// Required extensions that Pappus reads.
const READ: [&str; 2] = ["KHR_mesh_quantization", super::draco::EXTENSION];

/// Whether a required extension concerns only materials, textures or lights (by its name's
/// prefix, as the Khronos and vendor registries name them), so that the geometry reads the same
/// without it.
fn appearance_only(extension: &str) -> bool {
    const PREFIXES: [&str; 8] = [
        "KHR_materials_",
        "KHR_texture_",
        "EXT_texture_",
        "MSFT_texture_",
        "KHR_lights_",
        "EXT_lights_",
        "ADOBE_materials_",
        "KHR_technique_webgl",
    ];
    PREFIXES.iter().any(|p| extension.starts_with(p))
}

/// Parses and checks a `.gltf` or `.glb` file.
///
/// # Errors
/// A file the decoder cannot read (a glTF 1.0 one named as such), a required extension Pappus
/// does not read, or a validation error it does not tolerate.
pub(super) fn parse(bytes: &[u8]) -> Result<Parsed, ParseError> {
    let error = |message: String| ParseError::byte(0, message);
    let unsupported = |message: String| ParseError::byte(0, message).unsupported();
    if let Some(header) = bytes.get(..12).filter(|h| h.starts_with(b"glTF")) {
        // The crate subtracts the header's size from the length it declares before comparing.
        let length = u32::from_le_bytes([header[8], header[9], header[10], header[11]]);
        if length < 12 {
            return Err(ParseError::byte(
                8,
                format!("the GLB header declares {length} bytes, fewer than itself"),
            ));
        }
        let version = u32::from_le_bytes([header[4], header[5], header[6], header[7]]);
        if version == 1 {
            return Err(unsupported(
                "binary glTF 1.0 (GLB version 1) is not supported: re-export as glTF 2.0".into(),
            ));
        }
    }
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| match old_version(bytes) {
            Some(version) => unsupported(not_two(&version)),
            None => error(e.to_string()),
        })?;
    let mut json = document.into_json();
    if !json.asset.version.starts_with('2') {
        return Err(unsupported(not_two(&json.asset.version)));
    }
    let mut notes = Vec::new();
    notes.extend(required_extensions(&mut json).map_err(unsupported)?);
    notes.extend(validate(&json)?);
    Ok(Parsed {
        document: gltf::Document::from_json_without_validation(json),
        blob,
        notes,
    })
}

/// The accessors of the primitives compressed with Draco (their attributes' and indices'), which
/// need no data of their own.
fn draco_accessors(json: &Root) -> Vec<usize> {
    let compressed = |p: &&gltf::json::mesh::Primitive| {
        p.extensions
            .as_ref()
            .is_some_and(|e| e.others.contains_key(super::draco::EXTENSION))
    };
    let mut accessors: Vec<usize> = json
        .meshes
        .iter()
        .flat_map(|mesh| mesh.primitives.iter().filter(compressed))
        .flat_map(|p| {
            let attributes = p.attributes.values().map(|a| a.value());
            attributes.chain(p.indices.map(|i| i.value()))
        })
        .collect();
    accessors.sort_unstable();
    accessors.dedup();
    accessors
}

/// The refusal of a version other than 2.
fn not_two(version: &str) -> String {
    format!("glTF {version} is not supported: re-export as glTF 2.0")
}

/// The `asset.version` of a document the 2.0 decoder could not read, when it is not 2.x; a
/// document without one that is shaped as 1.0 is (its `meshes` an object keyed by id, not a
/// list) reads as `"1.0"`.
fn old_version(bytes: &[u8]) -> Option<String> {
    let text = if bytes.starts_with(b"glTF") {
        gltf::binary::Glb::from_slice(bytes).ok()?.json.into_owned()
    } else {
        bytes.to_vec()
    };
    let value: serde_json::Value = serde_json::from_slice(&text).ok()?;
    let version = value.pointer("/asset/version").and_then(|v| match v {
        serde_json::Value::String(s) => Some(s.clone()),
        serde_json::Value::Number(n) => Some(n.to_string()),
        _ => None,
    });
    match version {
        Some(v) if v.starts_with('2') => None,
        Some(v) => Some(v),
        None => value
            .get("meshes")
            .is_some_and(serde_json::Value::is_object)
            .then(|| "1.0".to_owned()),
    }
}

/// Checks the required extensions: refuses one that encodes the geometry in a way Pappus does
/// not decode, or one it does not know; takes those that concern only appearance out of the
/// list (so validation passes) and names them in the note.
fn required_extensions(json: &mut Root) -> Result<Option<String>, String> {
    for extension in &json.extensions_required {
        if let Some((_, why)) = UNDECODED.iter().find(|(name, _)| name == extension) {
            return Err((*why).to_owned());
        }
        if !appearance_only(extension) && !READ.contains(&extension.as_str()) {
            return Err(format!(
                "the file requires the extension `{extension}`, which Pappus does not read"
            ));
        }
    }
    let mut tolerated = std::mem::take(&mut json.extensions_required);
    tolerated.retain(|e| !READ.contains(&e.as_str()));
    Ok((!tolerated.is_empty()).then(|| {
        format!(
            "read without the required extension(s) {}: they concern only materials, textures \
             or lights, which Pappus does not read",
            tolerated.join(", ")
        )
    }))
}

/// Runs the crate's validation; a `POSITION` accessor's missing or malformed bounds are
/// tolerated (counted in the note), and so is a Draco-compressed primitive's accessor without
/// data; anything else is an error listing every finding.
fn validate(json: &Root) -> Result<Option<String>, ParseError> {
    let error = |message: String| ParseError::byte(0, message);
    // The crate's validation indexes the accessors by POSITION's number before it checks the
    // number: check it first.
    for mesh in &json.meshes {
        for primitive in &mesh.primitives {
            if let Some(bad) = primitive
                .attributes
                .values()
                .find(|a| a.value() >= json.accessors.len())
            {
                return Err(error(format!(
                    "an attribute names accessor {}, which does not exist",
                    bad.value()
                )));
            }
        }
    }
    let mut findings: Vec<(JsonPath, Invalid)> = Vec::new();
    json.validate(json, JsonPath::new, &mut |path, error| {
        findings.push((path(), error));
    });
    let bounds = |path: &JsonPath| {
        let path = path.as_str();
        path.contains(r#"attributes["POSITION"]"#)
            && (path.ends_with(".min") || path.ends_with(".max"))
    };
    let compressed = draco_accessors(json);
    let no_data = |path: &JsonPath, error: &Invalid| {
        let index = path
            .as_str()
            .strip_prefix("accessors[")
            .and_then(|rest| rest.strip_suffix("].bufferView"))
            .and_then(|index| index.parse::<usize>().ok());
        *error == Invalid::Missing && index.is_some_and(|i| compressed.contains(&i))
    };
    findings.retain(|(path, error)| !no_data(path, error));
    let (tolerated, rest): (Vec<_>, Vec<_>) = findings.into_iter().partition(|(p, _)| bounds(p));
    if !rest.is_empty() {
        let listed: Vec<String> = rest.iter().map(|(p, e)| format!("{p}: {e}")).collect();
        return Err(error(format!("invalid glTF: {}", listed.join("; "))));
    }
    // A primitive's missing `min` and `max` are two findings on one path.
    let mut primitives: Vec<&str> = tolerated
        .iter()
        .map(|(p, _)| p.as_str().trim_end_matches(".min").trim_end_matches(".max"))
        .collect();
    primitives.dedup();
    let primitives = primitives.len();
    Ok((primitives > 0).then(|| {
        format!(
            "read {primitives} primitive(s) whose POSITION accessor lacks its min/max bounds \
             (the positions themselves are read)"
        )
    }))
}
