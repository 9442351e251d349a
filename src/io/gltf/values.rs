//! An accessor's items as floats, whatever their component type.
//!
//! Core glTF stores positions and normals as floats, and texture coordinates as floats or
//! normalised unsigned bytes or shorts. `KHR_mesh_quantization` (what gltfpack writes) lets
//! positions be any 8- or 16-bit integer, normalised or not, normals signed normalised ones, and
//! texture coordinates any of these. A normalised integer maps to a fraction as glTF 2.0 §3.11
//! says (`c / 255` for an unsigned byte, `max(c / 127, −1)` for a signed one, and so on for
//! shorts); one that is not normalised is taken as the number it is, and the node transforms
//! scale it back to the model's size.

use gltf::accessor::util::{Item, Iter};
use gltf::accessor::{Accessor, DataType};

use super::buffers::Buffers;

/// Every item of `accessor` as `N` floats; `None` when its data cannot be read (the caller has
/// checked the accessor first) or its component type is a 32-bit integer.
pub(super) fn floats<const N: usize>(
    accessor: &Accessor,
    buffers: &Buffers,
) -> Option<Vec<[f32; N]>>
where
    [f32; N]: Item,
    [i8; N]: Item,
    [u8; N]: Item,
    [i16; N]: Item,
    [u16; N]: Item,
{
    let normalized = accessor.normalized();
    match accessor.data_type() {
        DataType::F32 => read::<f32, N>(accessor, buffers, |c| c),
        DataType::I8 => read::<i8, N>(accessor, buffers, |c| {
            scaled(f32::from(c), normalized, i8::MAX.into())
        }),
        DataType::U8 => read::<u8, N>(accessor, buffers, |c| {
            scaled(f32::from(c), normalized, u8::MAX.into())
        }),
        DataType::I16 => read::<i16, N>(accessor, buffers, |c| {
            scaled(f32::from(c), normalized, i16::MAX.into())
        }),
        DataType::U16 => read::<u16, N>(accessor, buffers, |c| {
            scaled(f32::from(c), normalized, u16::MAX.into())
        }),
        DataType::U32 => None,
    }
}

/// A component's value: divided by its type's largest value when normalised (and kept at
/// −1 or above, as the two lowest signed values both mean −1).
pub(super) fn scaled(c: f32, normalized: bool, largest: f32) -> f32 {
    if normalized {
        (c / largest).max(-1.0)
    } else {
        c
    }
}

fn read<T: Copy, const N: usize>(
    accessor: &Accessor,
    buffers: &Buffers,
    value: impl Fn(T) -> f32,
) -> Option<Vec<[f32; N]>>
where
    [T; N]: Item,
{
    let items = Iter::<[T; N]>::new(accessor.clone(), |b| buffers.get(b))?;
    Some(items.map(|item| item.map(&value)).collect())
}

#[cfg(test)]
mod tests {
    use super::scaled;

    #[test]
    fn normalised_integers_map_to_fractions_and_others_stay_as_they_are() {
        assert_eq!(scaled(255.0, true, 255.0), 1.0);
        assert_eq!(scaled(-128.0, true, 127.0), -1.0);
        assert_eq!(scaled(-127.0, true, 127.0), -1.0);
        assert_eq!(scaled(16383.5, true, 32767.0), 0.5);
        assert_eq!(scaled(-300.0, false, 32767.0), -300.0);
    }
}
