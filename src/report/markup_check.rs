//! Test support: a small well-formedness checker for the XML and HTML the reports write
//! (no XML or HTML parser crate is a dependency). Balanced and properly nested tags, quoted
//! attributes, known entities, raw text in `<style>`. Only for tests; never used at run time.

/// One element as found, with the names of its ancestors (outermost first).
#[derive(Debug, Clone, PartialEq)]
pub struct Element {
    pub name: String,
    pub attributes: Vec<(String, String)>,
    pub ancestors: Vec<String>,
    /// The text directly inside the element, entities left as written.
    pub text: String,
}

impl Element {
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    /// True when the element's parent is `parent`.
    pub fn parent_is(&self, parent: &str) -> bool {
        self.ancestors.last().map(String::as_str) == Some(parent)
    }
}

/// HTML elements that have no end tag.
pub const HTML_VOID: &[&str] = &[
    "area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source", "track", "wbr",
];

/// Parses `text` as markup and returns every element in document order, or what is wrong
/// and where (byte offset). `void` names elements without end tag (HTML); in XML pass `&[]`.
pub fn check_markup(text: &str, void: &[&str]) -> Result<Vec<Element>, String> {
    let mut elements: Vec<Element> = Vec::new();
    // Open elements: (name, index into `elements`).
    let mut open: Vec<(String, usize)> = Vec::new();
    let mut roots = 0;
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'<' {
            let rest = &text[i..];
            if rest.starts_with("<!--") {
                let end = rest.find("-->").ok_or(format!("unclosed comment at {i}"))?;
                i += end + 3;
            } else if rest.starts_with("<![CDATA[") {
                let end = rest.find("]]>").ok_or(format!("unclosed CDATA at {i}"))?;
                i += end + 3;
            } else if rest.starts_with("<?") {
                let end = rest.find("?>").ok_or(format!("unclosed declaration at {i}"))?;
                if i != 0 {
                    return Err(format!("processing instruction not at the start, at {i}"));
                }
                i += end + 2;
            } else if let Some(declaration) = rest.strip_prefix("<!") {
                if !declaration.to_ascii_lowercase().starts_with("doctype") || !elements.is_empty() {
                    return Err(format!("unexpected <! at {i}"));
                }
                let end = rest.find('>').ok_or(format!("unclosed doctype at {i}"))?;
                i += end + 1;
            } else if let Some(close) = rest.strip_prefix("</") {
                let end = close.find('>').ok_or(format!("unclosed end tag at {i}"))?;
                let name = close[..end].trim();
                match open.pop() {
                    Some((open_name, _)) if open_name == name => {}
                    Some((open_name, _)) => return Err(format!("</{name}> at {i} closes <{open_name}>")),
                    None => return Err(format!("</{name}> at {i} without a start tag")),
                }
                i += 2 + end + 1;
            } else {
                let (element, self_closing, len) = start_tag(&text[i..], i)?;
                if open.is_empty() {
                    roots += 1;
                    if roots > 1 {
                        return Err(format!("second root element <{}> at {i}", element.name));
                    }
                }
                let name = element.name.clone();
                let mut element = element;
                element.ancestors = open.iter().map(|(n, _)| n.clone()).collect();
                elements.push(element);
                i += len;
                if !self_closing && !void.contains(&name.as_str()) {
                    if name == "style" || name == "script" {
                        let end_tag = format!("</{name}>");
                        let end = text[i..]
                            .find(&end_tag)
                            .ok_or(format!("<{name}> at {i} is never closed"))?;
                        let last = elements.len() - 1;
                        elements[last].text.push_str(&text[i..i + end]);
                        i += end + end_tag.len();
                    } else {
                        open.push((name, elements.len() - 1));
                    }
                }
            }
        } else {
            let next = text[i..].find('<').map(|n| i + n).unwrap_or(text.len());
            let chunk = &text[i..next];
            check_entities(chunk, i)?;
            if chunk.contains('>') {
                return Err(format!("unescaped '>' in text at {i}"));
            }
            match open.last() {
                Some(&(_, index)) => elements[index].text.push_str(chunk),
                None if chunk.trim().is_empty() => {}
                None => return Err(format!("text outside the root element at {i}")),
            }
            i = next;
        }
    }
    if let Some((name, _)) = open.last() {
        return Err(format!("<{name}> is never closed"));
    }
    if roots == 0 {
        return Err("no root element".into());
    }
    Ok(elements)
}

/// Parses `<name attr="v" ...>` or `<name .../>` at the start of `tag`.
fn start_tag(tag: &str, at: usize) -> Result<(Element, bool, usize), String> {
    let b = tag.as_bytes();
    let mut j = 1;
    while j < b.len() && (b[j].is_ascii_alphanumeric() || matches!(b[j], b'-' | b'_' | b':' | b'.')) {
        j += 1;
    }
    let name = &tag[1..j];
    if name.is_empty() || !b[1].is_ascii_alphabetic() {
        return Err(format!("'<' not starting a tag at {at} (escape it as &lt;)"));
    }
    let mut attributes: Vec<(String, String)> = Vec::new();
    loop {
        while j < b.len() && b[j].is_ascii_whitespace() {
            j += 1;
        }
        match b.get(j) {
            None => return Err(format!("<{name}> at {at} is not closed with '>'")),
            Some(b'>') => {
                let e = element(name, attributes);
                return Ok((e, false, j + 1));
            }
            Some(b'/') if b.get(j + 1) == Some(&b'>') => {
                let e = element(name, attributes);
                return Ok((e, true, j + 2));
            }
            _ => {}
        }
        let start = j;
        while j < b.len() && !b[j].is_ascii_whitespace() && !matches!(b[j], b'=' | b'>' | b'/') {
            j += 1;
        }
        let attr = &tag[start..j];
        if attr.is_empty() || b.get(j) != Some(&b'=') {
            return Err(format!(
                "attribute '{attr}' of <{name}> at {at} has no quoted value"
            ));
        }
        j += 1;
        let quote = *b.get(j).ok_or(format!("<{name}> at {at} ends in an attribute"))?;
        if quote != b'"' && quote != b'\'' {
            return Err(format!("attribute '{attr}' of <{name}> at {at} is not quoted"));
        }
        let value_start = j + 1;
        let len = tag[value_start..]
            .find(quote as char)
            .ok_or(format!("attribute '{attr}' of <{name}> at {at} is not closed"))?;
        let value = &tag[value_start..value_start + len];
        if value.contains('<') {
            return Err(format!("'<' in attribute '{attr}' of <{name}> at {at}"));
        }
        check_entities(value, at)?;
        if attributes.iter().any(|(n, _)| n == attr) {
            return Err(format!("attribute '{attr}' twice in <{name}> at {at}"));
        }
        attributes.push((attr.to_string(), value.to_string()));
        j = value_start + len + 1;
        if j < b.len() && !b[j].is_ascii_whitespace() && b[j] != b'>' && b[j] != b'/' {
            return Err(format!("no space after attribute '{attr}' of <{name}> at {at}"));
        }
    }
}

fn element(name: &str, attributes: Vec<(String, String)>) -> Element {
    Element {
        name: name.to_string(),
        attributes,
        ancestors: Vec::new(),
        text: String::new(),
    }
}

/// Every `&` starts `&name;` of a predefined entity or a numeric reference.
fn check_entities(text: &str, at: usize) -> Result<(), String> {
    for (k, _) in text.match_indices('&') {
        let rest = &text[k + 1..];
        let end = rest.find(';').ok_or(format!("bare '&' at {}", at + k))?;
        let name = &rest[..end];
        let ok = matches!(name, "amp" | "lt" | "gt" | "quot" | "apos" | "nbsp")
            || name
                .strip_prefix("#x")
                .is_some_and(|h| !h.is_empty() && h.chars().all(|c| c.is_ascii_hexdigit()))
            || name
                .strip_prefix('#')
                .is_some_and(|d| !d.is_empty() && d.chars().all(|c| c.is_ascii_digit()));
        if !ok {
            return Err(format!("unknown entity '&{name};' at {}", at + k));
        }
    }
    Ok(())
}

/// Undoes the escaping of text and attribute values.
pub fn unescape(text: &str) -> String {
    text.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&#39;", "'")
        .replace("&apos;", "'")
        .replace("&amp;", "&")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accepts_good_markup() {
        let html = "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><style>a > b {}</style></head>\
                    <body><p class='x'>a &amp; b &#x2713;</p><svg><line x1=\"0\"/></svg></body></html>";
        let e = check_markup(html, HTML_VOID).unwrap();
        let p = e.iter().find(|e| e.name == "p").unwrap();
        assert_eq!(p.attr("class"), Some("x"));
        assert_eq!(p.ancestors, vec!["html", "body"]);
        assert_eq!(p.text, "a &amp; b &#x2713;");
        let line = e.iter().find(|e| e.name == "line").unwrap();
        assert!(line.parent_is("svg"));
    }

    #[test]
    fn refuses_bad_markup() {
        for (bad, why) in [
            ("<a><b></a></b>", "closes"),
            ("<a>", "never closed"),
            ("<a x=1></a>", "not quoted"),
            ("<a>1 < 2</a>", "not starting a tag"),
            ("<a>R&D</a>", "bare"),
            ("<a>&bogus;</a>", "unknown entity"),
            ("<a></a><b></b>", "second root"),
            ("<a x=\"1\"x=\"2\"></a>", "no space"),
            ("<a>x > y</a>", "unescaped"),
        ] {
            let e = check_markup(bad, &[]).unwrap_err();
            assert!(e.contains(why), "{bad}: {e}");
        }
    }
}
