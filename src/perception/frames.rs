//! Video frames as RGB pixel buffers: from an mp4 through an `ffmpeg` subprocess (raw RGB
//! streamed over a pipe, only the frames asked for kept), or from a folder of PNG images
//! (`frame_00000.png`, ...; the layout of the paper's extracted frames).
//!
//! Input: a video path and 0-based frame indices. Output: [`RgbFrame`]s in the order asked, or a
//! [`FramesError`] that names the file and says what to do (ffmpeg missing, not a video, a frame
//! past the end, a PNG of another size).

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// One decoded frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbFrame {
    /// 0-based frame index in the video.
    pub index: usize,
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// RGB, row-major from the top-left, 3 bytes per pixel.
    pub rgb: Vec<u8>,
}

impl RgbFrame {
    /// The RGB bytes of pixel `(x, y)`; `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 3]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let at = (y as usize * self.width as usize + x as usize) * 3;
        Some([self.rgb[at], self.rgb[at + 1], self.rgb[at + 2]])
    }
}

/// Size and length of a video.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VideoInfo {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// Number of frames.
    pub frame_count: usize,
}

/// Where frames come from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FrameSource {
    /// An mp4 (or any container ffmpeg reads).
    Video(PathBuf),
    /// A folder of `frame_NNNNN.png` images, numbered from 0.
    PngFolder(PathBuf),
}

/// Why frames could not be read.
#[derive(Debug, thiserror::Error)]
pub enum FramesError {
    /// The ffmpeg tools are not installed.
    #[error(
        "`{program}` is not installed, so `{path}` cannot be decoded; install ffmpeg (Debian: `apt-get install ffmpeg`) or give a folder of PNG frames"
    )]
    FfmpegMissing {
        /// `ffmpeg` or `ffprobe`.
        program: String,
        /// The video asked for.
        path: PathBuf,
    },
    /// The file does not exist.
    #[error("`{path}` does not exist")]
    Missing {
        /// The file or folder.
        path: PathBuf,
    },
    /// ffmpeg could not read the file as a video.
    #[error("`{path}` is not a readable video: {detail}")]
    NotAVideo {
        /// The file.
        path: PathBuf,
        /// What ffmpeg said.
        detail: String,
    },
    /// A frame index past the end.
    #[error("`{path}` has {count} frames; frame {index} does not exist")]
    OutOfRange {
        /// The video.
        path: PathBuf,
        /// The index asked for.
        index: usize,
        /// Frames in the video.
        count: usize,
    },
    /// A frame's size differs from what was expected.
    #[error(
        "`{path}`: frame {index} is {width}×{height}, expected {expected_width}×{expected_height}"
    )]
    SizeMismatch {
        /// The video or image.
        path: PathBuf,
        /// The frame.
        index: usize,
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
        /// The expected width.
        expected_width: u32,
        /// The expected height.
        expected_height: u32,
    },
    /// A PNG could not be decoded.
    #[error("`{path}` is not a readable PNG: {detail}")]
    BadImage {
        /// The image.
        path: PathBuf,
        /// The decoder's message.
        detail: String,
    },
    /// Reading or running failed.
    #[error("cannot read `{path}`")]
    Io {
        /// The file or program.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
}

/// The program to run for `name` (`ffmpeg`, `ffprobe`): `CONTPHY_FFMPEG_DIR/name` when that
/// variable is set, else `name` on `PATH`.
fn program(name: &str) -> PathBuf {
    match std::env::var_os("CONTPHY_FFMPEG_DIR") {
        Some(dir) => Path::new(&dir).join(name),
        None => PathBuf::from(name),
    }
}

/// Whether `ffmpeg` and `ffprobe` can be run.
pub fn ffmpeg_available() -> bool {
    ["ffmpeg", "ffprobe"].iter().all(|name| {
        Command::new(program(name))
            .arg("-version")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    })
}

/// Runs an ffmpeg tool, mapping "not found" to [`FramesError::FfmpegMissing`].
fn spawn(
    name: &str,
    video: &Path,
    command: &mut Command,
) -> Result<std::process::Child, FramesError> {
    command.spawn().map_err(|source| {
        if source.kind() == std::io::ErrorKind::NotFound {
            FramesError::FfmpegMissing {
                program: name.to_string(),
                path: video.to_path_buf(),
            }
        } else {
            FramesError::Io {
                path: program(name),
                source,
            }
        }
    })
}

/// The PNG folder of a video's RGB frames, relative to its folder (the paper's extracted-frame
/// layout; the generator writes it).
pub const RGB_FRAME_DIR: &str = "frames/output_Full_ori";
/// The PNG folder of a video's segmentation frames, relative to its folder.
pub const SEGMENTATION_FRAME_DIR: &str = "frames/output_Full_seg";
/// A video folder's RGB mp4 (the release's name).
pub const RGB_VIDEO_FILE: &str = "output_Full.mp4";
/// A video folder's segmentation mp4.
pub const SEGMENTATION_VIDEO_FILE: &str = "output_Full_seg.mp4";

/// Which of a video folder's two frame streams.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stream {
    /// The rendered RGB frames.
    Rgb,
    /// The instance-segmentation frames.
    Segmentation,
}

impl FrameSource {
    /// A video folder's `stream`: its PNG folder when there is one (lossless, no decoding),
    /// else its mp4.
    pub fn of_video(video_dir: &Path, stream: Stream) -> Result<FrameSource, FramesError> {
        let (folder, file) = match stream {
            Stream::Rgb => (RGB_FRAME_DIR, RGB_VIDEO_FILE),
            Stream::Segmentation => (SEGMENTATION_FRAME_DIR, SEGMENTATION_VIDEO_FILE),
        };
        let png = video_dir.join(folder);
        if png.is_dir() {
            return Ok(FrameSource::PngFolder(png));
        }
        FrameSource::open(&video_dir.join(file))
    }

    /// The source at `path`: a folder of PNGs or a video file.
    pub fn open(path: &Path) -> Result<FrameSource, FramesError> {
        if path.is_dir() {
            Ok(FrameSource::PngFolder(path.to_path_buf()))
        } else if path.is_file() {
            Ok(FrameSource::Video(path.to_path_buf()))
        } else {
            Err(FramesError::Missing {
                path: path.to_path_buf(),
            })
        }
    }

    /// The path read.
    pub fn path(&self) -> &Path {
        match self {
            FrameSource::Video(path) | FrameSource::PngFolder(path) => path,
        }
    }

    /// Size and frame count.
    pub fn info(&self) -> Result<VideoInfo, FramesError> {
        match self {
            FrameSource::Video(path) => probe_video(path),
            FrameSource::PngFolder(dir) => {
                let frames = png_frames(dir)?;
                let Some(first) = frames.first() else {
                    return Err(FramesError::NotAVideo {
                        path: dir.clone(),
                        detail: "the folder holds no frame_NNNNN.png images".into(),
                    });
                };
                let (width, height) =
                    image::image_dimensions(first).map_err(|error| FramesError::BadImage {
                        path: first.clone(),
                        detail: error.to_string(),
                    })?;
                Ok(VideoInfo {
                    width,
                    height,
                    frame_count: frames.len(),
                })
            }
        }
    }

    /// The frames at `indices` (0-based, any order, repeats allowed), in the order asked. Only
    /// these frames are kept; a video is decoded once up to the last one asked for.
    pub fn read(&self, indices: &[usize]) -> Result<Vec<RgbFrame>, FramesError> {
        if indices.is_empty() {
            return Ok(Vec::new());
        }
        let info = self.info()?;
        if let Some(&index) = indices.iter().find(|&&i| i >= info.frame_count) {
            return Err(FramesError::OutOfRange {
                path: self.path().to_path_buf(),
                index,
                count: info.frame_count,
            });
        }
        match self {
            FrameSource::Video(path) => decode_video(path, info, indices),
            FrameSource::PngFolder(dir) => {
                let files = png_frames(dir)?;
                indices
                    .iter()
                    .map(|&index| read_png(&files[index], index, info))
                    .collect()
            }
        }
    }
}

/// `frame_NNNNN.png` files of `dir`, sorted by number; numbers must run 0, 1, 2, ...
fn png_frames(dir: &Path) -> Result<Vec<PathBuf>, FramesError> {
    let entries = fs_err::read_dir(dir).map_err(|source| FramesError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut numbered = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|source| FramesError::Io {
            path: dir.to_path_buf(),
            source,
        })?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if let Some(number) = name
            .strip_prefix("frame_")
            .and_then(|rest| rest.strip_suffix(".png"))
            .and_then(|digits| digits.parse::<usize>().ok())
        {
            numbered.push((number, entry.path()));
        }
    }
    numbered.sort();
    if let Some((position, (number, _))) = numbered
        .iter()
        .enumerate()
        .find(|(position, (number, _))| position != number)
    {
        return Err(FramesError::NotAVideo {
            path: dir.to_path_buf(),
            detail: format!(
                "frame numbers must run from 0 without gaps; found frame {number} at position {position}"
            ),
        });
    }
    Ok(numbered.into_iter().map(|(_, path)| path).collect())
}

fn read_png(path: &Path, index: usize, info: VideoInfo) -> Result<RgbFrame, FramesError> {
    let image = image::open(path).map_err(|error| FramesError::BadImage {
        path: path.to_path_buf(),
        detail: error.to_string(),
    })?;
    let rgb = image.to_rgb8();
    if rgb.width() != info.width || rgb.height() != info.height {
        return Err(FramesError::SizeMismatch {
            path: path.to_path_buf(),
            index,
            width: rgb.width(),
            height: rgb.height(),
            expected_width: info.width,
            expected_height: info.height,
        });
    }
    Ok(RgbFrame {
        index,
        width: rgb.width(),
        height: rgb.height(),
        rgb: rgb.into_raw(),
    })
}

fn probe_video(path: &Path) -> Result<VideoInfo, FramesError> {
    if !path.is_file() {
        return Err(FramesError::Missing {
            path: path.to_path_buf(),
        });
    }
    let child = spawn(
        "ffprobe",
        path,
        Command::new(program("ffprobe"))
            .args([
                "-v",
                "error",
                "-select_streams",
                "v:0",
                "-count_packets",
                "-show_entries",
                "stream=width,height,nb_read_packets",
                "-of",
                "csv=p=0",
            ])
            .arg(path)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped()),
    )?;
    let output = child.wait_with_output().map_err(|source| FramesError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let text = String::from_utf8_lossy(&output.stdout);
    let fields: Vec<&str> = text.trim().split(',').collect();
    let parsed = match fields.as_slice() {
        [width, height, frames] => width
            .parse::<u32>()
            .ok()
            .zip(height.parse::<u32>().ok())
            .zip(frames.parse::<usize>().ok()),
        _ => None,
    };
    match parsed {
        Some(((width, height), frame_count))
            if output.status.success() && width > 0 && height > 0 =>
        {
            Ok(VideoInfo {
                width,
                height,
                frame_count,
            })
        }
        _ => {
            let stderr = String::from_utf8_lossy(&output.stderr);
            let detail = stderr
                .lines()
                .last()
                .filter(|line| !line.trim().is_empty())
                .unwrap_or("it has no video stream")
                .trim()
                .to_string();
            Err(FramesError::NotAVideo {
                path: path.to_path_buf(),
                detail,
            })
        }
    }
}

/// An ffmpeg `select` expression keeping frames `indices` (sorted, distinct), as ranges.
fn select_expression(indices: &[usize]) -> String {
    let mut ranges: Vec<(usize, usize)> = Vec::new();
    for &index in indices {
        match ranges.last_mut() {
            Some((_, end)) if *end + 1 == index => *end = index,
            _ => ranges.push((index, index)),
        }
    }
    ranges
        .iter()
        .map(|(start, end)| {
            if start == end {
                format!("eq(n\\,{start})")
            } else {
                format!("between(n\\,{start}\\,{end})")
            }
        })
        .collect::<Vec<_>>()
        .join("+")
}

fn decode_video(
    path: &Path,
    info: VideoInfo,
    indices: &[usize],
) -> Result<Vec<RgbFrame>, FramesError> {
    let mut wanted: Vec<usize> = indices.to_vec();
    wanted.sort_unstable();
    wanted.dedup();
    let last = wanted.last().copied().unwrap_or(0);
    let mut child = spawn(
        "ffmpeg",
        path,
        Command::new(program("ffmpeg"))
            .args(["-v", "error", "-nostdin", "-i"])
            .arg(path)
            .args([
                "-vf",
                &format!("select='{}'", select_expression(&wanted)),
                "-fps_mode",
                "passthrough",
                "-frames:v",
                &wanted.len().to_string(),
                "-f",
                "rawvideo",
                "-pix_fmt",
                "rgb24",
                "-",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped()),
    )?;
    let frame_bytes = info.width as usize * info.height as usize * 3;
    let mut decoded: Vec<RgbFrame> = Vec::with_capacity(wanted.len());
    let mut failure = None;
    if let Some(stdout) = child.stdout.as_mut() {
        for &index in &wanted {
            let mut rgb = vec![0; frame_bytes];
            if let Err(source) = stdout.read_exact(&mut rgb) {
                failure = Some(source);
                break;
            }
            decoded.push(RgbFrame {
                index,
                width: info.width,
                height: info.height,
                rgb,
            });
        }
    }
    let output = child.wait_with_output().map_err(|source| FramesError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    if decoded.len() < wanted.len() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let detail = stderr
            .lines()
            .last()
            .map(str::trim)
            .filter(|line| !line.is_empty())
            .map(ToString::to_string)
            .or_else(|| failure.map(|e| e.to_string()))
            .unwrap_or_else(|| format!("it ended before frame {last}"));
        return Err(FramesError::NotAVideo {
            path: path.to_path_buf(),
            detail,
        });
    }
    Ok(indices
        .iter()
        .filter_map(|index| decoded.iter().find(|f| f.index == *index).cloned())
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_ffmpeg_is_one_clear_error() {
        let error = spawn(
            "ffmpeg",
            Path::new("video.mp4"),
            &mut Command::new("/nonexistent/contphy/ffmpeg"),
        )
        .unwrap_err();
        assert!(matches!(error, FramesError::FfmpegMissing { .. }));
        assert_eq!(
            error.to_string(),
            "`ffmpeg` is not installed, so `video.mp4` cannot be decoded; install ffmpeg (Debian: `apt-get install ffmpeg`) or give a folder of PNG frames"
        );
    }

    #[test]
    fn select_expressions_merge_runs() {
        assert_eq!(select_expression(&[3]), "eq(n\\,3)");
        assert_eq!(
            select_expression(&[0, 1, 2, 7, 9, 10]),
            "between(n\\,0\\,2)+eq(n\\,7)+between(n\\,9\\,10)"
        );
    }

    #[test]
    fn png_folders_read_in_order_and_name_their_problems() {
        let dir = tempfile::tempdir().unwrap();
        for index in 0..3_u8 {
            let image = image::RgbImage::from_pixel(4, 2, image::Rgb([index, 10, 20]));
            image
                .save(dir.path().join(format!("frame_{index:05}.png")))
                .unwrap();
        }
        let source = FrameSource::open(dir.path()).unwrap();
        assert_eq!(
            source.info().unwrap(),
            VideoInfo {
                width: 4,
                height: 2,
                frame_count: 3
            }
        );
        let frames = source.read(&[2, 0, 2]).unwrap();
        let first_pixels: Vec<u8> = frames.iter().map(|f| f.pixel(0, 0).unwrap()[0]).collect();
        assert_eq!(first_pixels, vec![2, 0, 2]);
        let error = source.read(&[3]).unwrap_err().to_string();
        assert!(
            error.ends_with("has 3 frames; frame 3 does not exist"),
            "{error}"
        );
        image::RgbImage::from_pixel(5, 2, image::Rgb([0, 0, 0]))
            .save(dir.path().join("frame_00003.png"))
            .unwrap();
        let error = source.read(&[3]).unwrap_err().to_string();
        assert!(error.contains("frame 3 is 5×2, expected 4×2"), "{error}");
        fs_err::write(dir.path().join("frame_00005.png"), b"not a png").unwrap();
        let error = source.info().unwrap_err().to_string();
        assert!(
            error.contains("without gaps; found frame 5 at position 4"),
            "{error}"
        );
        let missing = FrameSource::open(&dir.path().join("nope")).unwrap_err();
        assert!(missing.to_string().ends_with("does not exist"));
    }
}
