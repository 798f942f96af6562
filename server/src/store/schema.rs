//! The schema, as migrations: each takes it from version `i` to `i + 1`, in one
//! transaction. A database of any earlier release opens and is brought forward; nothing
//! already stored is dropped. Both engines run the same definitions, written in SQLite's
//! words: PostgreSQL reads them with its own names for the same types (`postgres_ddl`).
//! SQLite keeps the version in `PRAGMA user_version`, PostgreSQL in `estlab_schema`, and
//! there a lock makes processes that start together migrate one after the other.

use super::db::{self, Connection, Engine};
use Step::{OldRows, Schema};

/// One step of the schema's history.
enum Step {
    /// Tables, columns and indexes, on both engines.
    Schema(&'static str),
    /// A rewrite of rows an earlier release stored. A PostgreSQL database began with a
    /// release after every such step, so it holds no such rows: SQLite's alone.
    OldRows(&'static str),
}

const MIGRATIONS: &[Step] = &[
    // 1 (estlab 0.1.0): the submissions of an open server.
    Schema("CREATE TABLE submissions (
        id INTEGER PRIMARY KEY,
        course TEXT NOT NULL,
        student TEXT NOT NULL,
        lab TEXT NOT NULL,
        seed INTEGER NOT NULL,
        source TEXT NOT NULL,
        status TEXT NOT NULL CHECK (status IN ('queued', 'grading', 'graded')),
        submitted_at TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now')),
        graded_at TEXT,
        score REAL,
        result TEXT
    );
    CREATE INDEX submissions_by_student ON submissions (course, student, id);"),
    // 2: courses, their people and assignments, and what signs people in. Times that are
    // compared are Unix seconds; codes and tokens are kept as hashes only. A submission
    // made by a signed-in student names them (`member`); those of an open server name
    // nobody and belong to no course's people.
    Schema("CREATE TABLE courses (
        name TEXT PRIMARY KEY,
        title TEXT NOT NULL,
        created_at INTEGER NOT NULL
    );
    CREATE TABLE members (
        id INTEGER PRIMARY KEY,
        course TEXT NOT NULL REFERENCES courses (name),
        login TEXT NOT NULL,
        name TEXT NOT NULL,
        email TEXT NOT NULL,
        role TEXT NOT NULL CHECK (role IN ('student', 'assistant', 'instructor')),
        dropped INTEGER NOT NULL DEFAULT 0,
        UNIQUE (course, login)
    );
    CREATE TABLE codes (
        selector TEXT PRIMARY KEY,
        member INTEGER NOT NULL REFERENCES members (id),
        hash TEXT NOT NULL,
        once INTEGER NOT NULL,
        expires_at INTEGER,
        created_at INTEGER NOT NULL
    );
    CREATE INDEX codes_by_member ON codes (member);
    CREATE TABLE sessions (
        hash TEXT PRIMARY KEY,
        member INTEGER NOT NULL REFERENCES members (id),
        created_at INTEGER NOT NULL,
        expires_at INTEGER NOT NULL
    );
    CREATE TABLE tokens (
        id INTEGER PRIMARY KEY,
        course TEXT NOT NULL REFERENCES courses (name),
        role TEXT NOT NULL CHECK (role IN ('assistant', 'instructor')),
        hash TEXT NOT NULL UNIQUE,
        created_at INTEGER NOT NULL,
        revoked_at INTEGER
    );
    CREATE TABLE assignments (
        course TEXT NOT NULL REFERENCES courses (name),
        lab TEXT NOT NULL,
        due INTEGER NOT NULL,
        cutoff INTEGER NOT NULL,
        late_penalty REAL NOT NULL,
        counts TEXT NOT NULL CHECK (counts IN ('best', 'last')),
        PRIMARY KEY (course, lab)
    );
    CREATE TABLE settings (
        key TEXT PRIMARY KEY,
        value TEXT NOT NULL
    );
    ALTER TABLE submissions ADD COLUMN member INTEGER REFERENCES members (id);
    ALTER TABLE submissions ADD COLUMN late_seconds INTEGER NOT NULL DEFAULT 0;
    ALTER TABLE submissions ADD COLUMN penalty REAL NOT NULL DEFAULT 0;
    CREATE INDEX submissions_by_member ON submissions (member, lab, id);"),
    // 3: the instructor's side. Each result names the grader that produced it; a
    // regrade keeps the result it replaces (`results`) and goes item by item, so a stop
    // resumes it; extensions move one student's dates; staff actions are logged.
    Schema("ALTER TABLE submissions ADD COLUMN grader TEXT;
    CREATE TABLE regrades (
        id INTEGER PRIMARY KEY,
        course TEXT NOT NULL,
        lab TEXT NOT NULL,
        scope TEXT NOT NULL,
        requested_by TEXT NOT NULL,
        grader TEXT NOT NULL,
        created_at INTEGER NOT NULL,
        finished_at INTEGER
    );
    CREATE TABLE regrade_items (
        regrade INTEGER NOT NULL REFERENCES regrades (id),
        submission INTEGER NOT NULL REFERENCES submissions (id),
        done INTEGER NOT NULL DEFAULT 0,
        old_score REAL,
        new_score REAL,
        PRIMARY KEY (regrade, submission)
    );
    CREATE INDEX regrade_items_waiting ON regrade_items (done, regrade, submission);
    CREATE TABLE results (
        id INTEGER PRIMARY KEY,
        submission INTEGER NOT NULL REFERENCES submissions (id),
        grader TEXT,
        score REAL,
        result TEXT NOT NULL,
        graded_at TEXT,
        replaced_by INTEGER REFERENCES regrades (id)
    );
    CREATE INDEX results_by_submission ON results (submission, id);
    CREATE TABLE extensions (
        course TEXT NOT NULL,
        lab TEXT NOT NULL,
        member INTEGER NOT NULL REFERENCES members (id),
        due INTEGER NOT NULL,
        cutoff INTEGER NOT NULL,
        granted_by TEXT NOT NULL,
        granted_at INTEGER NOT NULL,
        PRIMARY KEY (course, lab, member)
    );
    CREATE TABLE audit (
        id INTEGER PRIMARY KEY,
        course TEXT NOT NULL,
        at INTEGER NOT NULL,
        actor TEXT NOT NULL,
        action TEXT NOT NULL,
        detail TEXT NOT NULL
    );
    CREATE INDEX audit_by_course ON audit (course, id);"),
    // 4: a submission's late penalty waived by staff, with their reason. Lateness itself
    // is not stored for the scores: it is judged from `submitted_at` and the dates in force.
    Schema("CREATE TABLE waivers (
        submission INTEGER PRIMARY KEY REFERENCES submissions (id),
        reason TEXT NOT NULL,
        waived_by TEXT NOT NULL,
        waived_at INTEGER NOT NULL
    );"),
    // 5: each test of a result says what it tests (`subject`: a function, or a run). A
    // result stored before said it in its name alone: a function's test is named
    // `predict: 12 cases`, a run's begins with the run's name (`o3 data set, ...`,
    // `square path: ...`).
    OldRows("CREATE TEMP TABLE tested (kept TEXT, id INTEGER, result TEXT, PRIMARY KEY (kept, id));
    INSERT INTO tested
    SELECT kept, id, json_set(result, '$.tests', json((
        SELECT json_group_array(json_set(test.value, '$.subject', json_object(
            'kind', CASE WHEN test.value ->> 'name' GLOB '*: [0-9]* cases'
                THEN 'function' ELSE 'run' END,
            'name', CASE WHEN test.value ->> 'name' GLOB '*: [0-9]* cases'
                THEN substr(test.value ->> 'name', 1, instr(test.value ->> 'name', ':') - 1)
                ELSE substr(test.value ->> 'name', 1, instr(test.value ->> 'name' || ' ', ' ') - 1)
                END)) ORDER BY test.key)
        FROM json_each(result, '$.tests') AS test)))
    FROM (SELECT 'submissions' AS kept, id, result FROM submissions
          UNION ALL SELECT 'results', id, result FROM results)
    WHERE json_valid(result) AND json_type(result, '$.tests') = 'array';
    UPDATE submissions SET result = (SELECT t.result FROM tested t WHERE t.kept = 'submissions' AND t.id = submissions.id)
    WHERE id IN (SELECT id FROM tested WHERE kept = 'submissions');
    UPDATE results SET result = (SELECT t.result FROM tested t WHERE t.kept = 'results' AND t.id = results.id)
    WHERE id IN (SELECT id FROM tested WHERE kept = 'results');
    DROP TABLE tested;"),
    // 6: the class challenge. A submission's figure (its filter's error over its class's
    // held-out run, lower the better; none where the exercise has no challenge or the run
    // gave no figure) kept beside its score, so that a rank is a query away; and whether an
    // assignment shows its students their rank.
    Schema("ALTER TABLE submissions ADD COLUMN challenge REAL;
    ALTER TABLE assignments ADD COLUMN ranked INTEGER NOT NULL DEFAULT 1;"),
    // 7: the language a submission is written in (`labs::Language`'s name); every earlier
    // one is JavaScript.
    Schema("ALTER TABLE submissions ADD COLUMN language TEXT NOT NULL DEFAULT 'javascript';"),
    // 8: the languages an assignment takes (names, comma-separated); none: every language
    // the server grades, those of later releases too.
    Schema("ALTER TABLE assignments ADD COLUMN languages TEXT;"),
    // 9: the written hand-in. An assignment's question sets (`questions`: their TOML as a
    // JSON array, in order; none: the exercise's own sets) and each student's answers,
    // the latest to each question, by the set's place and the question's id.
    Schema("ALTER TABLE assignments ADD COLUMN questions TEXT;
    CREATE TABLE answers (
        member INTEGER NOT NULL REFERENCES members (id),
        lab TEXT NOT NULL,
        part INTEGER NOT NULL,
        question TEXT NOT NULL,
        answer TEXT NOT NULL,
        saved_at INTEGER NOT NULL,
        PRIMARY KEY (member, lab, part, question)
    );"),
    // 10: peer review of the written answers. A round hands one question set's answer
    // sheets (each frozen as it stood when the round opened, or when its author joined
    // late) to reviewers among their authors, each pair numbered for its reviewer (who
    // never learns the author); a mark is one reviewer's judgement of one answer. The
    // round keeps the set as it was (its TOML), so that a change of the assignment's sets
    // leaves what it reviews alone.
    Schema("CREATE TABLE review_rounds (
        id INTEGER PRIMARY KEY,
        course TEXT NOT NULL,
        lab TEXT NOT NULL,
        part INTEGER NOT NULL,
        per_sheet INTEGER NOT NULL,
        seed INTEGER NOT NULL,
        bonus_above REAL NOT NULL,
        questions TEXT NOT NULL,
        opened_by TEXT NOT NULL,
        opened_at INTEGER NOT NULL,
        closed_at INTEGER
    );
    CREATE TABLE review_sheets (
        round INTEGER NOT NULL REFERENCES review_rounds (id),
        author INTEGER NOT NULL REFERENCES members (id),
        answers TEXT NOT NULL,
        PRIMARY KEY (round, author)
    );
    CREATE TABLE review_pairs (
        round INTEGER NOT NULL REFERENCES review_rounds (id),
        reviewer INTEGER NOT NULL REFERENCES members (id),
        author INTEGER NOT NULL REFERENCES members (id),
        number INTEGER NOT NULL,
        submitted_at INTEGER,
        PRIMARY KEY (round, reviewer, author),
        UNIQUE (round, reviewer, number)
    );
    CREATE TABLE review_marks (
        round INTEGER NOT NULL REFERENCES review_rounds (id),
        reviewer INTEGER NOT NULL,
        author INTEGER NOT NULL,
        question TEXT NOT NULL,
        correct INTEGER NOT NULL CHECK (correct IN (0, 1)),
        comment TEXT NOT NULL,
        PRIMARY KEY (round, reviewer, author, question)
    );
    -- Every number a reviewer's sheet had in a round, so that none is given twice.
    CREATE TABLE review_numbers (
        round INTEGER NOT NULL REFERENCES review_rounds (id),
        reviewer INTEGER NOT NULL,
        number INTEGER NOT NULL,
        PRIMARY KEY (round, reviewer, number)
    );"),
    // 11: the report. A student's analyses of its runs (a JSON object, run name to text);
    // each hand-in counts up `handed_in`, names the submission whose runs it shows and
    // keeps the analyses and answers as they were (`handed_analyses`, `handed_answers`,
    // JSON), which staff read and judge whatever changes later;
    // staff's rubric (JSON, a verdict and comment per part) judges the hand-in whose count
    // it keeps in `reviewed`. The runs of a submission's report, once made, are kept (the
    // harness's outputs, JSON) with the grader that made them: the same code, seed and
    // grader give the same runs, and another grader's data sets are not these.
    Schema("CREATE TABLE reports (
        member INTEGER NOT NULL REFERENCES members (id),
        lab TEXT NOT NULL,
        analyses TEXT NOT NULL,
        saved_at INTEGER NOT NULL,
        handed_in INTEGER NOT NULL DEFAULT 0,
        submission INTEGER REFERENCES submissions (id),
        handed_in_at INTEGER,
        handed_analyses TEXT,
        handed_answers TEXT,
        rubric TEXT,
        reviewed INTEGER,
        reviewed_by TEXT,
        reviewed_at INTEGER,
        PRIMARY KEY (member, lab)
    );
    CREATE TABLE report_runs (
        submission INTEGER PRIMARY KEY REFERENCES submissions (id),
        grader TEXT NOT NULL,
        outputs TEXT NOT NULL
    );"),
    // 12: graders and web processes of their own. A grading is leased: the grader holding it
    // (`leased_by`, see `leases::Holder`) renews `lease_until` (milliseconds since 1970)
    // while it grades, and writes its result only while it holds the lease; a lease that
    // ran out is another grader's to take. A submission names the grader the web process
    // that took it grades with (`wanted_grader`): a grader of another release leaves it.
    Schema("ALTER TABLE submissions ADD COLUMN leased_by TEXT;
    ALTER TABLE submissions ADD COLUMN lease_until INTEGER NOT NULL DEFAULT 0;
    ALTER TABLE submissions ADD COLUMN wanted_grader TEXT;
    ALTER TABLE regrade_items ADD COLUMN leased_by TEXT;
    ALTER TABLE regrade_items ADD COLUMN lease_until INTEGER NOT NULL DEFAULT 0;
    CREATE INDEX submissions_unfinished ON submissions (status) WHERE status != 'graded';
    -- The limits every web process counts alike (`rates`): an event of a key of a scope
    -- (a sign-in tried, a phase run) at a moment (milliseconds since 1970).
    CREATE TABLE rate_events (
        id INTEGER PRIMARY KEY,
        scope TEXT NOT NULL,
        key TEXT NOT NULL,
        at INTEGER NOT NULL
    );
    CREATE INDEX rate_events_by_key ON rate_events (scope, key, at);
    CREATE INDEX rate_events_by_moment ON rate_events (scope, at);
    -- The graders running (`leases::Holder`), with the versions they grade (a JSON
    -- array), seen at each look at the database: a submission is left for a grader of
    -- its version only while one runs.
    CREATE TABLE graders (
        holder TEXT PRIMARY KEY,
        versions TEXT NOT NULL,
        seen INTEGER NOT NULL
    );
    -- A student's report's runs being made (one student's at a time), under a lease of
    -- the web process making them, or why its last try failed, to be told once.
    CREATE TABLE report_makings (
        member INTEGER PRIMARY KEY REFERENCES members (id),
        submission INTEGER NOT NULL,
        leased_by TEXT,
        lease_until INTEGER NOT NULL DEFAULT 0,
        failed TEXT
    );"),
    // 13: the class challenge over several runs: the spread of a submission's figure (the
    // runs' standard deviation), shown beside it; none for a figure over one run.
    Schema("ALTER TABLE submissions ADD COLUMN challenge_spread REAL;"),
    // 14: the languages each grader can grade (a JSON array of names, as `versions`): a
    // submission in a language no running grader grades is shown waiting for one, and
    // does not hold back its student's next submission in another language.
    Schema("ALTER TABLE graders ADD COLUMN languages TEXT NOT NULL DEFAULT '[]';"),
    // 15: sign-in codes made in the background (`codes_jobs`): how many of how many are
    // made, under the lease of the web process making them, and the codes file (JSON)
    // until the instructor has fetched it once.
    Schema("CREATE TABLE codes_jobs (
        id INTEGER PRIMARY KEY,
        course TEXT NOT NULL REFERENCES courses (name),
        total INTEGER NOT NULL,
        done INTEGER NOT NULL DEFAULT 0,
        leased_by TEXT,
        lease_until INTEGER NOT NULL DEFAULT 0,
        file TEXT,
        fetched INTEGER NOT NULL DEFAULT 0,
        failed TEXT
    );"),
];

/// Brings the schema up to the newest version, one migration per transaction.
pub fn migrate(connection: &Connection) -> db::Result<()> {
    match connection.engine() {
        Engine::Sqlite => {
            let version: i64 = connection.query_row("PRAGMA user_version", (), |row| row.get(0))?;
            known(version)?;
            for (i, step) in MIGRATIONS.iter().enumerate().skip(version as usize) {
                let (Schema(sql) | OldRows(sql)) = step;
                connection.execute_batch(&format!(
                    "BEGIN; {sql}; PRAGMA user_version = {}; COMMIT;",
                    i + 1
                ))?;
            }
            Ok(())
        }
        Engine::Postgres => {
            // Held until the session's end or the unlock below, by one process at a time.
            connection.execute_batch(&format!("SELECT pg_advisory_lock({MIGRATION_LOCK})"))?;
            let migrated = migrate_postgres(connection);
            if migrated.is_err() {
                // A failed step leaves its transaction open: the unlock waits for its end.
                let _ = connection.execute_batch("ROLLBACK");
            }
            let unlocked =
                connection.execute_batch(&format!("SELECT pg_advisory_unlock({MIGRATION_LOCK})"));
            migrated.and(unlocked)
        }
    }
}

/// Refuses a schema of a later release: this one would read and write its rows without
/// knowing what they mean (a release before graders had leases would grade beside the
/// graders, unleased).
fn known(version: i64) -> db::Result<()> {
    if version > MIGRATIONS.len() as i64 {
        return Err(db::Error::Schema(format!(
            "its schema is version {version}, of a later estlab release; this release knows versions up to {}: run the later release",
            MIGRATIONS.len()
        )));
    }
    Ok(())
}

/// The key of PostgreSQL's advisory lock that migrations take (EL2320, the course).
const MIGRATION_LOCK: i64 = 2320;

fn migrate_postgres(connection: &Connection) -> db::Result<()> {
    connection.execute_batch(POSTGRES_FUNCTIONS)?;
    connection.execute_batch(
        "CREATE TABLE IF NOT EXISTS estlab_schema (version BIGINT NOT NULL);
         INSERT INTO estlab_schema SELECT 0 WHERE NOT EXISTS (SELECT 1 FROM estlab_schema);",
    )?;
    let version: i64 =
        connection.query_row("SELECT version FROM estlab_schema", (), |row| row.get(0))?;
    known(version)?;
    for (i, step) in MIGRATIONS.iter().enumerate().skip(version as usize) {
        let sql = match step {
            Schema(sql) => postgres_ddl(sql),
            OldRows(_) => String::new(),
        };
        connection.execute_batch(&format!(
            "BEGIN; {sql}; UPDATE estlab_schema SET version = {}; COMMIT;",
            i + 1
        ))?;
    }
    Ok(())
}

/// What the store's queries call that SQLite has built in: `json_each(text)` over a JSON
/// array, giving each element as text in a column `value`. (PostgreSQL's own `json_each`
/// takes `json` or `jsonb`; a text argument picks this one.)
const POSTGRES_FUNCTIONS: &str = "CREATE OR REPLACE FUNCTION json_each(list text)
    RETURNS TABLE (value text) LANGUAGE sql IMMUTABLE
    AS $$ SELECT jsonb_array_elements_text(CAST(list AS jsonb)) $$;";

/// A definition in SQLite's words, in PostgreSQL's: 64-bit integers (SQLite's are), a
/// row id drawn from a sequence, double precision, text compared and sorted byte by byte
/// as SQLite does (the "C" collation, whatever the database's locale), and the moment now
/// as SQLite formats it (`2026-12-05T09:30:00.000Z`).
fn postgres_ddl(sql: &str) -> String {
    sql.replace(
        "id INTEGER PRIMARY KEY,",
        "id BIGINT GENERATED BY DEFAULT AS IDENTITY PRIMARY KEY,",
    )
    .replace(" INTEGER", " BIGINT")
    .replace(" REAL", " DOUBLE PRECISION")
    .replace(" TEXT", " TEXT COLLATE \"C\"")
    .replace(
        "strftime('%Y-%m-%dT%H:%M:%fZ', 'now')",
        "to_char(now() AT TIME ZONE 'UTC', 'YYYY-MM-DD\"T\"HH24:MI:SS.MS\"Z\"')",
    )
}
