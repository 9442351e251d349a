//! The soup a save writes: the mesh as it stands, with vertex normals that edits made stale
//! recomputed — angle-weighted (Thürmer & Wüthrich 1998), as `process --normals angle` writes
//! them — so that no file gets normals pointing the way the surface used to face.
//!
//! A mesh's normals are the file's until an edit changes the mesh ([`StaleNormals`] marks it,
//! in [`super::Edit::run`]); an unedited mesh saves them bit for bit.

use bevy::prelude::World;

use crate::mesh::attributes::{MeshAttributes, StaleNormals};
use crate::mesh::tables::extract;
use crate::mesh::{MeshId, PolygonSoup, to_soup};
use crate::ops::geometry::{NormalWeighting, Surface, vertex_normals};

/// The note a save gives when it recomputed the normals.
pub const RECOMPUTED_NORMALS: &str = "vertex normals recomputed (angle-weighted): edits had changed the surface since they were read";

/// Marks `mesh`'s normals stale when it has normals and `edit` does not declare that they
/// still describe the surface (a seam mark, a reversal, a normalization do). [`super::Edit::run`] calls it, and the editor's job commit, whose
/// edit ran on a copy.
pub fn mark_normals_stale(world: &mut World, mesh: MeshId, edit: &super::Edit) {
    if MeshAttributes::of(world, mesh).normals
        && !edit.declaration().keeps_normals
        && let Ok(mut entity) = world.get_entity_mut(mesh.0)
    {
        entity.insert(StaleNormals);
    }
}

/// The soup to save for `mesh`, and the note to give when its normals were recomputed.
pub fn soup_to_save(world: &World, mesh: MeshId) -> (PolygonSoup, Option<&'static str>) {
    let mut soup = to_soup(world, mesh);
    if soup.vertex_normals.is_none() || world.get::<StaleNormals>(mesh.0).is_none() {
        return (soup, None);
    }
    // The soup's vertices are the mesh's table rows (see `to_soup`).
    let surface = Surface::from_tables(&extract(world, mesh).tables);
    let normals = vertex_normals(&surface, NormalWeighting::Angle);
    soup.vertex_normals = Some(normals.iter().map(|n| n.as_vec3()).collect());
    (soup, Some(RECOMPUTED_NORMALS))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edit::{Edit, EditContext};
    use crate::mesh::{MeshInfo, MeshMembers, build_mesh, shapes};
    use bevy::math::Vec3;

    /// An unedited mesh saves the file's normals bit for bit, however wrong; after an edit
    /// they are the angle-weighted normals of the surface as it now stands, and the save says so.
    #[test]
    fn normals_an_edit_made_stale_are_recomputed_on_save() {
        let mut soup = shapes::icosphere(2);
        soup.vertex_normals = Some(vec![Vec3::new(0.0, -0.0, 1.0); soup.positions.len()]);
        let mut world = World::new();
        let mesh = build_mesh(&mut world, &soup, MeshInfo::default())
            .unwrap()
            .mesh;
        let (saved, note) = soup_to_save(&world, mesh);
        assert_eq!(note, None);
        let bits = |n: &Vec<Vec3>| {
            n.iter()
                .map(|v| v.to_array().map(f32::to_bits))
                .collect::<Vec<_>>()
        };
        assert_eq!(
            bits(saved.vertex_normals.as_ref().unwrap()),
            bits(soup.vertex_normals.as_ref().unwrap())
        );
        let mut context = EditContext {
            progress: &mut |_| true,
        };
        // Reversing and normalizing declare that the normals still hold (turned and moved
        // with the surface): written as they are, with no note.
        for step in ["reverse", "normalize"] {
            let edit = Edit::registered(step).unwrap();
            edit.run(&mut world, mesh, &mut context).unwrap();
            assert_eq!(soup_to_save(&world, mesh).1, None, "{step}");
        }
        let (saved, _) = soup_to_save(&world, mesh);
        assert_eq!(
            bits(saved.vertex_normals.as_ref().unwrap()),
            bits(
                &soup
                    .vertex_normals
                    .as_ref()
                    .unwrap()
                    .iter()
                    .map(|n| -*n)
                    .collect()
            )
        );
        let v = MeshMembers::collect(&world, mesh).vertices[0];
        Edit::Move(vec![(v, Vec3::new(0.0, 0.0, 2.0))])
            .run(&mut world, mesh, &mut context)
            .unwrap();
        let (saved, note) = soup_to_save(&world, mesh);
        assert_eq!(note, Some(RECOMPUTED_NORMALS));
        let normals = saved.vertex_normals.unwrap();
        // On a sphere, every recomputed normal points about outward: none is the stale +z.
        for (p, n) in saved.positions.iter().zip(&normals) {
            assert!((n.length() - 1.0).abs() < 1e-5);
            if p.z < -0.5 {
                assert!(n.z < 0.0, "{p} {n}");
            }
        }
    }
}
