//! One connection to either engine the store runs on: an embedded SQLite file, or a
//! PostgreSQL server that several processes share. The store's queries are written once,
//! in the SQL both engines speak, with SQLite's numbered parameters (`?1`), which the
//! PostgreSQL side renames (`$1`); values cross as the four kinds SQLite stores (integer,
//! real, text, null), read and bound by what each column or parameter is on either side.

mod pg;

pub use pg::Postgres;

/// What a statement on either engine can fail with.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("{0}")]
    Sqlite(#[from] rusqlite::Error),
    #[error("{}", postgres_message(.0))]
    Postgres(#[from] postgres::Error),
    /// A statement that must give a row gave none.
    #[error("no row where one was expected")]
    NoRow,
    /// A column whose value is not what the query reads it as.
    #[error("column {column}: {reason}")]
    Column { column: usize, reason: String },
    /// A database this release cannot use as it is.
    #[error("{0}")]
    Schema(String),
}

pub type Result<T> = std::result::Result<T, Error>;

/// PostgreSQL's own message (the server's, where it sent one) with its code.
fn postgres_message(error: &postgres::Error) -> String {
    match error.as_db_error() {
        Some(db) => format!("{} ({})", db.message(), db.code().code()),
        None => error.to_string(),
    }
}

impl Error {
    /// Whether the statement lost a race with another process's transaction (PostgreSQL's
    /// serialization failure or deadlock) and may simply be tried again.
    pub fn is_retryable(&self) -> bool {
        use postgres::error::SqlState;
        matches!(self, Error::Postgres(e) if e.code() == Some(&SqlState::T_R_SERIALIZATION_FAILURE)
            || e.code() == Some(&SqlState::T_R_DEADLOCK_DETECTED))
    }
}

/// Maps a missing row to `None`, as rusqlite's extension of the same name does.
pub trait OptionalExtension<T> {
    fn optional(self) -> Result<Option<T>>;
}

impl<T> OptionalExtension<T> for Result<T> {
    fn optional(self) -> Result<Option<T>> {
        match self {
            Ok(value) => Ok(Some(value)),
            Err(Error::NoRow) => Ok(None),
            Err(e) => Err(e),
        }
    }
}

/// A value as both engines store it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value<'a> {
    Null,
    Integer(i64),
    Real(f64),
    Text(&'a str),
}

/// What can be bound to a statement's parameter.
pub trait Param {
    fn value(&self) -> Value<'_>;
}

macro_rules! integer_param {
    ($($t:ty),*) => {$(
        impl Param for $t {
            fn value(&self) -> Value<'_> {
                Value::Integer(i64::from(*self))
            }
        }
    )*};
}
integer_param!(i64, i32, u32, bool);

impl Param for usize {
    fn value(&self) -> Value<'_> {
        Value::Integer(i64::try_from(*self).expect("counts fit in 63 bits"))
    }
}

impl Param for f64 {
    fn value(&self) -> Value<'_> {
        Value::Real(*self)
    }
}

impl Param for str {
    fn value(&self) -> Value<'_> {
        Value::Text(self)
    }
}

impl Param for String {
    fn value(&self) -> Value<'_> {
        Value::Text(self)
    }
}

impl Param for Value<'_> {
    fn value(&self) -> Value<'_> {
        *self
    }
}

impl<T: Param + ?Sized> Param for &T {
    fn value(&self) -> Value<'_> {
        (**self).value()
    }
}

impl<T: Param> Param for Option<T> {
    fn value(&self) -> Value<'_> {
        self.as_ref().map_or(Value::Null, Param::value)
    }
}

/// A statement's parameters, in order: `params![a, b]`.
macro_rules! params {
    ($($p:expr),+ $(,)?) => {
        &[$(&$p as &dyn $crate::store::db::Param),+] as &[&dyn $crate::store::db::Param]
    };
}
pub(crate) use params;

/// A statement's parameters: `params![a, b]`, or an array of values of one type.
pub trait Params {
    fn values(&self) -> Vec<Value<'_>>;
}

impl Params for &[&dyn Param] {
    fn values(&self) -> Vec<Value<'_>> {
        self.iter().map(|p| p.value()).collect()
    }
}

/// No parameters.
impl Params for () {
    fn values(&self) -> Vec<Value<'_>> {
        Vec::new()
    }
}

impl<T: Param, const N: usize> Params for [T; N] {
    fn values(&self) -> Vec<Value<'_>> {
        self.iter().map(Param::value).collect()
    }
}

/// What a column can be read as.
pub trait Column: Sized {
    fn from_value(value: Value<'_>) -> std::result::Result<Self, String>;
}

impl Column for i64 {
    fn from_value(value: Value<'_>) -> std::result::Result<Self, String> {
        match value {
            Value::Integer(i) => Ok(i),
            other => Err(format!("{other:?} is not an integer")),
        }
    }
}

impl Column for u32 {
    fn from_value(value: Value<'_>) -> std::result::Result<Self, String> {
        let i = i64::from_value(value)?;
        u32::try_from(i).map_err(|_| format!("{i} is out of range"))
    }
}

impl Column for bool {
    fn from_value(value: Value<'_>) -> std::result::Result<Self, String> {
        i64::from_value(value).map(|i| i != 0)
    }
}

impl Column for f64 {
    fn from_value(value: Value<'_>) -> std::result::Result<Self, String> {
        match value {
            Value::Real(x) => Ok(x),
            Value::Integer(i) => Ok(i as f64),
            other => Err(format!("{other:?} is not a number")),
        }
    }
}

impl Column for String {
    fn from_value(value: Value<'_>) -> std::result::Result<Self, String> {
        match value {
            Value::Text(text) => Ok(text.to_owned()),
            other => Err(format!("{other:?} is not text")),
        }
    }
}

impl<T: Column> Column for Option<T> {
    fn from_value(value: Value<'_>) -> std::result::Result<Self, String> {
        match value {
            Value::Null => Ok(None),
            value => T::from_value(value).map(Some),
        }
    }
}

/// A row of a result, from either engine.
pub enum Row<'a> {
    Sqlite(&'a rusqlite::Row<'a>),
    Postgres(&'a postgres::Row),
}

impl Row<'_> {
    /// The value of a column (by its place, from 0) read as `T`.
    pub fn get<I: RowIndex, T: Column>(&self, index: I) -> Result<T> {
        let column = index.index();
        let failed = |reason: String| Error::Column { column, reason };
        match self {
            Row::Sqlite(row) => {
                use rusqlite::types::ValueRef;
                let value = match row.get_ref(column)? {
                    ValueRef::Null => Value::Null,
                    ValueRef::Integer(i) => Value::Integer(i),
                    ValueRef::Real(x) => Value::Real(x),
                    ValueRef::Text(bytes) => {
                        Value::Text(std::str::from_utf8(bytes).map_err(|e| failed(e.to_string()))?)
                    }
                    ValueRef::Blob(_) => return Err(failed("a blob".into())),
                };
                T::from_value(value).map_err(failed)
            }
            Row::Postgres(row) => {
                let value = pg::value(row, column).map_err(failed)?;
                T::from_value(value).map_err(failed)
            }
        }
    }
}

/// A column's place in a row.
pub trait RowIndex {
    fn index(&self) -> usize;
}

impl RowIndex for usize {
    fn index(&self) -> usize {
        *self
    }
}

impl rusqlite::ToSql for Value<'_> {
    fn to_sql(&self) -> rusqlite::Result<rusqlite::types::ToSqlOutput<'_>> {
        use rusqlite::types::{ToSqlOutput, ValueRef};
        Ok(ToSqlOutput::Borrowed(match *self {
            Value::Null => ValueRef::Null,
            Value::Integer(i) => ValueRef::Integer(i),
            Value::Real(x) => ValueRef::Real(x),
            Value::Text(text) => ValueRef::Text(text.as_bytes()),
        }))
    }
}

/// Which engine a connection speaks to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Engine {
    Sqlite,
    Postgres,
}

/// A connection to either engine. Statements take `&self` as rusqlite's do; PostgreSQL's
/// rows are read in full before any is handed out.
pub enum Connection {
    Sqlite(rusqlite::Connection),
    Postgres(Postgres),
}

impl Connection {
    pub fn engine(&self) -> Engine {
        match self {
            Connection::Sqlite(_) => Engine::Sqlite,
            Connection::Postgres(_) => Engine::Postgres,
        }
    }

    /// Runs a statement; returns how many rows it changed.
    pub fn execute(&self, sql: &str, params: impl Params) -> Result<usize> {
        match self {
            Connection::Sqlite(connection) => {
                let values = params.values();
                Ok(connection.execute(sql, rusqlite::params_from_iter(values))?)
            }
            Connection::Postgres(server) => {
                let count = server.execute(sql, &params.values())?;
                Ok(usize::try_from(count).unwrap_or(usize::MAX))
            }
        }
    }

    /// Runs several statements without parameters.
    pub fn execute_batch(&self, sql: &str) -> Result<()> {
        match self {
            Connection::Sqlite(connection) => Ok(connection.execute_batch(sql)?),
            Connection::Postgres(server) => Ok(server.batch_execute(sql)?),
        }
    }

    /// Every row of a query, each read by `read`.
    pub fn query_map<T>(
        &self,
        sql: &str,
        params: impl Params,
        mut read: impl FnMut(&Row) -> Result<T>,
    ) -> Result<Vec<T>> {
        let values = params.values();
        match self {
            Connection::Sqlite(connection) => {
                let mut statement = connection.prepare_cached(sql)?;
                let mut rows = statement.query(rusqlite::params_from_iter(values))?;
                let mut read_rows = Vec::new();
                while let Some(row) = rows.next()? {
                    read_rows.push(read(&Row::Sqlite(row))?);
                }
                Ok(read_rows)
            }
            Connection::Postgres(server) => {
                let rows = server.query(sql, &values)?;
                rows.iter().map(|row| read(&Row::Postgres(row))).collect()
            }
        }
    }

    /// The first row of a query read by `read`; `Error::NoRow` when there is none.
    pub fn query_row<T>(
        &self,
        sql: &str,
        params: impl Params,
        mut read: impl FnMut(&Row) -> Result<T>,
    ) -> Result<T> {
        let values = params.values();
        match self {
            Connection::Sqlite(connection) => {
                let mut statement = connection.prepare_cached(sql)?;
                let mut rows = statement.query(rusqlite::params_from_iter(values))?;
                match rows.next()? {
                    Some(row) => read(&Row::Sqlite(row)),
                    None => Err(Error::NoRow),
                }
            }
            Connection::Postgres(server) => match server.query(sql, &values)?.first() {
                Some(row) => read(&Row::Postgres(row)),
                None => Err(Error::NoRow),
            },
        }
    }

    /// Begins a transaction that takes the write lock at once on SQLite (so that two
    /// processes never deadlock upgrading a read), serializable on PostgreSQL; it is rolled
    /// back unless committed.
    pub fn transaction(&self) -> Result<Transaction<'_>> {
        self.execute_batch(match self {
            Connection::Sqlite(_) => "BEGIN IMMEDIATE",
            Connection::Postgres(_) => "BEGIN ISOLATION LEVEL SERIALIZABLE",
        })?;
        Ok(Transaction {
            connection: self,
            done: false,
        })
    }
}

/// A transaction under way: statements go through it, as through its connection.
pub struct Transaction<'c> {
    connection: &'c Connection,
    done: bool,
}

impl Transaction<'_> {
    pub fn commit(mut self) -> Result<()> {
        // A failed COMMIT leaves the transaction to be rolled back as it is dropped.
        self.connection.execute_batch("COMMIT")?;
        self.done = true;
        Ok(())
    }
}

impl std::ops::Deref for Transaction<'_> {
    type Target = Connection;
    fn deref(&self) -> &Connection {
        self.connection
    }
}

impl Drop for Transaction<'_> {
    fn drop(&mut self) {
        if !self.done {
            // A failed rollback leaves nothing to undo: the connection's next BEGIN fails
            // loudly rather than silently nesting.
            let _ = self.connection.execute_batch("ROLLBACK");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_read_back_as_written_on_sqlite() {
        let connection = Connection::Sqlite(rusqlite::Connection::open_in_memory().unwrap());
        connection
            .execute_batch("CREATE TABLE t (i INTEGER, x REAL, s TEXT, n INTEGER)")
            .unwrap();
        let none: Option<i64> = None;
        connection
            .execute(
                "INSERT INTO t VALUES (?1, ?2, ?3, ?4)",
                params![7_i64, 2.5, "é", none],
            )
            .unwrap();
        let row: (i64, f64, String, Option<i64>, bool) = connection
            .query_row("SELECT i, x, s, n, i > 3 FROM t", (), |row| {
                Ok((
                    row.get(0)?,
                    row.get(1)?,
                    row.get(2)?,
                    row.get(3)?,
                    row.get(4)?,
                ))
            })
            .unwrap();
        assert_eq!(row, (7, 2.5, "é".to_string(), None, true));
        let missing = connection
            .query_row("SELECT i FROM t WHERE i = ?1", params![8_i64], |row| {
                row.get::<_, i64>(0)
            })
            .optional()
            .unwrap();
        assert_eq!(missing, None);
        let wrong = connection.query_row("SELECT s FROM t", (), |row| row.get::<_, i64>(0));
        assert!(matches!(wrong, Err(Error::Column { column: 0, .. })));
    }
}
