//! `estlab grader`: a process that grades and does nothing else, beside web processes
//! (`estlab serve --no-grading`) and other graders sharing one database. It takes the
//! waiting submissions and regrades' items under a lease (`store::leases`), and stops at
//! Ctrl-C or SIGTERM; what it was grading is taken over by another grader (or by itself,
//! started again on the same machine).

use super::data::Data;
use super::grading;
use super::serve::{init_logging, stop_asked};
use crate::error::Error;
use crate::web::{self, connections};
use connections::{Limits, raise_descriptor_limit};
use std::net::SocketAddr;

/// Grade the submissions of a database that web processes share.
#[derive(clap::Args)]
pub struct Args {
    /// The data directory (the server's secret, the same on every machine) and the
    /// database.
    #[command(flatten)]
    data: Data,
    #[command(flatten)]
    grading: grading::Grading,
    /// Serve `/metrics` (the sandbox's lanes, CPU time, outcomes) on this address, for
    /// Prometheus: it asks for the token in the data directory's `metrics-token`.
    #[arg(long, value_name = "ADDR")]
    metrics: Option<SocketAddr>,
}

pub fn run(args: &Args) -> Result<(), Error> {
    init_logging();
    let runtime = tokio::runtime::Runtime::new().map_err(Error::io("the async runtime"))?;
    runtime.block_on(async {
        let store = args.data.open()?;
        let place = store.place().to_string();
        let grader = args.grading.grader(&args.data, store, false)?;
        let found = grader.resume()?;
        println!(
            "estlab grader {} is grading submissions in {place}, {} at once ({found} waiting)",
            grader.holder(),
            args.grading.parallel()
        );
        match args.metrics {
            Some(addr) => {
                let listener = tokio::net::TcpListener::bind(addr)
                    .await
                    .map_err(Error::io(addr.to_string()))?;
                let addr = listener.local_addr().map_err(Error::io(addr.to_string()))?;
                println!("estlab grader: metrics on http://{addr}/metrics");
                let limits = Limits::for_server(raise_descriptor_limit(), false);
                let router = web::metrics::router(grader);
                connections::serve(listener, router, limits, stop_asked()).await;
            }
            None => stop_asked().await,
        }
        Ok(())
    })
}
