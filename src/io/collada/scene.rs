//! Where a COLLADA scene places its geometries: the `<visual_scene>`'s node tree walked with
//! each node's transforms applied.
//!
//! A node's transform is the product, in document order, of its `<matrix>` (16 numbers, row
//! by row), `<translate>`, `<rotate>` (an axis and degrees), `<scale>` and `<lookat>` (eye,
//! interest, up: the node is placed as a camera looking there) elements, after its parent's
//! (COLLADA 1.4.1 §5 "Transform elements"). Every `<instance_geometry>` is one placement, so a
//! geometry used twice gives two copies; `<instance_node>` walks the node it names, and an
//! `<instance_controller>` places the mesh its `<skin>` (in its bind pose, after the
//! `bind_shape_matrix`) or `<morph>` deforms. The scene's `<up_axis>` is turned to Y-up last
//! (Z-up: `(x, y, z)` → `(x, z, −y)`, as Blender's and Bevy's importers do).
//!
//! The scene is the one `<scene>` instantiates, else the first `<visual_scene>`; a file with
//! no scene places each `<geometry>` once where it stands.

use bevy::math::{Mat4, Vec3, Vec4};
use roxmltree::Node;

use super::geometry::floats;
use super::xml::{Ids, child, children, line_of, reference};
use crate::io::error::ParseError;
use crate::io::text::Numbers;

/// Node trees nested deeper than this (or `<instance_node>`s naming each other in a cycle)
/// are refused.
const MAX_DEPTH: usize = 64;

/// Scenes that walk more nodes than this (instances of instances multiply) are refused.
const MAX_NODES: usize = 1 << 20;

/// One geometry placed in the scene.
pub(super) struct Placement<'a, 'input> {
    /// The `<geometry>` element.
    pub geometry: Node<'a, 'input>,
    /// From the geometry's coordinates to the scene's, Y-up.
    pub transform: Mat4,
    /// The node's name (else its id, else the geometry's).
    pub name: String,
}

/// Every placement of the scene, and what the walk left out.
#[derive(Default)]
pub(super) struct Scene<'a, 'input> {
    /// In document order.
    pub placements: Vec<Placement<'a, 'input>>,
    /// Meshes placed through a skin or morph controller (read in their bind pose).
    pub controlled: usize,
    /// `<skew>` transforms, not applied.
    pub skews: usize,
    /// `<instance_camera>` and `<instance_light>` nodes.
    pub cameras_and_lights: usize,
    /// The transforms' numbers, and those mended on the way.
    pub numbers: Numbers,
}

/// Walks the document's scene.
///
/// # Errors
/// A transform with the wrong count of numbers, a reference to an element that does not exist,
/// or nodes nested deeper than [`MAX_DEPTH`], naming the line.
pub(super) fn walk<'a, 'input>(
    root: Node<'a, 'input>,
    ids: &Ids<'a, 'input>,
) -> Result<Scene<'a, 'input>, ParseError> {
    let up = up_axis(root);
    let mut scene = Scene::default();
    let instantiated = child(root, "scene")
        .and_then(|s| child(s, "instance_visual_scene"))
        .and_then(|i| ids.get(reference(i.attribute("url")?)).copied());
    let first = || {
        children(root, "library_visual_scenes")
            .flat_map(|l| children(l, "visual_scene"))
            .next()
    };
    match instantiated.or_else(first) {
        Some(visual_scene) => {
            let mut walker = Walker {
                ids,
                scene: &mut scene,
                walked: 0,
            };
            for node in children(visual_scene, "node") {
                walker.node(node, up, 0)?;
            }
        }
        None => {
            for geometry in
                children(root, "library_geometries").flat_map(|l| children(l, "geometry"))
            {
                scene.placements.push(Placement {
                    geometry,
                    transform: up,
                    name: name_of(geometry).to_owned(),
                });
            }
        }
    }
    Ok(scene)
}

struct Walker<'w, 'a, 'input> {
    ids: &'w Ids<'a, 'input>,
    scene: &'w mut Scene<'a, 'input>,
    /// Nodes walked so far (instances counted each time).
    walked: usize,
}

impl<'a, 'input> Walker<'_, 'a, 'input> {
    /// Walks a `<node>` under a parent transform.
    fn node(
        &mut self,
        node: Node<'a, 'input>,
        parent: Mat4,
        depth: usize,
    ) -> Result<(), ParseError> {
        if depth > MAX_DEPTH {
            return Err(ParseError::line(
                line_of(node),
                format!("nodes nested deeper than {MAX_DEPTH} (an <instance_node> cycle?)"),
            ));
        }
        self.walked += 1;
        if self.walked > MAX_NODES {
            return Err(ParseError::line(
                line_of(node),
                format!("the scene places more than {MAX_NODES} nodes (instances of instances)"),
            ));
        }
        let mut transform = parent;
        for element in node.children().filter(Node::is_element) {
            if let Some(local) = self.transform(element)? {
                transform *= local;
            }
        }
        for element in node.children().filter(Node::is_element) {
            match element.tag_name().name() {
                "node" => self.node(element, transform, depth + 1)?,
                "instance_node" => {
                    let target = self.target(element)?;
                    self.node(target, transform, depth + 1)?;
                }
                "instance_geometry" => {
                    let geometry = self.target(element)?;
                    self.place(geometry, transform, node);
                }
                "instance_controller" => {
                    let controller = self.target(element)?;
                    self.controlled(controller, transform, node)?;
                }
                "instance_camera" | "instance_light" => self.scene.cameras_and_lights += 1,
                _ => {}
            }
        }
        Ok(())
    }

    /// The element an instance's `url` names.
    fn target(&self, instance: Node) -> Result<Node<'a, 'input>, ParseError> {
        let url = instance.attribute("url").unwrap_or_default();
        self.ids.get(reference(url)).copied().ok_or_else(|| {
            ParseError::line(
                line_of(instance),
                format!(
                    "<{}> names `{url}`, which does not exist",
                    instance.tag_name().name()
                ),
            )
        })
    }

    fn place(&mut self, geometry: Node<'a, 'input>, transform: Mat4, node: Node) {
        let name = node
            .attribute("name")
            .or_else(|| node.attribute("id"))
            .unwrap_or_else(|| name_of(geometry));
        self.scene.placements.push(Placement {
            geometry,
            transform,
            name: name.to_owned(),
        });
    }

    /// Places the mesh a skin or morph controller deforms, in its bind pose.
    fn controlled(
        &mut self,
        controller: Node<'a, 'input>,
        transform: Mat4,
        node: Node,
    ) -> Result<(), ParseError> {
        let Some(deformer) = child(controller, "skin").or_else(|| child(controller, "morph"))
        else {
            return Ok(());
        };
        let url = deformer.attribute("source").unwrap_or_default();
        let Some(&geometry) = self.ids.get(reference(url)) else {
            return Err(ParseError::line(
                line_of(deformer),
                format!("controller source `{url}` does not exist"),
            ));
        };
        let bind = match child(deformer, "bind_shape_matrix") {
            Some(m) => matrix(m, &mut self.scene.numbers)?,
            None => Mat4::IDENTITY,
        };
        self.scene.controlled += 1;
        self.place(geometry, transform * bind, node);
        Ok(())
    }

    /// A transform element's matrix; `None` for any other element.
    fn transform(&mut self, element: Node) -> Result<Option<Mat4>, ParseError> {
        let mut numbers = |count: usize| -> Result<Vec<f32>, ParseError> {
            let values = floats(element, &mut self.scene.numbers)?;
            if values.len() == count {
                Ok(values)
            } else {
                Err(ParseError::line(
                    line_of(element),
                    format!(
                        "<{}> holds {} numbers, expected {count}",
                        element.tag_name().name(),
                        values.len()
                    ),
                ))
            }
        };
        let v3 = |v: &[f32]| Vec3::new(v[0], v[1], v[2]);
        Ok(Some(match element.tag_name().name() {
            "matrix" => matrix(element, &mut self.scene.numbers)?,
            "translate" => Mat4::from_translation(v3(&numbers(3)?)),
            "scale" => Mat4::from_scale(v3(&numbers(3)?)),
            "rotate" => {
                let v = numbers(4)?;
                match v3(&v).try_normalize() {
                    Some(axis) => Mat4::from_axis_angle(axis, v[3].to_radians()),
                    None => Mat4::IDENTITY,
                }
            }
            "lookat" => {
                let v = numbers(9)?;
                let view = Mat4::look_at_rh(v3(&v), v3(&v[3..]), v3(&v[6..]));
                if view.is_finite() && view.determinant().abs() > f32::EPSILON {
                    view.inverse()
                } else {
                    Mat4::IDENTITY
                }
            }
            "skew" => {
                self.scene.skews += 1;
                return Ok(None);
            }
            _ => return Ok(None),
        }))
    }
}

/// A `<matrix>`-like element: 16 numbers, row by row.
fn matrix(element: Node, numbers: &mut Numbers) -> Result<Mat4, ParseError> {
    let values = floats(element, numbers)?;
    let array: [f32; 16] = values.as_slice().try_into().map_err(|_| {
        ParseError::line(
            line_of(element),
            format!(
                "<{}> holds {} numbers, expected 16",
                element.tag_name().name(),
                values.len()
            ),
        )
    })?;
    Ok(Mat4::from_cols_array(&array).transpose())
}

/// The rotation that turns the document's up axis to +Y.
fn up_axis(root: Node) -> Mat4 {
    let axis = child(root, "asset")
        .and_then(|a| child(a, "up_axis"))
        .and_then(|u| u.text())
        .map(str::trim);
    match axis {
        // (x, y, z) → (x, z, −y)
        Some("Z_UP") => Mat4::from_cols(Vec4::X, Vec4::NEG_Z, Vec4::Y, Vec4::W),
        // (x, y, z) → (−y, x, z)
        Some("X_UP") => Mat4::from_cols(Vec4::Y, Vec4::NEG_X, Vec4::Z, Vec4::W),
        _ => Mat4::IDENTITY,
    }
}

/// An element's name, else its id, else "unnamed".
fn name_of<'a>(node: Node<'a, '_>) -> &'a str {
    node.attribute("name")
        .or_else(|| node.attribute("id"))
        .unwrap_or("unnamed")
}
