//! Typed ids: one newtype over [`Entity`] per element kind.
//!
//! Passing a [`FaceId`] where a [`VertexId`] is expected does not compile. Every id prints as its
//! entity with a kind prefix (`v12v0`, `h7v0`, `e3v0`, `f5v0`, `m1v0`): that text is what the
//! inspector shows and what [`parse_element`] reads back. An id can go stale when its element is
//! despawned; the generation inside the [`Entity`] makes that detectable (`world.get_entity`
//! fails), so a stale id is refused, never misread as another element.

use bevy::ecs::entity::{ContainsEntity, EntityGeneration, EntityIndex, EntityMapper, MapEntities};
use bevy::prelude::Entity;
use std::fmt;

/// `e`'s place in an array indexed by entity index. Indices are unique among live entities of
/// every kind, so such an array can hold one value per element, read without hashing.
#[inline]
pub fn slot(e: Entity) -> usize {
    e.index_u32() as usize
}

/// The length an array indexed by entity index needs to hold a value for each of `entities`.
pub fn slots_for(entities: impl IntoIterator<Item = Entity>) -> usize {
    entities.into_iter().map(|e| slot(e) + 1).max().unwrap_or(0)
}

macro_rules! element_id {
    ($(#[$doc:meta])* $name:ident, $prefix:literal) => {
        $(#[$doc])*
        #[derive(Copy, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
        #[repr(transparent)]
        pub struct $name(pub Entity);

        impl $name {
            /// The kind prefix used when printing and parsing this id.
            pub const PREFIX: &'static str = $prefix;

            /// The entity behind this id.
            #[inline]
            pub fn entity(self) -> Entity {
                self.0
            }

            /// Its place in an array indexed by entity index (see [`slots_for`]).
            #[inline]
            pub fn slot(self) -> usize {
                slot(self.0)
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "{}{}", $prefix, self.0)
            }
        }

        impl fmt::Debug for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                fmt::Display::fmt(self, f)
            }
        }

        impl MapEntities for $name {
            fn map_entities<E: EntityMapper>(&mut self, mapper: &mut E) {
                self.0 = mapper.get_mapped(self.0);
            }
        }

        impl ContainsEntity for $name {
            fn entity(&self) -> Entity {
                self.0
            }
        }

        impl From<$name> for Entity {
            fn from(id: $name) -> Entity {
                id.0
            }
        }
    };
}

element_id!(
    /// A vertex entity (carries [`crate::mesh::Vertex`] and [`crate::mesh::Position`]).
    VertexId,
    "v"
);
element_id!(
    /// A halfedge entity (carries [`crate::mesh::Halfedge`]).
    HalfedgeId,
    "h"
);
element_id!(
    /// An edge entity (carries [`crate::mesh::Edge`]): the pair of twin halfedges.
    EdgeId,
    "e"
);
element_id!(
    /// A face entity (carries [`crate::mesh::Face`]).
    FaceId,
    "f"
);
element_id!(
    /// A mesh entity: the owner of elements (carries [`crate::mesh::MeshInfo`]).
    MeshId,
    "m"
);

/// Any element id, as typed by a user or held by a selection.
#[derive(Copy, Clone, PartialEq, Eq, Hash, Debug)]
pub enum ElementId {
    /// A vertex.
    Vertex(VertexId),
    /// A halfedge.
    Halfedge(HalfedgeId),
    /// An edge.
    Edge(EdgeId),
    /// A face.
    Face(FaceId),
    /// A whole mesh.
    Mesh(MeshId),
}

impl ElementId {
    /// An id of the same kind for another entity (where an element was brought back under a
    /// new entity).
    pub fn with_entity(self, e: Entity) -> ElementId {
        match self {
            Self::Vertex(_) => Self::Vertex(VertexId(e)),
            Self::Halfedge(_) => Self::Halfedge(HalfedgeId(e)),
            Self::Edge(_) => Self::Edge(EdgeId(e)),
            Self::Face(_) => Self::Face(FaceId(e)),
            Self::Mesh(_) => Self::Mesh(MeshId(e)),
        }
    }

    /// Its kind in a word: "vertex", "halfedge", "edge", "face" or "mesh".
    pub fn kind(self) -> &'static str {
        match self {
            Self::Vertex(_) => "vertex",
            Self::Halfedge(_) => "halfedge",
            Self::Edge(_) => "edge",
            Self::Face(_) => "face",
            Self::Mesh(_) => "mesh",
        }
    }

    /// The entity behind the id.
    pub fn entity(self) -> Entity {
        match self {
            Self::Vertex(v) => v.0,
            Self::Halfedge(h) => h.0,
            Self::Edge(e) => e.0,
            Self::Face(f) => f.0,
            Self::Mesh(m) => m.0,
        }
    }
}

impl fmt::Display for ElementId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Vertex(v) => v.fmt(f),
            Self::Halfedge(h) => h.fmt(f),
            Self::Edge(e) => e.fmt(f),
            Self::Face(x) => x.fmt(f),
            Self::Mesh(m) => m.fmt(f),
        }
    }
}

macro_rules! element_from {
    ($($variant:ident($id:ident)),*) => {$(
        impl From<$id> for ElementId {
            fn from(id: $id) -> Self {
                Self::$variant(id)
            }
        }
    )*};
}
element_from!(
    Vertex(VertexId),
    Halfedge(HalfedgeId),
    Edge(EdgeId),
    Face(FaceId),
    Mesh(MeshId)
);

/// Parses an entity written as `{index}v{generation}` (Bevy's display form), e.g. `12v0`.
/// A bare index (`12`) means generation 0. Returns `None` for anything else.
pub fn parse_entity(text: &str) -> Option<Entity> {
    let text = text.trim();
    let (index, generation) = match text.split_once('v') {
        Some((i, g)) => (i.parse::<u32>().ok()?, g.parse::<u32>().ok()?),
        None => (text.parse::<u32>().ok()?, 0),
    };
    Some(Entity::from_index_and_generation(
        EntityIndex::from_raw_u32(index)?,
        EntityGeneration::from_bits(generation),
    ))
}

/// Parses an element id as displayed (`v12v0`, `h7v0`, `e3v0`, `f5v0`, `m1v0`; the generation may be
/// left out: `h7`). Whether the element still exists is for the caller to check.
pub fn parse_element(text: &str) -> Option<ElementId> {
    let text = text.trim();
    let kind = text.chars().next()?;
    let entity = parse_entity(&text[kind.len_utf8()..])?;
    Some(match kind.to_ascii_lowercase() {
        'v' => ElementId::Vertex(VertexId(entity)),
        'h' => ElementId::Halfedge(HalfedgeId(entity)),
        'e' => ElementId::Edge(EdgeId(entity)),
        'f' => ElementId::Face(FaceId(entity)),
        'm' => ElementId::Mesh(MeshId(entity)),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_print_with_prefix_and_parse_back() {
        let e = parse_entity("12v3").unwrap();
        assert_eq!(e.index_u32(), 12);
        assert_eq!(e.generation(), EntityGeneration::from_bits(3));
        let h = HalfedgeId(e);
        assert_eq!(h.to_string(), "h12v3");
        assert_eq!(parse_element("h12v3"), Some(ElementId::Halfedge(h)));
        assert_eq!(
            parse_element(" f7 "),
            Some(ElementId::Face(FaceId(parse_entity("7v0").unwrap())))
        );
        assert_eq!(parse_element("x7v0"), None);
        assert_eq!(parse_element("v"), None);
        assert_eq!(parse_element("vxv0"), None);
        assert_eq!(parse_element(""), None);
    }
}
