//! The XML the COLLADA reader walks: elements by id, a node's children by tag name, where an
//! element starts, and what a `#id` URL names. Below the scene and the geometry readers, which
//! take these from here.

use roxmltree::Node;
use std::collections::HashMap;

/// Every element with an `id`, by id.
pub(super) type Ids<'a, 'input> = HashMap<&'a str, Node<'a, 'input>>;

/// The first child element with this tag name.
pub(super) fn child<'a, 'input>(node: Node<'a, 'input>, name: &str) -> Option<Node<'a, 'input>> {
    node.children().find(|c| c.has_tag_name(name))
}

/// The child elements with this tag name.
pub(super) fn children<'a, 'input>(
    node: Node<'a, 'input>,
    name: &'static str,
) -> impl Iterator<Item = Node<'a, 'input>> {
    node.children().filter(move |c| c.has_tag_name(name))
}

/// The 1-based line an element starts on.
pub(super) fn line_of(node: Node) -> usize {
    node.document().text_pos_at(node.range().start).row as usize
}

/// The id a `#id` URL names (a URL without `#` is taken as the id itself).
pub(super) fn reference(url: &str) -> &str {
    url.strip_prefix('#').unwrap_or(url)
}
