//! Data roots and video folders, laid out as in the public release:
//! `DATA/<scenario folder>/<video_id>/{outputs.json, outputs4D.json, output_Full.mp4,
//! output_Full_seg.mp4}`.

use std::path::{Path, PathBuf};

use super::fields::{Node, read_json};
use super::{DatasetError, Scenario, VideoId};

/// A data root: the folder holding `pulley_group/`, `fluid_slides/`, ... and the sampled question
/// files `<scenario folder>_<split>.json`.
#[derive(Debug, Clone)]
pub struct DataRoot {
    dir: PathBuf,
}

/// One video folder.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VideoFolder {
    /// The scenario it belongs to.
    pub scenario: Scenario,
    /// The folder name.
    pub id: VideoId,
    /// The folder.
    pub dir: PathBuf,
}

/// The videos of one scenario under a data root.
#[derive(Debug, Clone, Default)]
pub struct VideoListing {
    /// Valid videos, sorted by id (numerically where ids are numbers).
    pub valid: Vec<VideoFolder>,
    /// Videos whose `outputs.json` says `"validity": false`; skipped, never an error.
    pub invalid: Vec<VideoId>,
}

impl DataRoot {
    /// Opens a data root; it must be an existing folder.
    pub fn open(dir: &Path) -> Result<DataRoot, DatasetError> {
        if dir.is_dir() {
            Ok(DataRoot {
                dir: dir.to_path_buf(),
            })
        } else {
            Err(DatasetError::MissingRoot {
                path: dir.to_path_buf(),
            })
        }
    }

    /// The root folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The scenarios that have a folder under this root, in the paper's order.
    pub fn scenarios(&self) -> Vec<Scenario> {
        Scenario::ALL
            .into_iter()
            .filter(|s| self.scenario_dir(*s).is_dir())
            .collect()
    }

    /// `DATA/<scenario folder>`.
    pub fn scenario_dir(&self, scenario: Scenario) -> PathBuf {
        self.dir.join(scenario.folder_name())
    }

    /// The folder of one video (which may not exist).
    pub fn video(&self, scenario: Scenario, id: &VideoId) -> VideoFolder {
        VideoFolder {
            scenario,
            id: id.clone(),
            dir: self.scenario_dir(scenario).join(&id.0),
        }
    }

    /// Lists the video folders of `scenario`: sub-folders holding an `outputs.json`. Invalid
    /// trials are counted and skipped. Sub-folders without `outputs.json` are an error, because
    /// a half-copied dataset should not silently lose videos.
    pub fn list_videos(&self, scenario: Scenario) -> Result<VideoListing, DatasetError> {
        let dir = self.scenario_dir(scenario);
        #[expect(
            clippy::disallowed_methods,
            reason = "the error below names the path itself"
        )]
        let entries = std::fs::read_dir(&dir).map_err(|source| DatasetError::read(&dir, source))?;
        let mut folders = Vec::new();
        for entry in entries {
            let entry = entry.map_err(|source| DatasetError::read(&dir, source))?;
            let path = entry.path();
            if !path.is_dir() {
                continue;
            }
            let id = VideoId(entry.file_name().to_string_lossy().into_owned());
            folders.push(VideoFolder {
                scenario,
                id,
                dir: path,
            });
        }
        folders.sort_by(|a, b| a.id.sort_key().cmp(&b.id.sort_key()));
        let mut listing = VideoListing::default();
        for folder in folders {
            let annotation = folder.outputs_json();
            if !annotation.is_file() {
                return Err(DatasetError::MissingAnnotation { path: folder.dir });
            }
            if read_validity(&annotation)? {
                listing.valid.push(folder);
            } else {
                listing.invalid.push(folder.id);
            }
        }
        Ok(listing)
    }
}

impl VideoFolder {
    /// Opens a video folder given directly (as `exec --video DIR` does). The scenario comes from
    /// the parent folder's name unless given; a folder outside every scenario folder needs it
    /// given.
    pub fn open(dir: &Path, scenario: Option<Scenario>) -> Result<VideoFolder, DatasetError> {
        if !dir.is_dir() {
            return Err(DatasetError::Read {
                path: dir.to_path_buf(),
                source: std::io::Error::new(std::io::ErrorKind::NotFound, "no such folder"),
            });
        }
        let outputs = dir.join("outputs.json");
        if !outputs.is_file() {
            return Err(DatasetError::MissingAnnotation {
                path: dir.to_path_buf(),
            });
        }
        let id = VideoId(
            dir.file_name()
                .map_or_else(|| ".".into(), |n| n.to_string_lossy().into_owned()),
        );
        let parent = dir
            .parent()
            .and_then(Path::file_name)
            .map(|n| n.to_string_lossy().into_owned());
        let scenario = scenario
            .or_else(|| parent.as_deref().and_then(Scenario::from_folder_name))
            .ok_or_else(|| DatasetError::UnknownVideoScenario {
                path: dir.to_path_buf(),
            })?;
        Ok(VideoFolder {
            scenario,
            id,
            dir: dir.to_path_buf(),
        })
    }

    /// `outputs.json`: the annotations.
    pub fn outputs_json(&self) -> PathBuf {
        self.dir.join("outputs.json")
    }

    /// `outputs4D.json`: 4-D sensor data (rigid-body poses, soft-body particles).
    pub fn outputs_4d_json(&self) -> PathBuf {
        self.dir.join("outputs4D.json")
    }

    /// `output_Full.mp4`: the RGB video.
    pub fn rgb_video(&self) -> PathBuf {
        self.dir.join("output_Full.mp4")
    }

    /// `output_Full_seg.mp4`: the instance-segmentation video (lossy colours).
    pub fn segmentation_video(&self) -> PathBuf {
        self.dir.join("output_Full_seg.mp4")
    }
}

/// Reads the `validity` flag of an `outputs.json`. The generator writes it first, so a cheap peek
/// at the head usually decides; otherwise the whole file is parsed.
pub fn read_validity(path: &Path) -> Result<bool, DatasetError> {
    let head = peek(path, 64)?;
    let compact: String = head.chars().filter(|c| !c.is_whitespace()).collect();
    if compact.starts_with("{\"validity\":false") {
        return Ok(false);
    }
    let value = read_json(path)?;
    Node::root(path, &value).field("validity", |node| node.boolean())
}

fn peek(path: &Path, bytes: usize) -> Result<String, DatasetError> {
    use std::io::Read;
    #[expect(
        clippy::disallowed_methods,
        reason = "the error below names the path itself"
    )]
    let file = std::fs::File::open(path).map_err(|source| DatasetError::read(path, source))?;
    let mut buffer = Vec::with_capacity(bytes);
    file.take(bytes as u64)
        .read_to_end(&mut buffer)
        .map_err(|source| DatasetError::read(path, source))?;
    Ok(String::from_utf8_lossy(&buffer).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(path: &Path, text: &str) {
        fs_err::create_dir_all(path.parent().unwrap()).unwrap();
        fs_err::write(path, text).unwrap();
    }

    #[test]
    fn listing_sorts_numerically_and_skips_invalid_trials() {
        let root = tempfile::tempdir().unwrap();
        let rope = root.path().join("pulley_group");
        write(&rope.join("10/outputs.json"), r#"{"validity": true}"#);
        write(&rope.join("2/outputs.json"), r#"{"validity": true}"#);
        write(&rope.join("3/outputs.json"), r#"{"validity":false}"#);
        write(&rope.join("notes.txt"), "not a video");
        let data = DataRoot::open(root.path()).unwrap();
        assert_eq!(data.scenarios(), vec![Scenario::Rope]);
        let listing = data.list_videos(Scenario::Rope).unwrap();
        let ids: Vec<&str> = listing.valid.iter().map(|v| v.id.0.as_str()).collect();
        assert_eq!(ids, vec!["2", "10"]);
        assert_eq!(listing.invalid, vec![VideoId("3".into())]);
    }

    #[test]
    fn a_video_folder_outside_the_scenario_folders_needs_its_scenario_given() {
        let root = tempfile::tempdir().unwrap();
        let loose = root.path().join("videos/7");
        write(&loose.join("outputs.json"), r#"{"validity": true}"#);
        let error = VideoFolder::open(&loose, None).unwrap_err().to_string();
        assert!(
            error.starts_with("cannot tell the scenario of video folder")
                && error.contains("pass --scenario"),
            "{error}"
        );
        let given = VideoFolder::open(&loose, Some(Scenario::Rope)).unwrap();
        assert_eq!((given.scenario, given.id.0.as_str()), (Scenario::Rope, "7"));
        let inside = root.path().join("pulley_group/3");
        write(&inside.join("outputs.json"), r#"{"validity": true}"#);
        assert_eq!(
            VideoFolder::open(&inside, None).unwrap().scenario,
            Scenario::Rope
        );
    }

    #[test]
    fn missing_pieces_are_named() {
        let root = tempfile::tempdir().unwrap();
        let missing = DataRoot::open(&root.path().join("nope")).unwrap_err();
        assert!(missing.to_string().contains("does not exist"), "{missing}");
        fs_err::create_dir_all(root.path().join("pulley_group/5")).unwrap();
        let data = DataRoot::open(root.path()).unwrap();
        let error = data.list_videos(Scenario::Rope).unwrap_err();
        assert!(
            error.to_string().contains("has no `outputs.json`"),
            "{error}"
        );
        write(
            &root.path().join("pulley_group/5/outputs.json"),
            r#"{"validity": tr"#,
        );
        let error = data.list_videos(Scenario::Rope).unwrap_err();
        assert!(error.to_string().contains("is not valid JSON"), "{error}");
    }
}
