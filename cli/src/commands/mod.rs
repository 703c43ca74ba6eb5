//! The command line: clap derive, one module per command group. Bad flags or values
//! exit 2 with clap's message; a command that fails exits 1 with `error: …`; a closed
//! output pipe (`stridekit demo | head -1`) ends the command quietly.

mod calibrate;
mod demo;
mod eval;
mod replay;
mod soak;
mod train;

use std::path::PathBuf;
use std::process::ExitCode;

#[cfg(test)]
use clap::CommandFactory;
use clap::{Parser, Subcommand};

/// stridekit: running pace, orientation and pedestrian navigation from phone, watch
/// and foot-pod sensors.
///
/// Start with `stridekit demo` (a simulated run, a summary and a report with plots);
/// replay your own recordings with `pace`, `steps`, `foot`, `pdr`, `orientation` or
/// `odometry`; measure the engines on the shared data sets with `eval …`.
#[derive(Debug, Parser)]
#[command(name = "stridekit", version, arg_required_else_help = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    Demo(demo::DemoArgs),
    Pace(replay::PaceArgs),
    Steps(replay::StepsArgs),
    Foot(replay::FootArgs),
    Pdr(replay::PdrArgs),
    Orientation(replay::OrientationArgs),
    Odometry(replay::OdometryArgs),
    /// Learn a personal calibration from recordings.
    #[command(subcommand)]
    Calibrate(calibrate::Calibrate),
    /// Measure the engines on real recordings and the simulators.
    #[command(subcommand)]
    Eval(eval::Eval),
    /// Train the models the SDK ships.
    #[command(subcommand)]
    Train(train::Train),
    Soak(soak::SoakArgs),
}

/// Parse the command line and run it.
pub fn main() -> ExitCode {
    quiet_broken_pipe();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo(a) => demo::run(a),
        Command::Pace(a) => replay::pace(a),
        Command::Steps(a) => replay::steps(a),
        Command::Foot(a) => replay::foot(a),
        Command::Pdr(a) => replay::pdr(a),
        Command::Orientation(a) => replay::orientation(a),
        Command::Odometry(a) => replay::odometry(a),
        Command::Calibrate(c) => calibrate::run(c),
        Command::Eval(e) => eval::run(e),
        Command::Train(t) => train::run(t),
        Command::Soak(a) => soak::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The command line as typed (recorded in the model files the trainers write).
fn command_line() -> String {
    let args: Vec<String> = std::env::args().skip(1).collect();
    format!("stridekit {}", args.join(" "))
}

/// `explicit`, else `<shared data>/<sub>` when that folder exists.
fn data_dir(explicit: Option<PathBuf>, sub: &str, what: &str) -> Result<PathBuf, String> {
    let dir = match explicit {
        Some(d) => d,
        None => stridekit_formats::data_dir()
            .map(|d| d.join(sub))
            .ok_or_else(|| format!("{what} not found: pass --data DIR or set STRIDEKIT_DATA"))?,
    };
    if dir.is_dir() {
        Ok(dir)
    } else {
        Err(format!("{what} not found in {}", dir.display()))
    }
}

/// `NAME=NUMBER` for the `--set` flags.
fn name_value(s: &str) -> Result<(String, f64), String> {
    let (k, v) = s
        .split_once('=')
        .ok_or_else(|| format!("expected NAME=NUMBER, got {s}"))?;
    let v: f64 = v
        .parse()
        .map_err(|_| format!("expected NAME=NUMBER, {v} is not a number"))?;
    Ok((k.to_string(), v))
}

/// Writing to a closed pipe makes `println!` panic ("failed printing to stdout: Broken
/// pipe"): end the process quietly instead, as command-line tools do. Any other panic
/// keeps the default report.
fn quiet_broken_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let msg = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if msg.contains("Broken pipe") {
            std::process::exit(0);
        }
        default(info);
    }));
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::error::ErrorKind;

    fn parse(args: &[&str]) -> Result<Cli, clap::Error> {
        Cli::try_parse_from(std::iter::once("stridekit").chain(args.iter().copied()))
    }

    #[test]
    fn the_command_line_is_checked() {
        let Command::Soak(a) = parse(&["soak"]).unwrap().command else {
            panic!("soak");
        };
        assert_eq!((a.hours, a.seed), (24.0, 1));
        let Command::Soak(a) = parse(&["soak", "--hours", "0.5", "--seed", "7"])
            .unwrap()
            .command
        else {
            panic!("soak");
        };
        assert_eq!((a.hours, a.seed), (0.5, 7));
        for bad in [
            &["soak", "--hours", "-1"][..],
            &["soak", "--hours"],
            &["soak", "--bogus"],
            &["demo", "--oot", "x"],
            &["demo", "--seed", "abc"],
            &["demo", "extra"],
            &["pace", "run.fit", "--mode"],
            &["pace", "a.fit", "b.fit"],
            &["foot", "f.csv", "--lables", "vicon_opt"],
            &["eval", "pdr", "--sim", "--data", "d"],
            &["eval", "foot", "--tune", "--diagnose"],
            &["eval", "bogus"],
        ] {
            let e = parse(bad).expect_err(&bad.join(" "));
            assert_eq!(e.exit_code(), 2, "{}", bad.join(" "));
        }
        assert_eq!(
            parse(&[]).unwrap_err().kind(),
            ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
        );
        assert_eq!(
            parse(&["pace", "--help"]).unwrap_err().kind(),
            ErrorKind::DisplayHelp
        );
        assert_eq!(
            parse(&["--version"]).unwrap_err().kind(),
            ErrorKind::DisplayVersion
        );
        assert!(parse(&["eval", "pdr", "--seeds", "2"]).is_ok());
        Cli::command().debug_assert();
    }

    #[test]
    fn name_value_pairs() {
        assert_eq!(name_value("gain=0.5").unwrap(), ("gain".to_string(), 0.5));
        assert!(name_value("gain").is_err());
        assert!(name_value("gain=x").is_err());
    }
}
