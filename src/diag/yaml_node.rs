//! A YAML file as a tree in which every node, and every mapping key, keeps its place in
//! the text. Loaders walk this tree (with `Reader` and `Fields`) instead of deserialising
//! into structs, so they can report every problem of a file at once, each at its place.
//! Data only: parsing is `yaml_parse`'s, and no key has a meaning here.

use super::span::{Span, Spanned};

/// One node and where it is written. Mappings and lists point at their first character.
#[derive(Debug, Clone)]
pub struct YamlNode {
    pub value: YamlValue,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub enum YamlValue {
    Null,
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
    Seq(Vec<YamlNode>),
    /// Entries in file order; keys are always text.
    Map(Vec<(Spanned<String>, YamlNode)>),
}

impl YamlNode {
    /// What kind of node this is, for "expected X, found Y" messages: `a list`, `text`.
    pub fn kind(&self) -> &'static str {
        match self.value {
            YamlValue::Null => "nothing",
            YamlValue::Bool(_) => "true/false",
            YamlValue::Int(_) => "a whole number",
            YamlValue::Float(_) => "a number",
            YamlValue::Str(_) => "text",
            YamlValue::Seq(_) => "a list",
            YamlValue::Map(_) => "a mapping",
        }
    }

    pub fn is_null(&self) -> bool {
        matches!(self.value, YamlValue::Null)
    }

    /// The node as text: strings as they are, numbers and booleans written out (YAML turns
    /// `6000` into a number, but a recipe value `6000` means the same as `"6000"`).
    pub fn as_text(&self) -> Option<String> {
        match &self.value {
            YamlValue::Str(s) => Some(s.clone()),
            YamlValue::Int(i) => Some(i.to_string()),
            YamlValue::Float(f) => Some(self.whole_as_written(*f).unwrap_or_else(|| f.to_string())),
            YamlValue::Bool(b) => Some(b.to_string()),
            _ => None,
        }
    }

    /// A whole number beyond YAML's 64-bit integers (`18446744073709551616`, one below
    /// i64::MIN), which the parser hands over as a rounded float, as it is written; `None`
    /// for any other number.
    fn whole_as_written(&self, f: f64) -> Option<String> {
        let written = self.written();
        let digits = written.strip_prefix(['-', '+']).unwrap_or(written);
        let whole = !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit());
        (whole && written.parse::<f64>().ok() == Some(f)).then(|| written.to_string())
    }

    /// True for a number that is not finite: `.nan`, `.inf`, or `1e400` (too large for a
    /// float), which the parser hands over as the text `.nan`, `.inf` or `-.inf`.
    pub fn is_non_finite_number(&self) -> bool {
        match &self.value {
            YamlValue::Float(f) => !f.is_finite(),
            YamlValue::Str(s) => matches!(s.as_str(), ".nan" | ".inf" | "-.inf" | "+.inf"),
            _ => false,
        }
    }

    /// The node's text as written in the file.
    pub fn written(&self) -> &str {
        self.span.written()
    }

    /// The entries of a mapping; `None` for any other node.
    pub fn entries(&self) -> Option<&[(Spanned<String>, YamlNode)]> {
        match &self.value {
            YamlValue::Map(entries) => Some(entries),
            _ => None,
        }
    }

    /// The value of `key` in a mapping (the first, should a key be written twice).
    pub fn get(&self, key: &str) -> Option<&YamlNode> {
        self.entries()?
            .iter()
            .find(|(k, _)| k.value == key)
            .map(|(_, v)| v)
    }

    /// A mapping with the entries of `key` left out; any other node as it is.
    pub fn without(&self, key: &str) -> YamlNode {
        match &self.value {
            YamlValue::Map(entries) => YamlNode {
                value: YamlValue::Map(entries.iter().filter(|(k, _)| k.value != key).cloned().collect()),
                span: self.span.clone(),
            },
            _ => self.clone(),
        }
    }
}
