//! `docs/architecture.md`, layers: data flows one way through the modules. This test walks
//! `src/<module>/` and fails on any `crate::<other>` reference that points to a module at the same
//! or a higher layer.

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
        "dependencies against the flow of `docs/architecture.md`, layers:\n{}",
        violations.join("\n")
    );
}

#[test]
fn reference_scanner_sees_grouped_and_plain_paths() {
    let source = "use crate::{dataset::Question, util};\nlet x = crate::score::score(a);";
    assert_eq!(crate_references(source), vec!["dataset", "util", "score"]);
}

// ---------------------------------------------------------------------------------------------
// Scenario seam and code shape (issue 11).

/// The benchmark's scenarios by name, their release folder names, and object words only one
/// scenario has: shared code names none of them.
const SCENARIO_WORDS: &[&str] = &[
    "rope",
    "fluid",
    "cloth",
    "ball",
    "pulley",
    "pulley_group",
    "fluid_slides",
    "cloth_collision",
    "soft_body",
];

/// Scenario folders: a path component with one of these names is scenario code.
const SCENARIO_FOLDERS: &[&str] = &["rope", "fluid", "cloth", "ball"];

/// Shared files that map scenarios to their parts: the scenario list itself and the scenario
/// table.
const SCENARIO_MAPS: &[&str] = &["dataset/scenario.rs", "scenarios/mod.rs"];

/// A source file reduced to its code: comments and the contents of string and character
/// literals blanked (string contents are kept apart, per line), `#[cfg(test)]` items removed.
struct Code {
    /// Code lines (literals replaced by `""` / `' '`).
    lines: Vec<String>,
    /// String literal contents, by line.
    strings: Vec<Vec<String>>,
}

/// Splits `source` into code and string literal contents, line by line.
fn lex(source: &str) -> Code {
    let mut lines = vec![String::new()];
    let mut strings: Vec<Vec<String>> = vec![Vec::new()];
    let chars: Vec<char> = source.chars().collect();
    let mut i = 0;
    let newline = |lines: &mut Vec<String>, strings: &mut Vec<Vec<String>>| {
        lines.push(String::new());
        strings.push(Vec::new());
    };
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
            continue;
        }
        if c == '/' && next == Some('*') {
            i += 2;
            while i + 1 < chars.len() && !(chars[i] == '*' && chars[i + 1] == '/') {
                if chars[i] == '\n' {
                    newline(&mut lines, &mut strings);
                }
                i += 1;
            }
            i += 2;
            continue;
        }
        // Raw strings r"…", r#"…"#, and byte strings b"…".
        let raw_hashes = if c == 'r' && matches!(next, Some('"' | '#')) {
            let mut j = i + 1;
            let mut hashes = 0;
            while chars.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            (chars.get(j) == Some(&'"')).then_some((hashes, j))
        } else {
            None
        };
        let previous_is_ident = i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_');
        if let (Some((hashes, quote)), false) = (raw_hashes, previous_is_ident) {
            let mut j = quote + 1;
            let mut text = String::new();
            loop {
                if j >= chars.len() {
                    break;
                }
                if chars[j] == '"' && (1..=hashes).all(|k| chars.get(j + k) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                if chars[j] == '\n' {
                    strings.last_mut().unwrap().push(std::mem::take(&mut text));
                    newline(&mut lines, &mut strings);
                } else {
                    text.push(chars[j]);
                }
                j += 1;
            }
            strings.last_mut().unwrap().push(text);
            lines.last_mut().unwrap().push_str("\"\"");
            i = j;
            continue;
        }
        if c == '"' {
            let mut j = i + 1;
            let mut text = String::new();
            while j < chars.len() && chars[j] != '"' {
                if chars[j] == '\\' {
                    text.push(' ');
                    j += 2;
                    continue;
                }
                if chars[j] == '\n' {
                    strings.last_mut().unwrap().push(std::mem::take(&mut text));
                    newline(&mut lines, &mut strings);
                } else {
                    text.push(chars[j]);
                }
                j += 1;
            }
            strings.last_mut().unwrap().push(text);
            lines.last_mut().unwrap().push_str("\"\"");
            i = j + 1;
            continue;
        }
        // Character literals ('{', '\n', '\''); lifetimes ('a) are left alone.
        if c == '\'' {
            let close = if next == Some('\\') {
                (i + 3..(i + 12).min(chars.len())).find(|&j| chars[j] == '\'')
            } else {
                (chars.get(i + 2) == Some(&'\'')).then_some(i + 2)
            };
            if let Some(close) = close {
                lines.last_mut().unwrap().push_str("' '");
                i = close + 1;
                continue;
            }
        }
        if c == '\n' {
            newline(&mut lines, &mut strings);
        } else {
            lines.last_mut().unwrap().push(c);
        }
        i += 1;
    }
    if source.ends_with('\n') {
        lines.pop();
        strings.pop();
    }
    drop_test_items(&Code { lines, strings })
}

/// `{` minus `}` on a line of code.
fn brace_balance(line: &str) -> i64 {
    let count = |brace: char| i64::try_from(line.matches(brace).count()).unwrap_or(i64::MAX);
    count('{') - count('}')
}

/// Removes `#[cfg(test)]` items (a module or function with its attributes).
fn drop_test_items(code: &Code) -> Code {
    let mut kept = Code {
        lines: Vec::new(),
        strings: Vec::new(),
    };
    let mut index = 0;
    while index < code.lines.len() {
        if code.lines[index].trim_start().starts_with("#[cfg(test)]") {
            // Skip to the item and past its braces (or its `;`).
            let mut depth = 0_i64;
            let mut opened = false;
            while index < code.lines.len() {
                let line = &code.lines[index];
                depth += brace_balance(line);
                opened |= line.contains('{');
                index += 1;
                if (opened && depth <= 0) || (!opened && line.trim_end().ends_with(';')) {
                    break;
                }
            }
            continue;
        }
        kept.lines.push(code.lines[index].clone());
        kept.strings.push(code.strings[index].clone());
        index += 1;
    }
    kept
}

/// Lower-case words of an identifier or text: split at non-alphanumerics and camel case, with
/// the whole snake-case identifier too (`pulley_group`).
fn words(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for token in text.split(|c: char| !(c.is_alphanumeric() || c == '_')) {
        if token.is_empty() {
            continue;
        }
        out.push(token.to_lowercase());
        let mut word = String::new();
        for c in token.chars() {
            if c == '_' || (c.is_uppercase() && !word.is_empty()) {
                if !word.is_empty() {
                    out.push(std::mem::take(&mut word).to_lowercase());
                }
                if c == '_' {
                    continue;
                }
            }
            word.push(c);
        }
        if !word.is_empty() {
            out.push(word.to_lowercase());
        }
    }
    out
}

/// Every `.rs` file of `src/` with its path relative to `src/`, test files left out.
fn source_files() -> Vec<(String, String)> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    files
        .into_iter()
        .filter(|path| path.file_name().is_none_or(|name| name != "tests.rs"))
        .map(|path| {
            let relative = path
                .strip_prefix(&src)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            (relative, fs_err::read_to_string(&path).unwrap())
        })
        .collect()
}

fn is_scenario_code(relative: &str) -> bool {
    SCENARIO_MAPS.contains(&relative)
        || relative
            .trim_end_matches(".rs")
            .split('/')
            .any(|part| SCENARIO_FOLDERS.contains(&part))
}

/// Where shared code names a scenario: `(file:line, word)`.
fn scenario_names_in_shared_code() -> Vec<String> {
    let mut found = Vec::new();
    for (relative, source) in source_files() {
        if is_scenario_code(&relative) {
            continue;
        }
        let code = lex(&source);
        for (number, (line, strings)) in code.lines.iter().zip(&code.strings).enumerate() {
            let declaration = line.trim().trim_start_matches("pub ").starts_with("mod ")
                && line.trim().ends_with(';');
            if declaration {
                continue;
            }
            let texts = std::iter::once(line.as_str()).chain(strings.iter().map(String::as_str));
            let mut named: Vec<String> = texts
                .flat_map(words)
                .filter(|word| SCENARIO_WORDS.contains(&word.as_str()))
                .collect();
            named.dedup();
            for word in named {
                found.push(format!("src/{relative}:{} names `{word}`", number + 1));
            }
        }
    }
    found
}

#[test]
fn shared_code_names_no_scenario() {
    let found = scenario_names_in_shared_code();
    assert!(
        found.is_empty(),
        "shared code must reach a scenario's parts through the scenario table (src/scenarios/), not by name:\n{}",
        found.join("\n")
    );
}

#[test]
fn the_scenario_check_sees_names_in_code_and_strings_but_not_in_comments_or_tests() {
    let source = "// a rope comment\nuse crate::dataset::rope::world;\nlet folder = \"pulley_group\";\nstruct PulleyCount;\n#[cfg(test)]\nmod tests {\n    fn rope() {}\n}\npub mod ball;\n";
    let code = lex(source);
    let named: Vec<String> = code
        .lines
        .iter()
        .zip(&code.strings)
        .flat_map(|(line, strings)| {
            let mut all = words(line);
            for text in strings {
                all.extend(words(text));
            }
            all
        })
        .filter(|w| SCENARIO_WORDS.contains(&w.as_str()))
        .collect();
    assert_eq!(
        named,
        vec![
            "rope",
            "rope",
            "pulley_group",
            "pulley",
            "pulley",
            "ball",
            "ball"
        ]
    );
    assert!(is_scenario_code("scene_api/rope/mod.rs"));
    assert!(is_scenario_code("program/builtin/rope.rs"));
    assert!(!is_scenario_code("scene_api/scene.rs"));
}

/// Public functions whose error type is a bare `String`, and `FromStr` impls with `Err = String`.
fn string_errors() -> Vec<String> {
    let mut found = Vec::new();
    for (relative, source) in source_files() {
        let code = lex(&source);
        let joined = code.lines.join("\n");
        let mut rest = joined.as_str();
        let mut offset = 0;
        while let Some(at) = rest.find("pub fn ") {
            let start = offset + at;
            let signature_end = joined[start..]
                .find(['{', ';'])
                .map_or(joined.len(), |end| start + end);
            let signature: String = joined[start..signature_end]
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" ");
            if signature.contains(", String>") && signature.contains("Result<") {
                let line = joined[..start].matches('\n').count() + 1;
                found.push(format!("src/{relative}:{line}: {signature}"));
            }
            offset = start + "pub fn ".len();
            rest = &joined[offset..];
        }
        for (number, line) in code.lines.iter().enumerate() {
            if line.contains("type Err = String") {
                found.push(format!("src/{relative}:{}: {}", number + 1, line.trim()));
            }
        }
    }
    found
}

#[test]
fn public_functions_have_typed_errors() {
    let found = string_errors();
    assert!(
        found.is_empty(),
        "public functions return a thiserror type, not `Result<_, String>`:\n{}",
        found.join("\n")
    );
}

/// Most lines of non-test code in one file of `src/`.
const MAX_FILE_LINES: usize = 800;
/// Most lines of one function, from `fn` to its closing brace.
const MAX_FUNCTION_LINES: usize = 150;

/// Files over [`MAX_FILE_LINES`] and functions over [`MAX_FUNCTION_LINES`].
fn oversized() -> Vec<String> {
    let mut found = Vec::new();
    for (relative, source) in source_files() {
        let code = lex(&source);
        if code.lines.len() > MAX_FILE_LINES {
            found.push(format!(
                "src/{relative}: {} lines of non-test code",
                code.lines.len()
            ));
        }
        for (start, line) in code.lines.iter().enumerate() {
            let trimmed = line.trim_start();
            let is_fn = trimmed.starts_with("fn ")
                || [
                    "pub fn ",
                    "pub(crate) fn ",
                    "pub(super) fn ",
                    "const fn ",
                    "pub const fn ",
                ]
                .iter()
                .any(|prefix| trimmed.starts_with(prefix));
            if !is_fn {
                continue;
            }
            let mut depth = 0_i64;
            let mut opened = false;
            let mut end = start;
            for (index, line) in code.lines.iter().enumerate().skip(start) {
                if !opened && line.trim_end().ends_with(';') && !line.contains('{') {
                    break;
                }
                depth += brace_balance(line);
                opened |= line.contains('{');
                end = index;
                if opened && depth <= 0 {
                    break;
                }
            }
            let length = end - start + 1;
            if opened && length > MAX_FUNCTION_LINES {
                let name: String = trimmed
                    .split("fn ")
                    .nth(1)
                    .unwrap_or("")
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                found.push(format!(
                    "src/{relative}:{}: fn {name} is {length} lines",
                    start + 1
                ));
            }
        }
    }
    found
}

#[test]
fn files_and_functions_stay_readable() {
    let found = oversized();
    assert!(
        found.is_empty(),
        "split these (at most {MAX_FILE_LINES} lines of non-test code per file, {MAX_FUNCTION_LINES} per function):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_size_check_measures_code_without_tests_and_ignores_braces_in_literals() {
    let source = "fn a() {\n    let s = \"{{\";\n    let c = '{';\n}\n#[cfg(test)]\nmod tests {\n    fn b() {}\n}\n";
    let code = lex(source);
    assert_eq!(code.lines.len(), 4, "{:?}", code.lines);
    assert_eq!(code.lines[1].trim(), "let s = \"\";");
    assert_eq!(code.lines[2].trim(), "let c = ' ';");
}
