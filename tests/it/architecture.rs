//! DESIGN.md §9: data flows one way through the modules. This test walks `src/<module>/` and
//! fails on any `crate::<other>` reference that points to a module at the same or a higher layer.

use std::path::Path;

/// The layers, lowest first. A module may name modules of strictly lower layers only.
const LAYERS: &[(&str, u32)] = &[
    ("util", 0),
    ("dataset", 1),
    ("physics", 1),
    ("perception", 1),
    ("synth", 2),
    ("prompt", 2),
    ("llm", 3),
    ("program", 4),
    ("scene_api", 5),
    ("scenarios", 6),
    ("sandbox", 7),
    ("answer", 8),
    ("score", 9),
    ("report", 10),
    ("app", 11),
    ("cli", 12),
];

fn layer(module: &str) -> Option<u32> {
    LAYERS
        .iter()
        .find(|(name, _)| *name == module)
        .map(|(_, layer)| *layer)
}

/// The module names referenced as `crate::name` or inside `crate::{a, b::c}`.
fn crate_references(source: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut rest = source;
    while let Some(at) = rest.find("crate::") {
        rest = &rest[at + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let end = group.find('}').unwrap_or(group.len());
            for item in group[..end].split(',') {
                let name: String = item
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if !name.is_empty() {
                    found.push(name);
                }
            }
        } else {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            found.push(name);
        }
    }
    found
}

fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in fs_err::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn modules_only_depend_on_lower_layers() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut violations = Vec::new();
    let mut checked = 0;
    for entry in fs_err::read_dir(&src).unwrap() {
        let dir = entry.unwrap().path();
        if !dir.is_dir() {
            continue;
        }
        let module = dir.file_name().unwrap().to_string_lossy().into_owned();
        let own =
            layer(&module).unwrap_or_else(|| panic!("module `{module}` is missing from LAYERS"));
        let mut files = Vec::new();
        rust_files(&dir, &mut files);
        for file in files {
            let source = fs_err::read_to_string(&file).unwrap();
            for name in crate_references(&source) {
                checked += 1;
                if name == module {
                    continue;
                }
                match layer(&name) {
                    Some(other) if other < own => {}
                    Some(_) => violations.push(format!(
                        "{}: `{module}` names `crate::{name}`",
                        file.display()
                    )),
                    None => violations.push(format!(
                        "{}: unknown module `crate::{name}`",
                        file.display()
                    )),
                }
            }
        }
    }
    assert!(
        checked > 20,
        "the walk found too few references ({checked}); is it looking in the right place?"
    );
    assert!(
        violations.is_empty(),
        "dependencies against the flow of DESIGN.md §9:\n{}",
        violations.join("\n")
    );
}

#[test]
fn reference_scanner_sees_grouped_and_plain_paths() {
    let source = "use crate::{dataset::Question, util};\nlet x = crate::score::score(a);";
    assert_eq!(crate_references(source), vec!["dataset", "util", "score"]);
}
