//! `estlab backup`: a consistent copy of the database while the server runs.

use super::print;
use crate::error::Error;
use crate::store::Store;
use std::path::PathBuf;

/// Write a consistent copy of the database (SQLite's online backup), safe to take while
/// the server runs. Restore by stopping the server and putting the copy in the data
/// directory as estlab.sqlite3 (keep the directory's `secret` with it).
#[derive(clap::Args)]
pub struct Args {
    /// Where the copy goes; an existing file is not overwritten.
    file: PathBuf,
    /// The server's data directory.
    #[arg(long = "data", value_name = "DIR", default_value = "data")]
    data_dir: PathBuf,
}

pub fn run(args: &Args) -> Result<(), Error> {
    if args.file.exists() {
        return Err(Error::Invalid(format!(
            "{} exists already: name a new file for the backup",
            args.file.display()
        )));
    }
    let database = args.data_dir.join(crate::store::FILE);
    if !database.exists() {
        return Err(Error::Invalid(format!(
            "there is no database at {}: name the server's data directory with --data",
            database.display()
        )));
    }
    let store = Store::open(&args.data_dir)?;
    store.backup(&args.file)?;
    let submissions = Store::check_copy(&args.file)?;
    print(&format!(
        "estlab: backed up {} to {} ({submissions} submissions)",
        store.path().display(),
        args.file.display()
    ))
}
