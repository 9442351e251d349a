//! Values a file gives per face corner that the mesh keeps per vertex (normals, colours).
//!
//! OBJ names a normal per corner, COLLADA a normal and a colour per corner; Pappus keeps one
//! per vertex. A vertex whose corners agree (bit for bit) keeps that value exactly; one whose
//! corners differ (a hard edge, a colour seam) takes their mean, and the reader says how many
//! did in the soup's notes.

use bevy::math::Vec3;

/// Per-vertex values gathered from per-corner ones.
pub(super) struct PerVertex {
    /// One per vertex: `None` where no corner gave one.
    pub values: Vec<Option<Vec3>>,
    /// How many vertices had corners that disagreed (and so took the mean).
    pub differing: usize,
}

/// Gathers `corner_values` (parallel to `indices`: the value of corner `k`, whose vertex is
/// `indices[k]`) into one value per each of `vertex_count` vertices. Corners that name no vertex
/// (an index out of range: a face the builder will drop) give none. Where a vertex's corners
/// differ, `mean(sum, count)` of their values is its value.
pub(super) fn per_vertex(
    indices: &[u32],
    vertex_count: usize,
    corner_values: impl Iterator<Item = Option<Vec3>>,
    mean: impl Fn(Vec3, u32) -> Vec3,
) -> PerVertex {
    let mut first: Vec<Option<Vec3>> = vec![None; vertex_count];
    let mut sum = vec![Vec3::ZERO; vertex_count];
    let mut count = vec![0u32; vertex_count];
    let mut differ = vec![false; vertex_count];
    for (&v, value) in indices.iter().zip(corner_values) {
        let (Some(value), Some(v)) = (value, Some(v as usize).filter(|&v| v < vertex_count)) else {
            continue;
        };
        sum[v] += value;
        count[v] += 1;
        match first[v] {
            None => first[v] = Some(value),
            Some(seen) if bits(seen) != bits(value) => differ[v] = true,
            Some(_) => {}
        }
    }
    let differing = differ.iter().filter(|&&d| d).count();
    let values = (0..vertex_count)
        .map(|v| match first[v] {
            Some(_) if differ[v] => Some(mean(sum[v], count[v])),
            value => value,
        })
        .collect();
    PerVertex { values, differing }
}

fn bits(v: Vec3) -> [u32; 3] {
    v.to_array().map(f32::to_bits)
}

/// Sets the soup's vertex normals from per-corner ones (parallel to its `indices`): each
/// vertex's corners' normal, their normalised mean where they differ (with a note), zero for
/// a vertex no corner gives one.
pub(super) fn attach_corner_normals(
    soup: &mut crate::mesh::soup::PolygonSoup,
    corner_normals: impl Iterator<Item = Option<Vec3>>,
) {
    let gathered = per_vertex(
        &soup.indices,
        soup.positions.len(),
        corner_normals,
        mean_normal,
    );
    if gathered.differing > 0 {
        soup.notes.push(differing_normals_note(gathered.differing));
    }
    let normals = gathered.values.into_iter().map(|n| n.unwrap_or(Vec3::ZERO));
    soup.vertex_normals = Some(normals.collect());
}

/// The normalised mean of normals that differ (for [`per_vertex`]).
fn mean_normal(sum: Vec3, _count: u32) -> Vec3 {
    sum.normalize_or_zero()
}

/// The note for vertices whose corners named different normals.
fn differing_normals_note(differing: usize) -> String {
    format!(
        "{differing} vertex(es) had different normals at different corners: each takes their normalised mean"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agreeing_corners_keep_their_value_and_differing_ones_take_the_mean() {
        let indices = [0, 1, 2, 1, 3, 9];
        let values = [
            Some(Vec3::Z),
            Some(Vec3::X),
            None,
            Some(Vec3::Y),
            Some(Vec3::new(0.0, -0.0, 1.0)),
            Some(Vec3::X),
        ];
        let out = per_vertex(&indices, 4, values.into_iter(), mean_normal);
        assert_eq!(out.differing, 1);
        assert_eq!(out.values[0], Some(Vec3::Z));
        assert_eq!(out.values[1], Some(Vec3::new(1.0, 1.0, 0.0).normalize()));
        assert_eq!(out.values[2], None);
        // Kept bit for bit (the negative zero survives).
        assert_eq!(out.values[3].unwrap().y.to_bits(), (-0.0f32).to_bits());
        let colours = per_vertex(
            &[0, 0],
            1,
            [Some(Vec3::ZERO), Some(Vec3::splat(255.0))].into_iter(),
            |s, c| s / c as f32,
        );
        assert_eq!(colours.values[0], Some(Vec3::splat(127.5)));
    }
}
