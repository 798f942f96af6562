//! A PostgreSQL server for the tests that run on it: Debian's own binaries, a cluster made
//! in a temporary folder at the first call of a test process, listening on a Unix socket
//! in that folder only (no port on the network), and a new empty database for each store
//! a test opens. The server runs as the `postgres` user when the tests run as root (it
//! refuses root), and stops when the test process ends: it is the child of a thread that
//! lives as long as the process, and is asked to stop (SIGINT, a fast shutdown) when its
//! parent goes. Folders of earlier runs whose process is gone are removed.
//!
//! The tests run on PostgreSQL when `ESTLAB_TEST_DATABASE=postgres` (`scripts/test` runs
//! the suites that matter a second time so); without PostgreSQL installed, that fails and
//! says so.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

/// The environment variable that puts the tests on PostgreSQL.
pub const ENGINE_VARIABLE: &str = "ESTLAB_TEST_DATABASE";

/// Whether this test run is on PostgreSQL (`ESTLAB_TEST_DATABASE=postgres`), rather than
/// the embedded SQLite.
pub fn wanted() -> bool {
    match std::env::var(ENGINE_VARIABLE).as_deref() {
        Ok("postgres") => true,
        Ok("sqlite") | Err(_) => false,
        Ok(other) => panic!("{ENGINE_VARIABLE}={other:?}: say postgres or sqlite"),
    }
}

/// The port the server's socket file is named for (no TCP port is opened).
const PORT: u16 = 5432;

/// How long the server may take to accept connections once started.
const START_BOUND: Duration = Duration::from_secs(120);

struct Cluster {
    /// Holds the data (`data/`), the socket and the server's log.
    dir: PathBuf,
}

/// The server, or why it did not start (said again to every test that asks).
static CLUSTER: OnceLock<Result<Cluster, String>> = OnceLock::new();
static DATABASES: AtomicU32 = AtomicU32::new(0);

/// The connection string of a new, empty database on this process's server, started at
/// the first call.
pub fn database() -> String {
    let cluster = CLUSTER
        .get_or_init(|| {
            std::panic::catch_unwind(Cluster::start).map_err(|panic| {
                panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default()
            })
        })
        .as_ref()
        .unwrap_or_else(|why| panic!("the test PostgreSQL server did not start: {why}"));
    let name = format!("t{}", DATABASES.fetch_add(1, Ordering::SeqCst));
    let admin = cluster.url("postgres");
    let create = format!("CREATE DATABASE {name}");
    // On a thread of its own: the client's runtime may not start inside a test's.
    std::thread::spawn(move || {
        postgres::Client::connect(&admin, postgres::NoTls)?.batch_execute(&create)
    })
    .join()
    .unwrap()
    .unwrap_or_else(|e| panic!("creating the test database {name}: {e}"));
    cluster.url(&name)
}

/// The directory of the server's binaries: `ESTLAB_POSTGRES_BIN`, or the newest of
/// Debian's `/usr/lib/postgresql/VERSION/bin`.
fn binaries() -> PathBuf {
    if let Some(dir) = std::env::var_os("ESTLAB_POSTGRES_BIN") {
        return PathBuf::from(dir);
    }
    let mut found: Vec<(u32, PathBuf)> = std::fs::read_dir("/usr/lib/postgresql")
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|entry| {
            let version = entry.file_name().to_str()?.parse().ok()?;
            let bin = entry.path().join("bin");
            bin.join("postgres").is_file().then_some((version, bin))
        })
        .collect();
    found.sort();
    found.pop().map(|(_, bin)| bin).unwrap_or_else(|| {
        panic!(
            "{ENGINE_VARIABLE}=postgres, but PostgreSQL is not installed: no /usr/lib/postgresql/*/bin/postgres \
             (apt-get install postgresql, as scripts/test does, or set ESTLAB_POSTGRES_BIN)"
        )
    })
}

/// The user and group the server runs as: the caller's own, or `postgres`'s for root.
fn server_user() -> Option<(u32, u32)> {
    // SAFETY: getuid has no preconditions.
    if unsafe { libc::getuid() } != 0 {
        return None;
    }
    let passwd = std::fs::read_to_string("/etc/passwd").expect("/etc/passwd is readable");
    let line = passwd
        .lines()
        .find(|line| line.starts_with("postgres:"))
        .unwrap_or_else(|| {
            panic!("the tests run as root, which PostgreSQL refuses, and there is no user postgres to run it as")
        });
    let fields: Vec<&str> = line.split(':').collect();
    Some((fields[2].parse().unwrap(), fields[3].parse().unwrap()))
}

impl Cluster {
    fn start() -> Cluster {
        let bin = binaries();
        remove_stale();
        let dir = std::env::temp_dir().join(format!("estlab-pg-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let user = server_user();
        if let Some((uid, gid)) = user {
            std::os::unix::fs::chown(&dir, Some(uid), Some(gid)).unwrap();
        }
        let data = dir.join("data");
        let mut initdb = Command::new(bin.join("initdb"));
        initdb
            .arg("-D")
            .arg(&data)
            .args([
                "-U",
                "estlab",
                "--auth=trust",
                "--no-locale",
                "-E",
                "UTF8",
                "--no-sync",
            ])
            .stdout(Stdio::null());
        as_user(&mut initdb, user);
        let made = initdb.output().expect("initdb runs");
        assert!(
            made.status.success(),
            "initdb failed: {}",
            String::from_utf8_lossy(&made.stderr)
        );
        let log = std::fs::File::create(dir.join("server.log")).unwrap();
        if let Some((uid, gid)) = user {
            std::os::unix::fs::chown(dir.join("server.log"), Some(uid), Some(gid)).unwrap();
        }
        let mut server = Command::new(bin.join("postgres"));
        server
            .arg("-D")
            .arg(&data)
            .arg("-k")
            .arg(&dir)
            .args(["-p", &PORT.to_string(), "-c", "listen_addresses="])
            // A test's data need not survive a crash of the machine.
            .args(["-c", "fsync=off", "-c", "synchronous_commit=off"])
            .args(["-c", "full_page_writes=off", "-c", "max_connections=200"])
            .stdout(Stdio::null())
            .stderr(log);
        as_user(&mut server, user);
        // SAFETY: prctl is async-signal-safe; it asks the kernel to send SIGINT to the
        // server when the thread that started it ends.
        unsafe {
            use std::os::unix::process::CommandExt;
            server.pre_exec(|| {
                if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGINT) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                Ok(())
            });
        }
        // Started by a thread that lives as long as the process: its end is the process's.
        let (started, spawned) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let child = server.spawn();
            let ok = child.is_ok();
            started.send(child.map(|_| ())).unwrap();
            if ok {
                loop {
                    std::thread::park();
                }
            }
        });
        spawned
            .recv()
            .unwrap()
            .unwrap_or_else(|e| panic!("PostgreSQL did not start: {e}"));
        let cluster = Cluster { dir };
        cluster.wait_until_ready();
        cluster
    }

    fn url(&self, database: &str) -> String {
        format!(
            "host={} port={PORT} user=estlab dbname={database}",
            self.dir.display()
        )
    }

    fn wait_until_ready(&self) {
        let give_up = Instant::now() + START_BOUND;
        loop {
            let url = self.url("postgres");
            let connected = std::thread::spawn(move || {
                postgres::Client::connect(&url, postgres::NoTls).map(drop)
            })
            .join()
            .unwrap();
            match connected {
                Ok(_) => return,
                Err(e) if Instant::now() > give_up => panic!(
                    "PostgreSQL did not accept connections within {START_BOUND:?}: {e}; its log: {}",
                    std::fs::read_to_string(self.dir.join("server.log")).unwrap_or_default()
                ),
                Err(_) => std::thread::sleep(Duration::from_millis(50)),
            }
        }
    }
}

fn as_user(command: &mut Command, user: Option<(u32, u32)>) {
    use std::os::unix::process::CommandExt;
    if let Some((uid, gid)) = user {
        command.uid(uid).gid(gid);
    }
}

/// Removes the folders of earlier test processes that are gone.
fn remove_stale() {
    let Ok(entries) = std::fs::read_dir(std::env::temp_dir()) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name
            .to_str()
            .and_then(|n| n.strip_prefix("estlab-pg-"))
            .and_then(|p| p.parse::<u32>().ok())
        else {
            continue;
        };
        if !Path::new(&format!("/proc/{pid}")).exists() {
            // A server its test process left running (killed before it could stop it)
            // stops first.
            let server = std::fs::read_to_string(entry.path().join("data/postmaster.pid"))
                .ok()
                .and_then(|text| text.lines().next()?.trim().parse::<i32>().ok());
            let postgres = |pid: i32| {
                std::fs::read(format!("/proc/{pid}/cmdline"))
                    .is_ok_and(|line| line.windows(8).any(|w| w == b"postgres"))
            };
            if let Some(server) = server.filter(|&pid| postgres(pid)) {
                // SAFETY: kill only sends a signal.
                unsafe {
                    libc::kill(server, libc::SIGQUIT);
                }
            }
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}
