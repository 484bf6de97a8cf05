//! `drivescript results serve`: the store's pages read in headless Chromium over HTTP, on
//! SQLite and on a real PostgreSQL server, following the links from page to page; the
//! filters of `results list`; the access token on an address other machines can reach;
//! and that no request reaches a file.

use crate::support::{
    assert_has, assert_lacks, cli, command, headless_chromium, postgres_with_folder, run_recording,
    unit_args, write_file, SHORT_RECIPE,
};
use crate::support_store::scratch_store;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Stdio};

/// `results serve` running; killed (SIGTERM, then waited for) when dropped.
struct Served {
    child: Child,
    url: String,
    address: SocketAddr,
}

impl Served {
    #[track_caller]
    fn start(store: &str, extra: &[&str]) -> Served {
        let mut child = command()
            .args(["results", "serve", "--results", store])
            .args(extra)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("starts");
        let mut line = String::new();
        let stdout = child.stdout.take().expect("its output");
        let _ = BufReader::new(stdout).read_line(&mut line);
        let Some(url) = line.split_whitespace().find(|w| w.starts_with("http://")) else {
            let mut err = String::new();
            let _ = child.stderr.take().map(|mut e| e.read_to_string(&mut err));
            let _ = child.kill();
            panic!("no address in {line:?}: {err}");
        };
        let url = url.trim_end_matches([';', ',']).to_string();
        let address = url["http://".len()..]
            .split('/')
            .next()
            .and_then(|a| a.parse().ok())
            .expect("an address in the URL");
        Served { child, url, address }
    }

    /// A page's address on this server from its path (`/run/…`).
    fn at(&self, path: &str) -> String {
        format!("http://{}{path}", self.address)
    }

    /// The page at `path` as headless Chromium built it (its profile in `dir`), once
    /// Chromium is known to be installed.
    fn page(&self, path: &str, dir: &Path) -> scraper::Html {
        rendered(&self.at(path), &dir.join("profile")).expect("chromium")
    }

    /// The page behind the first link `css` of `page` whose address holds `part`.
    fn followed(&self, page: &scraper::Html, css: &str, part: &str, dir: &Path) -> scraper::Html {
        let links = hrefs(page, css);
        let link = links.iter().find(|h| h.contains(part));
        let link = link.unwrap_or_else(|| panic!("no link {css} holding {part}: {links:?}"));
        self.page(link, dir)
    }

    /// Status and body of a GET of `path` with `headers` (`Name: value\r\n` each).
    fn get(&self, path: &str, headers: &str) -> (u16, String) {
        http(
            self.address,
            &format!(
                "GET {path} HTTP/1.1\r\nHost: {}\r\nConnection: close\r\n{headers}\r\n",
                self.address
            ),
        )
    }
}

impl Drop for Served {
    fn drop(&mut self) {
        // SIGTERM: the way a service manager ends it; it must end at once.
        #[cfg(unix)]
        let _ = std::process::Command::new("kill")
            .args(["-TERM", &self.child.id().to_string()])
            .status();
        // Windows has no SIGTERM (and no `kill`: waiting for a server never told to end
        // would hang the tests): ended as the Task Manager ends it.
        #[cfg(windows)]
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn http(at: SocketAddr, request: &str) -> (u16, String) {
    let mut s = TcpStream::connect(at).expect("connects");
    // A server that stops answering fails the test instead of holding it up.
    let _ = s.set_read_timeout(Some(std::time::Duration::from_secs(30)));
    s.write_all(request.as_bytes()).expect("sends");
    let mut answer = String::new();
    let _ = s.read_to_string(&mut answer);
    let status = answer.split(' ').nth(1).and_then(|c| c.parse().ok()).unwrap_or(0);
    (status, answer)
}

/// The DOM headless Chromium built from `url` (after redirects and cookies); `None`
/// where Chromium is not installed.
fn rendered(url: &str, profile: &Path) -> Option<scraper::Html> {
    let mut chromium = headless_chromium(profile)?;
    let out = chromium
        .arg("--dump-dom")
        .arg(url)
        .output()
        .expect("chromium runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    Some(scraper::Html::parse_document(&String::from_utf8_lossy(
        &out.stdout,
    )))
}

fn texts(doc: &scraper::Html, css: &str) -> Vec<String> {
    let s = scraper::Selector::parse(css).expect("selector");
    doc.select(&s).map(|e| e.text().collect::<String>()).collect()
}

fn hrefs(doc: &scraper::Html, css: &str) -> Vec<String> {
    let s = scraper::Selector::parse(css).expect("selector");
    doc.select(&s)
        .filter_map(|e| e.value().attr("href").map(str::to_string))
        .collect()
}

/// [`three_runs`] into `store`, then `results serve` of it on `listen`.
fn serving_three_runs(dir: &Path, store: &str, listen: &str) -> Served {
    three_runs(dir, store);
    Served::start(store, &["--listen", listen])
}

/// Three runs of two units at two stations into `store`.
fn three_runs(dir: &Path, store: &str) -> PathBuf {
    let recipe = write_file(dir, "served.yaml", SHORT_RECIPE);
    for (serial, station, operator, part) in [
        ("SP-1", "Bench A", "Ann", "P-1"),
        ("SP-2", "Bench B", "Bob", "P-2"),
        ("SP-1", "Bench A", "Ann", "P-1"),
    ] {
        let unit = unit_args(&[
            ("serial", serial),
            ("station", station),
            ("operator", operator),
            ("part", part),
        ]);
        let args: Vec<&str> = ["--fast", "--quiet"]
            .into_iter()
            .chain(unit.iter().map(String::as_str))
            .collect();
        let (code, out) = run_recording(&recipe, store, &args);
        assert_eq!(code, 0, "{out}");
    }
    recipe
}

/// Every page of the store read in Chromium, reached by the links of the one before.
fn browse(served: &Served, dir: &Path) {
    // The filters of `results list`, answered by the server.
    let rows = |query: &str| {
        let (status, page) = served.get(&format!("/?simulated=1&{query}"), "");
        assert_eq!(status, 200, "{page}");
        let doc = scraper::Html::parse_document(page.split_once("\r\n\r\n").map_or("", |p| p.1));
        texts(&doc, "#runs tbody tr td:nth-child(5)")
    };
    assert_eq!(rows(""), ["SP-1", "SP-2", "SP-1"]);
    assert_eq!(rows("station=Bench+B"), ["SP-2"]);
    assert_eq!(rows("operator=Ann"), ["SP-1", "SP-1"]);
    assert_eq!(rows("part=P-2"), ["SP-2"]);
    assert_eq!(rows("recipe=Short+acceptance").len(), 3);
    assert_eq!(rows("recipe=Other").len(), 0);
    assert_eq!(rows("since=2000-01-01&until=1d").len(), 0);
    assert_eq!(rows("since=2000-01-01").len(), 3);
    assert_eq!(rows("until=2000-01-01").len(), 0);
    assert_eq!(rows("unit=SP-1&limit=1"), ["SP-1"]);
    let (status, page) = served.get("/?since=last+tuesday", "");
    assert_eq!(status, 400);
    assert_has(&page, &["write a date (2026-11-01)"]);
    // Runs on the simulated drive are hidden unless asked for, as on the command line.
    let (_, hidden) = served.get("/", "");
    assert_has(&hidden, &["runs on the simulated drive are hidden"]);

    let Some(list) = rendered(&served.at("/?simulated=1"), &dir.join("profile")) else {
        return;
    };
    assert_eq!(texts(&list, "#runs tbody tr").len(), 3);
    assert!(texts(&list, "#runs .verdict-cell")
        .iter()
        .all(|v| v.contains("PASSED") && v.contains("SIMULATED")));
    let runs = hrefs(&list, "#runs a[href^='/run/']");
    assert_eq!(runs.len(), 3, "{runs:?}");
    let run = served.page(&runs[0], dir);
    assert_eq!(texts(&run, "#verdict")[0].trim(), "✔ PASSED (SIMULATED DRIVE)");
    assert_has(
        &texts(&run, "table.checks").concat(),
        &["speed_actual mean near 3000 rpm ± 1 %", "PASS"],
    );
    assert!(!texts(&run, "#approval").is_empty());
    let unit = hrefs(&run, "#unit a");
    assert_eq!(unit.len(), 1);
    let certificate = served.page(&unit[0], dir);
    assert_eq!(texts(&certificate, "h1"), ["Unit SP-1"]);
    assert_eq!(texts(&certificate, "#runs tbody tr").len(), 2);
    let trend = served.followed(&run, "table.checks a[href^='/trend']", "mean", dir);
    assert_eq!(texts(&trend, "#values tbody tr").len(), 3);
    assert!(!texts(&trend, "svg").is_empty());
    let capability = served.followed(&run, "table.checks a[href^='/capability']", "mean", dir);
    assert_has(&texts(&capability, "#capability").concat(), &["n3", "Cpk"]);
    let yields = served.followed(&capability, "nav a[href^='/yield']", "", dir);
    let rows = texts(&yields, "#yield tbody tr");
    assert_eq!(rows.len(), 2, "{rows:?}");
    assert!(
        rows.iter()
            .any(|r| r.contains("Bench A") && r.contains("100.0 %")),
        "{rows:?}"
    );
    // And back to the list from any page.
    let back = hrefs(&yields, "nav a");
    assert_eq!(back[0], "/?simulated=1");
}

#[test]
fn results_serve_shows_a_sqlite_store_in_chromium() {
    let (dir, store) = &scratch_store("serve-sqlite");
    let served = serving_three_runs(dir, store, "127.0.0.1:0");
    assert!(
        served.url.ends_with('/') && !served.url.contains("token"),
        "{}",
        served.url
    );
    browse(&served, dir);
}

#[test]
fn results_serve_shows_a_postgresql_store_in_chromium() {
    let Some((server, dir)) = postgres_with_folder("serve-postgres") else {
        return;
    };
    let served = serving_three_runs(&dir, &server.url(), "127.0.0.1:0");
    browse(&served, &dir);
    // A server restarted under it: the pages come back without restarting `serve`.
    server.down();
    assert_eq!(served.get("/?simulated=1", "").0, 503);
    server.up();
    assert_eq!(served.get("/?simulated=1", "").0, 200);
}

#[test]
fn results_serve_on_the_network_wants_its_token() {
    let (dir, store) = &scratch_store("serve-token");
    let served = serving_three_runs(dir, store, "0.0.0.0:0");
    let token = served
        .url
        .split("?token=")
        .nth(1)
        .expect("a generated token in the URL")
        .to_string();
    assert_eq!(token.len(), 64);
    assert_eq!(served.get("/?simulated=1", "").0, 401);
    assert_eq!(served.get("/run/x", "").0, 401);
    assert_eq!(served.get("/?token=0123456789abcdef0123", "").0, 403);
    let cookie = format!(
        "Cookie: drivescript_token_{}=0123456789abcdef0123\r\n",
        served.address.port()
    );
    assert_eq!(served.get("/", &cookie).0, 403);
    let (status, answer) = served.get(&format!("/?simulated=1&token={token}"), "");
    assert_eq!(status, 303);
    assert_has(
        &answer.to_ascii_lowercase(),
        &["httponly", "samesite=strict", "location: /?simulated=1\r\n"],
    );
    // The store is read-only over HTTP: nothing but GET and HEAD reaches it.
    let post = format!(
        "POST / HTTP/1.1\r\nHost: {}\r\nConnection: close\r\nContent-Length: 0\r\nCookie: drivescript_token_{}={token}\r\n\r\n",
        served.address,
        served.address.port()
    );
    assert_eq!(http(served.address, &post).0, 401);
    // A browser shown the printed address once keeps reading with the cookie.
    let first = format!(
        "http://127.0.0.1:{}/?simulated=1&token={token}",
        served.address.port()
    );
    if let Some(page) = rendered(&first, &dir.join("profile")) {
        assert_eq!(texts(&page, "#runs tbody tr").len(), 3);
    }
    drop(served);
    // A token file that holds no usable token: refused before anything listens.
    let empty = write_file(dir, "token", "\n");
    let ran = cli(
        &[
            "results",
            "serve",
            "--results",
            store,
            "--listen",
            "0.0.0.0:0",
            "--token-file",
            empty.to_str().expect("utf-8"),
        ],
        2,
    );
    assert_has(&ran.stderr, &["token", "shorter than 16 characters"]);
    let kept = write_file(dir, "kept-token", "bench-7-secret-token-0001\n");
    let served = Served::start(
        store,
        &[
            "--listen",
            "127.0.0.1:0",
            "--token-file",
            kept.to_str().expect("utf-8"),
        ],
    );
    assert!(
        !served.url.contains("bench-7"),
        "the file's token is printed: {}",
        served.url
    );
    assert_eq!(served.get("/", "").0, 401);
    assert_eq!(
        served
            .get("/", "x-drivescript-token: bench-7-secret-token-0001\r\n")
            .0,
        200
    );
}

#[test]
fn no_request_to_results_serve_reads_a_file() {
    let (dir, store) = &scratch_store("serve-paths");
    let served = serving_three_runs(dir, store, "127.0.0.1:0");
    let secret = write_file(dir, "secret.txt", "SECRET-FILE-CONTENT\n");
    let secret = secret.to_str().expect("utf-8").to_string();
    let escaped = drivescript::results::url_escape(&secret);
    for path in [
        "/secret.txt".to_string(),
        "/assets/secret.txt".into(),
        "/assets/..%2Fsecret.txt".into(),
        "/assets/../../../../etc/passwd".into(),
        "/run/..%2F..%2F..%2Fetc%2Fpasswd".into(),
        format!("/run/{escaped}"),
        format!("/unit/{escaped}?simulated=1"),
        format!("/?results={escaped}&simulated=1"),
        format!("/trend?check={escaped}&simulated=1"),
        format!("/capability?check={escaped}"),
        format!("/{escaped}"),
        "/%2Fetc%2Fpasswd".into(),
        "//etc/passwd".into(),
    ] {
        let (status, answer) = served.get(&path, "");
        assert_lacks(&answer, &["SECRET-FILE-CONTENT", "root:x:0:0"]);
        // A query that names a store is not one: the list shows this server's store.
        if path.starts_with("/?results=") {
            assert_eq!(status, 200);
            assert_has(&answer, &[store]);
        } else {
            assert!(matches!(status, 400 | 404), "{path}: {status}");
        }
    }
}
