//! Frames of the real rope video decoded through ffmpeg: the size and length of the release,
//! only the frames asked for, and the segmentation video's instance colours inside the boxes the
//! annotations give (the video is lossy, so colours match within a tolerance). These tests need
//! ffmpeg; `.ci/run` installs it, and under CI a missing ffmpeg is a failure, not a skip.

use std::path::PathBuf;

use contphy_eval::perception::frames::{FrameSource, FramesError, ffmpeg_available};

use crate::support::demo;

#[expect(clippy::print_stderr, reason = "a skipped test says why")]
pub(crate) fn need_ffmpeg() -> bool {
    if ffmpeg_available() {
        return true;
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "ffmpeg is not installed; .ci/run installs it"
    );
    eprintln!("skipping: ffmpeg is not installed");
    false
}

fn video(name: &str) -> PathBuf {
    demo().join("pulley_group/0").join(name)
}

#[test]
fn the_real_video_decodes_to_the_release_size_and_length() {
    if !need_ffmpeg() {
        return;
    }
    let source = FrameSource::open(&video("output_Full.mp4")).unwrap();
    let info = source.info().unwrap();
    assert_eq!(
        (info.width, info.height, info.frame_count),
        (1920, 1080, 150)
    );
    let frames = source.read(&[149, 0]).unwrap();
    assert_eq!(frames.len(), 2);
    assert_eq!((frames[0].index, frames[1].index), (149, 0));
    assert_eq!(frames[0].rgb.len(), 1920 * 1080 * 3);
    // The wall is a light plaster; the purple cube (box origin 676,548 size 91×78 in frame 0)
    // is purple.
    let wall = frames[1].pixel(100, 100).unwrap();
    assert!(wall.iter().all(|&c| c > 90), "{wall:?}");
    let cube = frames[1].pixel(676 + 45, 548 + 39).unwrap();
    assert!(
        cube[2] > cube[1] + 30 && cube[0] > cube[1] + 30,
        "purple: {cube:?}"
    );
    let error = source.read(&[150]).unwrap_err().to_string();
    assert!(
        error.ends_with("has 150 frames; frame 150 does not exist"),
        "{error}"
    );
}

#[test]
fn segmentation_colours_fill_the_annotated_boxes() {
    if !need_ffmpeg() {
        return;
    }
    let annotation: serde_json::Value =
        serde_json::from_slice(&fs_err::read(video("outputs.json")).unwrap()).unwrap();
    let per_frame = &annotation["imgAnnotationDescriptions"]["perFrameAnnotations"];
    let source = FrameSource::open(&video("output_Full_seg.mp4")).unwrap();
    let frames = [0_usize, 80, 149];
    let images = source.read(&frames).unwrap();
    let mut checked = 0;
    for (frame, image) in frames.iter().zip(&images) {
        let capture = &per_frame[(frame + 1).to_string()][0];
        let annotations = capture["annotations"].as_array().unwrap();
        let find = |kind: &str| {
            annotations
                .iter()
                .find(|a| a["@type"] == kind)
                .cloned()
                .unwrap()
        };
        let boxes = find("type.unity.com/unity.solo.BoundingBox2DAnnotation");
        let instances = find("type.unity.com/unity.solo.InstanceSegmentationAnnotation");
        for value in boxes["values"].as_array().unwrap() {
            let id = &value["instanceId"];
            let color: Vec<i32> = instances["instances"]
                .as_array()
                .unwrap()
                .iter()
                .find(|i| &i["instanceId"] == id)
                .unwrap()["color"]
                .as_array()
                .unwrap()
                .iter()
                .take(3)
                .map(|c| i32::try_from(c.as_i64().unwrap()).unwrap())
                .collect();
            let number =
                |v: &serde_json::Value, i: usize| v.as_array().unwrap()[i].as_f64().unwrap();
            let (x0, y0) = (number(&value["origin"], 0), number(&value["origin"], 1));
            let (x1, y1) = (
                x0 + number(&value["dimension"], 0),
                y0 + number(&value["dimension"], 1),
            );
            // Pixels of this instance's colour (the H.264 round trip moves colours a little).
            let (mut inside, mut outside) = (0_u32, 0_u32);
            let (mut low_x, mut low_y, mut high_x, mut high_y) =
                (f64::MAX, f64::MAX, 0.0_f64, 0.0_f64);
            for y in 0..image.height {
                for x in 0..image.width {
                    let p = image.pixel(x, y).unwrap();
                    let close = p
                        .iter()
                        .zip(&color)
                        .all(|(a, b)| (i32::from(*a) - b).abs() <= 40);
                    if !close {
                        continue;
                    }
                    let (fx, fy) = (f64::from(x), f64::from(y));
                    if fx >= x0 - 2.0 && fx <= x1 + 2.0 && fy >= y0 - 2.0 && fy <= y1 + 2.0 {
                        inside += 1;
                        low_x = low_x.min(fx);
                        low_y = low_y.min(fy);
                        high_x = high_x.max(fx + 1.0);
                        high_y = high_y.max(fy + 1.0);
                    } else {
                        outside += 1;
                    }
                }
            }
            assert!(inside > 50, "instance {id} frame {frame}: {inside} pixels");
            assert!(
                f64::from(outside) < 0.05 * f64::from(inside),
                "instance {id} frame {frame}: {outside} of its pixels outside its box"
            );
            // The mask's extent and the box overlap almost entirely (IoU).
            let width = (high_x.min(x1) - low_x.max(x0)).max(0.0);
            let height = (high_y.min(y1) - low_y.max(y0)).max(0.0);
            let intersection = width * height;
            let union = (x1 - x0) * (y1 - y0) + (high_x - low_x) * (high_y - low_y) - intersection;
            assert!(
                intersection / union > 0.85,
                "instance {id} frame {frame}: IoU {}",
                intersection / union
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 30, "ten boxes in each of three frames");
}

#[test]
fn a_file_that_is_not_a_video_is_named() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let fake = dir.path().join("output_Full.mp4");
    fs_err::write(&fake, b"this is not a video").unwrap();
    let error = FrameSource::open(&fake).unwrap().read(&[0]).unwrap_err();
    assert!(matches!(error, FramesError::NotAVideo { .. }), "{error}");
    let text = error.to_string();
    assert!(
        text.contains("output_Full.mp4` is not a readable video"),
        "{text}"
    );
}
