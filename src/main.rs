//! The `contphy-eval` binary: parses the command line and hands over to the library.

use contphy_eval::sandbox;

fn main() -> std::process::ExitCode {
    // A sandbox worker process (started by `sandbox::Pool`) takes over before any CLI parsing.
    if std::env::args_os()
        .nth(1)
        .is_some_and(|argument| argument == sandbox::WORKER_ARGUMENT)
    {
        return sandbox::worker_main(sandbox::HostRegistry::with_builtin_hosts);
    }
    std::process::ExitCode::SUCCESS
}
