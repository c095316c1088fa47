//! `view`: the static site of two runs of the demo's cloth questions, one with a unit made to
//! fail, opened in a real headless browser (Chromium): the leaderboard, the filters and a unit's
//! detail render with the expected content. The run's plots are checked against `results.json`.
//!
//! The browser is `$CONTPHY_BROWSER`, else `chromium-headless-shell` or `chromium` on the
//! `PATH`. Without one the browser half is skipped with a message, unless
//! `CONTPHY_REQUIRE_BROWSER=1` (CI sets it, and installs the browser) makes that a failure.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::support::{contphy, demo, kept_frames, root, stderr, stdout};

/// The failing unit planted in the second run.
const FAILED_UNIT: &str = "0/cloth_predictive_fall/0:A";

/// Two runs of the demo's cloth questions in `dir` (`a`, and `b` with [`FAILED_UNIT`] failed in
/// the sandbox), their programs in `dir/cache`.
fn two_runs(dir: &Path) {
    let questions = demo().join("cloth_collision/0.json");
    let output = contphy(
        dir,
        &[
            "--data",
            &demo().display().to_string(),
            "--questions",
            &questions.display().to_string(),
            "--out",
            "a",
            "--cache",
            "cache",
            "--jobs",
            "1",
            "-q",
        ],
    );
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    fs_err::create_dir_all(dir.join("b")).unwrap();
    for file in ["manifest.json", "questions.json"] {
        fs_err::copy(dir.join("a").join(file), dir.join("b").join(file)).unwrap();
    }
    let mut lines = Vec::new();
    for line in fs_err::read_to_string(dir.join("a/predictions.jsonl"))
        .unwrap()
        .lines()
    {
        let mut prediction: serde_json::Value = serde_json::from_str(line).unwrap();
        if prediction["unit"] == FAILED_UNIT {
            prediction["correct"] = false.into();
            prediction["answer"] = serde_json::Value::Null;
            prediction["error"] = serde_json::json!({
                "stage": "sandbox", "kind": "NameError", "message": "name 'x' is not defined"
            });
        }
        lines.push(prediction.to_string());
    }
    fs_err::write(dir.join("b/predictions.jsonl"), lines.join("\n") + "\n").unwrap();
}

fn percent(correct: &serde_json::Value, total: &serde_json::Value) -> String {
    let (correct, total) = (correct.as_f64().unwrap(), total.as_f64().unwrap());
    format!("{:.1}", 100.0 * correct / total)
}

/// The text contents of an SVG's `<text>` elements, in order.
fn svg_texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|part| {
            let start = part.find('>')? + 1;
            let end = part.find("</text>")?;
            Some(part[start..end].trim().to_string())
        })
        .collect()
}

#[test]
fn the_plots_show_the_numbers_of_results_json() {
    let dir = tempfile::tempdir().unwrap();
    two_runs(dir.path());
    let run = dir.path().join("a");
    let results: serde_json::Value =
        serde_json::from_slice(&fs_err::read(run.join("results.json")).unwrap()).unwrap();
    // The model's bars of the accuracy plot: per category, -Opt. from options, -Ques. from
    // questions (the property row has questions only), in Table-2 order.
    let mut expected = Vec::new();
    for group in results["scores"]["categories"].as_array().unwrap() {
        let model = &group["model"];
        if group["category"] != "property" {
            expected.push(percent(&model["options_correct"], &model["options"]));
        }
        expected.push(percent(&model["questions_correct"], &model["questions"]));
    }
    assert_eq!(expected.len(), 3, "Prop., P-Opt., P-Ques.");
    let accuracy =
        svg_texts(&fs_err::read_to_string(run.join("plots/accuracy-cloth.svg")).unwrap());
    assert!(
        accuracy
            .windows(3)
            .any(|window| window == expected.as_slice()),
        "{expected:?} in {accuracy:?}"
    );
    // The work plot's API calls per unit, family by family (in results.json's family order),
    // summed from predictions.jsonl.
    let predictions: Vec<serde_json::Value> = fs_err::read_to_string(run.join("predictions.jsonl"))
        .unwrap()
        .lines()
        .map(|line| serde_json::from_str(line).unwrap())
        .collect();
    let calls: Vec<String> = results["scores"]["families"]
        .as_array()
        .unwrap()
        .iter()
        .map(|family| {
            let units: Vec<&serde_json::Value> = predictions
                .iter()
                .filter(|p| p["family"] == family["family"])
                .collect();
            let sum: u64 = units
                .iter()
                .map(|p| p["work"]["api_calls"].as_u64().unwrap())
                .sum();
            format!("{:.1}", sum as f64 / units.len() as f64)
        })
        .collect();
    let work = svg_texts(&fs_err::read_to_string(run.join("plots/work.svg")).unwrap());
    assert!(
        work.windows(calls.len())
            .any(|window| window == calls.as_slice()),
        "{calls:?} in {work:?}"
    );
    let report = fs_err::read_to_string(run.join("report.md")).unwrap();
    assert!(report.contains("- [Cloth: accuracy (%) per setting](plots/accuracy-cloth.svg)"));
}

/// The browser to test with, if there is one.
fn browser() -> Option<PathBuf> {
    if let Some(path) = std::env::var_os("CONTPHY_BROWSER") {
        return Some(PathBuf::from(path));
    }
    let path = std::env::var_os("PATH")?;
    ["chromium-headless-shell", "chromium"]
        .iter()
        .flat_map(|name| std::env::split_paths(&path).map(move |dir| dir.join(name)))
        .find(|candidate| candidate.is_file())
}

/// The page's DOM after its scripts ran, and the browser's log (console errors included).
fn dump_dom(browser: &Path, page: &Path, hash: &str) -> (String, String) {
    let output = Command::new(browser)
        .args([
            "--no-sandbox",
            "--disable-gpu",
            "--virtual-time-budget=5000",
            "--dump-dom",
        ])
        .arg(format!("file://{}{hash}", page.display()))
        .output()
        .expect("the browser runs");
    (stdout(&output), stderr(&output))
}

/// The text of the element with `id` in a dumped DOM (tags removed).
fn element_text(dom: &str, id: &str) -> String {
    let start = dom
        .find(&format!("id=\"{id}\""))
        .unwrap_or_else(|| panic!("no #{id} in the page"));
    let open = start + dom[start..].find('>').unwrap() + 1;
    let tag_start = dom[..start].rfind('<').unwrap() + 1;
    let tag: String = dom[tag_start..]
        .chars()
        .take_while(char::is_ascii_alphanumeric)
        .collect();
    let close = open + dom[open..].find(&format!("</{tag}>")).unwrap();
    let mut text = String::new();
    let mut inside_tag = false;
    for c in dom[open..close].chars() {
        match c {
            '<' => inside_tag = true,
            '>' => {
                inside_tag = false;
                text.push(' ');
            }
            _ if !inside_tag => text.push(c),
            _ => {}
        }
    }
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[test]
fn the_site_renders_the_leaderboard_filters_and_a_units_detail_in_a_browser() {
    let dir = tempfile::tempdir().unwrap();
    two_runs(dir.path());
    let output = contphy(
        dir.path(),
        &["view", "a", "b", "--out", "site", "--cache", "cache"],
    );
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(
        stdout(&output).starts_with("wrote 15 files"),
        "{}",
        stdout(&output)
    );
    let site = dir.path().join("site");
    // Written again over itself: an earlier site is replaced, byte for byte the same.
    let first = fs_err::read(site.join("runs/2/units/0.js")).unwrap();
    let again = contphy(
        dir.path(),
        &["view", "a", "b", "--out", "site", "--cache", "cache"],
    );
    assert_eq!(again.status.code(), Some(0), "{}", stderr(&again));
    assert_eq!(fs_err::read(site.join("runs/2/units/0.js")).unwrap(), first);

    let Some(browser) = browser() else {
        assert!(
            std::env::var_os("CONTPHY_REQUIRE_BROWSER").is_none(),
            "CONTPHY_REQUIRE_BROWSER is set but no chromium-headless-shell or chromium is on the PATH"
        );
        eprintln!("skipped the browser half: no chromium-headless-shell or chromium on the PATH");
        return;
    };
    let site = site.canonicalize().unwrap();
    let mut log = String::new();

    let (dom, errors) = dump_dom(&browser, &site.join("index.html"), "");
    log.push_str(&errors);
    let leaderboard = element_text(&dom, "leaderboard");
    assert!(
        leaderboard.starts_with("Subset Setting RND FRQ a b ContPRO (paper) Human (paper)"),
        "{leaderboard}"
    );
    // One option of 36 failed in b: P-Opt. 100.0 against 97.2, P-Ques. one question of 12 lost.
    assert!(
        leaderboard.contains("P-Opt. 50.0 — 100.0 97.2 64.7 79.6"),
        "{leaderboard}"
    );
    assert!(
        leaderboard.contains("P-Ques. 17.7 — 100.0 91.7 60.0 77.3"),
        "{leaderboard}"
    );

    let run_page = site.join("runs/2/index.html");
    let (dom, errors) = dump_dom(&browser, &run_page, "");
    log.push_str(&errors);
    assert_eq!(
        element_text(&dom, "status"),
        "40 of 40 units shown, 39 correct"
    );
    let (dom, errors) = dump_dom(&browser, &run_page, "#stage=sandbox");
    log.push_str(&errors);
    assert_eq!(
        element_text(&dom, "status"),
        "1 of 40 units shown, 0 correct"
    );
    assert_eq!(
        element_text(&dom, "units"),
        format!(
            "Unit Scenario Family Correct Failed stage {FAILED_UNIT} cloth cloth/cloth_predictive_fall no sandbox"
        )
    );
    let (dom, errors) = dump_dom(
        &browser,
        &run_page,
        "#family=cloth/cloth_predictive_pose&correct=1",
    );
    log.push_str(&errors);
    assert_eq!(
        element_text(&dom, "status"),
        "20 of 40 units shown, 20 correct"
    );

    let (dom, errors) = dump_dom(&browser, &run_page, &format!("#unit={FAILED_UNIT}"));
    log.push_str(&errors);
    let detail = element_text(&dom, "detail");
    let program = builtin_program_line(dir.path());
    for expected in [
        "Unit 0/cloth_predictive_fall/0:A",
        "error sandbox / NameError: name 'x' is not defined",
        "truth no",
        "program origin builtin",
        "source: builtin",
        program.as_str(),
    ] {
        assert!(
            detail.contains(expected),
            "`{expected}` not in the detail: {detail}"
        );
    }
    assert!(!log.contains("Uncaught"), "a script failed:\n{log}");
}

/// A line of the failed unit's program, as the cache holds it (`<` and `&` escaped, as the
/// dumped DOM shows them).
fn builtin_program_line(dir: &Path) -> String {
    let predictions = fs_err::read_to_string(dir.join("a/predictions.jsonl")).unwrap();
    let key = predictions
        .lines()
        .map(|line| serde_json::from_str::<serde_json::Value>(line).unwrap())
        .find(|prediction| prediction["unit"] == FAILED_UNIT)
        .unwrap()["program_key"]
        .as_str()
        .unwrap()
        .to_string();
    let entry: serde_json::Value = serde_json::from_slice(
        &fs_err::read(dir.join(format!("cache/v1/{}/{key}.json", &key[..2]))).unwrap(),
    )
    .unwrap();
    let program = entry["program"].as_str().unwrap();
    let line = program
        .lines()
        .map(str::trim)
        .find(|line| line.len() > 20)
        .unwrap();
    let mut escaped = String::new();
    for c in line.chars() {
        match c {
            '<' => escaped.push_str("&lt;"),
            '>' => escaped.push_str("&gt;"),
            '&' => escaped.push_str("&amp;"),
            other => {
                let _ = write!(escaped, "{other}");
            }
        }
    }
    escaped.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[test]
fn view_errors_name_the_folder() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    fs_err::create_dir_all(path.join("empty")).unwrap();
    fs_err::create_dir_all(path.join("mine")).unwrap();
    fs_err::write(path.join("mine/notes.txt"), "keep me").unwrap();
    fs_err::write(path.join("file.txt"), "").unwrap();
    two_runs(path);
    let cases: [(&str, Vec<&str>); 4] = [
        ("not_a_run", vec!["view", "empty", "--out", "site"]),
        ("out_is_a_file", vec!["view", "a", "--out", "file.txt"]),
        ("out_holds_other_files", vec!["view", "a", "--out", "mine"]),
        (
            "missing_cache",
            vec!["view", "a", "--out", "site", "--cache", "nope"],
        ),
    ];
    let mut transcript = String::new();
    for (name, args) in cases {
        let output = contphy(path, &args);
        assert_eq!(output.status.code(), Some(1), "{name}: {}", stderr(&output));
        let _ = writeln!(transcript, "## {name}\n{}", stderr(&output));
    }
    assert_eq!(
        fs_err::read_to_string(path.join("mine/notes.txt")).unwrap(),
        "keep me"
    );
    insta::assert_snapshot!("view_errors", transcript);
}

#[test]
fn view_merges_the_shards_of_a_run_into_one_column() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let questions = demo().join("cloth_collision/0.json");
    for shard in ["0", "1"] {
        let output = contphy(
            path,
            &[
                "--data",
                &demo().display().to_string(),
                "--questions",
                &questions.display().to_string(),
                "--out",
                &format!("sharded/{shard}"),
                "--shard",
                &format!("{shard}/2"),
                "--jobs",
                "1",
                "-q",
            ],
        );
        assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    }
    let output = contphy(path, &["view", "sharded/0", "sharded/1", "--out", "site"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(
        stdout(&output).contains("for 1 run(s)"),
        "{}",
        stdout(&output)
    );
    let index = fs_err::read_to_string(path.join("site/index.html")).unwrap();
    assert!(index.contains(">sharded (2 shards)</a>"), "{index}");
    let units = fs_err::read_to_string(path.join("site/runs/1/units.js")).unwrap();
    assert_eq!(units.matches("\"cloth\"").count(), 1, "one scenario name");
    // Both shards' units, 40 in all, in one index.
    let start = units.find("\"units\":").unwrap();
    assert_eq!(units[start..].matches("],[").count() + 1, 40);
}

#[test]
fn a_perception_run_keeps_its_frames_and_the_viewer_shows_them_with_the_detections() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    // Two colour questions of the real video: perception's first pass only (frames 0–60).
    let mut questions: serde_json::Value =
        serde_json::from_slice(&fs_err::read(demo().join("pulley_group/0.json")).unwrap()).unwrap();
    let colors: Vec<serde_json::Value> = questions["question_dict"]["color"]
        .as_array()
        .unwrap()
        .iter()
        .take(2)
        .cloned()
        .collect();
    questions["question_dict"] = serde_json::json!({ "color": colors });
    fs_err::write(path.join("0.json"), questions.to_string()).unwrap();
    // From the repository's root, where the default model files are.
    let (question_file, run) = (path.join("0.json"), path.join("run"));
    let output = contphy(
        &root(),
        &[
            "--data",
            "eval/demo",
            "--questions",
            &question_file.display().to_string(),
            "--perception",
            "maskrcnn",
            "--out",
            &run.display().to_string(),
            "-q",
        ],
    );
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let frames = path.join("run/frames/rope/0");
    let (listing, listed) = kept_frames(&frames);
    assert_eq!(listed, [0, 10, 20, 30, 40, 50, 60]);
    for frame in listing["frames"].as_array().unwrap() {
        let image = fs_err::read(frames.join(frame["image"].as_str().unwrap())).unwrap();
        assert_eq!(&image[..3], [0xff, 0xd8, 0xff], "a JPEG");
        // The real video's mechanism: two ropes and eight elements, about ten detections.
        let found = frame["detections"].as_array().unwrap().len();
        assert!((6..=14).contains(&found), "{found} detections");
    }
    let output = contphy(path, &["view", "run", "--out", "site"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let site = path.join("site").canonicalize().unwrap();
    assert!(site.join("runs/1/frames/rope/0/0030.jpg").is_file());
    let Some(browser) = browser() else {
        assert!(
            std::env::var_os("CONTPHY_REQUIRE_BROWSER").is_none(),
            "CONTPHY_REQUIRE_BROWSER is set but no browser was found"
        );
        eprintln!("skipped the browser half: no chromium-headless-shell or chromium on the PATH");
        return;
    };
    let unit = fs_err::read_to_string(path.join("run/predictions.jsonl"))
        .unwrap()
        .lines()
        .map(|line| serde_json::from_str::<serde_json::Value>(line).unwrap())
        .next()
        .unwrap()["unit"]
        .as_str()
        .unwrap()
        .to_string();
    let (dom, errors) = dump_dom(
        &browser,
        &site.join("runs/1/index.html"),
        &format!("#unit={unit}"),
    );
    assert!(!errors.contains("Uncaught"), "a script failed:\n{errors}");
    let detail = element_text(&dom, "detail");
    assert!(detail.contains("What the detector saw"), "{detail}");
    assert!(
        detail.contains("frames 0, 10, 20, 30, 40, 50, 60"),
        "{detail}"
    );
    assert!(detail.contains("frame 30"), "{detail}");
    assert_eq!(
        dom.matches("src=\"frames/rope/0/").count(),
        7,
        "seven images"
    );
}
