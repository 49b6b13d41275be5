//! `rollfric`: the command line ([`rollfric::cli`]).

fn main() -> std::process::ExitCode {
    rollfric::cli::main()
}
