//! Scene readers' common ground (COLLADA, glTF): a mesh of a file read into a [`Part`], its
//! corners naming their own normals, UVs and colours, and the parts placed in the scene, each
//! read once, appended into one soup by [`assemble`] — each copy's positions transformed
//! (normals by the inverse transpose, the winding reversed under a mirroring transform so
//! faces keep facing out; the identity skipped so positions keep their bits), per-corner
//! normals and colours then gathered per vertex ([`super::corners`]), UVs kept per corner.
//!
//! Each face also keeps its object and material as a face group ([`crate::mesh::groups`]):
//! the material its primitive names, the object the name of the placement (node) it was read
//! through — so a scene of several objects saved to OBJ writes an `o` line for each. A part
//! whose groups are exact (a file Pappus wrote records each face's whole group) keeps them as
//! they are.

use bevy::math::{Mat3, Mat4, Vec2, Vec3};
use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::hash::Hash;

use super::corners::{attach_corner_normals, per_vertex};
use super::skipped::Skipped;
use super::text::Numbers;
use crate::io::error::ParseError;
use crate::memory_budget;
use crate::mesh::groups::{FaceGroups, Group, GroupRows, GroupTable};
use crate::mesh::soup::PolygonSoup;

/// A corner index that names no position.
pub(super) const NO_POSITION: u32 = u32::MAX;

/// One geometry's polygons, indexed into its own positions, and what its corners carry.
#[derive(Default)]
pub(super) struct Part {
    /// The `POSITION` source, in order.
    pub positions: Vec<Vec3>,
    /// Every face's corners, concatenated (indices into `positions`, or [`NO_POSITION`]).
    pub indices: Vec<u32>,
    /// Where each face starts in `indices`, then `indices.len()`.
    pub face_starts: Vec<u32>,
    /// A normal per corner, when an input gives them.
    pub normals: Option<Vec<Option<Vec3>>>,
    /// A texture coordinate per corner, when an input gives them.
    pub uvs: Option<Vec<Option<Vec2>>>,
    /// A colour per corner (0–255 per channel, as floats), when an input gives them.
    pub colors: Option<Vec<Option<Vec3>>>,
    /// What the geometry held that is not read.
    pub skipped: Skipped,
    /// A text format's numbers, and those mended on the way (COLLADA's arrays).
    pub numbers: Numbers,
    /// The groups its faces are in (empty: every face in the empty group).
    pub groups: Vec<Group>,
    /// Each face's row in `groups`.
    pub face_group: Vec<u32>,
    /// The row faces ended from now on take.
    current_group: u32,
    /// Whether `groups` name the object too (else a placement's name does).
    pub exact_groups: bool,
    /// The material libraries the file names (OBJ's `mtllib`, kept through a file Pappus wrote).
    pub material_libraries: Vec<String>,
}

impl Part {
    /// An empty part, ready for [`push_corner`](Self::push_corner) and
    /// [`end_face`](Self::end_face).
    pub fn new() -> Self {
        Part {
            face_starts: vec![0],
            ..Part::default()
        }
    }

    /// Appends a corner of the face being built: its position index (or [`NO_POSITION`]) and
    /// the values it names. A list starts (`None` for the corners before) at its first value.
    pub fn push_corner(
        &mut self,
        index: u32,
        normal: Option<Vec3>,
        uv: Option<Vec2>,
        color: Option<Vec3>,
    ) {
        let k = self.indices.len();
        self.indices.push(index);
        put(&mut self.normals, k, normal);
        put(&mut self.uvs, k, uv);
        put(&mut self.colors, k, color);
    }

    /// Ends the face whose corners were pushed since the last one ended.
    pub fn end_face(&mut self) {
        self.face_starts.push(self.indices.len() as u32);
        self.face_group.push(self.current_group);
    }

    /// Puts the faces ended from now on into `group` (a primitive's material).
    pub fn use_group(&mut self, group: Group) {
        self.current_group = match self.groups.iter().position(|g| *g == group) {
            Some(row) => row as u32,
            None => {
                self.groups.push(group);
                (self.groups.len() - 1) as u32
            }
        };
    }
}

/// Sets corner `k`'s value in a per-corner list (padding it with `None` up to `k`), creating
/// the list at its first value.
fn put<T: Copy>(list: &mut Option<Vec<Option<T>>>, k: usize, value: Option<T>) {
    match list {
        Some(list) => {
            list.resize(k, None);
            list.push(value);
        }
        None if value.is_some() => {
            let mut new = vec![None; k];
            new.push(value);
            *list = Some(new);
        }
        None => {}
    }
}

/// The note naming the objects (placed meshes) read into one mesh, when there are several:
/// `"3 objects (Cube, Cone, Plane) read as one mesh of several parts"`.
fn merged_objects_note(names: &[&str]) -> Option<String> {
    if names.len() < 2 {
        return None;
    }
    let shown: Vec<&str> = names.iter().take(5).copied().collect();
    let more = if names.len() > 5 { ", …" } else { "" };
    Some(format!(
        "{} objects ({}{more}) read as one mesh of several parts",
        names.len(),
        shown.join(", ")
    ))
}

/// A scene's meshes as one soup: each placement is (the key of its mesh, its transform, its
/// name); each distinct mesh is read once by `read` (`None`: not a polygon mesh, left out),
/// the copies are checked against the memory budget, then appended in order, and the soup's
/// notes name the objects merged. Returns the parts read too, by key, for the caller's notes.
///
/// # Errors
/// The first error of `read`, or the budget's refusal.
pub(super) fn assemble<K: Copy + Eq + Hash>(
    placements: &[(K, Mat4, &str)],
    mut read: impl FnMut(K) -> Result<Option<Part>, ParseError>,
) -> Result<(PolygonSoup, HashMap<K, Option<Part>>), ParseError> {
    let mut parts: HashMap<K, Option<Part>> = HashMap::new();
    for &(key, _, _) in placements {
        if let Entry::Vacant(entry) = parts.entry(key) {
            entry.insert(read(key)?);
        }
    }
    let placed = || {
        placements
            .iter()
            .filter_map(|(key, transform, name)| Some((parts.get(key)?.as_ref()?, transform, name)))
    };
    check_budget(placed().map(|(part, _, _)| part))?;
    let mut merged = Merged::default();
    let mut names = Vec::new();
    for (part, transform, name) in placed() {
        merged.append(part, *transform, name);
        names.push(*name);
    }
    let mut soup = merged.into_soup();
    soup.notes.extend(merged_objects_note(&names));
    Ok((soup, parts))
}

/// Refuses a scene whose placed copies (`placed`: each part once per placement) would not fit
/// the memory budget: instances multiply, so a small file can describe a huge mesh.
///
/// # Errors
/// The budget's refusal, as an unsupported-content error.
fn check_budget<'p>(placed: impl Iterator<Item = &'p Part>) -> Result<(), ParseError> {
    let (mut copies, mut faces, mut rows) = (0usize, 0u64, 0u64);
    for part in placed {
        copies += 1;
        let part_faces = part.face_starts.len().saturating_sub(1) as u64;
        faces = faces.saturating_add(part_faces);
        // Vertices, a halfedge a corner, half an edge a corner, and the faces.
        let corners = part.indices.len() as u64;
        rows =
            rows.saturating_add(part.positions.len() as u64 + corners + corners / 2 + part_faces);
    }
    memory_budget::check(&memory_budget::Estimate {
        what: format!("the scene's {copies} placed mesh(es)"),
        faces,
        rows,
        instead: "open a scene that places fewer copies",
    })
    .map_err(|refusal| ParseError::byte(0, refusal.to_string()).unsupported())
}

/// The parts appended one after another into one part, per-corner values kept until the end,
/// and the merged groups by row.
struct Merged(Part, GroupRows);

impl Default for Merged {
    fn default() -> Self {
        Merged(Part::new(), GroupRows::default())
    }
}

impl Merged {
    /// Appends a copy of `part` placed by `transform`, its faces in the object `name` (unless
    /// its groups are exact).
    pub fn append(&mut self, part: &Part, transform: Mat4, name: &str) {
        // The merged row of each of the part's groups.
        let rows: Vec<u32> = (0..part.groups.len().max(1))
            .map(|row| {
                let mut group = part.groups.get(row).cloned().unwrap_or_default();
                if !part.exact_groups && !name.is_empty() {
                    group.object = Some(name.to_owned());
                }
                self.1.row(&group)
            })
            .collect();
        for library in &part.material_libraries {
            if !self.0.material_libraries.contains(library) {
                self.0.material_libraries.push(library.clone());
            }
        }
        let merged = &mut self.0;
        let base = merged.positions.len() as u32;
        let identity = transform == Mat4::IDENTITY;
        // The identity is skipped, not applied: 1·x + 0·y would turn −0 into +0.
        merged.positions.extend(part.positions.iter().map(|&p| {
            if identity {
                p
            } else {
                transform.transform_point3(p)
            }
        }));
        let normal_matrix = Mat3::from_mat4(transform).inverse().transpose();
        let normal_matrix = if normal_matrix.is_finite() {
            normal_matrix
        } else {
            Mat3::IDENTITY
        };
        let mirrored = transform.determinant() < 0.0;
        for (f, face) in part.face_starts.windows(2).enumerate() {
            merged.current_group = rows[part.face_group.get(f).copied().unwrap_or(0) as usize];
            let corners = face[0] as usize..face[1] as usize;
            let corners: Vec<usize> = if mirrored {
                corners.rev().collect()
            } else {
                corners.collect()
            };
            for k in corners {
                let index = match part.indices[k] {
                    NO_POSITION => NO_POSITION,
                    v => base + v,
                };
                let normal = corner(&part.normals, k).map(|n: Vec3| {
                    if identity {
                        n
                    } else {
                        (normal_matrix * n).normalize_or_zero()
                    }
                });
                merged.push_corner(index, normal, corner(&part.uvs, k), corner(&part.colors, k));
            }
            merged.end_face();
        }
    }

    /// The soup, per-corner normals and colours gathered per vertex; face groups where any
    /// face has a name.
    pub fn into_soup(self) -> PolygonSoup {
        let Part {
            positions,
            indices,
            face_starts,
            normals,
            uvs,
            colors,
            face_group,
            material_libraries,
            ..
        } = self.0;
        let groups = self.1.into_groups();
        let named = groups.iter().any(|g| *g != Group::default());
        let mut soup = PolygonSoup {
            positions,
            indices,
            face_starts,
            face_groups: (named || !material_libraries.is_empty()).then_some(FaceGroups {
                table: GroupTable {
                    material_libraries,
                    groups,
                },
                of_face: face_group,
            }),
            ..PolygonSoup::default()
        };
        let n = soup.positions.len();
        if let Some(normals) = normals {
            attach_corner_normals(&mut soup, normals.into_iter());
        }
        if let Some(uvs) = uvs {
            let missing = uvs.iter().filter(|u| u.is_none()).count();
            if missing > 0 {
                soup.notes.push(format!(
                    "{missing} face corner(s) have no texture coordinate: given (0, 0)"
                ));
            }
            soup.corner_uvs = Some(uvs.into_iter().map(|u| u.unwrap_or(Vec2::ZERO)).collect());
        }
        if let Some(colors) = colors {
            let gathered = per_vertex(&soup.indices, n, colors.into_iter(), |sum, count| {
                sum / count as f32
            });
            if gathered.differing > 0 {
                soup.notes.push(format!(
                    "{} vertex(es) had different colours at different corners: each takes their mean",
                    gathered.differing
                ));
            }
            soup.vertex_colors = Some(
                gathered
                    .values
                    .into_iter()
                    .map(|c| c.map_or([0; 3], |c| c.round().to_array().map(|v| v as u8)))
                    .collect(),
            );
        }
        soup
    }
}

/// Corner `k`'s value in a part's per-corner list, if it has one.
fn corner<T: Copy>(list: &Option<Vec<Option<T>>>, k: usize) -> Option<T> {
    list.as_ref().and_then(|l| l.get(k).copied().flatten())
}
