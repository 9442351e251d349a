//! Attributes a mesh may carry beside its positions: texture coordinates per corner, normals and
//! colours per vertex. Components on the elements, and a record on the mesh of which it has.
//!
//! | attribute | component        | on                       | type                       |
//! |-----------|------------------|--------------------------|----------------------------|
//! | UV        | [`CornerUv`]     | every face halfedge      | `Vec2`                     |
//! | normal    | [`VertexNormal`] | every vertex             | `Vec3` (as the file gave)  |
//! | colour    | [`VertexColor`]  | every vertex             | `[u8; 3]`, 8-bit sRGB      |
//! | group     | [`FaceGroup`]    | every face               | a row of the [`GroupTable`] |
//!
//! # The corner convention
//! A UV belongs to a **corner**: a vertex inside one face. The corner of face halfedge `h` is its
//! tip, `to_vertex(h)`, inside `face(h)` (Pappus's [`crate::mesh::Halfedge::vertex`] is the
//! vertex a halfedge points to). So a vertex has one corner per face around it, and a seam (the
//! same vertex at two places of the texture) is two corners of one vertex with different UVs.
//! Boundary halfedges have no face and carry no UV.
//!
//! # The record
//! [`MeshAttributes`] on the mesh entity says which attributes the mesh has; absent means none.
//! Invariant: when it says UVs, every face halfedge of the mesh has a [`CornerUv`]; when it
//! says normals (colours), every vertex has a [`VertexNormal`] ([`VertexColor`]); when it does
//! not, no element has that component. So "has UVs" is one lookup, and a mesh without
//! attributes pays nothing: every pass that carries them looks at the record first.
//!
//! # Colours are 8-bit
//! PLY stores colours as `uchar` and MeshLab, Blender and most scanners write them so: 8-bit
//! sRGB keeps those files bit for bit. An OBJ colour (a float per channel, 0–1) is rounded to
//! the nearest 1/255; what Pappus writes (`c / 255` in the shortest form that reads back) reads
//! back to the same bytes.
//!
//! # Who carries what
//! - Files ([`crate::mesh::build`], `io`): read into the components and written back, bit for bit.
//! - Tables ([`crate::mesh::tables`]): [`AttributeColumns`] in the [`Connectivity`] columns
//!   (UV by halfedge row, normal and colour by vertex row), read by `extract` and written by
//!   the table writers; so whole-mesh undo and the editor's jobs keep them exactly.
//! - Local undo records ([`crate::mesh::change`]): every element's attributes with its links.
//! - Local operations (split, bisect, flip, collapse, dissolve, face split, hole fill):
//!   interpolate at new points and keep what is old (see each operation's module doc).
//! - Subdivision: UVs interpolated linearly per corner, colours averaged, normals dropped.
//! - Remeshing, simplification, and what moves along the simplification history: dropped, and
//!   the outcome says so ([`MeshAttributes::dropped_note`]).
//!
//! Face groups (OBJ's objects, groups, materials) have their own module,
//! [`crate::mesh::groups`], which says who carries them.
//!
//! [`Connectivity`]: crate::mesh::tables::Connectivity
//! [`FaceGroup`]: crate::mesh::groups::FaceGroup
//! [`GroupTable`]: crate::mesh::groups::GroupTable

use bevy::math::{Vec2, Vec3};
use bevy::prelude::{Component, Entity, World};

use super::elements::{Halfedge, InMesh, Vertex};
use super::groups::{FaceGroups, remove_face_groups};
use super::ids::{HalfedgeId, MeshId, VertexId};

/// The texture coordinate of a corner: on a face halfedge `h`, the UV of `to_vertex(h)` inside
/// `face(h)`.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
#[component(storage = "SparseSet")]
pub struct CornerUv(pub Vec2);

/// A vertex normal, as the file gave it (not renormalised, so it writes back bit for bit).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct VertexNormal(pub Vec3);

/// On a mesh entity: an edit has changed the mesh since its vertex normals were read, so they
/// may point the way the surface used to face; a save recomputes them
/// ([`crate::edit::soup_to_save`]).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StaleNormals;

/// A vertex colour, 8-bit sRGB (red, green, blue).
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct VertexColor(pub [u8; 3]);

/// A seam mark on an edge: the parameterization cuts the surface open along it, so the corners
/// on its two sides get UVs of their own. Marked by hand (the `seam` operation, Ctrl+E); files have no
/// place for it (a parameterized mesh's seams are where its corner UVs differ).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Seam;

/// Which attributes a mesh has: a component on the mesh entity (absent: none).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshAttributes {
    /// Every face halfedge has a [`CornerUv`].
    pub uv: bool,
    /// Every vertex has a [`VertexNormal`].
    pub normals: bool,
    /// Every vertex has a [`VertexColor`].
    pub colors: bool,
    /// Edges may carry a [`Seam`] mark (when false, none does; when true, some may).
    pub seams: bool,
    /// Every face has a [`crate::mesh::groups::FaceGroup`], and the mesh entity a
    /// [`crate::mesh::groups::GroupTable`].
    pub groups: bool,
}

impl MeshAttributes {
    /// No attributes.
    pub const NONE: Self = Self {
        uv: false,
        normals: false,
        colors: false,
        seams: false,
        groups: false,
    };

    /// The record of `mesh` (none if it has no record or is gone).
    pub fn of(world: &World, mesh: MeshId) -> Self {
        world.get::<Self>(mesh.0).copied().unwrap_or_default()
    }

    /// Whether there is no attribute.
    pub fn is_empty(self) -> bool {
        self == Self::NONE
    }

    /// Those of `self` that `now` lacks.
    pub fn lost_in(self, now: Self) -> Self {
        Self {
            uv: self.uv && !now.uv,
            normals: self.normals && !now.normals,
            colors: self.colors && !now.colors,
            seams: self.seams && !now.seams,
            groups: self.groups && !now.groups,
        }
    }

    /// Names for messages, in a fixed order: `UVs`, `normals`, `colours`, `seam marks`,
    /// `groups`.
    pub fn names(self) -> Vec<&'static str> {
        [
            ("UVs", self.uv),
            ("normals", self.normals),
            ("colours", self.colors),
            ("seam marks", self.seams),
            ("groups", self.groups),
        ]
        .into_iter()
        .filter_map(|(n, has)| has.then_some(n))
        .collect()
    }

    /// The names joined for a sentence: `UVs`, `UVs and normals`, `UVs, normals and colours`.
    pub fn describe(self) -> String {
        listed(&self.names())
    }

    /// The note an outcome ends with when an operation dropped these (empty when none):
    /// ` — UVs and normals dropped: remeshing does not carry them`.
    pub fn dropped_note(self, why: &str) -> String {
        if self.is_empty() {
            String::new()
        } else {
            format!(" — {} dropped: {why}", self.describe())
        }
    }
}

/// Attributes in table form, beside the connectivity tables: `uv` by halfedge row (a boundary
/// halfedge's entry is unused), `normals` and `colors` by vertex row. A column that is `None`,
/// or whose length is not its kind's row count, is an attribute the tables do not carry.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AttributeColumns {
    /// Corner UVs, by halfedge row.
    pub uv: Option<Vec<Vec2>>,
    /// Normals, by vertex row.
    pub normals: Option<Vec<Vec3>>,
    /// Colours, by vertex row.
    pub colors: Option<Vec<[u8; 3]>>,
    /// Seam marks, by edge row.
    pub seams: Option<Vec<bool>>,
    /// Face groups, by face row, with their names.
    pub groups: Option<FaceGroups>,
}

impl AttributeColumns {
    /// Which columns are present (whatever their length).
    pub fn present(&self) -> MeshAttributes {
        MeshAttributes {
            uv: self.uv.is_some(),
            normals: self.normals.is_some(),
            colors: self.colors.is_some(),
            seams: self.seams.is_some(),
            groups: self.groups.is_some(),
        }
    }

    /// Whether no column is present.
    pub fn is_empty(&self) -> bool {
        self.present().is_empty()
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.uv.as_ref().map_or(0, |v| v.capacity() * 8)
            + self.normals.as_ref().map_or(0, |v| v.capacity() * 12)
            + self.colors.as_ref().map_or(0, |v| v.capacity() * 3)
            + self.seams.as_ref().map_or(0, Vec::capacity)
            + self.groups.as_ref().map_or(0, |g| g.of_face.capacity() * 4)
    }
}

/// The UV of face halfedge `h`'s corner, if it has one.
pub fn corner_uv(world: &World, h: HalfedgeId) -> Option<Vec2> {
    world.get::<CornerUv>(h.0).map(|c| c.0)
}

/// Sets the UV of `h`'s corner (inserting the component where it is missing).
pub fn set_corner_uv(world: &mut World, h: HalfedgeId, uv: Vec2) {
    if let Some(mut c) = world.get_mut::<CornerUv>(h.0) {
        c.0 = uv;
    } else if let Ok(mut e) = world.get_entity_mut(h.0) {
        e.insert(CornerUv(uv));
    }
}

/// The attributes of the mesh that element `e` belongs to (none if it is gone).
pub fn of_element(world: &World, e: Entity) -> MeshAttributes {
    world
        .get::<InMesh>(e)
        .map_or(MeshAttributes::NONE, |m| MeshAttributes::of(world, m.0))
}

/// Gives new vertex `v` the normal and colour at parameter `t` from `a` to `b` (normals
/// interpolated linearly and renormalised, colours rounded), where the mesh has them.
pub fn interpolate_vertex(
    world: &mut World,
    has: MeshAttributes,
    v: VertexId,
    (a, b): (VertexId, VertexId),
    t: f32,
) {
    if has.normals {
        let get = |x: VertexId| world.get::<VertexNormal>(x.0).map_or(Vec3::ZERO, |n| n.0);
        let n = get(a).lerp(get(b), t).normalize_or_zero();
        world.entity_mut(v.0).insert(VertexNormal(n));
    }
    if has.colors {
        let get = |x: VertexId| world.get::<VertexColor>(x.0).map_or([0; 3], |c| c.0);
        let c = lerp_color(get(a), get(b), t);
        world.entity_mut(v.0).insert(VertexColor(c));
    }
}

/// A colour between `a` and `b` at parameter `t`, each channel rounded.
pub fn lerp_color(a: [u8; 3], b: [u8; 3], t: f32) -> [u8; 3] {
    std::array::from_fn(|k| {
        let (x, y) = (f32::from(a[k]), f32::from(b[k]));
        (x + (y - x) * t).round().clamp(0.0, 255.0) as u8
    })
}

/// The mean of colours, each channel rounded (black for none).
pub fn mean_color(colors: impl IntoIterator<Item = [u8; 3]>) -> [u8; 3] {
    let (mut sum, mut n) = ([0u32; 3], 0u32);
    for c in colors {
        for k in 0..3 {
            sum[k] += u32::from(c[k]);
        }
        n += 1;
    }
    if n == 0 {
        return [0; 3];
    }
    sum.map(|s| ((s + n / 2) / n) as u8)
}

/// Removes every attribute of `mesh` (components and record) and returns what it had.
pub fn drop_attributes(world: &mut World, mesh: MeshId) -> MeshAttributes {
    let had = MeshAttributes::of(world, mesh);
    if had.is_empty() {
        return had;
    }
    remove_attributes(world, mesh, had);
    had
}

/// Removes the attributes `which` from every element of `mesh` and from its record.
pub fn remove_attributes(world: &mut World, mesh: MeshId, which: MeshAttributes) {
    if which.is_empty() {
        return;
    }
    let mut gone: Vec<Entity> = Vec::new();
    if which.uv
        && let Some(mut q) = world.try_query::<(Entity, &InMesh, &CornerUv)>()
    {
        gone.extend(
            q.iter(world)
                .filter(|(_, m, _)| m.0 == mesh)
                .map(|(e, ..)| e),
        );
    }
    for e in gone.drain(..) {
        world.entity_mut(e).remove::<CornerUv>();
    }
    if which.seams
        && let Some(mut q) = world.try_query::<(Entity, &InMesh, &Seam)>()
    {
        gone.extend(
            q.iter(world)
                .filter(|(_, m, _)| m.0 == mesh)
                .map(|(e, ..)| e),
        );
    }
    for e in gone.drain(..) {
        world.entity_mut(e).remove::<Seam>();
    }
    if which.normals || which.colors {
        if let Some(mut q) = world.try_query::<(Entity, &InMesh, &Vertex)>() {
            gone.extend(
                q.iter(world)
                    .filter(|(_, m, _)| m.0 == mesh)
                    .map(|(e, ..)| e),
            );
        }
        for e in gone.drain(..) {
            let mut x = world.entity_mut(e);
            if which.normals {
                x.remove::<VertexNormal>();
            }
            if which.colors {
                x.remove::<VertexColor>();
            }
        }
    }
    if which.groups {
        remove_face_groups(world, mesh);
    }
    let now = MeshAttributes::of(world, mesh).lost_in(which);
    set_record(world, mesh, now);
}

/// Writes the record of `mesh` (removing it when empty, so a mesh without attributes keeps the
/// shape it always had).
pub fn set_record(world: &mut World, mesh: MeshId, has: MeshAttributes) {
    let Ok(mut e) = world.get_entity_mut(mesh.0) else {
        return;
    };
    if has.is_empty() {
        if e.contains::<MeshAttributes>() {
            e.remove::<MeshAttributes>();
        }
    } else {
        e.insert(has);
    }
}

/// Whether halfedge `h` is a face halfedge (and so should carry a UV when the mesh has them).
pub fn is_corner(world: &World, h: HalfedgeId) -> bool {
    world.get::<Halfedge>(h.0).is_some_and(|x| x.face.is_some())
}

/// Names joined for a sentence: empty for none, `UVs`, `UVs and normals`, `UVs, normals and colours`.
pub fn listed(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => (*one).to_string(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_read_as_a_sentence() {
        let all = MeshAttributes {
            uv: true,
            normals: true,
            colors: true,
            seams: false,
            groups: false,
        };
        assert_eq!(all.describe(), "UVs, normals and colours");
        let marked = MeshAttributes { seams: true, ..all };
        assert_eq!(marked.describe(), "UVs, normals, colours and seam marks");
        let two = MeshAttributes {
            colors: false,
            ..all
        };
        assert_eq!(
            two.dropped_note("remeshing does not carry them"),
            " — UVs and normals dropped: remeshing does not carry them"
        );
        assert_eq!(MeshAttributes::NONE.dropped_note("x"), "");
        assert_eq!(
            all.lost_in(two),
            MeshAttributes {
                colors: true,
                ..MeshAttributes::NONE
            }
        );
    }

    #[test]
    fn colours_mix_with_rounding() {
        assert_eq!(lerp_color([0, 255, 10], [255, 0, 11], 0.5), [128, 128, 11]);
        assert_eq!(mean_color([[0, 0, 0], [1, 2, 255]]), [1, 1, 128]);
        assert_eq!(mean_color([]), [0, 0, 0]);
    }
}
