//! Where a command finds the data: the data directory (the server's secret, and the
//! SQLite database unless another is named) or a PostgreSQL database that several estlab
//! processes share.

use crate::store::{self, Store};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Data {
    /// The data directory: the server's secret, and the SQLite database unless
    /// --database names another.
    #[arg(
        long = "data",
        value_name = "DIR",
        default_value = "data",
        global = true
    )]
    pub dir: PathBuf,
    /// A PostgreSQL database instead of the SQLite one, shared by every web and grader
    /// process: `postgres://USER:PASSWORD@HOST/NAME` or libpq's `host=... dbname=...`.
    /// Best given in ESTLAB_DATABASE, which keeps a password out of the process list.
    #[arg(
        long,
        value_name = "URL",
        env = "ESTLAB_DATABASE",
        hide_env_values = true,
        global = true
    )]
    pub database: Option<String>,
}

impl Data {
    /// Opens the database, migrating its schema forward as needed.
    pub fn open(&self) -> Result<Store, store::Error> {
        match &self.database {
            Some(url) => Store::connect(url),
            None => Store::open(&self.dir),
        }
    }
}
