//! `exec`: the paper's rope example and a hand-written program per rope family, run through the
//! sandbox worker on the real video, with answers derived by hand from its annotations
//! (masses 0.2 / 0.25 / 0.15 kg; purple and green cubes share a rope group; a heavier purple
//! cube turns the blue pulley anti-clockwise; a lighter one sends the green cube down).

use serde_json::{Value, json};

use crate::support::{contphy, demo, root, stderr, stdout};

fn exec(program: &str, extra: &[&str]) -> (Option<i32>, Value, String) {
    exec_on(&demo().join("pulley_group/0"), program, extra)
}

/// `exec` of the fixture `program` on `video`, with `extra` arguments.
fn exec_on(video: &std::path::Path, program: &str, extra: &[&str]) -> (Option<i32>, Value, String) {
    let program = root().join("tests/fixtures/programs").join(program);
    let mut args = vec![
        "exec",
        "--video",
        video.to_str().unwrap(),
        "--program",
        program.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let output = contphy(&root(), &args);
    let value: Value = serde_json::from_str(&stdout(&output)).unwrap_or(Value::Null);
    (output.status.code(), value, stderr(&output))
}

#[test]
fn family_programs_give_the_hand_derived_answers() {
    let cases = [
        ("paper_eg1.py", json!("yes"), "yes"),
        ("mass.py", json!("yes"), "yes"),
        (
            "mass_other_group.py",
            json!("can not answer"),
            "can not answer",
        ),
        ("tension.py", json!("can not answer"), "can not answer"),
        ("shape.py", json!(3), "3"),
        ("color.py", json!(3), "3"),
        ("existence.py", json!("yes"), "yes"),
        ("counterfactual.py", json!("yes"), "yes"),
        ("counterfactual_direction.py", json!("down"), "down"),
        ("goal_driven.py", json!("yes"), "yes"),
        ("predictive.py", json!("yes"), "yes"),
        ("answer_global.py", json!(2), "2"),
    ];
    for (program, value, answer) in cases {
        let (code, output, stderr) = exec(program, &[]);
        assert_eq!(code, Some(0), "{program}: {stderr}");
        assert_eq!(output["value"], value, "{program}: {output}");
        assert_eq!(output["answer"], answer, "{program}: {output}");
        assert_eq!(output["error"], Value::Null, "{program}: {output}");
        assert_eq!(output["work"]["sim_runs"], 0, "{program}: {output}");
    }
}

#[test]
fn exec_scores_against_a_question_when_given_one() {
    let questions = demo().join("pulley_group/0.json");
    let (code, output, stderr) = exec(
        "shape.py",
        &[
            "--questions",
            questions.to_str().unwrap(),
            "--question-id",
            "0/shape/3",
        ],
    );
    assert_eq!(code, Some(0), "{stderr}");
    // Question 0/shape/3 of the demo file asks for solid pulleys: gold 3.
    assert_eq!(output["gold"], "3", "{output}");
    assert_eq!(output["correct"], true, "{output}");
}

#[test]
fn failures_are_typed_with_their_stage_and_exit_1() {
    let (code, output, _) = exec("misuse.py", &[]);
    assert_eq!(code, Some(1));
    assert_eq!(output["error"]["stage"], "scene_api", "{output}");
    assert_eq!(output["error"]["kind"], "misuse", "{output}");
    let message = output["error"]["message"].as_str().unwrap();
    assert!(
        message.contains("rope scenes have mass (cubes, spheres) and tension (ropes)"),
        "{message}"
    );

    let (code, output, _) = exec("runaway.py", &["--program-timeout", "0.5"]);
    assert_eq!(code, Some(1));
    assert_eq!(output["error"]["stage"], "sandbox", "{output}");
    assert_eq!(output["error"]["kind"], "timeout", "{output}");
}

/// A description that names nothing is the program's misuse when every object is known (annotation
/// perception), and a perception miss when the objects were read from pixels: the question may
/// name an object the detector missed or read in another colour.
#[test]
fn naming_an_absent_object_is_misuse_or_a_perception_miss() {
    let video = demo().join("fluid_slides/0");
    for (perception, kind, class) in [
        ("annotation", "misuse", "SceneApiError"),
        ("maskrcnn", "not_seen", "SceneNotSeenError"),
    ] {
        let (code, value, _) = exec_on(
            &video,
            "fluid_absent_container.py",
            &["--perception", perception],
        );
        assert_eq!(code, Some(1), "{perception}: {value}");
        assert_eq!(
            value["error"]["stage"], "scene_api",
            "{perception}: {value}"
        );
        assert_eq!(value["error"]["kind"], kind, "{perception}: {value}");
        let message = value["error"]["message"].as_str().unwrap_or_default();
        assert!(
            message.contains(&format!(
                "`{class}`: happen: the target of 'entering' names no container"
            )) && message.contains("the containers are: purple container, pink container"),
            "{perception}: {message}"
        );
    }
}

/// The same for an empty list passed where one object is needed (`query_pair` of a fluid
/// `find` did not find).
#[test]
fn an_empty_list_for_one_object_is_misuse_or_a_perception_miss() {
    let video = demo().join("fluid_slides/0");
    for (perception, kind) in [("annotation", "misuse"), ("maskrcnn", "not_seen")] {
        let (code, value, _) = exec_on(
            &video,
            "fluid_absent_fluid.py",
            &["--perception", perception],
        );
        assert_eq!(code, Some(1), "{perception}: {value}");
        assert_eq!(value["error"]["kind"], kind, "{perception}: {value}");
        let message = value["error"]["message"].as_str().unwrap_or_default();
        assert!(
            message.contains("query_pair: `object1` is an empty list: `find` found no such object"),
            "{perception}: {message}"
        );
    }
}

/// A sandbox worker whose parent dies ends on its own, even though its stdin stays open (a
/// killed `run` whose worker is inside a long simulation): the shell that starts it exits at
/// once, leaving it orphaned with a FIFO it holds open both ways as stdin.
#[test]
fn an_orphaned_sandbox_worker_exits() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("stdin");
    let output = std::process::Command::new("sh")
        .args([
            "-c",
            r#"mkfifo "$2" || exit 1
CONTPHY_SANDBOX_PARENT=$$ "$1" __sandbox-worker <>"$2" >/dev/null 2>&1 &
echo $!"#,
            "sh",
            env!("CARGO_BIN_EXE_contphy-eval"),
            fifo.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let pid = stdout(&output).trim().to_string();
    assert!(!pid.is_empty(), "no pid: {}", stderr(&output));
    let running = || {
        fs_err::read_to_string(format!("/proc/{pid}/stat"))
            // A reaped process has no entry; an unreaped one is a zombie (state `Z`).
            .is_ok_and(|stat| {
                stat.rsplit(')')
                    .next()
                    .is_some_and(|rest| !rest.trim_start().starts_with('Z'))
            })
    };
    // A liveness bound, not a speed target: the worker checks every 200 ms.
    let deadline = std::time::Instant::now() + std::time::Duration::from_mins(1);
    while running() && std::time::Instant::now() < deadline {
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    assert!(!running(), "worker {pid} still runs after its parent died");
}
