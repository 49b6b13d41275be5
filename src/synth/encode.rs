//! Writing: the `ffmpeg` program fed through a pipe, into a temporary file renamed when
//! complete.

use super::yuv::{bgr_to_yuv420, YuvRange};
use anyhow::{bail, ensure, Context, Result};
use opencv::core::Mat;
use opencv::prelude::*;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};

/// Removes the temporary file unless the render completed.
pub(super) struct TempFile(pub(super) Option<PathBuf>);

impl TempFile {
    pub(super) fn path(&self) -> PathBuf {
        self.0.clone().unwrap_or_default()
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if let Some(p) = self.0.take() {
            let _ = std::fs::remove_file(p);
        }
    }
}

fn temp_name(path: &Path) -> PathBuf {
    crate::fsutil::temp_path(path, true)
}

/// Whether the `ffmpeg` program has the encoder `name` (asked once per process).
fn ffmpeg_has_encoder(name: &str) -> bool {
    static LIST: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    let list = LIST.get_or_init(|| {
        Command::new("ffmpeg")
            .args(["-hide_banner", "-nostdin", "-encoders"])
            .stdin(Stdio::null())
            .stderr(Stdio::null())
            .output()
            .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
            .unwrap_or_default()
    });
    list.lines()
        .any(|l| l.split_whitespace().nth(1) == Some(name))
}

/// `fps` as FFmpeg reads a frame rate: an integer when it is one, else the decimal.
fn rate_arg(fps: f64) -> String {
    if fps.fract() == 0.0 {
        format!("{}", fps as u64)
    } else {
        format!("{fps}")
    }
}

/// The codecs the `ffmpeg` program writes here.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FfmpegCodec {
    /// MJPEG at `-q:v 3` (lossy like a camera's),
    /// with the standard Huffman tables (optimal ones cost the encoder a quarter more
    /// time for files a sixth smaller), on one thread (frame threads cost it a third
    /// more time, and the renderer keeps the other core busy), in `.avi`.
    Mjpeg,
    /// MJPEG as [`FfmpegCodec::Mjpeg`] but 4:4:4 (`yuvj444p`), from BGR frames converted
    /// by ffmpeg: for an odd width or height, which 4:2:0 cannot hold whole.
    Mjpeg444,
    /// H.264 by x264 (`veryfast`, CRF 18) in the container of the file's extension.
    H264,
}

impl FfmpegCodec {
    fn raw(self) -> RawFrames {
        match self {
            FfmpegCodec::Mjpeg => RawFrames::Yuv420(YuvRange::Full),
            FfmpegCodec::Mjpeg444 => RawFrames::Bgr,
            FfmpegCodec::H264 => RawFrames::Yuv420(YuvRange::Limited),
        }
    }
}

/// What the pipe carries: frames converted here to planar Y'CbCr 4:2:0 (even sizes), or
/// the rendered BGR frames as they are (odd sizes, converted by ffmpeg).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum RawFrames {
    Yuv420(YuvRange),
    Bgr,
}

impl RawFrames {
    /// The bytes of a rendered `w` x `h` BGR frame as the pipe takes them (`buf` holds
    /// a conversion).
    pub(super) fn bytes<'a>(
        self,
        bgr: &'a [u8],
        (w, h): (usize, usize),
        buf: &'a mut Vec<u8>,
    ) -> &'a [u8] {
        debug_assert_eq!(bgr.len(), 3 * w * h);
        match self {
            RawFrames::Yuv420(range) => {
                bgr_to_yuv420(bgr, w, h, range, buf);
                buf
            }
            RawFrames::Bgr => bgr,
        }
    }
}

/// Frames piped to the `ffmpeg` program as raw planar Y'CbCr 4:2:0 (or BGR), one after
/// another at a constant rate (every frame kept: `-fps_mode passthrough`), or at the times the
/// `setpts` filters of a variable rate give them (then counted in milliseconds by the
/// encoder and the container). The output carries no
/// version strings or metadata (`bitexact`), and x264 runs a fixed number of threads
/// and no threaded lookahead, so that the same frames give the same bytes on any
/// machine with the same FFmpeg.
pub(super) struct FfmpegPipe {
    child: Child,
    pub(super) stdin: Option<ChildStdin>,
    /// The last lines ffmpeg wrote to stderr, gathered by a thread.
    stderr: Option<std::thread::JoinHandle<Vec<String>>>,
    pub(super) raw: RawFrames,
}

impl FfmpegPipe {
    /// Start ffmpeg writing `path` and hand it the first frame; an error names what
    /// ffmpeg said when it cannot be started or exits before taking that frame.
    fn start(
        path: &Path,
        codec: FfmpegCodec,
        (w, h): (usize, usize),
        fps: f64,
        times: Option<&str>,
        crf: Option<u32>,
        first: &Mat,
    ) -> Result<Self> {
        let raw = codec.raw();
        // `synthetic.crf`: x264's rate factor, or MJPG's quantiser from it.
        let crf = crf.unwrap_or(18);
        let q = (3 + (i64::from(crf) - 18) / 2).clamp(2, 31);
        let mut cmd = Command::new("ffmpeg");
        cmd.args(["-nostdin", "-hide_banner", "-loglevel", "error"])
            .args(["-f", "rawvideo", "-pix_fmt"])
            .arg(match raw {
                RawFrames::Yuv420(YuvRange::Full) => "yuvj420p",
                RawFrames::Yuv420(YuvRange::Limited) => "yuv420p",
                RawFrames::Bgr => "bgr24",
            })
            .args(["-s", &format!("{w}x{h}"), "-r", &rate_arg(fps), "-i", "-"])
            .args(["-map", "0:v", "-an", "-fps_mode", "passthrough"]);
        if let Some(filters) = times {
            cmd.args(["-vf", filters, "-enc_time_base", "1/1000"]);
        }
        match codec {
            FfmpegCodec::Mjpeg | FfmpegCodec::Mjpeg444 => {
                cmd.args([
                    "-c:v",
                    "mjpeg",
                    "-q:v",
                    &q.to_string(),
                    "-huffman",
                    "default",
                ]);
                if codec == FfmpegCodec::Mjpeg444 {
                    cmd.args(["-pix_fmt", "yuvj444p"]);
                }
                cmd.args(["-threads", "1", "-f", "avi"])
            }
            FfmpegCodec::H264 => cmd
                .args([
                    "-c:v",
                    "libx264",
                    "-preset",
                    "veryfast",
                    "-crf",
                    &crf.to_string(),
                ])
                .args(["-pix_fmt", "yuv420p", "-threads", "4"])
                // With x264's threaded lookahead (on by default with frame threads) the
                // file depended on the threads' timing: the same frames piped in six
                // times gave three different files on a two-core machine (a 960x540
                // sweep twin at 60 frames/s; 80 of its 2361 frames differed). Without it,
                // 9 of 9 gave the same bytes, in the same time.
                .args(["-x264-params", "sync-lookahead=0"])
                .args(["-color_range", "tv", "-colorspace", "smpte170m"]),
        };
        cmd.args(["-fflags", "+bitexact", "-flags:v", "+bitexact"])
            .args(["-map_metadata", "-1"])
            .args([
                "-metadata",
                &format!("comment={}", crate::clobber::TWIN_MARK),
                "-y",
            ])
            .arg(path)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        let mut child = cmd
            .spawn()
            .with_context(|| format!("{}: cannot start ffmpeg", path.display()))?;
        let stdin = child.stdin.take();
        let err = child.stderr.take().expect("piped");
        let stderr = std::thread::spawn(move || {
            let mut tail = std::collections::VecDeque::new();
            for line in BufReader::new(err).lines() {
                let Ok(line) = line else { break };
                if tail.len() == 8 {
                    tail.pop_front();
                }
                tail.push_back(line);
            }
            tail.into()
        });
        let mut pipe = Self {
            child,
            stdin,
            stderr: Some(stderr),
            raw,
        };
        let mut buf = Vec::new();
        let bytes = raw.bytes(first.data_bytes()?, (w, h), &mut buf);
        if let Err(e) = pipe.write(bytes) {
            let why = pipe.abort();
            bail!(
                "{}: ffmpeg did not take the first frame: {}",
                path.display(),
                if why.is_empty() { e.to_string() } else { why }
            );
        }
        Ok(pipe)
    }

    fn write(&mut self, yuv: &[u8]) -> std::io::Result<()> {
        match &mut self.stdin {
            Some(s) => s.write_all(yuv),
            None => Err(std::io::ErrorKind::BrokenPipe.into()),
        }
    }

    /// ffmpeg's last words on stderr, one line.
    fn stderr_tail(&mut self) -> String {
        self.stderr
            .take()
            .and_then(|t| t.join().ok())
            .unwrap_or_default()
            .join(" | ")
    }

    /// Stop ffmpeg (the file is incomplete) and return its last words.
    pub(super) fn abort(&mut self) -> String {
        self.stdin = None;
        let _ = self.child.kill();
        let _ = self.child.wait();
        self.stderr_tail()
    }

    /// Close the pipe and wait for ffmpeg to finish the file.
    pub(super) fn finish(&mut self, path: &Path) -> Result<()> {
        self.stdin = None;
        let status = self
            .child
            .wait()
            .with_context(|| format!("{}: waiting for ffmpeg", path.display()))?;
        let tail = self.stderr_tail();
        ensure!(
            status.success(),
            "{}: ffmpeg failed ({status}): {}",
            path.display(),
            if tail.is_empty() { "no message" } else { &tail }
        );
        Ok(())
    }
}

impl Drop for FfmpegPipe {
    fn drop(&mut self) {
        if self.stdin.is_some() {
            self.abort();
        }
    }
}

/// Start the `ffmpeg` program writing `codec` into a temporary name for `fin`.
fn start_ffmpeg(
    fin: &Path,
    codec: FfmpegCodec,
    (w, h): (usize, usize),
    fps: f64,
    times: Option<&str>,
    crf: Option<u32>,
    first: &Mat,
) -> Result<(FfmpegPipe, TempFile)> {
    let tmp = TempFile(Some(temp_name(fin)));
    let pipe = FfmpegPipe::start(&tmp.path(), codec, (w, h), fps, times, crf, first)?;
    Ok((pipe, tmp))
}

/// Open the `ffmpeg` program's encoder and give it the rendered frame 0. Unless `out`
/// ends in `.avi`: H.264 by x264 into `out`. Otherwise, or when the size is odd (4:2:0
/// H.264 needs it even) or this ffmpeg has no x264: MJPG into `out` with `.avi` (4:4:4
/// for an odd size). Returns the writer, the temporary and final paths and the codec's
/// name with the container and who wrote it.
///
/// The `ffmpeg` program is required (OpenCV's `videoio` is not linked, see
/// [`crate::picture`]): [`super::render`] says so before anything is written.
pub(super) fn open_writer(
    out: &Path,
    (w, h): (usize, usize),
    fps: f64,
    times: Option<&str>,
    crf: Option<u32>,
    first: &Mat,
) -> Result<(FfmpegPipe, TempFile, PathBuf, String)> {
    let vfr = if times.is_some() {
        ", variable frame rate"
    } else {
        ""
    };
    let odd = w % 2 == 1 || h % 2 == 1;
    let ext = out
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if ext != "avi" {
        let why = if odd {
            "H.264 needs an even width and height"
        } else if !ffmpeg_has_encoder("libx264") {
            "this ffmpeg has no H.264 encoder (libx264)"
        } else {
            let (pipe, tmp) = start_ffmpeg(out, FfmpegCodec::H264, (w, h), fps, times, crf, first)?;
            let codec = format!("H.264 ({ext}, ffmpeg{vfr})");
            return Ok((pipe, tmp, out.to_path_buf(), codec));
        };
        eprintln!(
            "{}: {why}; writing MJPG to {} instead",
            out.display(),
            out.with_extension("avi").display()
        );
    }
    let fin = out.with_extension("avi");
    let (codec, name) = if odd {
        (FfmpegCodec::Mjpeg444, "MJPG 4:4:4")
    } else {
        (FfmpegCodec::Mjpeg, "MJPG")
    };
    let (pipe, tmp) = start_ffmpeg(&fin, codec, (w, h), fps, times, crf, first)?;
    Ok((pipe, tmp, fin, format!("{name} (avi, ffmpeg{vfr})")))
}
