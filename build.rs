//! Build steps: the git revision of the build (for run manifests), when built from a git
//! checkout; and the list of prompt files compiled into the binary (`prompts/**/*.jinja`,
//! `api_spec/scene_api.pyi`, `api_spec/VERSION`, `api_spec/examples/**/*.py`), so a new
//! template or example is embedded without editing code.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=.git/HEAD");
    println!("cargo:rerun-if-changed=.git/refs/heads");
    let revision = Command::new("git")
        .args(["rev-parse", "--short=12", "HEAD"])
        .output()
        .ok()
        .filter(|output| output.status.success())
        .and_then(|output| String::from_utf8(output.stdout).ok())
        .map(|text| text.trim().to_string())
        .filter(|text| !text.is_empty());
    if let Some(revision) = revision {
        println!("cargo:rustc-env=CONTPHY_GIT_REVISION={revision}");
    }
    embed_prompt_files();
}

/// Writes `$OUT_DIR/embedded_prompt_files.rs`: a `&[(path, text)]` expression of every prompt
/// file, sorted by path (relative to the repository root, `/`-separated).
fn embed_prompt_files() {
    let root = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let mut files = Vec::new();
    for dir in ["prompts", "api_spec"] {
        println!("cargo:rerun-if-changed={dir}");
        collect(&root, &root.join(dir), &mut files);
    }
    files.sort();
    let mut code = String::from("&[\n");
    for relative in files {
        let absolute = root.join(&relative);
        let _ = writeln!(
            code,
            "    ({relative:?}, include_str!({:?})),",
            absolute.display().to_string()
        );
    }
    code.push_str("]\n");
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets it"));
    #[expect(
        clippy::disallowed_methods,
        reason = "a build script has no fs-err; a failure here stops the build with the panic"
    )]
    std::fs::write(out.join("embedded_prompt_files.rs"), code).expect("OUT_DIR is writable");
}

/// Adds the prompt files under `dir` (recursively) to `files`, as paths relative to `root`:
/// the rule of `prompt::files::is_prompt_file` (a test checks the two agree).
fn collect(root: &Path, dir: &Path, files: &mut Vec<String>) {
    #[expect(
        clippy::disallowed_methods,
        reason = "a build script has no fs-err; a missing folder embeds nothing from it"
    )]
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            collect(root, &path, files);
            continue;
        }
        let relative = path
            .strip_prefix(root)
            .expect("walked from the root")
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect::<Vec<_>>()
            .join("/");
        let has_extension = |wanted: &str| {
            path.extension()
                .is_some_and(|found| found.eq_ignore_ascii_case(wanted))
        };
        let wanted = (relative.starts_with("prompts/") && has_extension("jinja"))
            || relative == "api_spec/scene_api.pyi"
            || relative == "api_spec/VERSION"
            || (relative.starts_with("api_spec/examples/") && has_extension("py"));
        if wanted {
            files.push(relative);
        }
    }
}
