//! Diagnostics and the YAML field reader shared by every loader (recipes, dictionaries,
//! limits files): the file read within limits ([`Source`], `read_source`), places in it
//! ([`Span`]), one problem with its place, label and help ([`Diagnostic`]) and all of a
//! check's problems at once ([`Diagnostics`]), rendered by miette, and a file refused with
//! them ([`FileInvalid`]); the spanned YAML tree
//! ([`YamlNode`]) and the reader that checks mappings against a [`Shape`] and reads typed
//! values ([`Reader`], [`Fields`]). It must not know what any file means: recipes,
//! dictionaries and limits files give their keys and their words.

mod diagnostic;
mod diagnostics;
mod did_you_mean;
mod fields;
mod file_invalid;
mod reader;
mod shape;
mod source;
mod span;
mod text_file;
mod yaml_node;
mod yaml_parse;

pub use diagnostic::Diagnostic;
#[cfg(test)]
pub(crate) use diagnostics::three_out_of_order;
pub use diagnostics::{render_diagnostic, report_handler, Diagnostics, MAX_SHOWN};
pub use did_you_mean::{did_you_mean, suggestion_text};
pub use fields::Fields;
pub use file_invalid::FileInvalid;
pub use reader::{expected, Reader};
pub use shape::Shape;
pub use source::Source;
pub use span::{Span, Spanned};
pub use text_file::{
    read_source, read_text_file, read_text_or_windows_1252, windows_1252, TextFileError, MAX_TEXT_FILE_BYTES,
};
pub use yaml_node::{YamlNode, YamlValue};
pub use yaml_parse::{YamlError, MAX_ALIAS_COPIES, MAX_DEPTH, MAX_VALUES};
