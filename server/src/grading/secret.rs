//! The server's secret: 32 random bytes made at the first start and kept in the data
//! directory (readable by the server's user only), never in a response or a log. The
//! hidden cases of a submission are drawn from it and the submission's id, so a student
//! cannot know them in advance, every submission gets new ones, and grading the same
//! submission again draws the same ones.

use crate::store::Error;
use labs::Exercise;
use labs::grading::{Hidden, Plan, Reach};
use sha2::{Digest, Sha256};
use std::io::Write;
use std::os::unix::fs::OpenOptionsExt;
use std::path::Path;

/// The secret's file inside the data directory.
const FILE: &str = "secret";
const BYTES: usize = 32;

pub struct Secret([u8; BYTES]);

impl std::fmt::Debug for Secret {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Secret(..)")
    }
}

impl Secret {
    /// The secret in `dir`, made (and written with mode 0600) if there is none yet.
    pub fn load_or_create(dir: &Path) -> Result<Secret, Error> {
        let path = dir.join(FILE);
        match Secret::read(&path) {
            Err(Error::Secret { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => {
                let secret = Secret::random(&path)?;
                secret.write(&path)?;
                Ok(secret)
            }
            read => read,
        }
    }

    /// The secret kept in the file `path` (the data directory's `secret`, or a package's).
    pub fn read(path: &Path) -> Result<Secret, Error> {
        let bytes = std::fs::read(path).map_err(failed(path))?;
        let bytes: [u8; BYTES] = bytes.try_into().map_err(|bytes: Vec<u8>| {
            failed(path)(std::io::Error::other(format!(
                "holds {} bytes, not {BYTES}; remove it to make a new secret (hidden cases of earlier submissions then change at a regrade)",
                bytes.len()
            )))
        })?;
        Ok(Secret(bytes))
    }

    /// A new secret from the system's random source, for the file `path` (named in an
    /// error).
    pub fn random(path: &Path) -> Result<Secret, Error> {
        let mut bytes = [0; BYTES];
        getrandom::fill(&mut bytes)
            .map_err(|e| failed(path)(std::io::Error::other(e.to_string())))?;
        Ok(Secret(bytes))
    }

    /// Writes the secret to a new file `path`, readable by its owner only; an existing
    /// file is never replaced.
    pub fn write(&self, path: &Path) -> Result<(), Error> {
        let mut file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .mode(0o600)
            .open(path)
            .map_err(failed(path))?;
        file.write_all(&self.0).map_err(failed(path))?;
        file.sync_all().map_err(failed(path))
    }

    /// A fingerprint of the secret, which tells secrets apart without telling anything of
    /// them: the first 8 bytes of SHA-256 of a label and the secret, in hex.
    pub fn fingerprint(&self) -> String {
        hex(&self.labelled(b"fingerprint of an estlab secret ")[..8])
    }

    /// The token that `/metrics` asks for (as `Authorization: Bearer TOKEN`): SHA-256 of
    /// a label and the secret, in hex, so every process of one secret (web processes and
    /// graders on other machines) answers the same token, and the token tells nothing of
    /// the secret.
    pub fn metrics_token(&self) -> String {
        hex(&self.labelled(b"estlab metrics token "))
    }

    /// SHA-256 of `label` and the secret.
    fn labelled(&self, label: &[u8]) -> [u8; 32] {
        Sha256::new()
            .chain_update(label)
            .chain_update(self.0)
            .finalize()
            .into()
    }

    /// The secret's bytes, to put in a package.
    pub fn bytes(&self) -> &[u8; BYTES] {
        &self.0
    }

    /// What a grading of the submission `submission` made in the class `class` (a course,
    /// or a platform) draws from the secret: the submission's hidden cases, and the
    /// class's held-out run.
    pub fn hidden(&self, submission: i64, class: &str) -> Hidden {
        Hidden {
            cases: self.hidden_seed(submission),
            class: self.seed_of(&[b"held-out run of class ", class.as_bytes()]),
        }
    }

    /// The seed of the hidden cases of a submission: SHA-256 of the secret and the id,
    /// cut to a whole number below 2^53 like every seed.
    pub fn hidden_seed(&self, submission: i64) -> u64 {
        self.seed_of(&[b"hidden cases of submission ", &submission.to_le_bytes()])
    }

    /// SHA-256 of the secret and `parts`, cut to a whole number below 2^53.
    fn seed_of(&self, parts: &[&[u8]]) -> u64 {
        let digest = parts
            .iter()
            .fold(Sha256::new().chain_update(self.0), |hash, part| {
                hash.chain_update(part)
            })
            .finalize();
        let mut first = [0; 8];
        first.copy_from_slice(&digest[..8]);
        u64::from_le_bytes(first) & ((1 << 53) - 1)
    }
}

/// Bytes in hex.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// An error about the secret's file `path`.
fn failed(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Secret {
        path: path.to_owned(),
        source,
    }
}

/// The version of an exercise's grader: the release, a hash of the job of one plan of the
/// exercise (with the hidden cases the secret draws, if there is one) as far into its
/// data sets as students' JavaScript gets (`javascript`: on V8, the whole; on QuickJS,
/// the first readings), and that engine, so that it changes when the exercise's cases,
/// its runs, the secret or the engine change, and only then: a file correct for the
/// first readings that drifts later is graded otherwise on the two engines, and their
/// results never pass for one grader's.
pub fn grader_version(exercise: Exercise, secret: Option<&Secret>, javascript: Reach) -> String {
    let hidden = secret.map(|secret| secret.hidden(0, ""));
    let job = Plan::reaching(exercise, 1, hidden, javascript).job();
    let digest = Sha256::digest(serde_json::to_vec(&job).expect("jobs serialise"));
    let hash: String = digest[..6].iter().map(|b| format!("{b:02x}")).collect();
    let engine = match javascript {
        Reach::Whole => "V8",
        Reach::Prefix => "QuickJS",
    };
    format!(
        "estlab {} plan {hash}, JavaScript on {engine}",
        env!("CARGO_PKG_VERSION")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each exercise's grader has a version of its own, so that a change to one exercise
    /// leaves the others' results as graded by the same grader; another secret is another
    /// grader, and so is one whose students' JavaScript runs on the other engine.
    #[test]
    fn each_exercise_secret_and_engine_has_its_grader_version() {
        let (one, other) = (Secret([1; BYTES]), Secret([2; BYTES]));
        let version = |exercise, secret, reach| grader_version(exercise, secret, reach);
        let ekf = version(Exercise::EkfLocalization, Some(&one), Reach::Whole);
        assert_eq!(
            ekf,
            version(Exercise::EkfLocalization, Some(&one), Reach::Whole)
        );
        assert_ne!(ekf, version(Exercise::Odometry, Some(&one), Reach::Whole));
        assert_ne!(
            ekf,
            version(Exercise::EkfLocalization, Some(&other), Reach::Whole)
        );
        assert_ne!(ekf, version(Exercise::EkfLocalization, None, Reach::Whole));
        let quickjs = version(Exercise::EkfLocalization, Some(&one), Reach::Prefix);
        assert!(ekf.ends_with(", JavaScript on V8"), "{ekf}");
        assert!(quickjs.ends_with(", JavaScript on QuickJS"), "{quickjs}");
        // The runs go as far on both engines: the plan's hash agrees, the engine does not.
        let odometry = |reach| version(Exercise::Odometry, Some(&one), reach);
        assert_ne!(odometry(Reach::Whole), odometry(Reach::Prefix));
    }

    #[test]
    fn is_made_once_kept_private_and_gives_each_submission_its_own_seed() {
        let dir = tempfile::tempdir().unwrap();
        let first = Secret::load_or_create(dir.path()).unwrap();
        let again = Secret::load_or_create(dir.path()).unwrap();
        assert_eq!(first.0, again.0);
        let mode = std::fs::metadata(dir.path().join(FILE)).unwrap();
        assert_eq!(
            std::os::unix::fs::PermissionsExt::mode(&mode.permissions()) & 0o777,
            0o600
        );
        assert_eq!(first.hidden_seed(7), again.hidden_seed(7));
        assert_ne!(first.hidden_seed(7), first.hidden_seed(8));
        assert!(first.hidden_seed(7) < 1 << 53);
        assert_eq!(format!("{first:?}"), "Secret(..)");

        let other = tempfile::tempdir().unwrap();
        let other = Secret::load_or_create(other.path()).unwrap();
        assert_ne!(first.hidden_seed(7), other.hidden_seed(7));
        assert_eq!(first.fingerprint(), again.fingerprint());
        assert_ne!(first.fingerprint(), other.fingerprint());
        assert_eq!(first.fingerprint().len(), 16);
    }

    /// A class's held-out run is the same for every submission of the class, another for
    /// another class or secret; a submission's hidden cases are its own.
    #[test]
    fn a_class_shares_its_held_out_run_and_nothing_else() {
        let (one, other) = (Secret([1; BYTES]), Secret([2; BYTES]));
        let (a, b) = (one.hidden(7, "el2320"), one.hidden(8, "el2320"));
        assert_eq!(a.class, b.class);
        assert_ne!(a.cases, b.cases);
        assert_eq!(a.cases, one.hidden_seed(7));
        assert_ne!(a.class, one.hidden(7, "el2320-ht27").class);
        assert_ne!(a.class, other.hidden(7, "el2320").class);
        assert!(a.class < 1 << 53);
    }

    #[test]
    fn a_damaged_secret_is_refused_with_its_path() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join(FILE), b"short").unwrap();
        let error = Secret::load_or_create(dir.path()).unwrap_err().to_string();
        assert!(
            error.contains("secret") && error.contains("holds 5 bytes"),
            "{error}"
        );
    }
}
