//! Reading the reports back with real parsers: the JUnit file with roxmltree (strict XML
//! 1.0) and the structure of the common JUnit schema, the HTML page with html5ever (through
//! scraper) and its parse errors. Each check says what is wrong, so a test can also show
//! that a broken report is refused.

use roxmltree::{Document, Node};
use scraper::{ElementRef, Html, Selector};

pub const XML_DECLARATION: &str = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>";

/// Parses `xml` and checks it against the structure of the common JUnit schema.
pub fn junit(xml: &str) -> Result<Document<'_>, String> {
    if !xml.starts_with(XML_DECLARATION) {
        return Err("no XML declaration with UTF-8 at the start".into());
    }
    let doc = Document::parse(xml).map_err(|e| format!("not well-formed XML: {e}"))?;
    junit_schema(&doc)?;
    Ok(doc)
}

/// The structure both Jenkins' junit-10.xsd and the Ant/Surefire layout accept:
/// testsuites[tests, failures, errors] > testsuite[name, tests, failures, errors, skipped,
/// time] > properties > property[name, value], and testcase[name, classname, time] >
/// failure|error[message, type], skipped[message], system-out|system-err. No `properties` or
/// attributes other than those inside test cases, no `skipped` on testsuites, no suite-level
/// `system-out`. Times are numbers; text only in failure, error, skipped, system-out and
/// system-err; each suite's counts agree with its test cases, and the totals with the suites.
pub fn junit_schema(doc: &Document) -> Result<(), String> {
    let root = doc.root_element();
    if root.tag_name().name() != "testsuites" {
        return Err(format!(
            "the root is <{}>, not <testsuites>",
            root.tag_name().name()
        ));
    }
    for e in root.descendants().filter(Node::is_element) {
        let name = e.tag_name().name();
        let (parents, required): (&[&str], &[&str]) = match name {
            "testsuites" => (&[], &["tests", "failures", "errors"]),
            "testsuite" => (
                &["testsuites"],
                &["name", "tests", "failures", "errors", "skipped", "time"],
            ),
            "properties" => (&["testsuite"], &[]),
            "property" => (&["properties"], &["name", "value"]),
            "testcase" => (&["testsuite"], &["name", "classname", "time"]),
            "failure" | "error" => (&["testcase"], &["message", "type"]),
            "skipped" => (&["testcase"], &["message"]),
            "system-out" | "system-err" => (&["testcase"], &[]),
            other => return Err(format!("element <{other}> is not in the JUnit schema")),
        };
        let parent = e.parent_element().map(|p| p.tag_name().name());
        match parent {
            None if parents.is_empty() => {}
            Some(p) if parents.contains(&p) => {}
            _ => return Err(format!("<{name}> inside {parent:?}")),
        }
        for a in required {
            if e.attribute(*a).is_none() {
                return Err(format!("<{name}> lacks {a}"));
            }
        }
        let allowed: &[&str] = match name {
            "testsuites" => &["name", "tests", "failures", "errors", "time"],
            "testsuite" => &["name", "tests", "failures", "errors", "skipped", "time"],
            "testcase" => &["name", "classname", "time"],
            "failure" | "error" => &["message", "type"],
            "skipped" => &["message"],
            "property" => &["name", "value"],
            _ => &[],
        };
        if let Some(a) = e.attributes().find(|a| !allowed.contains(&a.name())) {
            return Err(format!("<{name}> has attribute {} outside the schemas", a.name()));
        }
        if let Some(t) = e.attribute("time") {
            if t.parse::<f64>().is_err() {
                return Err(format!("<{name}> time {t} is not a number"));
            }
        }
        let mixed = matches!(
            name,
            "failure" | "error" | "skipped" | "system-out" | "system-err"
        );
        if !mixed {
            if let Some(t) = e
                .children()
                .find(|c| c.is_text() && !c.text().unwrap_or("").trim().is_empty())
            {
                return Err(format!("text {:?} directly inside <{name}>", t.text()));
            }
        }
    }
    let mut totals = [0; 3];
    for suite in root.children().filter(|n| n.has_tag_name("testsuite")) {
        let cases: Vec<Node> = suite.children().filter(|n| n.has_tag_name("testcase")).collect();
        let count = |kind: &str| {
            cases
                .iter()
                .filter(|c| c.children().any(|n| n.has_tag_name(kind)))
                .count()
        };
        let counts = [cases.len(), count("failure"), count("error")];
        for (attr, (want, total)) in ["tests", "failures", "errors"]
            .iter()
            .zip(counts.iter().zip(&mut totals))
        {
            *total += want;
            let got = suite.attribute(*attr);
            if got != Some(want.to_string().as_str()) {
                return Err(format!("testsuite {attr}={got:?}, but it holds {want}"));
            }
        }
        let want = count("skipped");
        if suite.attribute("skipped") != Some(want.to_string().as_str()) {
            return Err(format!(
                "testsuite skipped={:?}, but it holds {want}",
                suite.attribute("skipped")
            ));
        }
    }
    for (attr, total) in ["tests", "failures", "errors"].iter().zip(totals) {
        let got = root.attribute(*attr);
        if got != Some(total.to_string().as_str()) {
            return Err(format!("testsuites {attr}={got:?}, but the suites hold {total}"));
        }
    }
    Ok(())
}

/// Elements named `name` in document order.
pub fn xml_elements<'a, 'input>(doc: &'a Document<'input>, name: &str) -> Vec<Node<'a, 'input>> {
    doc.descendants().filter(|n| n.has_tag_name(name)).collect()
}

/// The text of the `system-out` of the test case named `case`.
pub fn case_out<'a>(doc: &'a Document, case: &str) -> Option<&'a str> {
    doc.descendants()
        .find(|n| n.has_tag_name("testcase") && n.attribute("name") == Some(case))?
        .children()
        .find(|n| n.has_tag_name("system-out"))
        .and_then(|n| n.text())
}

/// `xml` checked with `xmllint --schema tests/junit-10.xsd` (Jenkins' JUnit schema) and
/// each of its `<testsuite>`s, the root of a Surefire file, with Maven Surefire's
/// `tests/surefire-test-report-3.0.xsd`; `None` when xmllint is not installed (CI
/// installs it: `.ci/run`).
pub fn junit_xsd(xml: &str) -> Option<Result<(), String>> {
    let jenkins = xmllint(xml, concat!(env!("CARGO_MANIFEST_DIR"), "/tests/junit-10.xsd"))?;
    let mut rest = xml;
    let mut suites = 0;
    let mut surefire = Ok(());
    while let (Some(a), Some(b)) = (rest.find("<testsuite "), rest.find("</testsuite>")) {
        let end = b + "</testsuite>".len();
        let suite = format!("{XML_DECLARATION}\n{}", &rest[a..end]);
        let checked = xmllint(
            &suite,
            concat!(env!("CARGO_MANIFEST_DIR"), "/tests/surefire-test-report-3.0.xsd"),
        )?;
        surefire = surefire.and(checked.map_err(|e| format!("Surefire, suite {}: {e}", suites + 1)));
        suites += 1;
        rest = &rest[end..];
    }
    if suites == 0 {
        return Some(Err("no <testsuite> element".into()));
    }
    Some(jenkins.and(surefire))
}

fn xmllint(xml: &str, xsd: &str) -> Option<Result<(), String>> {
    use std::io::Write;
    use std::process::{Command, Stdio};
    let mut child = Command::new("xmllint")
        .args(["--noout", "--schema", xsd, "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .ok()?;
    let written = child.stdin.take().map(|mut i| i.write_all(xml.as_bytes()));
    let out = child.wait_with_output().ok()?;
    if written.is_some_and(|w| w.is_err()) || !out.status.success() {
        return Some(Err(String::from_utf8_lossy(&out.stderr).into_owned()));
    }
    Some(Ok(()))
}

/// The elements an HTML report is made of; anything else got in through text that was not
/// escaped.
const HTML_ELEMENTS: &[&str] = &[
    "html",
    "head",
    "meta",
    "title",
    "style",
    "body",
    "header",
    "footer",
    "section",
    "h1",
    "h2",
    "p",
    "pre",
    "colgroup",
    "col",
    "strong",
    "span",
    "code",
    "ul",
    "li",
    "table",
    "thead",
    "tbody",
    "tr",
    "th",
    "td",
    "figure",
    "figcaption",
    "svg",
    "g",
    "line",
    "polyline",
    "circle",
    "rect",
    "text",
    "clipPath",
];

/// Parses `text` as an HTML5 document: it must start with the HTML5 doctype, parse without
/// a single parse error, and hold only the elements the report writes.
pub fn html(text: &str) -> Result<Html, String> {
    html_with(text, &[])
}

/// [`html`] for the index page of several files, which links each file's report.
pub fn html_index(text: &str) -> Result<Html, String> {
    html_with(text, &["a"])
}

fn html_with(text: &str, more: &[&str]) -> Result<Html, String> {
    if !text.starts_with("<!DOCTYPE html>") {
        return Err("no <!DOCTYPE html> at the start".into());
    }
    let doc = Html::parse_document(text);
    if !doc.errors.is_empty() {
        return Err(format!("HTML parse errors: {:?}", doc.errors));
    }
    for e in doc.root_element().descendent_elements() {
        let name = e.value().name();
        if !HTML_ELEMENTS.contains(&name) && !more.contains(&name) {
            return Err(format!("unexpected element <{name}>: {}", e.html()));
        }
    }
    Ok(doc)
}

pub fn select<'a>(doc: &'a Html, css: &str) -> Vec<ElementRef<'a>> {
    let selector = Selector::parse(css).unwrap_or_else(|e| panic!("selector {css}: {e}"));
    doc.select(&selector).collect()
}

/// Elements by local name (SVG names keep their case: `clipPath`).
pub fn elements<'a>(doc: &'a Html, name: &str) -> Vec<ElementRef<'a>> {
    doc.root_element()
        .descendent_elements()
        .filter(|e| e.value().name() == name)
        .collect()
}

/// The text inside `e`, entities decoded and inner tags dropped.
pub fn text(e: &ElementRef) -> String {
    e.text().collect()
}

/// The texts of the elements `css` selects.
pub fn texts(doc: &Html, css: &str) -> Vec<String> {
    select(doc, css).iter().map(text).collect()
}

/// True when `e` lies inside an element named `name`.
pub fn inside(e: &ElementRef, name: &str) -> bool {
    e.ancestors()
        .filter_map(ElementRef::wrap)
        .any(|a| a.value().name() == name)
}

/// The text of each cell of each body row of the table in section `id`.
pub fn rows(doc: &Html, id: &str) -> Vec<Vec<String>> {
    select(doc, &format!("section#{id} tbody > tr"))
        .iter()
        .map(|row| {
            row.child_elements()
                .filter(|c| c.value().name() == "td")
                .map(|c| text(&c))
                .collect()
        })
        .collect()
}
