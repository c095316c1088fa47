//! The `contphy-eval` binary: a sandbox worker when started as one, otherwise the command line.

use std::process::ExitCode;

use contphy_eval::sandbox::{self, HostRegistry, SceneHost};

fn main() -> ExitCode {
    // A sandbox worker process (started by `sandbox::Pool`) takes over before any CLI parsing.
    if std::env::args_os()
        .nth(1)
        .is_some_and(|argument| argument == sandbox::WORKER_ARGUMENT)
    {
        return sandbox::worker_main(|| {
            let mut registry = HostRegistry::with_builtin_hosts();
            SceneHost::register(&mut registry);
            registry
        });
    }
    contphy_eval::cli::main()
}
