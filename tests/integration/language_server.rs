//! yaml-language-server driven over stdio as an editor drives it: initialize, open a
//! document, ask for hovers and completions, read the diagnostics it publishes. The
//! language server protocol is JSON-RPC with `Content-Length` headers; this client speaks
//! just enough of it for the editor tests, and answers the server's own requests
//! (its settings) as VS Code's YAML extension does.

use crate::support::repo_root;
use serde_json::{json, Value};
use std::collections::HashMap;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::time::Duration;

/// How long one answer may take: the first one loads the schema, on a machine busy
/// compiling.
const ANSWER_TIMEOUT: Duration = Duration::from_secs(60);

/// The executable: `$YAML_LANGUAGE_SERVER`, else where `.ci/run` installs it
/// (`target/yaml-language-server/`), else `yaml-language-server` on the PATH.
fn candidates() -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = std::env::var_os("YAML_LANGUAGE_SERVER")
        .map(PathBuf::from)
        .into_iter()
        .collect();
    found.push(repo_root().join("target/yaml-language-server/node_modules/.bin/yaml-language-server"));
    found.push(PathBuf::from("yaml-language-server"));
    found
}

/// A document position: line and character (UTF-16 units, which ASCII text counts as
/// bytes) of the end of the first `needle` in `text`, or of its start plus `into`.
pub fn position(text: &str, needle: &str, into: Option<usize>) -> Value {
    let start = text
        .find(needle)
        .unwrap_or_else(|| panic!("`{needle}` is not in the document"));
    let at = start + into.unwrap_or(needle.len());
    let before = &text[..at];
    let line = before.matches('\n').count();
    let character = at - before.rfind('\n').map_or(0, |i| i + 1);
    json!({ "line": line, "character": character })
}

/// `file://` URI of an absolute path, percent-encoding what a URI path may not hold.
pub fn file_uri(path: &Path) -> String {
    let mut uri = String::from("file://");
    for b in path.to_string_lossy().bytes() {
        if b.is_ascii_alphanumeric() || b"/._-~".contains(&b) {
            uri.push(b as char);
        } else {
            uri.push_str(&format!("%{b:02X}"));
        }
    }
    uri
}

pub struct LanguageServer {
    child: Child,
    stdin: ChildStdin,
    messages: Receiver<Value>,
    next_id: u64,
    diagnostics: HashMap<String, Vec<Value>>,
}

impl LanguageServer {
    /// A started and initialized yaml-language-server, or None where it (or node, which
    /// runs it) is not installed.
    pub fn start() -> Option<LanguageServer> {
        let program = candidates().into_iter().find(|p| {
            Command::new(p)
                .arg("--version")
                .output()
                .is_ok_and(|o| o.status.success())
        })?;
        let mut child = Command::new(&program)
            .arg("--stdio")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("yaml-language-server starts");
        let stdin = child.stdin.take().expect("stdin is piped");
        let stdout = child.stdout.take().expect("stdout is piped");
        let (tx, messages) = channel();
        std::thread::spawn(move || {
            let mut reader = BufReader::new(stdout);
            while let Some(message) = read_message(&mut reader) {
                if tx.send(message).is_err() {
                    break;
                }
            }
        });
        let mut server = LanguageServer {
            child,
            stdin,
            messages,
            next_id: 0,
            diagnostics: HashMap::new(),
        };
        let capabilities = json!({
            "textDocument": {
                "hover": { "contentFormat": ["markdown", "plaintext"] },
                "completion": { "completionItem": { "snippetSupport": true, "documentationFormat": ["markdown", "plaintext"] } },
                "publishDiagnostics": {}
            },
            "workspace": { "configuration": true }
        });
        server.request(
            "initialize",
            json!({ "processId": std::process::id(), "rootUri": file_uri(&repo_root()), "capabilities": capabilities }),
        );
        server.notify("initialized", json!({}));
        server.notify(
            "workspace/didChangeConfiguration",
            json!({ "settings": { "yaml": settings() } }),
        );
        Some(server)
    }

    /// Opens `text` as the document at `path` (which need not exist: an editor's unsaved
    /// buffer); its URI.
    pub fn open(&mut self, path: &Path, text: &str) -> String {
        let uri = file_uri(path);
        self.diagnostics.remove(&uri);
        self.notify(
            "textDocument/didOpen",
            json!({ "textDocument": { "uri": uri, "languageId": "yaml", "version": 1, "text": text } }),
        );
        uri
    }

    /// The messages of the diagnostics the server published for `uri` after opening it.
    pub fn diagnostics(&mut self, uri: &str) -> Vec<String> {
        while !self.diagnostics.contains_key(uri) {
            let message = self.next_message("textDocument/publishDiagnostics");
            self.handle(message);
        }
        self.diagnostics[uri]
            .iter()
            .map(|d| {
                let line = d["range"]["start"]["line"].as_u64().unwrap_or_default() + 1;
                format!("{line}: {}", d["message"].as_str().unwrap_or_default())
            })
            .collect()
    }

    /// The hover text (markdown) at `at`, empty when there is none.
    pub fn hover(&mut self, uri: &str, at: Value) -> String {
        let result = self.request(
            "textDocument/hover",
            json!({ "textDocument": { "uri": uri }, "position": at }),
        );
        result["contents"]["value"]
            .as_str()
            .unwrap_or_default()
            .to_string()
    }

    /// (label, text inserted) of each completion offered at `at`.
    pub fn completion(&mut self, uri: &str, at: Value) -> Vec<(String, String)> {
        let result = self.request(
            "textDocument/completion",
            json!({ "textDocument": { "uri": uri }, "position": at }),
        );
        let items = result["items"].as_array().cloned().unwrap_or_default();
        items
            .iter()
            .map(|i| {
                let label = i["label"].as_str().unwrap_or_default().to_string();
                let inserted = i["textEdit"]["newText"]
                    .as_str()
                    .or(i["insertText"].as_str())
                    .unwrap_or(&label)
                    .to_string();
                (label, inserted)
            })
            .collect()
    }

    fn request(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        self.send(json!({ "jsonrpc": "2.0", "id": id, "method": method, "params": params }));
        loop {
            let message = self.next_message(method);
            if message.get("method").is_none() && message["id"] == json!(id) {
                assert!(message.get("error").is_none(), "{method}: {message}");
                return message["result"].clone();
            }
            self.handle(message);
        }
    }

    fn notify(&mut self, method: &str, params: Value) {
        self.send(json!({ "jsonrpc": "2.0", "method": method, "params": params }));
    }

    /// Keeps published diagnostics and answers the server's requests: its settings (the
    /// `yaml` section), null to anything else.
    fn handle(&mut self, message: Value) {
        match message["method"].as_str() {
            Some("textDocument/publishDiagnostics") => {
                let params = &message["params"];
                let uri = params["uri"].as_str().unwrap_or_default().to_string();
                let list = params["diagnostics"].as_array().cloned().unwrap_or_default();
                self.diagnostics.insert(uri, list);
            }
            Some("workspace/configuration") if message.get("id").is_some() => {
                let items = message["params"]["items"].as_array().cloned().unwrap_or_default();
                let answer: Vec<Value> = items
                    .iter()
                    .map(|i| {
                        if i["section"] == "yaml" {
                            settings()
                        } else {
                            Value::Null
                        }
                    })
                    .collect();
                self.send(json!({ "jsonrpc": "2.0", "id": message["id"], "result": answer }));
            }
            Some(_) if message.get("id").is_some() => {
                self.send(json!({ "jsonrpc": "2.0", "id": message["id"], "result": null }));
            }
            _ => {}
        }
    }

    fn next_message(&self, waiting_for: &str) -> Value {
        self.messages.recv_timeout(ANSWER_TIMEOUT).unwrap_or_else(|_| {
            panic!("yaml-language-server did not answer {waiting_for} within {ANSWER_TIMEOUT:?}")
        })
    }

    fn send(&mut self, message: Value) {
        let body = message.to_string();
        write!(self.stdin, "Content-Length: {}\r\n\r\n{body}", body.len())
            .and_then(|()| self.stdin.flush())
            .expect("yaml-language-server reads its input");
    }
}

impl Drop for LanguageServer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The settings an editor gives: validation, hover and completion on.
fn settings() -> Value {
    json!({ "validate": true, "hover": true, "completion": true, "format": { "enable": false } })
}

/// One message: headers up to an empty line, then `Content-Length` bytes of JSON; None at
/// the end of the stream.
fn read_message(reader: &mut impl BufRead) -> Option<Value> {
    let mut length = None;
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line).ok()? == 0 {
            return None;
        }
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some((name, value)) = line.split_once(':') {
            if name.eq_ignore_ascii_case("content-length") {
                length = value.trim().parse::<usize>().ok();
            }
        }
    }
    let mut body = vec![0; length?];
    reader.read_exact(&mut body).ok()?;
    serde_json::from_slice(&body).ok()
}
