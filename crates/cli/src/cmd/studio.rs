//! `synthavision studio`: look into a model in a browser (see `sv_studio`).

use crate::error::{bad_input, runtime, CliError};
use clap::Args;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args, Debug)]
pub struct StudioArgs {
    /// Scene, deck, input or director's script (.svs); the bundled
    /// helicopter when none is given.
    pub file: Option<PathBuf>,
    /// Port on 127.0.0.1 (0 picks a free one).
    #[arg(long, default_value_t = 7171)]
    pub port: u16,
    /// Listen on this address instead of 127.0.0.1 (e.g. 0.0.0.0 to let
    /// other machines in: anyone with the address and token can then look
    /// at the model).
    #[arg(long, value_name = "ADDR")]
    pub listen: Option<IpAddr>,
    /// Folder for the pictures rendered to files from the page.
    #[arg(long, default_value = "studio-renders")]
    pub output: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Run `studio` until interrupted.
pub fn studio(args: StudioArgs) -> Result<ExitCode, CliError> {
    let ip = args.listen.unwrap_or(IpAddr::V4(Ipv4Addr::LOCALHOST));
    if !ip.is_loopback() {
        eprintln!(
            "warning: listening on {ip}, not only on this machine: whoever reaches it and has the token can see the model"
        );
    }
    if args.threads == Some(0) {
        return Err(bad_input("--threads must be at least 1"));
    }
    let options = sv_studio::Options {
        file: args.file,
        listen: SocketAddr::new(ip, args.port),
        output: args.output,
        threads: args.threads,
        poll_ms: 300,
    };
    let runtime_threads = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(runtime)?;
    runtime_threads.block_on(async {
        let studio = sv_studio::Studio::start(options)
            .await
            .map_err(|e| match e {
                sv_studio::StudioError::Load(_) => CliError::Input(e.to_string()),
                other => runtime(other),
            })?;
        println!("SynthaVision studio: {}", studio.url());
        println!("(open it in a browser; Ctrl-C stops)");
        std::future::pending::<()>().await;
        Ok(ExitCode::SUCCESS)
    })
}
