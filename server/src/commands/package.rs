//! `estlab package`: the grader packaged for Gradescope or PrairieLearn.

use super::VERSION;
use crate::error::Error;
use crate::grading::Secret;
use crate::platforms::{Settings, elf, gradescope, prairielearn};
use labs::Exercise;
use labs::grading::DEFAULT_COURSE;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// Package the grader for a platform: Gradescope's autograder zip, or PrairieLearn's
/// grader image and question folders.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    platform: Platform,
}

#[derive(clap::Subcommand)]
enum Platform {
    /// The zip to upload on Gradescope's "Configure Autograder" page.
    Gradescope {
        #[command(flatten)]
        common: Common,
        /// The zip to write (never replaced).
        #[arg(long)]
        out: PathBuf,
    },
    /// A folder with the grader image (`grader/`) and the question (`question/`).
    Prairielearn {
        #[command(flatten)]
        common: Common,
        /// The folder to write (must not exist yet).
        #[arg(long)]
        out: PathBuf,
        /// The grader image's name, as you will build and push it (default:
        /// estlab/grader-<the exercise's name>).
        #[arg(long)]
        image: Option<String>,
        /// The address of an estlab site where students can run the tests in their
        /// browser, linked from the question (e.g. https://estlab.example.org).
        #[arg(long, value_parser = site_address)]
        workbench: Option<String>,
    },
}

#[derive(clap::Args)]
struct Common {
    /// The exercise.
    #[arg(long, value_parser = Exercise::from_str, default_value_t = Exercise::default())]
    lab: Exercise,
    /// The course whose variants students get (a Gradescope student's variant is their
    /// e-mail address within it, as the workbench computes it).
    #[arg(long, default_value = DEFAULT_COURSE)]
    course: String,
    /// A secret file to draw the hidden cases from (e.g. a server's DATA/secret, or an
    /// earlier package's, to keep the hidden cases of earlier submissions at a regrade);
    /// without one the package gets a new secret.
    #[arg(long)]
    secret: Option<PathBuf>,
    /// The statically linked estlab to put in the package (scripts/build-static makes
    /// it); without one, this estlab if it is static, or the static build beside it.
    #[arg(long)]
    binary: Option<PathBuf>,
}

pub fn run(args: &Args) -> Result<(), Error> {
    match &args.platform {
        Platform::Gradescope { common, out } => {
            let (binary, settings, secret) = common.contents(out)?;
            let zip = gradescope::package(&binary, &settings, &secret)?;
            write_new(out, &zip)?;
            println!(
                "Wrote {} ({:.1} MB): upload it on the assignment's \"Configure Autograder\" page (Ubuntu base image, any version).",
                out.display(),
                zip.len() as f64 / 1e6
            );
        }
        Platform::Prairielearn {
            common,
            out,
            image,
            workbench,
        } => {
            let (binary, settings, secret) = common.contents(&out.join("question/tests/secret"))?;
            let image = image
                .clone()
                .unwrap_or_else(|| format!("estlab/grader-{}", common.lab));
            let image = image.as_str();
            prairielearn::package(
                out,
                &prairielearn::Package {
                    binary: &binary,
                    settings: &settings,
                    secret: &secret,
                    image,
                    uuid: uuid()?,
                    starter: common.lab.declaration().starters.javascript,
                    workbench: workbench.as_deref(),
                },
            )?;
            println!(
                "Wrote {}: build the image with `docker build -t {image} {}`, push it, and copy {} into your course's questions/ (see {}).",
                out.display(),
                out.join("grader").display(),
                out.join("question").display(),
                out.join("README.md").display()
            );
        }
    }
    Ok(())
}

impl Common {
    /// The binary, the settings and the secret's bytes; `secret_path` names the secret in
    /// errors when a new one is made.
    fn contents(&self, secret_path: &Path) -> Result<(Vec<u8>, Settings, Vec<u8>), Error> {
        let (path, binary) = static_binary(self.binary.as_deref())?;
        println!("Packaging {} (estlab {VERSION}).", path.display());
        let secret = match &self.secret {
            Some(path) => Secret::read(path)?,
            None => Secret::random(secret_path)?,
        };
        let settings = Settings {
            lab: self.lab,
            course: self.course.clone(),
        };
        Ok((binary, settings, secret.bytes().to_vec()))
    }
}

/// The statically linked estlab to package and its bytes: `given`, or this estlab if it
/// is static, or the static build beside this one's target folder. It must be built from
/// the same sources as this estlab (`estlab --version` says which), so that a package
/// never carries an older grader than the one that made it.
fn static_binary(given: Option<&Path>) -> Result<(PathBuf, Vec<u8>), Error> {
    let this = std::env::current_exe().map_err(Error::io("the estlab executable"))?;
    let path = match given {
        Some(path) => path.to_owned(),
        None => {
            let beside = this
                .parent()
                .and_then(Path::parent)
                .map(|target| target.join("x86_64-unknown-linux-musl/release/estlab"));
            let static_one = std::iter::once(this.clone()).chain(beside).find(|path| {
                std::fs::read(path).is_ok_and(|bytes| elf::is_static(&bytes) == Ok(true))
            });
            static_one.ok_or_else(|| {
                Error::Invalid(
                    "this estlab is dynamically linked and there is no static build beside it: build one with scripts/build-static (or pass --binary)".to_owned(),
                )
            })?
        }
    };
    let bytes = std::fs::read(&path).map_err(Error::io(&path))?;
    match elf::is_static(&bytes) {
        Ok(true) => {}
        Ok(false) => {
            return Err(Error::Invalid(format!(
                "{} is dynamically linked: it would need the platform's C library to be like this machine's. Build the static estlab with scripts/build-static.",
                path.display()
            )));
        }
        Err(problem) => return Err(Error::Invalid(format!("{}: {problem}", path.display()))),
    }
    let said = std::process::Command::new(&path)
        .arg("--version")
        .output()
        .map_err(Error::io(&path))?;
    let theirs = String::from_utf8_lossy(&said.stdout).trim().to_owned();
    let ours = format!("estlab {VERSION}");
    if theirs != ours {
        return Err(Error::Invalid(format!(
            "{} is {theirs:?}, not this {ours:?}: it was built from other sources. Rebuild it with scripts/build-static (or package with the estlab it is).",
            path.display()
        )));
    }
    Ok((path, bytes))
}

/// An http(s) address without a path's end slash, safe to write into an HTML attribute.
fn site_address(text: &str) -> Result<String, String> {
    let address = text.trim().trim_end_matches('/');
    let rest = address
        .strip_prefix("https://")
        .or_else(|| address.strip_prefix("http://"))
        .ok_or("an address starting with https:// (or http://)")?;
    if rest.is_empty()
        || rest
            .chars()
            .any(|c| c.is_whitespace() || c.is_control() || "\"'<>`\\".contains(c))
    {
        return Err("an address of a site, without quotes, spaces or angle brackets".into());
    }
    Ok(address.to_owned())
}

/// A random (version 4) UUID, as PrairieLearn wants one per question.
fn uuid() -> Result<String, Error> {
    let mut bytes = [0u8; 16];
    getrandom::fill(&mut bytes).map_err(|e| Error::Invalid(e.to_string()))?;
    bytes[6] = (bytes[6] & 0x0f) | 0x40;
    bytes[8] = (bytes[8] & 0x3f) | 0x80;
    let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
    Ok(format!(
        "{}-{}-{}-{}-{}",
        &hex[..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..]
    ))
}

/// Writes `bytes` to a new file: an existing file is never replaced.
fn write_new(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    use std::io::Write;
    let mut file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)
        .map_err(Error::io(path))?;
    file.write_all(bytes).map_err(Error::io(path))
}
