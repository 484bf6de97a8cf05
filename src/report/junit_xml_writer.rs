//! A minimal XML writer for the JUnit report: elements, attributes and text, escaped so
//! that any text from a recipe or a drive gives well-formed XML 1.0 (characters XML cannot
//! hold become U+FFFD). Knows nothing of JUnit.

/// Builds one indented XML document.
pub struct XmlWriter {
    out: String,
    depth: usize,
}

impl XmlWriter {
    pub fn new() -> Self {
        XmlWriter {
            out: "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n".to_string(),
            depth: 0,
        }
    }

    fn start(&mut self, name: &str, attrs: &[(&str, &str)]) {
        self.out.push_str(&"  ".repeat(self.depth));
        self.out.push('<');
        self.out.push_str(name);
        for (k, v) in attrs {
            self.out.push(' ');
            self.out.push_str(k);
            self.out.push_str("=\"");
            escape_into(&mut self.out, v, true);
            self.out.push('"');
        }
    }

    /// `<name attrs>` on its own line; [`XmlWriter::close`] ends it.
    pub fn open(&mut self, name: &str, attrs: &[(&str, &str)]) {
        self.start(name, attrs);
        self.out.push_str(">\n");
        self.depth += 1;
    }

    pub fn close(&mut self, name: &str) {
        self.depth = self.depth.saturating_sub(1);
        self.out.push_str(&"  ".repeat(self.depth));
        self.out.push_str("</");
        self.out.push_str(name);
        self.out.push_str(">\n");
    }

    /// `<name attrs/>`.
    pub fn empty(&mut self, name: &str, attrs: &[(&str, &str)]) {
        self.start(name, attrs);
        self.out.push_str("/>\n");
    }

    /// `<name attrs>text</name>` (the text as it is, no indentation added inside).
    pub fn text_element(&mut self, name: &str, attrs: &[(&str, &str)], text: &str) {
        if text.is_empty() {
            return self.empty(name, attrs);
        }
        self.start(name, attrs);
        self.out.push('>');
        escape_into(&mut self.out, text, false);
        self.out.push_str("</");
        self.out.push_str(name);
        self.out.push_str(">\n");
    }

    pub fn finish(self) -> String {
        self.out
    }
}

impl Default for XmlWriter {
    fn default() -> Self {
        Self::new()
    }
}

/// Escapes markup characters; in attributes also quotes and line breaks (which a parser
/// would otherwise turn into spaces).
fn escape_into(out: &mut String, text: &str, attribute: bool) {
    for ch in text.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' if attribute => out.push_str("&quot;"),
            '\n' if attribute => out.push_str("&#10;"),
            '\t' if attribute => out.push_str("&#9;"),
            '\r' => out.push_str("&#13;"),
            '\t' | '\n' => out.push(ch),
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_markup_and_characters_xml_cannot_hold() {
        let mut w = XmlWriter::new();
        w.open("a", &[("x", "1 < 2 & \"3\"\nnext")]);
        w.text_element("b", &[], "<t> & \u{1}\r\n");
        w.close("a");
        let xml = w.finish();
        assert!(
            xml.contains("x=\"1 &lt; 2 &amp; &quot;3&quot;&#10;next\""),
            "{xml}"
        );
        assert!(xml.contains("<b>&lt;t&gt; &amp; \u{FFFD}&#13;\n</b>"), "{xml}");
        assert!(xml.ends_with("</a>\n"), "{xml}");
    }
}
