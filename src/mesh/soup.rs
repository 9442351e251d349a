//! A polygon soup: positions plus faces as lists of vertex indices.
//!
//! This is the neutral exchange form between file formats and the entity mesh: every reader in
//! `io` produces one, [`crate::mesh::build`] turns one into entities (repairing what it must), and
//! [`crate::mesh::build::to_soup`] turns a mesh back into one for the writers.
//!
//! Faces are stored flat (CSR): `indices` holds every face's vertex indices one after another and
//! `face_starts[i]..face_starts[i + 1]` is face `i`. A soup makes no promise about its contents:
//! indices may be out of range, faces may repeat vertices, positions may be NaN. The builder is
//! what checks and repairs.

use bevy::math::{Vec2, Vec3};

use super::attributes::{MeshAttributes, listed};
use super::groups::FaceGroups;

/// Positions and polygonal faces, unchecked.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolygonSoup {
    /// Vertex positions, indexed by the face indices.
    pub positions: Vec<Vec3>,
    /// Every face's vertex indices, concatenated.
    pub indices: Vec<u32>,
    /// Start of each face in `indices`, plus one final entry equal to `indices.len()`.
    /// Always holds `face_count() + 1` entries (a default soup starts with `[0]` once a face is
    /// pushed; an empty soup may hold `[]` or `[0]`).
    pub face_starts: Vec<u32>,
    /// A scalar per vertex (PLY's `quality`), when the soup carries one: a quantity computed on
    /// the mesh for export (curvature, valence, …). One per position.
    pub vertex_quality: Option<Vec<f32>>,
    /// Other named scalars per vertex, in the order the file declared them (a PLY's vertex
    /// properties Pappus has no column for: `confidence`, `intensity`, `alpha`, …), one value
    /// per position each.
    pub vertex_scalars: Vec<(String, Vec<f32>)>,
    /// Named scalars per face, in the order the file declared them (a PLY's face properties:
    /// `quality`, `flags`, `area`, …), one value per face each, in face order (NaN where a
    /// face had none: one read from an element that does not declare the property).
    pub face_scalars: Vec<(String, Vec<f32>)>,
    /// A colour per vertex (8-bit sRGB), when the soup carries one. One per position.
    pub vertex_colors: Option<Vec<[u8; 3]>>,
    /// A normal per vertex, when the soup carries one. One per position.
    pub vertex_normals: Option<Vec<Vec3>>,
    /// A texture coordinate per face corner, when the soup carries them: parallel to
    /// `indices` (`corner_uvs[k]` is the UV of vertex `indices[k]` inside its face), so two
    /// faces may give one vertex different UVs (a seam).
    pub corner_uvs: Option<Vec<Vec2>>,
    /// The object, group, material and smoothing group of each face, when the soup carries
    /// them (OBJ's `o`, `g`, `usemtl`, `s`): one per face, in face order.
    pub face_groups: Option<FaceGroups>,
    /// What a reader had to approximate, one sentence each (corners of one vertex that gave it
    /// different normals, corners without a UV in a file with UVs), for the load message.
    pub notes: Vec<String>,
}

impl PolygonSoup {
    /// An empty soup with room for `vertices` positions and `faces` faces of `corners` indices in all.
    pub fn with_capacity(vertices: usize, faces: usize, corners: usize) -> Self {
        let mut face_starts = Vec::with_capacity(faces + 1);
        face_starts.push(0);
        Self {
            positions: Vec::with_capacity(vertices),
            indices: Vec::with_capacity(corners),
            face_starts,
            vertex_quality: None,
            vertex_scalars: Vec::new(),
            face_scalars: Vec::new(),
            vertex_colors: None,
            vertex_normals: None,
            corner_uvs: None,
            face_groups: None,
            notes: Vec::new(),
        }
    }

    /// Builds a soup from positions and a list of faces (convenient in tests and fixtures).
    pub fn from_faces<F: AsRef<[u32]>>(positions: Vec<Vec3>, faces: &[F]) -> Self {
        let corners = faces.iter().map(|f| f.as_ref().len()).sum();
        let mut soup = Self::with_capacity(positions.len(), faces.len(), corners);
        soup.positions = positions;
        for face in faces {
            soup.push_face(face.as_ref());
        }
        soup
    }

    /// Appends one face (no checks: the builder validates).
    pub fn push_face(&mut self, face: &[u32]) {
        if self.face_starts.is_empty() {
            self.face_starts.push(0);
        }
        self.indices.extend_from_slice(face);
        self.face_starts.push(self.indices.len() as u32);
    }

    /// The per-vertex attributes the soup carries that a mesh built from it does not keep, by
    /// name (`quality` and the other scalars: UVs, normals and colours are kept), for a
    /// message.
    pub fn vertex_attributes(&self) -> Vec<&str> {
        let quality = self.vertex_quality.is_some().then_some("quality");
        quality
            .into_iter()
            .chain(self.vertex_scalars.iter().map(|(name, _)| name.as_str()))
            .collect()
    }

    /// The scalars the soup carries that a mesh built from it does not keep, in a person's
    /// words for a message (`"vertex quality, confidence and face flags"`); `None` without any.
    pub fn scalars_not_kept(&self) -> Option<String> {
        let faces: Vec<&str> = self.face_scalars.iter().map(|(n, _)| n.as_str()).collect();
        let parts: Vec<String> = [("vertex", self.vertex_attributes()), ("face", faces)]
            .into_iter()
            .filter(|(_, names)| !names.is_empty())
            .map(|(kind, names)| format!("{kind} {}", listed(&names)))
            .collect();
        (!parts.is_empty()).then(|| listed(&parts.iter().map(String::as_str).collect::<Vec<_>>()))
    }

    /// The attributes of the soup a mesh keeps: which of corner UVs, vertex normals, vertex
    /// colours and face groups it carries with one value per corner / position / face.
    pub fn attributes(&self) -> MeshAttributes {
        let n = self.positions.len();
        MeshAttributes {
            uv: self
                .corner_uvs
                .as_ref()
                .is_some_and(|u| u.len() == self.indices.len()),
            normals: self.vertex_normals.as_ref().is_some_and(|v| v.len() == n),
            colors: self.vertex_colors.as_ref().is_some_and(|v| v.len() == n),
            seams: false,
            groups: self
                .face_groups
                .as_ref()
                .is_some_and(|g| g.fits(self.face_count())),
        }
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.face_starts.len().saturating_sub(1)
    }

    /// The vertex indices of face `i`.
    ///
    /// # Panics
    /// If `i >= self.face_count()`.
    pub fn face(&self, i: usize) -> &[u32] {
        let (a, b) = (
            self.face_starts[i] as usize,
            self.face_starts[i + 1] as usize,
        );
        &self.indices[a..b]
    }

    /// Every face in order.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = &[u32]> + '_ {
        (0..self.face_count()).map(|i| self.face(i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_round_trip_through_flat_storage() {
        let soup = PolygonSoup::from_faces(vec![Vec3::ZERO; 5], &[vec![0, 1, 2], vec![1, 3, 4, 2]]);
        assert_eq!(soup.face_count(), 2);
        assert_eq!(soup.face(0), &[0, 1, 2]);
        assert_eq!(soup.face(1), &[1, 3, 4, 2]);
        assert_eq!(soup.faces().count(), 2);
        assert_eq!(PolygonSoup::default().face_count(), 0);
    }
}
