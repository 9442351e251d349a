//! Pappus: an interactive halfedge mesh editor on Bevy.
//!
//! The crate is layered so that every arrow points down:
//!
//! - [`mesh`]: the data model. Every vertex, halfedge, edge and face is an ECS entity; relations are
//!   typed ids inside components. Building from a polygon soup (with repairs), validation,
//!   statistics, procedural shapes. No rendering, no UI, no file formats.
//! - [`ops`]: operations on the entity mesh (plan, then apply; a refusal is a value).
//! - [`edit`]: the one edit layer: every operation as a value of [`edit::Edit`], with what the
//!   editor's pipeline and the command line need to know about it.
//! - [`io`]: file formats (OBJ, OFF, PLY, STL), all to and from a [`mesh::soup::PolygonSoup`].
//! - [`colormap`]: the colour maps quantities on a mesh are shown and exported with.
//! - [`checks`]: whether the build checks its own work as it goes (`CHECKED`).
//! - [`cli`]: the batch command line (`info`, `convert`, `process`), no window needed.
//! - [`process_memory`]: the `pappus` program's allocator settings (freed memory kept for reuse).
//! - `editor`: the Bevy application (the window, rendering, picking, the panels), behind the
//!   `editor` cargo feature, on by default. Without it the crate is the core above, built on
//!   Bevy's ECS and math alone: no window, no GPU, no rendering crates to compile.

pub mod checks;
pub mod cli;
pub mod colormap;
pub mod edit;
#[cfg(feature = "editor")]
pub mod editor;
pub mod fuzzing;
pub mod io;
pub mod memory_budget;
pub mod mesh;
pub mod ops;
pub mod process_memory;
pub mod recovery;
pub mod source;
