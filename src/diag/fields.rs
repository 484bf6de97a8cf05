//! The entries of one mapping that [`super::Reader::fields`] has checked against its
//! [`super::Shape`]: looked up by key, with their places. Lookup only; reporting problems
//! is the reader's.

use super::span::{Span, Spanned};
use super::yaml_node::YamlNode;

#[derive(Debug, Clone, Copy)]
pub struct Fields<'n> {
    pub(crate) node: &'n YamlNode,
    pub(crate) entries: &'n [(Spanned<String>, YamlNode)],
    pub(crate) nothing_is_absent: bool,
}

impl<'n> Fields<'n> {
    /// The value of `key`; absent when not given (or given as nothing, when the shape says
    /// nothing is absent).
    pub fn get(&self, key: &str) -> Option<&'n YamlNode> {
        self.entry(key).map(|(_, v)| v)
    }

    /// The key as written, when [`Self::get`] finds a value for it.
    pub fn key(&self, key: &str) -> Option<&'n Spanned<String>> {
        self.entry(key).map(|(k, _)| k)
    }

    /// The place of `key`'s value, or of the whole mapping when it is not given.
    pub fn span_of(&self, key: &str) -> &'n Span {
        self.get(key).map_or(&self.node.span, |v| &v.span)
    }

    /// Every entry in file order, unknown keys included.
    pub fn entries(&self) -> &'n [(Spanned<String>, YamlNode)] {
        self.entries
    }

    /// The mapping itself (it points at its first character).
    pub fn span(&self) -> &'n Span {
        &self.node.span
    }

    fn entry(&self, key: &str) -> Option<&'n (Spanned<String>, YamlNode)> {
        self.entries
            .iter()
            .find(|(k, v)| k.value == key && !(self.nothing_is_absent && v.is_null()))
    }
}
