//! The placeholders written when a run starts, read back with the real parsers.

use super::markup::{html, junit, select, text, texts, xml_elements};
use drivescript::report::{html_unfinished, junit_unfinished};

#[test]
fn the_placeholders_parse_and_say_not_finished() {
    let xml = junit_unfinished("Run <in>", "recipes/x.yaml");
    let doc = junit(&xml).unwrap_or_else(|e| panic!("{e}\n{xml}"));
    let suite = xml_elements(&doc, "testsuite")[0];
    assert_eq!(suite.attribute("name"), Some("Run <in>"));
    assert_eq!(suite.attribute("failures"), Some("1"));
    let failure = xml_elements(&doc, "failure")[0];
    assert_eq!(
        failure.parent_element().and_then(|c| c.attribute("name")),
        Some("run")
    );
    assert!(failure
        .attribute("message")
        .is_some_and(|m| m.starts_with("NOT FINISHED: the run has not finished")));

    let page = html_unfinished("Run <in>", "recipes/x.yaml");
    let doc = html(&page).unwrap_or_else(|e| panic!("{e}\n{page}"));
    assert_eq!(texts(&doc, "h1"), vec!["Run <in>"]);
    let verdict = select(&doc, "#verdict")[0];
    assert_eq!(verdict.attr("class"), Some("verdict not-finished"));
    assert_eq!(text(&verdict), "✘ NOT FINISHED");
}
