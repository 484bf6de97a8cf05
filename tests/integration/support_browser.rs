//! A real headless Chromium driven over the DevTools protocol through a pipe
//! (`--remote-debugging-pipe`: commands on descriptor 3, replies on 4, each message ended
//! by a NUL): navigate, read the page by evaluating JavaScript, type as a keyboard (a
//! barcode scanner is a keyboard), click with the mouse, take screenshots. No WebDriver
//! server, no client crate and no socket: the pipe belongs to this test alone. `None`
//! (after `tool_missing`) where Chromium is not installed.

#![cfg(unix)]

use crate::support::{chromium, scratch};
use serde_json::{json, Value};
use std::fs::File;
use std::io::{BufRead, BufReader, Write};
use std::os::fd::FromRawFd;
use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Child, Stdio};
use std::time::{Duration, Instant};

pub struct Browser {
    child: Child,
    to: File,
    from: BufReader<File>,
    next: u64,
    session: String,
}

/// A pipe whose ends are closed in every program started later (`O_CLOEXEC`).
fn pipe() -> (i32, i32) {
    let mut fds = [0i32; 2];
    // SAFETY: `fds` has room for the two descriptors pipe2 writes.
    let r = unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) };
    assert_eq!(r, 0, "pipe2: {}", std::io::Error::last_os_error());
    (fds[0], fds[1])
}

impl Browser {
    /// A fresh browser (its own profile under the scratch folder `name`) with a page of
    /// `width`×`height` CSS pixels.
    pub fn launch(name: &str, width: u32, height: u32) -> Option<Browser> {
        let profile = scratch(&format!("chromium-{name}"));
        let mut command = chromium(&profile)?;
        let (commands_in, commands_out) = pipe();
        let (replies_in, replies_out) = pipe();
        command
            .arg("--remote-debugging-pipe")
            .arg(format!("--window-size={width},{height}"))
            .arg("about:blank")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(File::create(profile.join("chromium.log")).expect("chromium's log"));
        // SAFETY: only async-signal-safe calls between fork and exec: descriptors moved
        // out of the way first (3 and 4 may be the pipes' own), then onto 3 and 4.
        unsafe {
            command.pre_exec(move || {
                let read = libc::fcntl(commands_in, libc::F_DUPFD_CLOEXEC, 10);
                let write = libc::fcntl(replies_out, libc::F_DUPFD_CLOEXEC, 10);
                if read < 0 || write < 0 || libc::dup2(read, 3) < 0 || libc::dup2(write, 4) < 0 {
                    return Err(std::io::Error::last_os_error());
                }
                Ok(())
            });
        }
        let child = command.spawn().expect("chromium starts");
        // SAFETY: the parent's ends, owned from here on; the child's ends are closed.
        let (to, from) = unsafe {
            libc::close(commands_in);
            libc::close(replies_out);
            (File::from_raw_fd(commands_out), File::from_raw_fd(replies_in))
        };
        let mut browser = Browser {
            child,
            to,
            from: BufReader::new(from),
            next: 1,
            session: String::new(),
        };
        // A page of its own (the command line's first one may not exist yet, or at all).
        let created = browser.call_browser("Target.createTarget", json!({"url": "about:blank"}));
        let target = created["targetId"].as_str().expect("a page").to_string();
        let attached = browser.call_browser(
            "Target.attachToTarget",
            json!({"targetId": target, "flatten": true}),
        );
        browser.session = attached["sessionId"].as_str().expect("a session").to_string();
        browser.resize(width, height);
        Some(browser)
    }

    fn send(&mut self, session: Option<&str>, method: &str, params: Value) -> Value {
        let id = self.next;
        self.next += 1;
        let mut message = json!({"id": id, "method": method, "params": params});
        if let Some(s) = session {
            message["sessionId"] = json!(s);
        }
        let mut bytes = message.to_string().into_bytes();
        bytes.push(0);
        self.to.write_all(&bytes).expect("chromium reads its pipe");
        loop {
            let mut reply = Vec::new();
            let n = self.from.read_until(0, &mut reply).expect("chromium's reply");
            assert!(n > 0, "chromium closed its pipe during {method}");
            reply.pop();
            let reply: Value = serde_json::from_slice(&reply).expect("a JSON reply");
            if reply["id"] != json!(id) {
                continue; // an event
            }
            if let Some(e) = reply.get("error") {
                panic!("{method} failed: {e}");
            }
            return reply["result"].clone();
        }
    }

    fn call_browser(&mut self, method: &str, params: Value) -> Value {
        self.send(None, method, params)
    }

    /// A DevTools command to the page.
    pub fn call(&mut self, method: &str, params: Value) -> Value {
        let session = self.session.clone();
        self.send(Some(&session), method, params)
    }

    pub fn resize(&mut self, width: u32, height: u32) {
        self.call(
            "Emulation.setDeviceMetricsOverride",
            json!({"width": width, "height": height, "deviceScaleFactor": 1, "mobile": false}),
        );
    }

    /// Opens `url` and waits until the page has loaded.
    pub fn open(&mut self, url: &str) {
        self.call("Page.navigate", json!({"url": url}));
        self.wait_for(
            "document.readyState === 'complete' && location.href !== 'about:blank'",
            "the page to load",
        );
    }

    /// The value of `expression` in the page (a promise is awaited).
    pub fn eval(&mut self, expression: &str) -> Value {
        let r = self.call(
            "Runtime.evaluate",
            json!({"expression": expression, "returnByValue": true, "awaitPromise": true}),
        );
        if let Some(e) = r.get("exceptionDetails") {
            panic!("{expression}: {e}");
        }
        r["result"]["value"].clone()
    }

    /// The text of the first element matching `selector` ("" when there is none or it is
    /// hidden).
    pub fn text(&mut self, selector: &str) -> String {
        let js = format!(
            "(() => {{ const e = document.querySelector({s}); return e && e.offsetParent !== null ? e.innerText : ''; }})()",
            s = json!(selector)
        );
        self.eval(&js).as_str().unwrap_or_default().to_string()
    }

    /// Waits until `condition` (JavaScript) is true in the page; fails saying `what`,
    /// with the page's text, after 30 s.
    #[track_caller]
    pub fn wait_for(&mut self, condition: &str, what: &str) {
        let started = Instant::now();
        loop {
            if self.eval(&format!("!!({condition})")) == json!(true) {
                return;
            }
            if started.elapsed() > Duration::from_secs(30) {
                let page = self.eval("document.body ? document.body.innerText : ''");
                panic!(
                    "waited 30 s for {what} ({condition}); the page shows:\n{}",
                    page.as_str().unwrap_or_default()
                );
            }
            std::thread::sleep(Duration::from_millis(40));
        }
    }

    /// Waits until the visible text of `selector` holds `part`.
    #[track_caller]
    pub fn wait_for_text(&mut self, selector: &str, part: &str) {
        let condition = format!(
            "(() => {{ const e = document.querySelector({s}); return e && e.offsetParent !== null && e.innerText.includes({p}); }})()",
            s = json!(selector),
            p = json!(part)
        );
        self.wait_for(&condition, &format!("{part:?} in {selector}"));
    }

    /// Types `text` where the focus is, as a keyboard does.
    pub fn type_text(&mut self, text: &str) {
        self.call("Input.insertText", json!({"text": text}));
    }

    /// Presses Enter (a barcode scanner ends each code with it).
    pub fn enter(&mut self) {
        for kind in ["keyDown", "keyUp"] {
            self.call(
                "Input.dispatchKeyEvent",
                json!({"type": kind, "key": "Enter", "code": "Enter", "windowsVirtualKeyCode": 13, "text": "\r"}),
            );
        }
    }

    /// Clicks the middle of the first visible element matching `selector` with the mouse.
    #[track_caller]
    pub fn click(&mut self, selector: &str) {
        let js = format!(
            "(() => {{ const e = [...document.querySelectorAll({s})].find(e => e.offsetParent !== null); if (!e) return null; e.scrollIntoView({{block: 'center'}}); const r = e.getBoundingClientRect(); return [r.x + r.width / 2, r.y + r.height / 2]; }})()",
            s = json!(selector)
        );
        let at = self.eval(&js);
        let (Some(x), Some(y)) = (at[0].as_f64(), at[1].as_f64()) else {
            panic!("nothing visible matches {selector}");
        };
        for kind in ["mousePressed", "mouseReleased"] {
            self.call(
                "Input.dispatchMouseEvent",
                json!({"type": kind, "x": x, "y": y, "button": "left", "clickCount": 1}),
            );
        }
    }

    /// Saves what the page shows as a PNG.
    pub fn screenshot(&mut self, path: &Path) {
        let shot = self.call("Page.captureScreenshot", json!({"format": "png"}));
        let data = base64(shot["data"].as_str().expect("image data"));
        assert!(data.starts_with(b"\x89PNG"), "a PNG");
        std::fs::write(path, data).expect("the screenshot is written");
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Standard base64 (the screenshot's encoding).
fn base64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let sextets: Vec<u8> = text.bytes().filter_map(value).collect();
    sextets
        .chunks(4)
        .flat_map(|c| {
            let n = c.iter().fold(0u32, |n, s| n << 6 | u32::from(*s)) << (6 * (4 - c.len()));
            let bytes = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
            bytes.into_iter().take(c.len().saturating_sub(1))
        })
        .collect()
}

#[test]
fn base64_decodes_with_and_without_padding() {
    assert_eq!(base64("TWFu"), b"Man");
    assert_eq!(base64("TWE="), b"Ma");
    assert_eq!(base64("TQ=="), b"M");
}
