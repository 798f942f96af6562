//! `estlab backup`: a consistent copy of the database while the server runs.

use super::data::Data;
use super::print;
use crate::error::Error;
use crate::store::Store;
use std::path::PathBuf;

/// Write a consistent copy of the SQLite database (SQLite's online backup), safe to take
/// while the server runs. Restore by stopping the server and putting the copy in the data
/// directory as estlab.sqlite3 (keep the directory's `secret` with it). A PostgreSQL
/// database is backed up with PostgreSQL's own pg_dump, which this names.
#[derive(clap::Args)]
pub struct Args {
    /// Where the copy goes; an existing file is not overwritten.
    file: PathBuf,
    #[command(flatten)]
    data: Data,
}

pub fn run(args: &Args) -> Result<(), Error> {
    if args.file.exists() {
        return Err(Error::Invalid(format!(
            "{} exists already: name a new file for the backup",
            args.file.display()
        )));
    }
    if args.data.database.is_some() {
        return Err(Error::Invalid(format!(
            "--database names a PostgreSQL database: back it up with PostgreSQL's pg_dump, \
             which copies it consistently while estlab runs: pg_dump --format=custom --file {} \
             --dbname \"$ESTLAB_DATABASE\" (restore with pg_restore into an empty database; keep \
             the data directory's secret with it)",
            args.file.display()
        )));
    }
    let database = args.data.dir.join(crate::store::FILE);
    if !database.exists() {
        return Err(Error::Invalid(format!(
            "there is no database at {}: name the server's data directory with --data",
            database.display()
        )));
    }
    let store = Store::open(&args.data.dir)?;
    store.backup(&args.file)?;
    let submissions = Store::check_copy(&args.file)?;
    print(&format!(
        "estlab: backed up {} to {} ({submissions} submissions)",
        store.place(),
        args.file.display()
    ))
}
