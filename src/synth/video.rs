//! Writing rendered frames: PNG folders (`frames/output_Full_ori/frame_00000.png` and
//! `frames/output_Full_seg/...`, the paper's extracted-frame layout) and mp4 files encoded by an
//! `ffmpeg` subprocess with the release's settings (`libx264 -profile:v high -crf 20 -pix_fmt
//! yuv420p`, 30 fps), fed raw RGB over a pipe so no frame is held longer than it takes to write.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};

use super::SynthError;

/// Which frame files a generated video gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameOutput {
    /// `output_Full.mp4` and `output_Full_seg.mp4` (needs ffmpeg).
    Mp4,
    /// PNG folders only.
    Png,
    /// Both.
    Both,
    /// Annotations only, no frame files (boxes and masks are still rendered and recorded).
    None,
}

impl FrameOutput {
    /// Whether mp4 files are written.
    pub fn mp4(self) -> bool {
        matches!(self, FrameOutput::Mp4 | FrameOutput::Both)
    }

    /// Whether PNG folders are written.
    pub fn png(self) -> bool {
        matches!(self, FrameOutput::Png | FrameOutput::Both)
    }
}

use crate::perception::frames::{
    RGB_FRAME_DIR, RGB_VIDEO_FILE, SEGMENTATION_FRAME_DIR, SEGMENTATION_VIDEO_FILE,
};

/// An mp4 being encoded.
struct Encoder {
    path: PathBuf,
    child: Child,
    stdin: Option<ChildStdin>,
}

impl Encoder {
    fn start(path: &Path, width: u32, height: u32) -> Result<Encoder, SynthError> {
        let ffmpeg = std::env::var_os("CONTPHY_FFMPEG_DIR").map_or_else(
            || PathBuf::from("ffmpeg"),
            |dir| Path::new(&dir).join("ffmpeg"),
        );
        let mut child = Command::new(ffmpeg)
            .args([
                "-y", "-v", "error", "-nostdin", "-f", "rawvideo", "-pix_fmt", "rgb24",
            ])
            .args([
                "-s",
                &format!("{width}x{height}"),
                "-framerate",
                "30",
                "-i",
                "-",
            ])
            .args(["-c:v", "libx264", "-profile:v", "high", "-crf", "20"])
            .args([
                "-preset", "veryfast", "-pix_fmt", "yuv420p", "-threads", "1",
            ])
            .arg(path)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|source| {
                if source.kind() == std::io::ErrorKind::NotFound {
                    SynthError::FfmpegMissing
                } else {
                    SynthError::Io {
                        path: path.to_path_buf(),
                        source,
                    }
                }
            })?;
        let stdin = child.stdin.take();
        Ok(Encoder {
            path: path.to_path_buf(),
            child,
            stdin,
        })
    }

    fn push(&mut self, rgb: &[u8]) -> Result<(), SynthError> {
        let Some(stdin) = self.stdin.as_mut() else {
            return Ok(());
        };
        if stdin.write_all(rgb).is_err() {
            // ffmpeg stopped reading: its own message says why.
            self.stdin = None;
            return self.finish_inner();
        }
        Ok(())
    }

    fn finish_inner(&mut self) -> Result<(), SynthError> {
        self.stdin = None;
        let mut stderr = String::new();
        if let Some(mut pipe) = self.child.stderr.take() {
            use std::io::Read;
            let _ = pipe.read_to_string(&mut stderr);
        }
        let status = self.child.wait().map_err(|source| SynthError::Io {
            path: self.path.clone(),
            source,
        })?;
        if status.success() {
            Ok(())
        } else {
            Err(SynthError::Encode {
                path: self.path.clone(),
                detail: stderr
                    .lines()
                    .last()
                    .unwrap_or("ffmpeg failed")
                    .trim()
                    .to_string(),
            })
        }
    }

    fn finish(mut self) -> Result<(), SynthError> {
        self.finish_inner()
    }
}

impl Drop for Encoder {
    fn drop(&mut self) {
        if self.stdin.is_some() {
            // Abandoned (an error elsewhere): stop ffmpeg rather than leave it waiting.
            self.stdin = None;
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// Where one video's frames go.
pub(crate) struct FrameSink {
    dir: PathBuf,
    output: FrameOutput,
    width: u32,
    height: u32,
    encoders: Option<(Encoder, Encoder)>,
}

impl FrameSink {
    /// Opens the sinks of a video folder `dir` (created already).
    pub(crate) fn open(
        dir: &Path,
        output: FrameOutput,
        width: u32,
        height: u32,
    ) -> Result<FrameSink, SynthError> {
        if output.png() {
            for sub in [RGB_FRAME_DIR, SEGMENTATION_FRAME_DIR] {
                let path = dir.join(sub);
                fs_err::create_dir_all(&path).map_err(|source| SynthError::Io { path, source })?;
            }
        }
        let encoders = if output.mp4() {
            Some((
                Encoder::start(&dir.join(RGB_VIDEO_FILE), width, height)?,
                Encoder::start(&dir.join(SEGMENTATION_VIDEO_FILE), width, height)?,
            ))
        } else {
            None
        };
        Ok(FrameSink {
            dir: dir.to_path_buf(),
            output,
            width,
            height,
            encoders,
        })
    }

    /// Writes frame `index` (RGB image and segmentation image, both RGB bytes).
    pub(crate) fn push(
        &mut self,
        index: usize,
        rgb: &[u8],
        segmentation: &[u8],
    ) -> Result<(), SynthError> {
        if self.output.png() {
            let name = format!("frame_{index:05}.png");
            write_png(
                &self.dir.join(RGB_FRAME_DIR).join(&name),
                self.width,
                self.height,
                rgb,
            )?;
            write_png(
                &self.dir.join(SEGMENTATION_FRAME_DIR).join(&name),
                self.width,
                self.height,
                segmentation,
            )?;
        }
        if let Some((color, seg)) = self.encoders.as_mut() {
            color.push(rgb)?;
            seg.push(segmentation)?;
        }
        Ok(())
    }

    /// Finishes the mp4 files.
    pub(crate) fn finish(self) -> Result<(), SynthError> {
        if let Some((color, seg)) = self.encoders {
            color.finish()?;
            seg.finish()?;
        }
        Ok(())
    }
}

/// Writes an RGB image as PNG (fast compression: frames are many and mostly flat).
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), SynthError> {
    use image::ImageEncoder;
    let file = fs_err::File::create(path).map_err(|source| SynthError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let writer = std::io::BufWriter::new(file);
    let encoder = image::codecs::png::PngEncoder::new_with_quality(
        writer,
        image::codecs::png::CompressionType::Fast,
        image::codecs::png::FilterType::Sub,
    );
    encoder
        .write_image(rgb, width, height, image::ExtendedColorType::Rgb8)
        .map_err(|error| SynthError::Encode {
            path: path.to_path_buf(),
            detail: error.to_string(),
        })
}
