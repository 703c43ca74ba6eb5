//! The command line: clap derive, one module per command group. Exit status (see
//! `crate::outcome`): bad flags or values exit 2 with clap's message (values checked
//! after parsing go through [`Failure::Usage`], printed the same way); a command that
//! fails or whose replay produced nothing usable exits 1 with `error: …`; a closed
//! output pipe (`stridekit demo | head -1`, `stridekit pace FILE --out - | head -1`)
//! ends the command quietly with 0.

mod calibrate;
mod demo;
mod eval;
pub(crate) mod foot;
mod odometry;
pub(crate) mod orientation;
pub(crate) mod pace;
pub(crate) mod pdr;
mod soak;
pub(crate) mod steps;
mod train;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{CommandFactory, Parser, Subcommand};

use crate::outcome::{Failure, EXIT_FAILED};

/// stridekit: running pace, orientation and pedestrian navigation from phone, watch
/// and foot-pod sensors.
///
/// Start with `stridekit demo` (a simulated run, a summary and a report with plots);
/// replay your own recordings with `pace`, `steps`, `foot`, `pdr`, `orientation` or
/// `odometry`; measure the engines on the shared data sets with `eval …`.
#[derive(Debug, Parser)]
#[command(
    name = "stridekit",
    version,
    arg_required_else_help = true,
    after_help = EXIT_CODES
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    Demo(demo::DemoArgs),
    Pace(pace::PaceArgs),
    Steps(steps::StepsArgs),
    Foot(foot::FootArgs),
    Pdr(pdr::PdrArgs),
    Orientation(orientation::OrientationArgs),
    Odometry(odometry::OdometryArgs),
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

/// The exit codes, as `--help` and the replays' help texts give them.
pub const EXIT_CODES: &str = "Exit status: 0 a usable result (warnings, e.g. a file cut \
off mid-write, may have been printed); 1 the input could not be read, or the replay \
produced nothing usable (every sample refused, a stream refused for its units, no \
step, stride or estimate); 2 a bad flag or value. A closed output pipe (`| head`) \
ends quietly with 0.";

/// Parse the command line and run it.
pub fn main() -> ExitCode {
    quiet_broken_pipe();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo(a) => demo::run(a).map_err(Failure::from),
        Command::Pace(a) => pace::run(a),
        Command::Steps(a) => steps::run(a),
        Command::Foot(a) => foot::run(a),
        Command::Pdr(a) => pdr::run(a),
        Command::Orientation(a) => orientation::run(a),
        Command::Odometry(a) => odometry::run(a),
        Command::Calibrate(c) => calibrate::run(c),
        Command::Eval(e) => eval::run(e),
        Command::Train(t) => train::run(t),
        Command::Soak(a) => soak::run(a).map_err(Failure::from),
    };
    match result {
        Ok(()) | Err(Failure::ClosedPipe) => ExitCode::SUCCESS,
        Err(Failure::Failed(e)) => {
            eprintln!("error: {e}");
            ExitCode::from(EXIT_FAILED)
        }
        Err(Failure::Usage(e)) => usage_exit(&e),
    }
}

/// A bad value found after parsing: clap's message and exit status (2).
fn usage_exit(message: &str) -> ! {
    Cli::command()
        .error(clap::error::ErrorKind::ValueValidation, message)
        .exit()
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

/// `NAME=VALUE` of `eval pace --set`: an `AdaptiveParams` name and a value the default
/// configuration accepts (checked by clap: exit 2).
fn pace_setting(s: &str) -> Result<(String, f64), String> {
    let (k, v) = name_value(s)?;
    let mut c = stridekit_core::PaceConfig::default();
    c.adaptive
        .set(&k, v)
        .and_then(|_| c.validate())
        .map_err(|e| e.to_string())?;
    Ok((k, v))
}

/// `NAME=VALUE` of `eval orientation --set`: a `DecoupledSettings` name and a value
/// the default filter accepts (checked by clap: exit 2).
fn orientation_setting(s: &str) -> Result<(String, f64), String> {
    let (k, v) = name_value(s)?;
    let mut settings = stridekit_core::AhrsSettings::default();
    stridekit_lab::orientation::eval::set_decoupled(&mut settings, &k, v)?;
    Ok((k, v))
}

/// A finite number above zero.
fn positive(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("{s} is not a number above 0")),
    }
}

/// A finite number, zero or above.
fn non_negative(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("{s} is not a number of 0 or above")),
    }
}

/// A count of 1 or more.
fn at_least_one(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(v) if v >= 1 => Ok(v),
        _ => Err(format!("{s} is not a whole number of 1 or more")),
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
            &["eval", "foot", "--diagnose", "--detector-gap"],
            &["eval", "bogus"],
            // Values checked by clap (exit 2), not later by the command (exit 1).
            &["foot", "f.csv", "--axes", "xyz"],
            &["foot", "f.csv", "--gyro-range", "-3"],
            &["foot", "f.csv", "--accel-range", "0"],
            &["foot", "f.csv", "--accel-range", "4"],
            &["calibrate", "foot", "f.csv", "--out", "x", "--axes", "xyz"],
            &["eval", "pace", "--set", "no_such_param=1"],
            &["eval", "orientation", "--set", "no_such_setting=1"],
            &["eval", "placement", "--drop", "no_such_feature"],
            &["eval", "placement", "--l2", "-1"],
            &["train", "zupt", "--split", "3/2"],
            &["train", "odometry", "--window", "0"],
            &["train", "odometry", "--lambda", "nan"],
            &["odometry", "sim:x:in_hand"],
            &["odometry", "sim:1:nowhere"],
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
