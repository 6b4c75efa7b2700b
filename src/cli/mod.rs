//! The `ihbm` command line and the [`Cli`] builder that gives a
//! user crate the same command line for its own models.
//!
//! Exit status: 0 on success; 2 for bad input (unknown model or parameter, a value
//! that does not parse or is out of range, a malformed study file); 1 when the
//! computation itself failed (a solve that did not converge — its JSON is still
//! written — or a study with failed parts, whose finished parts are still written);
//! 130 when a study or sweep was interrupted (SIGINT or SIGTERM: what finished is
//! written, a study's `summary.md` names the parts that did not, a sweep's points so
//! far are its files; a second signal ends it at once).
//! Every failure prints one line `error: ...` on standard error.

mod args;
mod commands;

use crate::engine::registry::Registry;
use crate::model::Model;
use clap::Parser;
use std::ffi::OsString;
use std::io::Write;
use std::process::ExitCode;

/// Exit status for bad input.
pub const EXIT_USAGE: u8 = 2;
/// Exit status for a computation that failed (non-converged solve, failed study parts).
pub const EXIT_FAILED: u8 = 1;

/// Exit status of a study or sweep cut short by SIGINT or SIGTERM (128 + SIGINT, as shells
/// report a process the signal ended).
pub const EXIT_INTERRUPTED: u8 = 130;

/// A failure of one command: the one-line reason and the exit status.
#[derive(Debug)]
pub struct Failure {
    /// Exit status ([`EXIT_USAGE`] or [`EXIT_FAILED`]).
    pub code: u8,
    /// One line, without the `error: ` prefix.
    pub message: String,
}

impl Failure {
    fn usage(e: impl std::fmt::Display) -> Self {
        Failure { code: EXIT_USAGE, message: e.to_string() }
    }
    fn failed(e: impl std::fmt::Display) -> Self {
        Failure { code: EXIT_FAILED, message: e.to_string() }
    }
    /// Bad input for input errors, failure for the rest.
    fn from_error(e: crate::Error) -> Self {
        use crate::Error::*;
        match e {
            UnknownParameter { .. }
            | UnknownOutput { .. }
            | UnknownModel { .. }
            | InvalidValue { .. }
            | TooLarge { .. }
            | Study(_) => Failure::usage(e),
            _ => Failure::failed(e),
        }
    }
}

/// The command line with a set of registered models.
///
/// ```no_run
/// use ihbm::models::Duffing;
/// fn main() -> std::process::ExitCode {
///     ihbm::Cli::new().model::<Duffing>("my-duffing").run()
/// }
/// ```
#[derive(Default)]
pub struct Cli {
    registry: Registry,
}

impl Cli {
    /// A command line with no models.
    pub fn new() -> Self {
        Cli::default()
    }

    /// The `ihbm` binary's command line: every built-in model registered
    /// ([`crate::models::builtin`]).
    pub fn builtin() -> Self {
        Cli { registry: Registry::builtin() }
    }

    /// Register `M::default()` under its own [`Model::name`].
    pub fn own_name<M: Model + Default + Clone + 'static>(self) -> Self {
        let model = M::default();
        self.model::<M>(model.name())
    }

    /// Register `M::default()` under `name`.
    pub fn model<M: Model + Default + Clone + 'static>(mut self, name: &str) -> Self {
        self.registry.add::<M>(name);
        self
    }

    /// The registered models.
    pub fn registry(&self) -> &Registry {
        &self.registry
    }

    /// Parse `std::env::args()` and run the command.
    pub fn run(&self) -> ExitCode {
        self.run_from(std::env::args_os())
    }

    /// Run with explicit arguments (the first is the program name), writing to the
    /// process's standard output and error.
    pub fn run_from<I, T>(&self, args: I) -> ExitCode
    where
        I: IntoIterator<Item = T>,
        T: Into<OsString> + Clone,
    {
        let code =
            self.run_with(args, &mut std::io::stdout().lock(), &mut std::io::stderr().lock());
        ExitCode::from(code)
    }

    /// Run with explicit arguments and output streams; returns the exit status.
    /// For tests and embedding: nothing is printed elsewhere (progress bars are
    /// hidden when the process's streams are not terminals).
    pub fn run_with<I, T>(&self, args: I, out: &mut dyn Write, err: &mut dyn Write) -> u8
    where
        I: IntoIterator<Item = T>,
        T: Into<OsString> + Clone,
    {
        let args: Vec<OsString> = args.into_iter().map(Into::into).collect();
        let parsed = match args::Args::try_parse_from(&args) {
            Ok(a) => a,
            Err(e) => {
                use clap::error::ErrorKind;
                return match e.kind() {
                    ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
                        let _ = write!(out, "{}", e.render());
                        if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
                            let _ = writeln!(err, "error: no command given (see --help)");
                            EXIT_USAGE
                        } else {
                            0
                        }
                    }
                    _ => {
                        // clap's message may continue on indented lines (e.g. the
                        // missing arguments); keep it, drop the usage, make it one line.
                        let text = e.render().to_string();
                        let line = text
                            .lines()
                            .take_while(|l| !l.trim().is_empty() && !l.starts_with("Usage:"))
                            .map(str::trim)
                            .collect::<Vec<_>>()
                            .join(" ");
                        let _ = writeln!(err, "{line}{} (see --help)", hint(&e, &args));
                        EXIT_USAGE
                    }
                };
            }
        };
        // A write error of the last buffered line surfaces only at the flush: a full
        // disk must fail the command, not pass for success.
        let done = commands::execute(&self.registry, parsed.command, out).and_then(|()| {
            out.flush().map_err(|e| Failure::failed(format!("writing to standard output: {e}")))
        });
        match done {
            Ok(()) => 0,
            Err(f) => {
                let _ = writeln!(err, "error: {}", f.message.replace('\n', " "));
                f.code
            }
        }
    }
}

/// A hint for a parse error clap cannot explain: `--converge 1e-4` (its optional value
/// needs `=`, else a following model name would be taken for it).
fn hint(e: &clap::Error, args: &[OsString]) -> &'static str {
    use clap::error::{ContextKind, ContextValue};
    let Some(ContextValue::String(arg)) = e.get(ContextKind::InvalidArg) else {
        return "";
    };
    let after_converge =
        args.windows(2).any(|w| w[0] == "--converge" && w[1].to_str() == Some(arg.as_str()));
    if after_converge {
        "; write the tolerance as --converge=TOL"
    } else {
        ""
    }
}
