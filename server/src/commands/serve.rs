//! `estlab serve`: the web application.

use super::data::Data;
use super::grading;
use crate::clock::{Clock, SystemClock};
use crate::datasets::Datasets;
use crate::error::Error;
use crate::web::connections::{self, Limits, raise_descriptor_limit};
use crate::web::{self, AppState, Assets};
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;

/// Serve the exercises, the experiments and the grader over HTTP.
#[derive(clap::Args)]
pub struct Args {
    /// Address and port to listen on; port 0 picks a free one.
    #[arg(long, default_value = "127.0.0.1:8080")]
    addr: SocketAddr,
    /// The built browser assets (scripts/build-web writes them to target/web/dist).
    #[arg(long = "static", value_name = "DIR", default_value = DEFAULT_STATIC_DIR)]
    static_dir: PathBuf,
    /// The data directory (created at start if missing) and the database.
    #[command(flatten)]
    data: Data,
    #[command(flatten)]
    grading: grading::Grading,
    /// Store submissions and leave their grading to `estlab grader` processes sharing the
    /// database (without this, the server grades too, beside any graders).
    #[arg(long)]
    no_grading: bool,
    /// The server is reached through a TLS reverse proxy: session cookies are marked
    /// Secure, and the client's address (for the sign-in limits) is the last one the
    /// proxy adds to X-Forwarded-For.
    #[arg(long)]
    behind_https: bool,
    /// The data directory's secret replaces, on purpose, the one the database's
    /// submissions were graded with (without this the server refuses to start with another
    /// secret): a regrade then draws other hidden cases.
    #[arg(long)]
    new_secret: bool,
    /// The address people reach the server at, for the sign-in links that `estlab
    /// course` prints (default: the address it listens on, with https:// when
    /// --behind-https).
    #[arg(long, value_name = "URL")]
    public_url: Option<String>,
    /// A folder of real data sets to offer on the pages (never shipped with estlab):
    /// `northstar/` with the Northstar report's trial files.
    #[arg(long, value_name = "DIR")]
    datasets: Option<PathBuf>,
}

/// Where `scripts/build-web` puts the assets, in the tree this binary was built from.
const DEFAULT_STATIC_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../target/web/dist");

pub fn run(args: &Args) -> Result<(), Error> {
    init_logging();
    return_large_blocks();
    let runtime = tokio::runtime::Runtime::new().map_err(Error::io("the async runtime"))?;
    runtime.block_on(serve(args))
}

async fn serve(args: &Args) -> Result<(), Error> {
    let assets = Assets::load(&args.static_dir)?;
    let datasets = match &args.datasets {
        Some(dir) => Datasets::load(dir)?,
        None => Datasets::default(),
    };
    let store = args.data.open()?;
    let store_place = store.place().to_string();
    let grader = args.grading.grader(&args.data, store, args.new_secret)?;
    let listener = tokio::net::TcpListener::bind(args.addr)
        .await
        .map_err(Error::io(args.addr.to_string()))?;
    let addr = listener
        .local_addr()
        .map_err(Error::io(args.addr.to_string()))?;
    let scheme = if args.behind_https { "https" } else { "http" };
    let public_url = args
        .public_url
        .clone()
        .unwrap_or_else(|| format!("{scheme}://{addr}"));
    grader.store().set_setting(
        crate::courses::setup::PUBLIC_URL,
        public_url.trim_end_matches('/'),
    )?;
    let clock: Arc<dyn Clock> = Arc::new(SystemClock);
    if args.no_grading {
        println!("estlab: grading is left to `estlab grader` processes");
    } else {
        let waiting = grader.resume()?;
        if waiting > 0 {
            println!("estlab: grading {waiting} submission(s) found waiting");
        }
    }
    let app = web::router(Arc::new(AppState {
        assets,
        grader,
        clock,
        behind_https: args.behind_https,
        datasets: Arc::new(datasets),
    }));
    println!(
        "estlab is serving on http://{addr}/ (submissions in {})",
        store_place
    );
    let limits = Limits::for_server(raise_descriptor_limit(), args.behind_https);
    connections::serve(listener, app, limits, stop_asked()).await;
    Ok(())
}

/// Every sign-in checks its code with Argon2id, which takes a 19 MiB block. glibc's
/// malloc serves blocks that large from mmap, but raises that threshold after the first
/// is freed, and then keeps such blocks in each thread's arena: 200 sign-ins left the
/// server holding 1.4 GB. A fixed threshold (glibc's default, 128 KiB) returns each block
/// to the system when it is freed. (musl's malloc, in the static build, returns such
/// blocks by itself.)
#[cfg(target_env = "gnu")]
fn return_large_blocks() {
    const THRESHOLD: libc::c_int = 128 * 1024;
    // SAFETY: mallopt only sets a parameter of the allocator; it is called before any
    // other thread starts.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, THRESHOLD);
    }
}

#[cfg(not(target_env = "gnu"))]
fn return_large_blocks() {}

/// Ctrl-C, or SIGTERM from a service manager: answer what is in flight, then stop.
/// Gradings cut off by the stop resume at the next start.
pub async fn stop_asked() {
    use tokio::signal::unix::{SignalKind, signal};
    match signal(SignalKind::terminate()) {
        Ok(mut terminate) => {
            tokio::select! {
                _ = tokio::signal::ctrl_c() => {}
                _ = terminate.recv() => {}
            }
        }
        Err(_) => {
            let _ = tokio::signal::ctrl_c().await;
        }
    }
}

/// Logs on stderr, one line per event, at the level `RUST_LOG` asks (default: info for
/// estlab and the requests it answers, warnings for the rest).
pub fn init_logging() {
    use tracing_subscriber::EnvFilter;
    let filter = EnvFilter::try_from_default_env()
        .unwrap_or_else(|_| EnvFilter::new("warn,estlab=info,tower_http=info"));
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .with_target(false)
        .init();
}
