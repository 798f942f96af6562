//! What `estlab serve` and `estlab grader` share to grade: how many at once, on which
//! engine, under which lease, and the grader they make (the secret checked against the
//! database's, each language's sandbox tried once and said).

use super::data::Data;
use crate::clock::{Clock, SystemClock};
use crate::error::Error;
use crate::grading::{Grader, Policy, Secret};
use crate::sandbox::{JavaScript, Sandbox, cores};
use crate::store::Store;
use labs::Language;
use std::io::Write;
use std::os::unix::fs::OpenOptionsExt;
use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

/// The file in the data directory that holds the token `/metrics` asks for.
pub const METRICS_TOKEN: &str = "metrics-token";

#[derive(clap::Args)]
pub struct Grading {
    /// How many submissions are graded at once (each in a worker process of its own);
    /// at most one per core. The cores are shared out between them, so that no more
    /// engines run at once than there are cores.
    #[arg(long, default_value_t = default_parallel())]
    pub parallel: usize,
    /// The engine of students' JavaScript: V8 in the operating system's sandbox, on the
    /// whole data sets (QuickJS where that sandbox does not start), or QuickJS always,
    /// on their first readings, as the platform packages grade.
    #[arg(long, value_enum, default_value_t)]
    pub javascript: JavaScript,
    /// How long a grading is leased to this process, renewed while it runs: where
    /// several processes grade from one database, the work of one that died is taken
    /// over by another after at most this.
    #[arg(long, value_name = "SECONDS", default_value_t = 30)]
    pub lease: u64,
}

/// Gradings at once: one per two cores, each with two engines side by side, which keeps
/// a lone grading quick.
pub fn default_parallel() -> usize {
    (cores() / 2).max(1)
}

impl Grading {
    /// Gradings at once, within the machine's cores.
    pub fn parallel(&self) -> usize {
        self.parallel.clamp(1, cores())
    }

    /// The grader over `store`, with the data directory's secret, which must be the one
    /// the database's submissions were graded with unless `new_secret` (a secret replaced
    /// on purpose).
    pub fn grader(
        &self,
        data: &Data,
        store: Store,
        new_secret: bool,
    ) -> Result<Arc<Grader>, Error> {
        let secret = Secret::load_or_create(&data.dir)?;
        if let Some(replaced) = store.check_secret(&secret.fingerprint(), new_secret)? {
            println!(
                "estlab: the secret (fingerprint {}) replaces the one of fingerprint {replaced}: regrade to grade on its hidden cases",
                secret.fingerprint()
            );
        }
        let parallel = self.parallel();
        let sandbox = Sandbox::current(cores() / parallel)
            .map_err(Error::io("the estlab executable"))?
            .with_javascript(self.javascript);
        // Each language's sandbox tried once, and said: a language that cannot be graded
        // here is refused at submission with a message that points to this log.
        match sandbox.v8() {
            Ok(()) => println!("estlab: JavaScript files are graded on V8, on whole data sets"),
            Err(why) => println!(
                "estlab: JavaScript files are graded on QuickJS, on the first readings of each data set: {why}"
            ),
        }
        for &language in Language::ALL {
            match sandbox.language(language) {
                Ok(()) => tracing::info!(%language, "students' files in this language are graded"),
                Err(unavailable) => {
                    println!(
                        "estlab: {} files cannot be graded here: {unavailable}",
                        language.title()
                    );
                    tracing::warn!(%language, %unavailable, "not graded here");
                }
            }
        }
        let policy = Policy {
            lease: Duration::from_secs(self.lease.max(1)),
            ..Policy::new(parallel)
        };
        write_metrics_token(&data.dir, &secret)?;
        let clock: Arc<dyn Clock> = Arc::new(SystemClock);
        Ok(Grader::with_policy(store, sandbox, secret, policy, clock))
    }
}

/// Writes the token `/metrics` asks for into the data directory's `metrics-token`
/// (readable by the server's user only), for Prometheus to send (its scrape's
/// `authorization: {credentials_file: ...}`).
fn write_metrics_token(dir: &Path, secret: &Secret) -> Result<(), Error> {
    let path = dir.join(METRICS_TOKEN);
    let token = secret.metrics_token();
    if std::fs::read_to_string(&path).ok().as_deref() != Some(token.as_str()) {
        let written = std::fs::OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(true)
            .mode(0o600)
            .open(&path)
            .and_then(|mut file| file.write_all(token.as_bytes()));
        written.map_err(Error::io(&path))?;
    }
    println!(
        "estlab: /metrics answers to the token in {}",
        path.display()
    );
    Ok(())
}
