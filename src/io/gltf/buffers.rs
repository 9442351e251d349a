//! A glTF document's buffers, resolved to bytes, and the checks that make reading an accessor
//! through the `gltf` crate safe.
//!
//! A buffer is the `.glb`'s binary chunk, a `data:` URI (base64), or a file beside the `.gltf`
//! (its URI percent-decoded). The crate's accessor iterators trust the file: an accessor with
//! `count` 0, a stride smaller than its element, a type the semantic does not allow, or a range
//! past its view would panic or read garbage inside the crate. [`Buffers::check_accessor`]
//! refuses each of those first, naming the accessor.

use base64::Engine;
use gltf::accessor::{DataType, Dimensions};
use gltf::buffer::{Source, View};
use std::path::Path;

/// Every buffer's bytes, by index.
pub(super) struct Buffers(Vec<Vec<u8>>);

impl Buffers {
    /// Resolves the document's buffers: the `.glb` binary chunk (`blob`), `data:` URIs, and
    /// files relative to `folder` (none when the bytes came from memory).
    ///
    /// # Errors
    /// A buffer that cannot be found or decoded, or that holds fewer bytes than it declares.
    pub fn resolve(
        document: &gltf::Document,
        mut blob: Option<Vec<u8>>,
        folder: Option<&Path>,
    ) -> Result<Buffers, String> {
        let mut buffers = Vec::new();
        for buffer in document.buffers() {
            let index = buffer.index();
            let data = match buffer.source() {
                Source::Bin => blob.take().ok_or_else(|| {
                    format!("buffer {index} names the binary chunk, which the file lacks")
                })?,
                Source::Uri(uri) if uri.starts_with("data:") => {
                    let (_, encoded) = uri
                        .split_once(";base64,")
                        .ok_or_else(|| format!("buffer {index}: a data URI without base64"))?;
                    base64::engine::general_purpose::STANDARD
                        .decode(encoded)
                        .map_err(|e| format!("buffer {index}: its base64 does not decode ({e})"))?
                }
                Source::Uri(uri) => {
                    let folder = folder.ok_or_else(|| {
                        format!("buffer {index} is the external file `{uri}`: open the .gltf from its folder")
                    })?;
                    let path = folder.join(percent_decoded(uri));
                    std::fs::read(&path)
                        .map_err(|e| format!("buffer {index}: {}: {e}", path.display()))?
                }
            };
            if data.len() < buffer.length() {
                return Err(format!(
                    "buffer {index} declares {} bytes but holds {}",
                    buffer.length(),
                    data.len()
                ));
            }
            buffers.push(data);
        }
        Ok(Buffers(buffers))
    }

    /// The bytes of a buffer, for the crate's readers.
    pub fn get(&self, buffer: gltf::Buffer) -> Option<&[u8]> {
        self.0.get(buffer.index()).map(Vec::as_slice)
    }

    /// The bytes of a buffer view; `None` when the view reaches past its buffer.
    pub fn view(&self, view: &View) -> Option<&[u8]> {
        let start = view.offset();
        self.get(view.buffer())?
            .get(start..start.checked_add(view.length())?)
    }

    /// Checks that an accessor can be read as one of `allowed` (component type, dimensions):
    /// it has items, and every item it names, sparse ones included, lies inside its view and
    /// buffer.
    ///
    /// # Errors
    /// What is wrong, naming the accessor and `what` it was read as.
    pub fn check_accessor(
        &self,
        accessor: &gltf::Accessor,
        allowed: &[(DataType, Dimensions)],
        what: &str,
    ) -> Result<(), String> {
        let index = accessor.index();
        let (ty, dims) = (accessor.data_type(), accessor.dimensions());
        if !allowed.contains(&(ty, dims)) {
            return Err(format!(
                "accessor {index} ({what}) is {dims:?} of {ty:?}, which glTF does not allow there"
            ));
        }
        let count = accessor.count();
        if count == 0 {
            return Err(format!("accessor {index} ({what}) is empty"));
        }
        let element = accessor.size();
        match (accessor.view(), accessor.sparse()) {
            (None, None) => {
                return Err(format!(
                    "accessor {index} ({what}) has no data (no buffer view)"
                ));
            }
            (Some(view), _) => self.check_range(&view, accessor.offset(), element, count, index)?,
            (None, Some(_)) => {}
        }
        if let Some(sparse) = accessor.sparse() {
            let n = sparse.count();
            if n == 0 {
                return Err(format!(
                    "accessor {index} ({what}) has an empty sparse part"
                ));
            }
            let indices = sparse.indices();
            let size = indices.index_type().size();
            self.check_range(&indices.view(), indices.offset(), size, n, index)?;
            let values = sparse.values();
            self.check_range(&values.view(), values.offset(), element, n, index)?;
        }
        Ok(())
    }

    /// Checks that `count` items of `element` bytes from `offset` fit a view (at its stride)
    /// and that the view fits its buffer.
    fn check_range(
        &self,
        view: &View,
        offset: usize,
        element: usize,
        count: usize,
        accessor: usize,
    ) -> Result<(), String> {
        let stride = view.stride().unwrap_or(element);
        let outside = || format!("accessor {accessor} reaches past the end of its data");
        if stride < element {
            return Err(format!(
                "accessor {accessor}: a stride of {stride} bytes for items of {element}"
            ));
        }
        let data = self.get(view.buffer()).ok_or_else(outside)?;
        let view_end = view
            .offset()
            .checked_add(view.length())
            .ok_or_else(outside)?;
        let end = stride
            .checked_mul(count - 1)
            .and_then(|n| n.checked_add(offset))
            .and_then(|n| n.checked_add(element))
            .ok_or_else(outside)?;
        if view_end > data.len() || end > view.length() {
            return Err(outside());
        }
        Ok(())
    }
}

/// A relative URI as a file name: `%XX` escapes decoded (a malformed one is kept as written).
fn percent_decoded(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match (
            bytes[i],
            bytes.get(i + 1).copied().and_then(hex),
            bytes.get(i + 2).copied().and_then(hex),
        ) {
            (b'%', Some(high), Some(low)) => {
                out.push((high * 16 + low) as u8);
                i += 3;
            }
            (b, _, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    use super::percent_decoded;

    #[test]
    fn uris_are_percent_decoded() {
        assert_eq!(percent_decoded("my%20mesh.bin"), "my mesh.bin");
        assert_eq!(percent_decoded("100%.bin"), "100%.bin");
        assert_eq!(percent_decoded("a%2"), "a%2");
    }
}
