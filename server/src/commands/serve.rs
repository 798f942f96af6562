//! `estlab serve`: the web application.

use crate::error::Error;
use crate::sandbox::Sandbox;
use crate::submissions::{Grader, Secret, Store};
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
    /// Where the submissions database lives; created at start if missing.
    #[arg(long = "data", value_name = "DIR", default_value = "data")]
    data_dir: PathBuf,
    /// How many submissions are graded at once (each in a worker process of its own);
    /// at most one per core. The cores are shared out between them, so that no more
    /// engines run at once than there are cores.
    #[arg(long, default_value_t = default_parallel())]
    parallel: usize,
}

/// The cores this process may use.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}

/// Gradings at once: one per two cores, each with two engines side by side, which keeps
/// a lone grading quick.
fn default_parallel() -> usize {
    (cores() / 2).max(1)
}

/// Where `scripts/build-web` puts the assets, in the tree this binary was built from.
const DEFAULT_STATIC_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../target/web/dist");

pub fn run(args: &Args) -> Result<(), Error> {
    let runtime = tokio::runtime::Runtime::new().map_err(Error::io("the async runtime"))?;
    runtime.block_on(serve(args))
}

async fn serve(args: &Args) -> Result<(), Error> {
    let assets = Assets::load(&args.static_dir)?;
    let store = Store::open(&args.data_dir).map_err(web::Error::from)?;
    let secret = Secret::load_or_create(&args.data_dir).map_err(web::Error::from)?;
    let parallel = args.parallel.clamp(1, cores());
    let sandbox =
        Sandbox::current(cores() / parallel).map_err(Error::io("the estlab executable"))?;
    let grader = Grader::new(store, sandbox, secret, parallel);
    let resumed = grader.resume().map_err(web::Error::from)?;
    if resumed > 0 {
        println!(
            "estlab: resuming the grading of {resumed} submission(s) cut off by the last stop"
        );
    }
    let app = web::router(Arc::new(AppState { assets, grader }));
    let listener = tokio::net::TcpListener::bind(args.addr)
        .await
        .map_err(Error::io(args.addr.to_string()))?;
    let addr = listener
        .local_addr()
        .map_err(Error::io(args.addr.to_string()))?;
    println!(
        "estlab is serving on http://{addr}/ (submissions in {})",
        args.data_dir.display()
    );
    axum::serve(listener, app)
        .with_graceful_shutdown(async {
            let _ = tokio::signal::ctrl_c().await;
        })
        .await
        .map_err(Error::io(addr.to_string()))
}
