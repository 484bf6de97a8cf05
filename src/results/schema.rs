//! The store's schema and its versioned migrations, applied when a store is opened: one
//! list, the same SQL on SQLite and PostgreSQL (and the keys of checks stored before they
//! were, filled in from their names through the same statements). A database with tables
//! but none of ours is refused as foreign; one of a newer version is refused with what to
//! do.

use super::backend::{Backend, Value};
use super::StoreError;

/// Marks a database as drivescript's: the table `drivescript_store` holding this.
const APPLICATION: &str = "drivescript results";

/// Migration N (1-based) brings a store from version N-1 to N. Append only.
const MIGRATIONS: &[&str] = &[
    // 1: runs, checks, steps and bucketed series.
    "CREATE TABLE drivescript_store (key TEXT PRIMARY KEY, value TEXT NOT NULL);
     CREATE TABLE runs (
        id TEXT PRIMARY KEY, kind TEXT NOT NULL, recipe TEXT NOT NULL, recipe_path TEXT NOT NULL,
        recipe_sha256 TEXT, tool_version TEXT NOT NULL, started_at TEXT NOT NULL,
        simulated BIGINT NOT NULL, drive TEXT NOT NULL, dictionary TEXT, family TEXT, port TEXT,
        address TEXT, host TEXT, serial TEXT, part TEXT, operator TEXT, station TEXT,
        params TEXT NOT NULL,
        ended_at TEXT, verdict TEXT, exit_code BIGINT, reason TEXT, drive_identity TEXT,
        final_state TEXT, final_speed DOUBLE PRECISION, speed_unit TEXT, coasting BIGINT,
        stop_confirmed BIGINT, safe_stop TEXT, report_files TEXT,
        omitted_steps BIGINT, omitted_checks BIGINT);
     CREATE INDEX runs_started ON runs (started_at);
     CREATE INDEX runs_serial ON runs (serial, started_at);
     CREATE INDEX runs_recipe ON runs (recipe, started_at);
     CREATE TABLE checks (
        run_id TEXT NOT NULL, seq BIGINT NOT NULL, name TEXT NOT NULL,
        measured DOUBLE PRECISION, measured_text TEXT, unit TEXT,
        low DOUBLE PRECISION, high DOUBLE PRECISION, passed BIGINT NOT NULL, marginal BIGINT NOT NULL,
        step TEXT NOT NULL, stage TEXT NOT NULL, attempt BIGINT NOT NULL, message TEXT NOT NULL,
        PRIMARY KEY (run_id, seq));
     CREATE INDEX checks_name ON checks (name, run_id);
     CREATE TABLE steps (
        run_id TEXT NOT NULL, seq BIGINT NOT NULL, step TEXT NOT NULL, label TEXT NOT NULL,
        ok BIGINT NOT NULL, detail TEXT NOT NULL, phase TEXT NOT NULL,
        started_s DOUBLE PRECISION NOT NULL, duration_s DOUBLE PRECISION NOT NULL,
        PRIMARY KEY (run_id, seq));
     CREATE TABLE series (
        run_id TEXT NOT NULL, seq BIGINT NOT NULL, object TEXT NOT NULL, unit TEXT,
        step TEXT NOT NULL, points TEXT NOT NULL,
        PRIMARY KEY (run_id, seq));",
    // 2: a check compared with the unit's last passed run names that run and its value.
    "ALTER TABLE checks ADD COLUMN reference_run TEXT;
     ALTER TABLE checks ADD COLUMN reference_at TEXT;
     ALTER TABLE checks ADD COLUMN reference_value DOUBLE PRECISION;",
    // 3: a check's key, the same in every run whatever its limits (`session::check_key`);
    // the rows before it get theirs from their names ([`fill_keys`]).
    "ALTER TABLE checks ADD COLUMN check_key TEXT;
     CREATE INDEX checks_key ON checks (check_key, run_id);",
    // 4: whether a check's limits include the values at them (`at_most`, `≤`) or not
    // (`below`, `<`), which a name the recipe gave does not show; NULL in the rows before
    // it, whose names show it where drivescript made them.
    "ALTER TABLE checks ADD COLUMN inclusive BIGINT;",
    // 5: a run voided (`results void`: the wrong unit scanned, a bench fault) with who,
    // when and why; the run itself stays, and so does this row, an audit record of its
    // own: nothing deletes either. A table of its own, so no other migration's columns
    // of `runs` or `checks` bear on it.
    // The decimal places a check's object resolves, which every page shows its value at
    // (NULL before: shown to three places at most).
    "CREATE TABLE IF NOT EXISTS voids (
        run_id TEXT PRIMARY KEY, voided_at TEXT NOT NULL, voided_by TEXT NOT NULL,
        why TEXT NOT NULL);
     ALTER TABLE checks ADD COLUMN decimals BIGINT;",
];

/// The version whose migration adds `checks.check_key`.
const KEYS: usize = 3;

/// The statements of migration `version` (1-based), as the drivescript of that version
/// applied them: a test builds an old store with them.
pub fn migration(version: usize) -> Option<&'static str> {
    MIGRATIONS.get(version.checked_sub(1)?).copied()
}

/// The schema version this drivescript writes.
pub fn current_version() -> i64 {
    MIGRATIONS.len() as i64
}

/// Brings the store behind `backend` to the current version, or says why it cannot.
pub fn migrate(backend: &mut dyn Backend) -> Result<(), StoreError> {
    match version(backend)? {
        Some(v) if v == current_version() => return Ok(()),
        // Refused before any lock or write: another application's file stays untouched.
        None => refuse_foreign(backend)?,
        Some(_) => {}
    }
    backend.begin_exclusive()?;
    let result = migrate_locked(backend);
    match &result {
        Ok(()) => backend.batch("COMMIT")?,
        Err(_) => {
            let _ = backend.batch("ROLLBACK");
        }
    }
    result
}

fn migrate_locked(backend: &mut dyn Backend) -> Result<(), StoreError> {
    let found = match version(backend)? {
        Some(v) => v,
        None => {
            refuse_foreign(backend)?;
            0
        }
    };
    if found > current_version() {
        return Err(StoreError::Newer {
            store: backend.name().to_string(),
            found,
            known: current_version(),
        });
    }
    for (at, sql) in MIGRATIONS.iter().enumerate().skip(found as usize) {
        backend.batch(sql)?;
        if at + 1 == KEYS {
            fill_keys(backend)?;
        }
    }
    if found == 0 {
        backend.execute(
            "INSERT INTO drivescript_store (key, value) VALUES ('application', $1)",
            &[APPLICATION.into()],
        )?;
        backend.execute(
            "INSERT INTO drivescript_store (key, value) VALUES ('schema', '0')",
            &[],
        )?;
    }
    backend.execute(
        "UPDATE drivescript_store SET value = $1 WHERE key = 'schema'",
        &[current_version().to_string().into()],
    )?;
    Ok(())
}

/// A database without a store that holds tables is another application's. One that holds
/// `drivescript_store` is drivescript's after all: another process created the store since
/// [`version`] looked (two runs opening a new PostgreSQL store at once), and the migration
/// reads its version again under the lock.
fn refuse_foreign(backend: &mut dyn Backend) -> Result<(), StoreError> {
    let tables = backend.tables()?;
    if tables.is_empty() || tables.iter().any(|t| t == "drivescript_store") {
        return Ok(());
    }
    Err(StoreError::Foreign {
        store: backend.name().to_string(),
        why: format!("it holds other tables ({})", tables.join(", ")),
    })
}

/// Gives the checks stored without a key the key their name shows (`current_actual max
/// below 5 A` → `current_actual max below`), one statement per distinct name (an index
/// finds its rows); a name that shows none (a name the recipe gave, a question) stays
/// without one and is its own key.
fn fill_keys(backend: &mut dyn Backend) -> Result<(), StoreError> {
    let names = backend.query("SELECT DISTINCT name FROM checks WHERE check_key IS NULL", &[])?;
    for name in names.iter().filter_map(|r| r.first().and_then(Value::text)) {
        if let Some(key) = crate::session::key_of_name(name) {
            backend.execute(
                "UPDATE checks SET check_key = $1 WHERE name = $2 AND check_key IS NULL",
                &[key.into(), name.into()],
            )?;
        }
    }
    Ok(())
}

/// The schema version, `None` when the database holds no store (yet); a newer one is an
/// error.
fn version(backend: &mut dyn Backend) -> Result<Option<i64>, StoreError> {
    if !backend.tables()?.iter().any(|t| t == "drivescript_store") {
        return Ok(None);
    }
    let rows = backend.query("SELECT key, value FROM drivescript_store", &[])?;
    let get = |key: &str| {
        rows.iter()
            .find(|r| r.first().and_then(Value::text) == Some(key))
            .and_then(|r| r.get(1).and_then(Value::text).map(str::to_string))
    };
    if get("application").as_deref() != Some(APPLICATION) {
        return Err(StoreError::Foreign {
            store: backend.name().to_string(),
            why: "its table drivescript_store does not name drivescript's results".into(),
        });
    }
    let v = get("schema").and_then(|v| v.parse::<i64>().ok()).unwrap_or(0);
    if v > current_version() {
        return Err(StoreError::Newer {
            store: backend.name().to_string(),
            found: v,
            known: current_version(),
        });
    }
    Ok(Some(v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::sqlite_backend::SqliteBackend;

    /// A store of schema `version` in the scratch folder `name`, holding the checks
    /// `checks` inserts, opened (so migrated) by this drivescript: the store, read raw, and
    /// its folder.
    fn migrated(name: &str, version: usize, checks: &str) -> (SqliteBackend, std::path::PathBuf) {
        let dir = crate::scratch_dir::scratch_dir(&format!("schema-{name}"));
        let path = dir.join("old.sqlite");
        let mut old = SqliteBackend::open(&path, true).expect("opens");
        for v in 1..=version {
            old.batch(migration(v).expect("a migration")).expect("applied");
        }
        old.batch(&format!(
            "INSERT INTO drivescript_store (key, value) VALUES ('application', 'drivescript results');
             INSERT INTO drivescript_store (key, value) VALUES ('schema', '{version}');
             INSERT INTO checks (run_id, seq, name, passed, marginal, step, stage, attempt, message)
                VALUES {checks};"
        ))
        .expect("old checks");
        drop(old);
        drop(
            crate::results::Locator::Sqlite(path.clone())
                .open(false)
                .expect("migrated"),
        );
        (SqliteBackend::open(&path, false).expect("opens"), dir)
    }

    /// A store another process finished creating after this one found none is not taken
    /// for another application's.
    #[test]
    fn a_store_created_meanwhile_is_not_refused_as_foreign() {
        let (mut b, dir) = migrated("meanwhile", 1, "('r1', 1, 'c', 1, 0, '1', '', 1, 'kept')");
        assert!(refuse_foreign(&mut b).is_ok());
        b.batch("CREATE TABLE notes (text TEXT); DROP TABLE drivescript_store;")
            .expect("another application's tables");
        assert!(matches!(refuse_foreign(&mut b), Err(StoreError::Foreign { .. })));
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A store written by the first version keeps its runs and takes the columns of a
    /// check's reference when opened by this one.
    #[test]
    fn a_version_1_store_is_migrated_and_keeps_its_runs() {
        let (mut b, dir) = migrated("v1", 1, "('r1', 1, 'c', 1, 0, '1', '', 1, 'kept')");
        assert_eq!(version(&mut b).expect("version"), Some(current_version()));
        let rows = b
            .query(
                "SELECT message, reference_run, check_key, inclusive FROM checks WHERE run_id = 'r1'",
                &[],
            )
            .expect("the new columns");
        assert_eq!(rows[0][0].text(), Some("kept"));
        assert_eq!(rows[0][1].text(), None);
        assert_eq!(rows[0][2].text(), None, "`c` is its own key");
        assert_eq!(rows[0][3].int(), None, "not known: read from the name");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A version 4 store (before voids and the places of a check's value) takes the table
    /// of voids, empty, and the column `decimals`, NULL in its rows (shown to three places
    /// at most); its checks stay as they were.
    #[test]
    fn a_version_4_store_takes_voids_and_the_places_of_a_value() {
        let (mut b, dir) = migrated(
            "v4",
            4,
            "('r1', 1, 'x below 5 A', 1, 0, '2', 'Stage 1', 1, 'kept')",
        );
        assert_eq!(version(&mut b).expect("version"), Some(current_version()));
        let rows = b
            .query("SELECT message, stage, decimals FROM checks", &[])
            .expect("the new column");
        assert_eq!(
            (rows[0][0].text(), rows[0][1].text(), rows[0][2].int()),
            (Some("kept"), Some("Stage 1"), None)
        );
        assert!(b
            .query("SELECT run_id FROM voids", &[])
            .expect("the table")
            .is_empty());
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// The checks of a version 2 store get the key their names show; a name the recipe
    /// gave shows none and stays its own key.
    #[test]
    fn a_version_2_store_keys_its_checks_from_their_names() {
        let (mut b, dir) = migrated(
            "v2",
            2,
            "('r1', 1, 'current_actual max below 5 A', 1, 0, '1', '', 1, ''),
             ('r1', 2, 'current_actual max below 5 A compared with last pass', 1, 0, '1', '', 1, ''),
             ('r2', 1, 'current_actual max below 5 A', 1, 0, '1', '', 1, ''),
             ('r2', 2, 'bearing current at 18000 rpm', 1, 0, '2', '', 1, '')",
        );
        let rows = b
            .query("SELECT name, check_key FROM checks ORDER BY run_id, seq", &[])
            .expect("the keys");
        let keys: Vec<Option<&str>> = rows.iter().map(|r| r[1].text()).collect();
        assert_eq!(
            keys,
            [
                Some("current_actual max below"),
                Some("current_actual max below compared with last pass"),
                Some("current_actual max below"),
                None
            ]
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
