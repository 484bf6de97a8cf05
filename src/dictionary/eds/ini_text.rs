//! The INI layer of a CiA 306 EDS/DCF file: `[section]` headers, `key=value` lines and `;`
//! comments, each kept with its place so every later problem can point at its line. Keys
//! and section names are compared ignoring case (vendor tools write `[1018sub2]` and
//! `[1018SUB2]`, `ParameterName` and `PARAMETERNAME`). It must not know what an object is.

use crate::diag::{Diagnostic, Diagnostics, Source, Span};
use std::collections::HashMap;
use std::sync::Arc;

/// One `key=value` line: the value trimmed, with the place of the whole line.
#[derive(Debug, Clone)]
pub(crate) struct IniEntry {
    pub key: String,
    pub value: String,
    pub span: Span,
}

/// One `[name]` section and its entries, in file order.
#[derive(Debug, Clone)]
pub(crate) struct IniSection {
    /// As written between the brackets, trimmed.
    pub name: String,
    pub span: Span,
    pub entries: Vec<IniEntry>,
    /// Entry by lower-case key: a section of thousands of keys is read in linear time.
    by_key: HashMap<String, usize>,
}

impl IniSection {
    /// The entry `key`, ignoring case.
    pub fn get(&self, key: &str) -> Option<&IniEntry> {
        self.by_key
            .get(&key.to_ascii_lowercase())
            .map(|&i| &self.entries[i])
    }
}

/// A whole file's sections, found by name ignoring case.
#[derive(Debug)]
pub(crate) struct IniText {
    pub sections: Vec<IniSection>,
    by_name: HashMap<String, usize>,
}

impl IniText {
    /// Reads `source`, recording every malformed line in `out` and going on without it.
    pub fn parse(source: &Arc<Source>, out: &mut Diagnostics) -> IniText {
        let mut sections: Vec<IniSection> = Vec::new();
        let mut by_name: HashMap<String, usize> = HashMap::new();
        let mut offset = 0usize;
        // After a section written twice, its lines until the next header are skipped (its
        // problem is reported once, at the header).
        let mut skipping = false;
        let text = source.text();
        for (i, raw) in text.split_inclusive('\n').enumerate() {
            let line_no = i + 1;
            let start = offset;
            offset += raw.len();
            let line = raw.trim_end_matches(['\n', '\r']);
            let trimmed = line.trim();
            let lead = line.len() - line.trim_start().len();
            let span = Span::new(source, start + lead, trimmed.len(), line_no, lead + 1);
            if trimmed.is_empty() || trimmed.starts_with(';') || trimmed.starts_with('#') {
                continue;
            }
            if let Some(rest) = trimmed.strip_prefix('[') {
                let Some(name) = rest.strip_suffix(']').map(str::trim) else {
                    out.push(
                        Diagnostic::at(&span, "a section header without its closing `]`", "not closed")
                            .with_help("write a section as `[1018]` or `[1018sub2]`"),
                    );
                    continue;
                };
                let key = name.to_ascii_lowercase();
                skipping = false;
                if let Some(&first) = by_name.get(&key) {
                    skipping = true;
                    out.push(
                        Diagnostic::at(
                            &span,
                            format!("section `[{name}]` is written twice"),
                            "again here",
                        )
                        .also_at(&sections[first].span, "first here")
                        .with_help("merge the two sections into one"),
                    );
                    continue;
                }
                by_name.insert(key, sections.len());
                sections.push(IniSection {
                    name: name.to_string(),
                    span,
                    entries: Vec::new(),
                    by_key: HashMap::new(),
                });
                continue;
            }
            if skipping {
                continue;
            }
            let Some((key, value)) = trimmed.split_once('=') else {
                out.push(
                    Diagnostic::at(
                        &span,
                        "a line that is neither `[section]` nor `key=value`",
                        "expected `key=value`",
                    )
                    .with_help("comments start with `;`"),
                );
                continue;
            };
            let key = key.trim();
            let Some(section) = sections.last_mut() else {
                out.push(
                    Diagnostic::at(
                        &span,
                        format!("`{key}=` comes before any `[section]`"),
                        "outside a section",
                    )
                    .with_help("an EDS starts with `[FileInfo]`"),
                );
                continue;
            };
            if key.is_empty() {
                out.push(Diagnostic::at(&span, "a `=` without a key before it", "no key"));
                continue;
            }
            if let Some(first) = section.get(key) {
                let first = first.span.clone();
                out.push(
                    Diagnostic::at(
                        &span,
                        format!("`{key}` is given twice in `[{}]`", section.name),
                        "again here",
                    )
                    .also_at(&first, "first here"),
                );
                continue;
            }
            section
                .by_key
                .insert(key.to_ascii_lowercase(), section.entries.len());
            section.entries.push(IniEntry {
                key: key.to_string(),
                value: value.trim().to_string(),
                span,
            });
        }
        IniText { sections, by_name }
    }

    /// The section `name`, ignoring case.
    pub fn section(&self, name: &str) -> Option<&IniSection> {
        self.by_name
            .get(&name.to_ascii_lowercase())
            .map(|&i| &self.sections[i])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> (IniText, Diagnostics) {
        let mut out = Diagnostics::new();
        let ini = IniText::parse(&Source::new("t.eds", text), &mut out);
        (ini, out)
    }

    #[test]
    fn sections_keys_and_comments_ignoring_case() {
        let (ini, out) =
            parse("; comment\n[FileInfo]\nFileName = t.eds\r\n\n[1018SUB2]\nParameterName=Product code\n");
        assert!(out.is_empty(), "{}", out.render(false));
        assert_eq!(
            ini.section("fileinfo").unwrap().get("FILENAME").unwrap().value,
            "t.eds"
        );
        let sub = ini.section("1018sub2").unwrap();
        assert_eq!(sub.get("parametername").unwrap().value, "Product code");
        assert_eq!(sub.get("ParameterName").unwrap().span.line(), 6);
    }

    #[test]
    fn malformed_lines_are_located_and_skipped() {
        let (ini, out) = parse("x=1\n[A\n[B]\njunk\nk=1\nK=2\n[b]\nskipped=1\n[C]\n=3\n");
        let lines: Vec<(usize, &str)> = out.iter().map(|d| (d.line(), d.message())).collect();
        assert_eq!(
            lines,
            [
                (1, "`x=` comes before any `[section]`"),
                (2, "a section header without its closing `]`"),
                (4, "a line that is neither `[section]` nor `key=value`"),
                (6, "`K` is given twice in `[B]`"),
                (7, "section `[b]` is written twice"),
                (10, "a `=` without a key before it"),
            ]
        );
        assert_eq!(ini.section("B").unwrap().entries.len(), 1);
    }
}
