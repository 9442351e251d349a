//! Local operations (placeholder while being written; every call refuses).
use crate::mesh::ids::{EdgeId, ElementId, VertexId};
use crate::ops::Refusal;
use bevy::math::Vec3;
use bevy::prelude::World;

/// Options of a collapse (placeholder).
#[derive(Clone, Copy, Debug, Default)]
pub struct CollapseOptions {
    /// Where the kept vertex goes (midpoint if `None`).
    pub position: Option<Vec3>,
    /// Refuse a collapse turning a face normal by more than this.
    pub max_normal_change_deg: Option<f32>,
}
/// What a collapse did (placeholder).
#[derive(Clone, Copy, Debug)]
pub struct CollapseResult {
    /// The surviving vertex.
    pub kept: VertexId,
    /// The removed vertex.
    pub removed: VertexId,
}
fn todo(e: EdgeId) -> Refusal {
    Refusal::Unsuitable(format!("{}: not implemented yet", ElementId::Edge(e)))
}
/// Flip (placeholder).
pub fn flip_edge(_w: &mut World, e: EdgeId) -> Result<EdgeId, Refusal> {
    Err(todo(e))
}
/// Split (placeholder).
pub fn split_edge(_w: &mut World, e: EdgeId, _t: f32) -> Result<VertexId, Refusal> {
    Err(todo(e))
}
/// Collapse (placeholder).
pub fn collapse_edge(
    _w: &mut World,
    e: EdgeId,
    _o: CollapseOptions,
) -> Result<CollapseResult, Refusal> {
    Err(todo(e))
}
