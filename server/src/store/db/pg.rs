//! The PostgreSQL side of a connection. The `postgres` client runs a small async runtime of
//! its own, which must not be started from inside another (the web server's): so each
//! connection's client lives on a thread of its own, and statements cross to it with their
//! text and owned values, and come back as rows, which are read where they were asked for.
//! Each statement is prepared once per connection (the store's are a few dozen texts), so
//! that running it again is one round trip to the server, not two.

use super::Value;
use postgres::types::{IsNull, ToSql, Type};
use std::collections::HashMap;
use std::error::Error as StdError;
use std::sync::mpsc;

type Job = Box<dyn FnOnce(&mut Session) + Send>;

/// What the connection's thread holds: the client and the statements it prepared.
struct Session {
    client: postgres::Client,
    prepared: HashMap<String, postgres::Statement>,
}

impl Session {
    /// The statement of `sql`, prepared at its first use.
    fn statement(&mut self, sql: &str) -> Result<postgres::Statement, postgres::Error> {
        if let Some(statement) = self.prepared.get(sql) {
            return Ok(statement.clone());
        }
        let statement = self.client.prepare(sql)?;
        self.prepared.insert(sql.to_owned(), statement.clone());
        Ok(statement)
    }
}

/// A connection to a PostgreSQL server, held by a thread of its own.
pub struct Postgres {
    jobs: mpsc::Sender<Job>,
}

impl Postgres {
    /// Connects (on the connection's own thread) as `config` says.
    pub fn connect(config: postgres::Config) -> Result<Postgres, postgres::Error> {
        let (jobs, waiting) = mpsc::channel::<Job>();
        let (ready, connected) = mpsc::channel();
        std::thread::Builder::new()
            .name("estlab-postgres".into())
            .spawn(move || {
                let mut session = match config.connect(postgres::NoTls) {
                    Ok(client) => Session {
                        client,
                        prepared: HashMap::new(),
                    },
                    Err(e) => {
                        let _ = ready.send(Err(e));
                        return;
                    }
                };
                let _ = ready.send(Ok(()));
                // Ends when the connection is dropped (its sender with it).
                for job in waiting {
                    // A server that restarted (or closed an idle session) is connected to
                    // again, its statements prepared anew; if it is still away, the
                    // statement fails and says so.
                    if session.client.is_closed()
                        && let Ok(again) = config.connect(postgres::NoTls)
                    {
                        session = Session {
                            client: again,
                            prepared: HashMap::new(),
                        };
                    }
                    job(&mut session);
                }
            })
            .expect("a thread for the database connection starts");
        connected
            .recv()
            .expect("the connection's thread says how connecting went")?;
        Ok(Postgres { jobs })
    }

    /// Runs `job` on the connection's thread and waits for its answer.
    fn run<R: Send + 'static>(&self, job: impl FnOnce(&mut Session) -> R + Send + 'static) -> R {
        let (reply, answer) = mpsc::sync_channel(1);
        self.jobs
            .send(Box::new(move |session| {
                let _ = reply.send(job(session));
            }))
            .expect("the connection's thread lives as long as the connection");
        answer
            .recv()
            .expect("the connection's thread answers every statement")
    }

    pub fn execute(&self, sql: &str, params: &[Value]) -> Result<u64, postgres::Error> {
        let (sql, params) = (postgres_sql(sql), owned(params));
        self.run(move |session| {
            let statement = session.statement(&sql)?;
            session.client.execute(&statement, &bound(&params))
        })
    }

    pub fn query(
        &self,
        sql: &str,
        params: &[Value],
    ) -> Result<Vec<postgres::Row>, postgres::Error> {
        let (sql, params) = (postgres_sql(sql), owned(params));
        self.run(move |session| {
            let statement = session.statement(&sql)?;
            session.client.query(&statement, &bound(&params))
        })
    }

    pub fn batch_execute(&self, sql: &str) -> Result<(), postgres::Error> {
        let sql = sql.to_owned();
        self.run(move |session| session.client.batch_execute(&sql))
    }
}

/// A parameter's value, owned, to cross to the connection's thread.
#[derive(Debug)]
enum Owned {
    Null,
    Integer(i64),
    Real(f64),
    Text(String),
}

fn owned(params: &[Value]) -> Vec<Owned> {
    params
        .iter()
        .map(|value| match *value {
            Value::Null => Owned::Null,
            Value::Integer(i) => Owned::Integer(i),
            Value::Real(x) => Owned::Real(x),
            Value::Text(text) => Owned::Text(text.to_owned()),
        })
        .collect()
}

fn bound(params: &[Owned]) -> Vec<&(dyn ToSql + Sync)> {
    params.iter().map(|p| p as &(dyn ToSql + Sync)).collect()
}

impl ToSql for Owned {
    /// Binds by what the server takes the parameter to be, as SQLite would convert it.
    fn to_sql(
        &self,
        ty: &Type,
        out: &mut bytes::BytesMut,
    ) -> Result<IsNull, Box<dyn StdError + Sync + Send>> {
        match (self, ty) {
            (Owned::Null, _) => Ok(IsNull::Yes),
            (&Owned::Integer(i), &Type::INT8) => i.to_sql(ty, out),
            (&Owned::Integer(i), &Type::INT4) => i32::try_from(i)?.to_sql(ty, out),
            (&Owned::Integer(i), &Type::INT2) => i16::try_from(i)?.to_sql(ty, out),
            (&Owned::Integer(i), &Type::BOOL) => (i != 0).to_sql(ty, out),
            (&Owned::Integer(i), &Type::FLOAT8) => (i as f64).to_sql(ty, out),
            (&Owned::Real(x), &Type::FLOAT8) => x.to_sql(ty, out),
            (&Owned::Real(x), &Type::FLOAT4) => (x as f32).to_sql(ty, out),
            (Owned::Text(text), &Type::TEXT | &Type::VARCHAR | &Type::BPCHAR | &Type::NAME) => {
                text.to_sql(ty, out)
            }
            (value, ty) => Err(format!("{value:?} bound to a parameter of type {ty}").into()),
        }
    }

    fn accepts(_: &Type) -> bool {
        true
    }

    postgres::types::to_sql_checked!();
}

/// A column as one of the four kinds (booleans as 0 and 1).
pub fn value(row: &postgres::Row, column: usize) -> Result<Value<'_>, String> {
    let column_type = row
        .columns()
        .get(column)
        .ok_or_else(|| "no such column".to_string())?
        .type_()
        .clone();
    let value = match column_type {
        Type::BOOL => row
            .try_get::<_, Option<bool>>(column)
            .map(|b| b.map(|b| Value::Integer(b.into()))),
        Type::INT2 => row
            .try_get::<_, Option<i16>>(column)
            .map(|i| i.map(|i| Value::Integer(i.into()))),
        Type::INT4 => row
            .try_get::<_, Option<i32>>(column)
            .map(|i| i.map(|i| Value::Integer(i.into()))),
        Type::INT8 => row
            .try_get::<_, Option<i64>>(column)
            .map(|i| i.map(Value::Integer)),
        Type::FLOAT4 => row
            .try_get::<_, Option<f32>>(column)
            .map(|x| x.map(|x| Value::Real(x.into()))),
        Type::FLOAT8 => row
            .try_get::<_, Option<f64>>(column)
            .map(|x| x.map(Value::Real)),
        Type::TEXT | Type::VARCHAR | Type::BPCHAR | Type::NAME => row
            .try_get::<_, Option<&str>>(column)
            .map(|t| t.map(Value::Text)),
        other => return Err(format!("a value of PostgreSQL's type {other}")),
    };
    value
        .map(|v| v.unwrap_or(Value::Null))
        .map_err(|e| e.to_string())
}

/// A statement written with SQLite's numbered parameters (`?1`) in PostgreSQL's (`$1`);
/// quoted text and identifiers are left as they are.
fn postgres_sql(sql: &str) -> String {
    let mut out = String::with_capacity(sql.len());
    let mut quote: Option<char> = None;
    for c in sql.chars() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None if c == '\'' || c == '"' => quote = Some(c),
            None if c == '?' => {
                out.push('$');
                continue;
            }
            None => {}
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameters_are_renamed_outside_quotes() {
        assert_eq!(
            postgres_sql("SELECT '?1', \"a?\" FROM t WHERE a = ?1 AND b = ?12"),
            "SELECT '?1', \"a?\" FROM t WHERE a = $1 AND b = $12"
        );
    }
}
