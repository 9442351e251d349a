//! Triangle strips, as COLLADA's `<tristrips>` and PLY's `tristrips` element store triangles:
//! corners `c0 c1 c2 c3 …` make triangles `(c0 c1 c2)`, `(c2 c1 c3)`, `(c2 c3 c4)`, … — every
//! odd triangle swaps its first two corners so that all keep one winding (OpenGL's
//! `GL_TRIANGLE_STRIP` convention, which both formats follow).

/// The triangles of one strip, in order, each wound as the first. Includes the degenerate
/// triangles (two corners the same) that strips use to turn corners; callers leave them out.
pub(super) fn strip_triangles<T: Copy>(corners: &[T]) -> impl Iterator<Item = [T; 3]> + '_ {
    corners.windows(3).enumerate().map(|(i, w)| {
        if i % 2 == 0 {
            [w[0], w[1], w[2]]
        } else {
            [w[1], w[0], w[2]]
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn odd_triangles_swap_their_first_two_corners() {
        let triangles: Vec<[u32; 3]> = strip_triangles(&[0, 1, 2, 3, 4]).collect();
        assert_eq!(triangles, vec![[0, 1, 2], [2, 1, 3], [2, 3, 4]]);
        assert_eq!(strip_triangles::<u32>(&[0, 1]).count(), 0);
    }
}
