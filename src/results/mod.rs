//! The paper's results: one scene per result, their plots, tables, citations and comparisons, and the book.

#[cfg(feature = "cli")]
pub mod archive;
pub mod citation;
#[cfg(feature = "plots")]
pub mod cite;
pub mod diff;
pub mod files;
#[cfg(feature = "plots")]
pub mod marker;
pub mod names;
#[cfg(feature = "plots")]
pub mod narrow;
pub(crate) mod output_lock;
pub mod output_set;
pub mod peers;
pub mod record;
#[cfg(feature = "plots")]
pub mod render;
pub mod scene;
#[cfg(feature = "plots")]
pub mod scenes;
#[cfg(feature = "plots")]
pub mod schematic;
pub mod settings;

#[cfg(feature = "book")]
pub mod book;
