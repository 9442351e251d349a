//! Turning an unchecked polygon soup into faces a halfedge mesh can hold, counting every repair.
//!
//! Files are messy (see `shared/models/README.md`). Nothing here panics or gives up on a whole
//! file for a local defect; each defect is repaired, counted in [`RepairReport`], and the rest
//! of the mesh is kept. In order:
//!
//! 1. **Bad faces are dropped**: fewer than 3 corners, an index out of range, or a corner at a
//!    non-finite position. A face that names a vertex twice (a keyhole, a corner written twice)
//!    is cut into triangles in its own plane ([`super::untangle`]), and dropped only when it
//!    cannot be.
//! 2. **Non-manifold edges**: faces are taken in file order and a face that would be the third
//!    on any edge is *detached*: it keeps its place and shape but gets its own copies of its
//!    vertices (it becomes a separate component). Detaching rather than dropping loses none of
//!    the user's geometry, and saving writes every face back.
//! 3. **Orientation**: across each manifold edge the two faces must run opposite ways. A
//!    breadth-first walk over each component flips faces to agree; per component the majority
//!    orientation of the file wins, so a well-oriented file is never flipped. A face that no
//!    flip can fit (a Möbius band) is detached as in 2.
//! 4. **Non-manifold vertices**: the faces around a vertex must form one fan. A vertex with
//!    several fans (two cones touching at the tip, a bow tie) is split into one vertex per fan.
//! 5. **Unreferenced vertices** are dropped.
//!
//! The result ([`RepairedFaces`]) pairs every face corner with its twin corner, ready for
//! [`Connectivity::from_corners`](super::tables::Connectivity::from_corners). "None" in its
//! tables is the tables' [`NONE`].

use bevy::math::Vec3;
use bevy::platform::collections::HashMap;

use super::soup::PolygonSoup;
use super::tables::{FaceCorners, NONE};
use super::untangle::untangle;

/// What the builder had to repair, by kind. Every count is zero for a clean mesh.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RepairReport {
    /// Input vertices no kept face uses (dropped).
    pub unreferenced_vertices: usize,
    /// Faces with fewer than 3 corners (dropped).
    pub too_few_corners: usize,
    /// Faces naming a vertex index that does not exist (dropped).
    pub out_of_range_faces: usize,
    /// Faces naming one vertex twice that no cut into triangles could mend (dropped).
    pub repeated_vertex_faces: usize,
    /// Faces naming one vertex twice (a keyhole: a polygon with a hole joined to its outline by
    /// a bridge; a corner written twice) cut into triangles in their own plane
    /// ([`super::untangle`]).
    pub untangled_faces: usize,
    /// Faces with a corner at a NaN or infinite position (dropped).
    pub non_finite_faces: usize,
    /// Faces that would have been the third (or more) on an edge (detached: own vertex copies).
    pub non_manifold_edge_faces: usize,
    /// Faces whose orientation could not agree with their neighbours' (detached).
    pub non_orientable_faces: usize,
    /// Faces whose vertex order was reversed to agree with their neighbours.
    pub reoriented_faces: usize,
    /// Vertices where several fans of faces met (each split into one vertex per fan).
    pub non_manifold_vertices: usize,
    /// Vertices created by detaching faces and splitting non-manifold vertices.
    pub added_vertices: usize,
}

impl RepairReport {
    /// Every count with its name, in a fixed order (the keys of `pappus info --json`'s
    /// `repairs` object).
    pub fn entries(&self) -> [(&'static str, usize); 11] {
        [
            ("unreferenced_vertices", self.unreferenced_vertices),
            ("too_few_corners", self.too_few_corners),
            ("out_of_range_faces", self.out_of_range_faces),
            ("repeated_vertex_faces", self.repeated_vertex_faces),
            ("untangled_faces", self.untangled_faces),
            ("non_finite_faces", self.non_finite_faces),
            ("non_manifold_edge_faces", self.non_manifold_edge_faces),
            ("non_orientable_faces", self.non_orientable_faces),
            ("reoriented_faces", self.reoriented_faces),
            ("non_manifold_vertices", self.non_manifold_vertices),
            ("added_vertices", self.added_vertices),
        ]
    }

    /// The faces the repair removed from the mesh.
    pub fn dropped_faces(&self) -> usize {
        self.too_few_corners
            + self.out_of_range_faces
            + self.repeated_vertex_faces
            + self.non_finite_faces
    }

    /// Whether nothing had to be repaired.
    pub fn is_clean(&self) -> bool {
        self.entries().iter().all(|&(_, n)| n == 0)
    }
}

impl std::fmt::Display for RepairReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.is_clean() {
            return write!(f, "no repairs");
        }
        let parts: Vec<String> = self
            .entries()
            .iter()
            .filter(|&&(_, n)| n > 0)
            .map(|(k, n)| format!("{n} {}", k.replace('_', " ")))
            .collect();
        write!(f, "{}", parts.join(", "))
    }
}

/// Faces ready to become a halfedge mesh: manifold, consistently oriented, every vertex used and
/// a single fan, every corner paired with its twin.
///
/// Corner `c` of a face stands for the halfedge from `indices[c]` to the next corner's vertex.
#[derive(Clone, Debug, Default)]
pub struct RepairedFaces {
    /// Vertex positions (all finite, all referenced).
    pub positions: Vec<Vec3>,
    /// Face corners, flat.
    pub indices: Vec<u32>,
    /// `face_starts[f]..face_starts[f + 1]` are face `f`'s corners.
    pub face_starts: Vec<u32>,
    /// The corner running the other way along the same edge, or [`NONE`] on the boundary.
    pub twin: Vec<u32>,
    /// For every input vertex, the vertex it became ([`NONE`] if dropped). A split vertex maps
    /// to its first fan.
    pub input_vertex: Vec<u32>,
    /// For every corner, the input corner (index into the soup's `indices`) it is: what carries
    /// the soup's corner and vertex attributes through the repairs (a reversed face's corners
    /// are reversed with it; a detached or split vertex's corners still name the input's).
    pub source_corner: Vec<u32>,
}

impl RepairedFaces {
    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.face_starts.len().saturating_sub(1)
    }

    /// The faces as corners with their twins, to lay out as tables.
    pub fn corners(&self) -> FaceCorners<'_> {
        FaceCorners {
            positions: &self.positions,
            indices: &self.indices,
            face_starts: &self.face_starts,
            twin: &self.twin,
        }
    }
}

/// Repairs `soup` (see the module doc) and says what it did.
pub fn repair(soup: &PolygonSoup) -> (RepairedFaces, RepairReport) {
    let mut report = RepairReport::default();
    let mut faces = keep_well_formed_faces(soup, &mut report);
    let mut positions = soup.positions.clone();
    let input_count = positions.len();

    let corner_face = corner_faces(&faces.starts);
    let mut twin =
        pair_corners_keeping_manifold_edges(&mut faces, &corner_face, input_count, &mut report);
    orient_consistently(&mut faces, &corner_face, &mut twin, &mut report);
    detach_faces(&mut faces, &mut positions, &twin, &mut report);
    split_non_manifold_vertices(&mut faces, &mut positions, &twin, &mut report);
    let input_vertex = drop_unreferenced(&mut faces, &mut positions, input_count, &mut report);

    let repaired = RepairedFaces {
        positions,
        indices: faces.indices,
        face_starts: faces.starts,
        twin,
        input_vertex,
        source_corner: faces.source,
    };
    (repaired, report)
}

/// Faces under repair: flat corners plus a per-face "detached" flag.
struct WorkFaces {
    indices: Vec<u32>,
    starts: Vec<u32>,
    detached: Vec<bool>,
    /// Each corner's input corner.
    source: Vec<u32>,
}

impl WorkFaces {
    fn corners(&self, f: usize) -> std::ops::Range<usize> {
        self.starts[f] as usize..self.starts[f + 1] as usize
    }

    fn count(&self) -> usize {
        self.starts.len() - 1
    }

    /// The corner after `c` in its face.
    #[inline]
    fn next_corner(&self, c: usize, f: usize) -> usize {
        if c + 1 == self.starts[f + 1] as usize {
            self.starts[f] as usize
        } else {
            c + 1
        }
    }

    /// The corner before `c` in its face.
    #[inline]
    fn prev_corner(&self, c: usize, f: usize) -> usize {
        if c == self.starts[f] as usize {
            self.starts[f + 1] as usize - 1
        } else {
            c - 1
        }
    }
}

fn keep_well_formed_faces(soup: &PolygonSoup, report: &mut RepairReport) -> WorkFaces {
    let n = soup.positions.len();
    let finite: Vec<bool> = soup.positions.iter().map(|p| p.is_finite()).collect();
    let mut indices = Vec::with_capacity(soup.indices.len());
    let mut source = Vec::with_capacity(soup.indices.len());
    let mut starts = Vec::with_capacity(soup.face_count() + 1);
    starts.push(0u32);
    let mut scratch = Vec::new();
    for (f, face) in soup.faces().enumerate() {
        if face.len() < 3 {
            report.too_few_corners += 1;
        } else if face.iter().any(|&i| i as usize >= n) {
            report.out_of_range_faces += 1;
        } else if face.iter().any(|&i| !finite[i as usize]) {
            report.non_finite_faces += 1;
        } else if has_repeat(face, &mut scratch) {
            let first = soup.face_starts[f];
            let triangles = untangle(face, &soup.positions);
            if triangles.is_empty() {
                report.repeated_vertex_faces += 1;
            } else {
                report.untangled_faces += 1;
            }
            for triangle in triangles {
                indices.extend(triangle.map(|k| face[k]));
                source.extend(triangle.map(|k| first + k as u32));
                starts.push(indices.len() as u32);
            }
        } else {
            indices.extend_from_slice(face);
            let first = soup.face_starts[f];
            source.extend(first..first + face.len() as u32);
            starts.push(indices.len() as u32);
        }
    }
    let count = starts.len() - 1;
    WorkFaces {
        indices,
        starts,
        detached: vec![false; count],
        source,
    }
}

fn has_repeat(face: &[u32], scratch: &mut Vec<u32>) -> bool {
    if face.len() <= 8 {
        return face
            .iter()
            .enumerate()
            .any(|(i, a)| face[i + 1..].contains(a));
    }
    scratch.clear();
    scratch.extend_from_slice(face);
    scratch.sort_unstable();
    scratch.windows(2).any(|w| w[0] == w[1])
}

fn corner_faces(starts: &[u32]) -> Vec<u32> {
    let mut out = Vec::with_capacity(*starts.last().unwrap_or(&0) as usize);
    for f in 0..starts.len().saturating_sub(1) {
        let len = (starts[f + 1] - starts[f]) as usize;
        out.extend(std::iter::repeat_n(f as u32, len));
    }
    out
}

/// Groups corners by undirected edge, detaches every face that would be the third on an edge
/// (file order decides), and returns each corner's partner on a two-face edge.
fn pair_corners_keeping_manifold_edges(
    faces: &mut WorkFaces,
    corner_face: &[u32],
    vertex_count: usize,
    report: &mut RepairReport,
) -> Vec<u32> {
    let corners = faces.indices.len();
    // Every corner's undirected edge, ordered by (edge, corner): a counting sort by the edge's
    // lower vertex, then each vertex's few edges sorted by their other end (a global sort
    // took most of the repair of a clean mesh). An entry is the other end and the corner; the
    // lower end is its bucket's vertex.
    let ends = |f: usize, c: usize| {
        let (a, b) = (faces.indices[c], faces.indices[faces.next_corner(c, f)]);
        if a < b { (a, b) } else { (b, a) }
    };
    let mut bucket_end = vec![0u32; vertex_count + 1];
    for f in 0..faces.count() {
        for c in faces.corners(f) {
            bucket_end[ends(f, c).0 as usize + 1] += 1;
        }
    }
    for v in 0..vertex_count {
        bucket_end[v + 1] += bucket_end[v];
    }
    let mut entries: Vec<(u32, u32)> = vec![(0, 0); corners];
    for f in 0..faces.count() {
        for c in faces.corners(f) {
            let (lo, hi) = ends(f, c);
            let at = &mut bucket_end[lo as usize];
            entries[*at as usize] = (hi, c as u32);
            *at += 1;
        }
    }
    // Each bucket now ends where the next began: each vertex's edges sorted by their other end.
    let mut crowded = false;
    let mut begin = 0;
    for &end in &bucket_end[..vertex_count] {
        let bucket = &mut entries[begin..end as usize];
        bucket.sort_unstable();
        crowded |= bucket.windows(3).any(|w| w[0].0 == w[2].0);
        begin = end as usize;
    }
    if !crowded {
        // No edge has three corners (most files): every face fits, and an edge's two corners
        // pair, without a group table or a face lookup.
        return pair_sorted_buckets(&entries, &bucket_end[..vertex_count], corners);
    }
    // Group id of every corner, and each group's corners in file order.
    let mut corner_group = vec![0u32; corners];
    let mut group_start = Vec::with_capacity(corners / 2 + 1);
    let mut begin = 0;
    for &end in &bucket_end[..vertex_count] {
        let bucket = &entries[begin..end as usize];
        for (i, &(hi, c)) in bucket.iter().enumerate() {
            if i == 0 || bucket[i - 1].0 != hi {
                group_start.push((begin + i) as u32);
            }
            corner_group[c as usize] = (group_start.len() - 1) as u32;
        }
        begin = end as usize;
    }
    group_start.push(entries.len() as u32);

    // Greedy in file order: a face joins only if every one of its edges has room.
    let mut used = vec![0u8; group_start.len() - 1];
    for f in 0..faces.count() {
        let fits = faces.corners(f).all(|c| used[corner_group[c] as usize] < 2);
        if fits {
            for c in faces.corners(f) {
                used[corner_group[c] as usize] += 1;
            }
        } else {
            faces.detached[f] = true;
            report.non_manifold_edge_faces += 1;
        }
    }

    // Some face was detached (an edge had three corners): an edge pairs the corners of the
    // faces kept on it.
    let mut twin = vec![NONE; corners];
    for g in 0..group_start.len() - 1 {
        let group = &entries[group_start[g] as usize..group_start[g + 1] as usize];
        let mut kept = group
            .iter()
            .map(|&(_, c)| c)
            .filter(|&c| !faces.detached[corner_face[c as usize] as usize]);
        if let (Some(a), Some(b), None) = (kept.next(), kept.next(), kept.next()) {
            twin[a as usize] = b;
            twin[b as usize] = a;
        }
    }
    twin
}

/// Each corner's partner on its edge, from each vertex's bucket of (other end, corner) entries
/// sorted, where no edge has more than two corners: the two corners of an edge pair, the lone
/// corner of a boundary edge has none.
fn pair_sorted_buckets(entries: &[(u32, u32)], bucket_end: &[u32], corners: usize) -> Vec<u32> {
    let mut twin = vec![NONE; corners];
    let mut begin = 0;
    for &end in bucket_end {
        let bucket = &entries[begin..end as usize];
        let mut i = 0;
        while i < bucket.len() {
            match bucket.get(i + 1) {
                Some(&(hi, b)) if hi == bucket[i].0 => {
                    let a = bucket[i].1;
                    twin[a as usize] = b;
                    twin[b as usize] = a;
                    i += 2;
                }
                _ => i += 1,
            }
        }
        begin = end as usize;
    }
    twin
}

/// Flips faces so that every manifold edge is used once in each direction.
fn orient_consistently(
    faces: &mut WorkFaces,
    corner_face: &[u32],
    twin: &mut [u32],
    report: &mut RepairReport,
) {
    // Most meshes come oriented: every paired corner runs against its twin, and the search
    // below would flip nothing.
    let consistent = twin
        .iter()
        .enumerate()
        .all(|(c, &d)| d == NONE || faces.indices[d as usize] != faces.indices[c]);
    if consistent {
        return;
    }
    const UNSEEN: u8 = 2;
    let count = faces.count();
    let mut flip = vec![UNSEEN; count];
    let mut queue = Vec::new();
    let mut component = Vec::new();
    for seed in 0..count {
        if faces.detached[seed] || flip[seed] != UNSEEN {
            continue;
        }
        flip[seed] = 0;
        queue.push(seed);
        component.clear();
        while let Some(f) = queue.pop() {
            if faces.detached[f] {
                continue;
            }
            component.push(f);
            for c in faces.corners(f) {
                let d = twin[c];
                if d == NONE {
                    continue;
                }
                let g = corner_face[d as usize] as usize;
                // Corners starting at the same vertex run the same way along the edge.
                let same_way = faces.indices[d as usize] == faces.indices[c];
                let wanted = flip[f] ^ u8::from(same_way);
                if flip[g] == UNSEEN {
                    flip[g] = wanted;
                    queue.push(g);
                } else if flip[g] != wanted {
                    faces.detached[g] = true;
                    report.non_orientable_faces += 1;
                    unpair_face(faces, g, twin);
                }
            }
        }
        let kept: Vec<usize> = component
            .iter()
            .copied()
            .filter(|&f| !faces.detached[f])
            .collect();
        let flipped = kept.iter().filter(|&&f| flip[f] == 1).count();
        if 2 * flipped > kept.len() {
            for &f in &kept {
                flip[f] ^= 1;
            }
        }
    }

    // Reverse the flipped faces and carry the corner pairing along.
    // Reversing v0..v(k-1) turns the edge of corner i into the edge of corner k-2-i (mod k).
    let corners = faces.indices.len();
    let mut moved: Vec<u32> = (0..corners as u32).collect();
    for (f, &flipped) in flip.iter().enumerate() {
        if flipped != 1 || faces.detached[f] {
            continue;
        }
        report.reoriented_faces += 1;
        let range = faces.corners(f);
        let (s, k) = (range.start, range.len());
        for i in 0..k {
            moved[s + i] = (s + (2 * k - 2 - i) % k) as u32;
        }
        faces.indices[range.clone()].reverse();
        faces.source[range].reverse();
    }
    if report.reoriented_faces > 0 {
        let mut new_twin = vec![NONE; corners];
        for c in 0..corners {
            if twin[c] != NONE {
                new_twin[moved[c] as usize] = moved[twin[c] as usize];
            }
        }
        twin.copy_from_slice(&new_twin);
    }
}

fn unpair_face(faces: &WorkFaces, f: usize, twin: &mut [u32]) {
    for c in faces.corners(f) {
        let d = twin[c];
        if d != NONE {
            twin[d as usize] = NONE;
            twin[c] = NONE;
        }
    }
}

/// Gives every detached face its own copies of the vertices it shares with other faces (a
/// vertex no other face uses stays its own).
fn detach_faces(
    faces: &mut WorkFaces,
    positions: &mut Vec<Vec3>,
    twin: &[u32],
    report: &mut RepairReport,
) {
    if !faces.detached.contains(&true) {
        return;
    }
    let mut taken = vec![false; positions.len()];
    for f in (0..faces.count()).filter(|&f| !faces.detached[f]) {
        for c in faces.corners(f) {
            taken[faces.indices[c] as usize] = true;
        }
    }
    for f in 0..faces.count() {
        if !faces.detached[f] {
            continue;
        }
        for c in faces.corners(f) {
            crate::checks::checked_assert_eq!(twin[c], NONE, "a detached face keeps no twins");
            let v = faces.indices[c] as usize;
            if taken[v] {
                positions.push(positions[v]);
                faces.indices[c] = (positions.len() - 1) as u32;
                report.added_vertices += 1;
            } else {
                taken[v] = true;
            }
        }
    }
}

/// Splits every vertex whose faces form more than one fan into one vertex per fan.
fn split_non_manifold_vertices(
    faces: &mut WorkFaces,
    positions: &mut Vec<Vec3>,
    twin: &[u32],
    report: &mut RepairReport,
) {
    let corners = faces.indices.len();
    // Union-find over outgoing halfedges (corners): c joins twin(prev(c)), the next one around
    // its vertex. Each resulting set is one fan.
    let mut parent: Vec<u32> = (0..corners as u32).collect();
    fn find(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            let up = parent[parent[x as usize] as usize];
            parent[x as usize] = up;
            x = up;
        }
        x
    }
    for f in 0..faces.count() {
        for c in faces.corners(f) {
            let t = twin[faces.prev_corner(c, f)];
            if t != NONE {
                let (a, b) = (find(&mut parent, c as u32), find(&mut parent, t));
                if a != b {
                    parent[a.max(b) as usize] = a.min(b);
                }
            }
        }
    }
    let mut first_fan = vec![NONE; positions.len()];
    let mut extra_fans: HashMap<u32, u32> = HashMap::default();
    let mut split: Vec<bool> = Vec::new();
    for c in 0..corners {
        let v = faces.indices[c];
        let fan = find(&mut parent, c as u32);
        if first_fan[v as usize] == NONE {
            first_fan[v as usize] = fan;
        } else if first_fan[v as usize] != fan {
            let copy = *extra_fans.entry(fan).or_insert_with(|| {
                positions.push(positions[v as usize]);
                (positions.len() - 1) as u32
            });
            if split.is_empty() {
                split = vec![false; first_fan.len()];
            }
            if !split[v as usize] {
                split[v as usize] = true;
                report.non_manifold_vertices += 1;
            }
            faces.indices[c] = copy;
        }
    }
    report.added_vertices += extra_fans.len();
}

/// Drops vertices no face uses and renumbers the rest in their original order.
fn drop_unreferenced(
    faces: &mut WorkFaces,
    positions: &mut Vec<Vec3>,
    input_count: usize,
    report: &mut RepairReport,
) -> Vec<u32> {
    let mut new_index = vec![NONE; positions.len()];
    for &v in &faces.indices {
        new_index[v as usize] = 0;
    }
    let mut next = 0u32;
    let mut kept = Vec::with_capacity(positions.len());
    for (v, slot) in new_index.iter_mut().enumerate() {
        if *slot == NONE {
            if v < input_count {
                report.unreferenced_vertices += 1;
            }
        } else {
            *slot = next;
            next += 1;
            kept.push(positions[v]);
        }
    }
    for v in &mut faces.indices {
        *v = new_index[*v as usize];
    }
    *positions = kept;
    new_index.truncate(input_count);
    new_index
}

#[cfg(test)]
mod tests {
    use super::*;

    fn soup(n: usize, faces: &[&[u32]]) -> PolygonSoup {
        let positions = (0..n)
            .map(|i| Vec3::new(i as f32, (i * i) as f32, 0.0))
            .collect();
        PolygonSoup::from_faces(positions, faces)
    }

    /// Every corner's twin runs the other way along the same edge, and twins are mutual.
    fn assert_paired(r: &RepairedFaces) {
        for f in 0..r.face_count() {
            let (s, e) = (r.face_starts[f] as usize, r.face_starts[f + 1] as usize);
            for c in s..e {
                let t = r.twin[c];
                if t == NONE {
                    continue;
                }
                assert_eq!(r.twin[t as usize], c as u32);
                let next = if c + 1 == e { s } else { c + 1 };
                let tf = r.face_starts.partition_point(|&x| x <= t) - 1;
                let (ts, te) = (r.face_starts[tf] as usize, r.face_starts[tf + 1] as usize);
                let tnext = if t as usize + 1 == te {
                    ts
                } else {
                    t as usize + 1
                };
                assert_eq!(r.indices[t as usize], r.indices[next]);
                assert_eq!(r.indices[tnext], r.indices[c]);
            }
        }
    }

    #[test]
    fn clean_input_is_untouched() {
        let s = soup(4, &[&[0, 1, 2], &[0, 2, 3]]);
        let (r, report) = repair(&s);
        assert!(report.is_clean(), "{report}");
        assert_eq!(r.indices, s.indices);
        assert_eq!(r.positions, s.positions);
        assert_paired(&r);
        assert_eq!(r.twin.iter().filter(|&&t| t != NONE).count(), 2);
    }

    #[test]
    fn bad_faces_are_dropped_and_counted() {
        let mut s = soup(
            5,
            &[&[0, 1, 2], &[0, 1], &[0, 1, 9], &[0, 1, 1], &[2, 3, 4]],
        );
        s.positions[4] = Vec3::NAN;
        let (r, report) = repair(&s);
        assert_eq!(report.too_few_corners, 1);
        assert_eq!(report.out_of_range_faces, 1);
        assert_eq!(report.repeated_vertex_faces, 1);
        assert_eq!(report.non_finite_faces, 1);
        assert_eq!(report.dropped_faces(), 4);
        assert_eq!(report.unreferenced_vertices, 2);
        assert_eq!(r.face_count(), 1);
        assert_eq!(r.positions.len(), 3);
        assert_eq!(r.input_vertex, vec![0, 1, 2, NONE, NONE]);
    }

    #[test]
    fn unreferenced_vertices_are_dropped_and_renumbered() {
        let s = soup(6, &[&[1, 3, 5]]);
        let (r, report) = repair(&s);
        assert_eq!(report.unreferenced_vertices, 3);
        assert_eq!(r.indices, vec![0, 1, 2]);
        assert_eq!(
            r.positions,
            vec![s.positions[1], s.positions[3], s.positions[5]]
        );
        assert_eq!(r.input_vertex, vec![NONE, 0, NONE, 1, NONE, 2]);
    }

    #[test]
    fn third_face_on_an_edge_is_detached() {
        // Three triangles on edge 0-1 (a "book" of three pages).
        let s = soup(5, &[&[0, 1, 2], &[1, 0, 3], &[0, 1, 4]]);
        let (r, report) = repair(&s);
        assert_eq!(report.non_manifold_edge_faces, 1);
        // Vertices 0 and 1 are copied; 4 is used by the detached face alone and stays.
        assert_eq!(report.added_vertices, 2);
        assert_eq!(report.unreferenced_vertices, 0);
        assert_eq!(r.face_count(), 3);
        assert_eq!(r.positions.len(), 7);
        assert_eq!(&r.indices[6..9], &[5, 6, 4]);
        assert_eq!(r.positions[5], s.positions[0]);
        assert_paired(&r);
    }

    #[test]
    fn inconsistent_orientation_is_fixed_by_majority() {
        // A strip of three triangles; the middle one is reversed.
        let s = soup(5, &[&[0, 1, 2], &[1, 2, 3], &[2, 3, 4]]);
        let (r, report) = repair(&s);
        assert_eq!(report.reoriented_faces, 1);
        assert_eq!(&r.indices[3..6], &[3, 2, 1]);
        assert_eq!(&r.indices[0..3], &[0, 1, 2]);
        assert_paired(&r);
        assert_eq!(r.twin.iter().filter(|&&t| t != NONE).count(), 4);
    }

    #[test]
    fn mobius_band_detaches_one_face() {
        // The minimal Möbius band: five triangles of consecutive vertices around a 5-cycle.
        let s = soup(
            5,
            &[&[0, 1, 2], &[1, 2, 3], &[2, 3, 4], &[3, 4, 0], &[4, 0, 1]],
        );
        let (r, report) = repair(&s);
        assert!(report.non_orientable_faces >= 1, "{report}");
        assert_eq!(r.face_count(), 5);
        assert_paired(&r);
    }

    #[test]
    fn bow_tie_vertex_is_split() {
        // Two triangles sharing only vertex 0.
        let s = soup(5, &[&[0, 1, 2], &[0, 3, 4]]);
        let (r, report) = repair(&s);
        assert_eq!(report.non_manifold_vertices, 1);
        assert_eq!(report.added_vertices, 1);
        assert_eq!(r.positions.len(), 6);
        assert_eq!(r.positions[5], s.positions[0]);
        assert_eq!(&r.indices[3..6], &[5, 3, 4]);
        assert_eq!(r.input_vertex[0], 0);
    }
}
