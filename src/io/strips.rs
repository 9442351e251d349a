//! Triangle strips, as COLLADA's `<tristrips>`, PLY's `tristrips` element and glTF's
//! `TRIANGLE_STRIP` store triangles: corners `c0 c1 c2 c3 …` make triangles `(c0 c1 c2)`,
//! `(c2 c1 c3)`, `(c2 c3 c4)`, … — every odd triangle swaps its first two corners so that all
//! keep one winding (OpenGL's `GL_TRIANGLE_STRIP` convention, which the formats follow).

/// The triangles of one strip, in order, each wound as the first, without the degenerate
/// ones — two corners at one vertex (`vertex` of each corner) — that strips use to turn
/// corners or join pieces: they are no faces.
pub(super) fn strip_triangles<'a, T: Copy, V: PartialEq>(
    corners: &'a [T],
    vertex: impl Fn(T) -> V + 'a,
) -> impl Iterator<Item = [T; 3]> + 'a {
    corners
        .windows(3)
        .enumerate()
        .map(|(i, w)| {
            if i % 2 == 0 {
                [w[0], w[1], w[2]]
            } else {
                [w[1], w[0], w[2]]
            }
        })
        .filter(move |&[a, b, c]| {
            let [a, b, c] = [vertex(a), vertex(b), vertex(c)];
            a != b && b != c && a != c
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn odd_triangles_swap_their_first_two_corners_and_turns_make_no_face() {
        let triangles: Vec<[u32; 3]> = strip_triangles(&[0, 1, 2, 3, 4], |v| v).collect();
        assert_eq!(triangles, vec![[0, 1, 2], [2, 1, 3], [2, 3, 4]]);
        assert_eq!(strip_triangles::<u32, u32>(&[0, 1], |v| v).count(), 0);
        // A repeated corner turns the strip: (1 2 2) and (2 2 3) are no faces.
        let turned: Vec<[u32; 3]> = strip_triangles(&[0, 1, 2, 2, 3], |v| v).collect();
        assert_eq!(turned, vec![[0, 1, 2]]);
        // Corners are compared by their vertex.
        let tuples: [(u32, u32); 4] = [(0, 9), (1, 9), (1, 8), (2, 7)];
        assert_eq!(strip_triangles(&tuples, |t| t.0).count(), 0);
    }
}
