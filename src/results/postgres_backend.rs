//! The fleet's store: a PostgreSQL server several benches write to, through the
//! synchronous `postgres` client. TLS goes through rustls with the Mozilla roots compiled
//! in (no OpenSSL or other system library), used when the server offers it and required
//! with `sslmode=require`; the certificate is always verified, against those roots and a
//! factory's own CA given as `sslrootcert=PATH`. The password stays in the connection settings: the store's
//! name, as every message shows it, never holds it.

use super::backend::{Backend, Value};
use super::StoreError;
use postgres::types::{ToSql, Type};
use postgres::{Client, Config, Statement};
use std::collections::HashMap;
use std::error::Error;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::Arc;
use std::time::Duration;

/// How long connecting may take before the store counts as unreachable (and a run spools).
const CONNECT_TIMEOUT: Duration = Duration::from_secs(5);
/// How long the whole connection may take, the server's first answers included.
const HANDSHAKE_TIMEOUT: Duration = Duration::from_secs(10);

pub struct PostgresBackend {
    client: Client,
    name: String,
    statements: HashMap<String, Statement>,
}

/// The address without `sslrootcert=PATH`, and that path: the CA certificates (PEM) a
/// server's certificate may also be signed by, as libpq names the setting (the postgres
/// client does not know it).
fn without_root_cert(url: &str) -> (String, Option<PathBuf>) {
    let Some((base, query)) = url.split_once('?') else {
        return (url.to_string(), None);
    };
    let mut root = None;
    let rest: Vec<&str> = query
        .split('&')
        .filter(|kv| match kv.strip_prefix("sslrootcert=") {
            Some(path) => {
                root = Some(PathBuf::from(path));
                false
            }
            None => true,
        })
        .collect();
    let url = if rest.is_empty() {
        base.to_string()
    } else {
        format!("{base}?{}", rest.join("&"))
    };
    (url, root)
}

/// `postgres://user@host:port/db`: the server as messages name it, without the password.
pub fn postgres_name(url: &str) -> String {
    let Ok(config) = Config::from_str(&without_root_cert(url).0) else {
        return "a postgres:// address that cannot be read".into();
    };
    let host = config
        .get_hosts()
        .iter()
        .map(|h| match h {
            postgres::config::Host::Tcp(name) => name.clone(),
            #[cfg(unix)]
            postgres::config::Host::Unix(path) => path.display().to_string(),
        })
        .collect::<Vec<_>>()
        .join(",");
    let port = config
        .get_ports()
        .first()
        .map(|p| format!(":{p}"))
        .unwrap_or_default();
    let user = config.get_user().map(|u| format!("{u}@")).unwrap_or_default();
    let db = config.get_dbname().unwrap_or_default();
    format!("postgres://{user}{host}{port}/{db}")
}

impl PostgresBackend {
    pub fn connect(url: &str) -> Result<PostgresBackend, StoreError> {
        let name = postgres_name(url);
        let (url, root_cert) = without_root_cert(url);
        let mut config = Config::from_str(&url).map_err(|e| StoreError::Foreign {
            store: name.clone(),
            why: format!("the address cannot be read ({e})"),
        })?;
        if config.get_connect_timeout().is_none() {
            config.connect_timeout(CONNECT_TIMEOUT);
        }
        config.application_name("drivescript");
        let tls = tls(&name, root_cert.as_deref())?;
        // The connect timeout bounds the socket's connection only: a server (or a proxy)
        // that takes the connection and never answers would hold the handshake for ever.
        let (sent, answer) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let _ = sent.send(config.connect(tls));
        });
        let handshake = HANDSHAKE_TIMEOUT;
        let client = match answer.recv_timeout(handshake) {
            Ok(connected) => connected.map_err(|e| StoreError::Unreachable {
                store: name.clone(),
                why: full_text(&e),
            })?,
            Err(_) => {
                return Err(StoreError::Unreachable {
                    store: name.clone(),
                    why: format!(
                        "it took the connection but did not answer within {} s",
                        handshake.as_secs()
                    ),
                })
            }
        };
        let mut backend = PostgresBackend {
            client,
            name,
            statements: HashMap::new(),
        };
        // A statement that hangs (a lock held elsewhere, a server in trouble) ends, so
        // the writer spools instead of waiting for ever. And a session of ours that sits
        // in an open transaction (a writer killed half-way whose connection the server
        // still sees open: a killed process under Wine, a laptop pulled off the network)
        // is ended by the server, so its locks do not hold every later delivery of that
        // run past the statement limit; our transactions never wait on anything else.
        backend.batch("SET statement_timeout = '10s'; SET idle_in_transaction_session_timeout = '30s'")?;
        Ok(backend)
    }

    fn error(&self, e: postgres::Error) -> StoreError {
        if e.as_db_error().is_none() || e.is_closed() {
            StoreError::Unreachable {
                store: self.name.clone(),
                why: full_text(&e),
            }
        } else {
            StoreError::Query {
                store: self.name.clone(),
                why: full_text(&e),
            }
        }
    }
}

/// The error with its causes: "error connecting to server: Connection refused".
fn full_text(e: &dyn Error) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        let more = s.to_string();
        if !text.contains(&more) {
            text = format!("{text}: {more}");
        }
        source = s.source();
    }
    text
}

/// rustls with its pure-Rust `ring` provider, the Mozilla root certificates and those in
/// `root_cert` (a factory's own CA).
fn tls(
    store: &str,
    root_cert: Option<&Path>,
) -> Result<tokio_postgres_rustls::MakeRustlsConnect, StoreError> {
    use rustls::pki_types::{pem::PemObject, CertificateDer};
    let mut roots = rustls::RootCertStore {
        roots: webpki_roots::TLS_SERVER_ROOTS.to_vec(),
    };
    if let Some(path) = root_cert {
        let unreadable = |why: String| StoreError::Unreachable {
            store: store.to_string(),
            why: format!(
                "the CA certificates of sslrootcert={} cannot be used: {why}",
                path.display()
            ),
        };
        for cert in CertificateDer::pem_file_iter(path).map_err(|e| unreadable(e.to_string()))? {
            let cert = cert.map_err(|e| unreadable(e.to_string()))?;
            roots.add(cert).map_err(|e| unreadable(e.to_string()))?;
        }
    }
    let provider = Arc::new(rustls::crypto::ring::default_provider());
    let config = rustls::ClientConfig::builder_with_provider(provider)
        .with_safe_default_protocol_versions()
        .map_err(|e| StoreError::Unreachable {
            store: store.to_string(),
            why: format!("TLS cannot be set up: {e}"),
        })?
        .with_root_certificates(roots)
        .with_no_client_auth();
    Ok(tokio_postgres_rustls::MakeRustlsConnect::new(config))
}

/// Each value as the type the server expects for its parameter (a NULL is typed too).
fn params(values: &[Value], types: &[Type]) -> Vec<Box<dyn ToSql + Sync>> {
    values
        .iter()
        .zip(types.iter().chain(std::iter::repeat(&Type::TEXT)))
        .map(|(v, ty)| -> Box<dyn ToSql + Sync> {
            let float = *ty == Type::FLOAT8 || *ty == Type::FLOAT4 || *ty == Type::NUMERIC;
            let int = *ty == Type::INT8 || *ty == Type::INT4 || *ty == Type::INT2;
            match v {
                Value::Null if float => Box::new(None::<f64>),
                Value::Null if int => Box::new(None::<i64>),
                Value::Null => Box::new(None::<String>),
                Value::Int(i) if float => Box::new(*i as f64),
                Value::Int(i) => Box::new(*i),
                Value::Real(r) if int => Box::new(*r as i64),
                Value::Real(r) => Box::new(*r),
                Value::Text(s) => Box::new(held(s)),
            }
        })
        .collect()
}

/// Marks what PostgreSQL's text cannot hold: a NUL (an answer, a serial number read from
/// a drive) is stored as `MARK 0` and the mark itself as `MARK MARK`, so a record with
/// one is stored, read back exactly, and never refused for ever (a spooled run behind it
/// would wait for ever too). The mark is a noncharacter, which no text means to hold.
const MARK: char = '\u{FFFF}';

fn held(s: &str) -> String {
    if !s.contains(['\0', MARK]) {
        return s.to_string();
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        match c {
            '\0' => out.extend([MARK, '0']),
            MARK => out.extend([MARK, MARK]),
            c => out.push(c),
        }
    }
    out
}

/// The text [`held`] stored, as it was given.
fn unheld(s: String) -> String {
    if !s.contains(MARK) {
        return s;
    }
    let mut out = String::with_capacity(s.len());
    let mut chars = s.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, chars.peek()) {
            (MARK, Some('0')) => {
                chars.next();
                out.push('\0');
            }
            (MARK, Some(&MARK)) => {
                chars.next();
                out.push(MARK);
            }
            (c, _) => out.push(c),
        }
    }
    out
}

impl PostgresBackend {
    /// The prepared statement of `sql`, prepared once per connection.
    fn statement(&mut self, sql: &str) -> Result<Statement, StoreError> {
        if let Some(s) = self.statements.get(sql) {
            return Ok(s.clone());
        }
        let prepared = self.client.prepare(sql).map_err(|e| self.error(e))?;
        self.statements.insert(sql.to_string(), prepared.clone());
        Ok(prepared)
    }
}

impl Backend for PostgresBackend {
    fn execute(&mut self, sql: &str, values: &[Value]) -> Result<u64, StoreError> {
        let statement = self.statement(sql)?;
        let boxed = params(values, statement.params());
        let refs: Vec<&(dyn ToSql + Sync)> = boxed.iter().map(|b| b.as_ref()).collect();
        self.client.execute(&statement, &refs).map_err(|e| self.error(e))
    }

    fn query(&mut self, sql: &str, values: &[Value]) -> Result<Vec<Vec<Value>>, StoreError> {
        let statement = self.statement(sql)?;
        let boxed = params(values, statement.params());
        let refs: Vec<&(dyn ToSql + Sync)> = boxed.iter().map(|b| b.as_ref()).collect();
        let rows = self.client.query(&statement, &refs).map_err(|e| self.error(e))?;
        Ok(rows
            .iter()
            .map(|row| {
                (0..row.len())
                    .map(|i| {
                        let ty = row.columns()[i].type_();
                        let got = if *ty == Type::INT8 {
                            cell::<i64>(row, i).map(Value::Int)
                        } else if *ty == Type::INT4 {
                            cell::<i32>(row, i).map(|v| Value::Int(v.into()))
                        } else if *ty == Type::FLOAT8 {
                            cell::<f64>(row, i).map(Value::Real)
                        } else if *ty == Type::BOOL {
                            cell::<bool>(row, i).map(|b| Value::Int(b.into()))
                        } else {
                            cell::<String>(row, i).map(|t| Value::Text(unheld(t)))
                        };
                        got.unwrap_or(Value::Null)
                    })
                    .collect()
            })
            .collect())
    }

    fn batch(&mut self, sql: &str) -> Result<(), StoreError> {
        self.client.batch_execute(sql).map_err(|e| self.error(e))
    }

    fn tables_query(&self) -> &'static str {
        "SELECT table_name::text FROM information_schema.tables WHERE table_schema = current_schema()"
    }

    fn begin_exclusive(&mut self) -> Result<(), StoreError> {
        // One lock number for drivescript's migrations: benches that open a new server at
        // the same moment apply them one after the other.
        self.batch("BEGIN; SELECT pg_advisory_xact_lock(7274737)")
    }

    fn name(&self) -> &str {
        &self.name
    }
}

/// Column `i` of `row` as a `T`; `None` for NULL or a value that does not read as one.
fn cell<'a, T: postgres::types::FromSql<'a>>(row: &'a postgres::Row, i: usize) -> Option<T> {
    row.try_get::<_, Option<T>>(i).ok().flatten()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_postgresql_cannot_hold_is_marked_and_read_back_exactly() {
        for text in [
            "plain",
            "a\0b",
            "\0",
            "mark \u{FFFF} here",
            "\u{FFFF}0",
            "\0\u{FFFF}\u{FFFF}0\0",
        ] {
            let stored = held(text);
            assert!(!stored.contains('\0'), "{stored:?}");
            assert_eq!(unheld(stored), text);
        }
        assert_eq!(held("plain"), "plain");
    }
}
