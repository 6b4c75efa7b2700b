//! The `ihbm` command line: the [`ihbm::Cli`] builder with the built-in models.

fn main() -> std::process::ExitCode {
    ihbm::Cli::builtin().run()
}
