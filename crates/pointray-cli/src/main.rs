//! `pointray`: point clouds rendered as smooth surfaces by ray tracing.

mod backend;
mod columns_arg;
mod commands;
mod environment;
mod patch_args;
mod point_arg;
mod prep_settings_args;
mod progress;
mod sample_parts;
mod scene_input;
mod setting_flag;
mod view_args;

use std::io::IsTerminal;

use clap::{Parser, Subcommand};

#[global_allocator]
static ALLOCATOR: pointray_io::HugePageAllocator = pointray_io::HugePageAllocator;

#[derive(Parser)]
#[command(name = "pointray", version, about = "Ray-traced point-set surfaces (Min & Kim's MLS patches)")]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Log more (repeat for more detail).
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    verbose: u8,
}

#[derive(Subcommand)]
enum Command {
    Sample(commands::sample::SampleArgs),
    Prep(commands::prep::PrepArgs),
    Info(commands::info::InfoArgs),
    Render(commands::render::RenderArgs),
    Devices(commands::devices::DevicesArgs),
    Fidelity(commands::fidelity::FidelityArgs),
    Consistency(commands::consistency::ConsistencyArgs),
    Bench(commands::bench::BenchArgs),
    View(commands::view::ViewArgs),
    Cache(commands::cache::CacheArgs),
    Scan(commands::scan::ScanArgs),
    Compare(commands::compare::CompareArgs),
}

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    init_logging(cli.verbose);
    end_quietly_on_a_closed_pipe();
    report_unwritable_output();
    remove_temporaries_on_interrupt();
    let result = match cli.command {
        Command::Sample(args) => commands::sample::run(args),
        Command::Prep(args) => commands::prep::run(args),
        Command::Info(args) => commands::info::run(args),
        Command::Render(args) => commands::render::run(args),
        Command::Devices(args) => commands::devices::run(args),
        Command::Fidelity(args) => commands::fidelity::run(args),
        Command::Consistency(args) => commands::consistency::run(args),
        Command::Bench(args) => commands::bench::run(args),
        Command::View(args) => commands::view::run(args),
        Command::Cache(args) => commands::cache::run(args),
        Command::Scan(args) => commands::scan::run(args),
        Command::Compare(args) => commands::compare::run(args),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {}", pointray_render::error_line(error.as_ref()));
            std::process::ExitCode::FAILURE
        }
    }
}

/// SIGINT, SIGTERM and SIGHUP end the process after removing the temporary file of any write
/// in progress; the destination is never partial either way. SIGKILL cannot be caught: the
/// next write into that folder removes what it left (`pointray_io::temporaries`).
fn remove_temporaries_on_interrupt() {
    let installed = ctrlc::set_handler(|| {
        pointray_io::temporaries::remove_live();
        std::process::exit(INTERRUPTED);
    });
    if let Err(error) = installed {
        tracing::warn!("cannot clean up on interrupt: {error}");
    }
}

/// Output piped into a program that stops reading (`pointray ... | head -1`) ends this one
/// as it ends other Unix tools, by SIGPIPE, instead of a panic in `println!`. Nothing is lost:
/// lines are printed only between writes, never while a temporary file is live.
fn end_quietly_on_a_closed_pipe() {
    // SAFETY: restores a signal's default action; no handler of ours is involved.
    unsafe { libc::signal(libc::SIGPIPE, libc::SIG_DFL) };
}

/// Output that cannot be written (`> /dev/full`, a full disk) makes `println!` panic; that
/// panic ends the process as any other error does, with one line and status 1, after removing
/// the temporary file of any write in progress. Every other panic is reported as before.
fn report_unwritable_output() {
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info.payload().downcast_ref::<String>().map(String::as_str).unwrap_or_default();
        let Some(problem) = message.strip_prefix("failed printing to stdout: ") else {
            return default_hook(info);
        };
        pointray_io::temporaries::remove_live();
        eprintln!("error: cannot write to stdout: {problem}");
        std::process::exit(1);
    }));
}

/// The exit status of a process ended by SIGINT, as shells report it.
const INTERRUPTED: i32 = 130;

fn init_logging(verbose: u8) {
    let level = match verbose {
        0 => tracing::Level::WARN,
        1 => tracing::Level::INFO,
        _ => tracing::Level::DEBUG,
    };
    // Colour codes only for a terminal: piped into a file or another program they are noise.
    let colour = std::io::stderr().is_terminal();
    tracing_subscriber::fmt().with_max_level(level).with_writer(std::io::stderr).with_ansi(colour).init();
}
