//! Writing: the `ffmpeg` program fed through a pipe, or OpenCV's `VideoWriter`, into a
//! temporary file renamed when complete.

use super::yuv::{bgr_to_yuv420, YuvRange};
use anyhow::{bail, ensure, Context, Result};
use opencv::core::{Mat, Size};
use opencv::prelude::*;
use opencv::videoio;
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
    /// MJPEG at `-q:v 3` (about the quality of OpenCV's MJPG; lossy like a camera's),
    /// with the standard Huffman tables (optimal ones cost the encoder a quarter more
    /// time for files a sixth smaller), on one thread (frame threads cost it a third
    /// more time, and the renderer keeps the other core busy), in `.avi`.
    Mjpeg,
    /// H.264 by x264 (`veryfast`, CRF 18) in the container of the file's extension.
    H264,
}

impl FfmpegCodec {
    fn range(self) -> YuvRange {
        match self {
            FfmpegCodec::Mjpeg => YuvRange::Full,
            FfmpegCodec::H264 => YuvRange::Limited,
        }
    }
}

/// Frames piped to the `ffmpeg` program as raw planar Y'CbCr 4:2:0, one after another at
/// a constant rate (every frame kept: `-fps_mode passthrough`), or at the times the
/// `setpts` filters of a variable rate give them (then counted in milliseconds by the
/// encoder and the container). The output carries no
/// version strings or metadata (`bitexact`), and x264 runs a fixed number of threads,
/// so that the same frames give the same bytes on any machine with the same FFmpeg.
pub(super) struct FfmpegPipe {
    child: Child,
    pub(super) stdin: Option<ChildStdin>,
    /// The last lines ffmpeg wrote to stderr, gathered by a thread.
    stderr: Option<std::thread::JoinHandle<Vec<String>>>,
    pub(super) range: YuvRange,
}

impl FfmpegPipe {
    /// Start ffmpeg writing `path` and hand it the first frame. `Ok(None)` when ffmpeg
    /// cannot be started or exits before taking that frame (said on stderr): the caller
    /// writes with OpenCV instead.
    fn start(
        path: &Path,
        codec: FfmpegCodec,
        (w, h): (usize, usize),
        fps: f64,
        times: Option<&str>,
        first: &Mat,
    ) -> Result<Option<Self>> {
        let range = codec.range();
        let mut cmd = Command::new("ffmpeg");
        cmd.args(["-nostdin", "-hide_banner", "-loglevel", "error"])
            .args(["-f", "rawvideo", "-pix_fmt"])
            .arg(match range {
                YuvRange::Full => "yuvj420p",
                YuvRange::Limited => "yuv420p",
            })
            .args(["-s", &format!("{w}x{h}"), "-r", &rate_arg(fps), "-i", "-"])
            .args(["-map", "0:v", "-an", "-fps_mode", "passthrough"]);
        if let Some(filters) = times {
            cmd.args(["-vf", filters, "-enc_time_base", "1/1000"]);
        }
        match codec {
            FfmpegCodec::Mjpeg => cmd
                .args(["-c:v", "mjpeg", "-q:v", "3", "-huffman", "default"])
                .args(["-threads", "1", "-f", "avi"]),
            FfmpegCodec::H264 => cmd
                .args(["-c:v", "libx264", "-preset", "veryfast", "-crf", "18"])
                .args(["-pix_fmt", "yuv420p", "-threads", "4"])
                .args(["-color_range", "tv", "-colorspace", "smpte170m"]),
        };
        cmd.args(["-fflags", "+bitexact", "-flags:v", "+bitexact"])
            .args(["-map_metadata", "-1", "-y"])
            .arg(path)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        let mut child = match cmd.spawn() {
            Ok(c) => c,
            Err(e) => {
                eprintln!(
                    "{}: cannot start ffmpeg ({e}); writing with OpenCV instead",
                    path.display()
                );
                return Ok(None);
            }
        };
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
            range,
        };
        let mut yuv = Vec::new();
        bgr_to_yuv420(first.data_bytes()?, w, h, range, &mut yuv);
        if let Err(e) = pipe.write(&yuv) {
            let why = pipe.abort();
            eprintln!(
                "{}: ffmpeg did not take the first frame ({}); writing with OpenCV instead",
                path.display(),
                if why.is_empty() { e.to_string() } else { why }
            );
            return Ok(None);
        }
        Ok(Some(pipe))
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

/// Where the frames go.
pub(super) enum Sink {
    /// The `ffmpeg` program, which already has frame 0.
    Ffmpeg(FfmpegPipe),
    OpenCv(videoio::VideoWriter),
}

/// Try to open a writer with one back-end and codec.
fn try_writer(
    path: &Path,
    api: i32,
    cc: [char; 4],
    fps: f64,
    size: Size,
) -> Result<Option<videoio::VideoWriter>> {
    let fourcc = videoio::VideoWriter::fourcc(cc[0], cc[1], cc[2], cc[3])?;
    match videoio::VideoWriter::new_with_backend(path, api, fourcc, fps, size, true) {
        Ok(wr) if wr.is_opened()? => Ok(Some(wr)),
        _ => {
            let _ = std::fs::remove_file(path);
            Ok(None)
        }
    }
}

/// Start the `ffmpeg` program writing `codec` into a temporary name for `fin`, if it is
/// installed (with x264 for H.264; its MJPEG encoder is always built in) and the size is
/// even (4:2:0).
fn try_ffmpeg(
    fin: &Path,
    codec: FfmpegCodec,
    (w, h): (usize, usize),
    fps: f64,
    times: Option<&str>,
    first: &Mat,
) -> Result<Option<(Sink, TempFile)>> {
    let usable = crate::video::have_ffmpeg()
        && (codec == FfmpegCodec::Mjpeg || ffmpeg_has_encoder("libx264"));
    if w % 2 == 1 || h % 2 == 1 || !usable {
        return Ok(None);
    }
    let tmp = TempFile(Some(temp_name(fin)));
    Ok(
        FfmpegPipe::start(&tmp.path(), codec, (w, h), fps, times, first)?
            .map(|p| (Sink::Ffmpeg(p), tmp)),
    )
}

/// Open a writer and give it the rendered frame 0 when it is the `ffmpeg` program.
/// Unless `out` ends in `.avi`: H.264 into `out`, by ffmpeg's x264, else by OpenCV's
/// FFmpeg back-end (fourcc `avc1`, else `H264`). Otherwise, or failing that: MJPG into
/// `out` with `.avi`, by ffmpeg, else by OpenCV (FFmpeg's encoder, else OpenCV's own at
/// quality 75; for odd sizes OpenCV's own first). ffmpeg is not used for odd sizes
/// (4:2:0). Returns the writer, the temporary and final paths and the codec's name
/// with the container and who wrote it.
///
/// OpenCV 4.6 leaves x264 at its default preset (`medium`, the slowest part of a
/// render: its `OPENCV_FFMPEG_WRITER_OPTIONS` do not reach the encoder in this
/// version), and converts BGR to Y'CbCr without a fast path: hence ffmpeg first, fed
/// frames converted here. OpenCV's MJPG is preferred from FFmpeg because OpenCV 4.6's
/// own MJPEG encoder writes an invalid DC coefficient in bright frames at some sizes (a
/// uniform frame brighter than 200 at 640x360: FFmpeg then reports `error dc` when
/// reading it).
///
/// `times`, the `setpts` filters of a variable frame rate, need ffmpeg (OpenCV's writer
/// has a constant rate): without it, or at an odd size, the render is refused.
pub(super) fn open_writer(
    out: &Path,
    (w, h): (usize, usize),
    fps: f64,
    times: Option<&str>,
    first: &Mat,
) -> Result<(Sink, TempFile, PathBuf, String)> {
    let vfr = if times.is_some() {
        ", variable frame rate"
    } else {
        ""
    };
    if times.is_some() {
        ensure!(
            w % 2 == 0 && h % 2 == 0,
            "a variable frame rate (`synthetic.vfr_jitter`) needs an even width and height, not {w}x{h}"
        );
        ensure!(
            crate::video::have_ffmpeg(),
            "a variable frame rate (`synthetic.vfr_jitter`) needs the ffmpeg program"
        );
    }
    let size = Size::new(w as i32, h as i32);
    let ext = out
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if ext != "avi" {
        let why = if w % 2 == 1 || h % 2 == 1 {
            "H.264 needs an even width and height"
        } else {
            if let Some((sink, tmp)) =
                try_ffmpeg(out, FfmpegCodec::H264, (w, h), fps, times, first)?
            {
                return Ok((
                    sink,
                    tmp,
                    out.to_path_buf(),
                    format!("H.264 ({ext}, ffmpeg{vfr})"),
                ));
            }
            ensure!(
                times.is_none(),
                "{}: ffmpeg cannot write H.264 (no libx264?), and OpenCV's writer has no variable frame rate (`synthetic.vfr_jitter`)",
                out.display()
            );
            for cc in [['a', 'v', 'c', '1'], ['H', '2', '6', '4']] {
                let tmp = TempFile(Some(temp_name(out)));
                let path = tmp.path();
                if let Some(wr) = try_writer(&path, videoio::CAP_FFMPEG, cc, fps, size)? {
                    let codec = format!("H.264 ({ext}, OpenCV)");
                    return Ok((Sink::OpenCv(wr), tmp, out.to_path_buf(), codec));
                }
            }
            "neither ffmpeg nor this OpenCV can write H.264"
        };
        eprintln!(
            "{}: {why}; writing MJPG to {} instead",
            out.display(),
            out.with_extension("avi").display()
        );
    }
    let fin = out.with_extension("avi");
    if let Some((sink, tmp)) = try_ffmpeg(&fin, FfmpegCodec::Mjpeg, (w, h), fps, times, first)? {
        return Ok((sink, tmp, fin, format!("MJPG (avi, ffmpeg{vfr})")));
    }
    ensure!(
        times.is_none(),
        "{}: ffmpeg did not start, and OpenCV's writer has no variable frame rate (`synthetic.vfr_jitter`)",
        fin.display()
    );
    // FFmpeg's MJPG (4:2:0) drops the last row or column of an odd size.
    let apis = if w % 2 == 1 || h % 2 == 1 {
        [videoio::CAP_OPENCV_MJPEG, videoio::CAP_FFMPEG]
    } else {
        [videoio::CAP_FFMPEG, videoio::CAP_OPENCV_MJPEG]
    };
    for api in apis {
        let tmp = TempFile(Some(temp_name(&fin)));
        let path = tmp.path();
        if let Some(mut wr) = try_writer(&path, api, ['M', 'J', 'P', 'G'], fps, size)? {
            // Honoured by OpenCV's own encoder only (FFmpeg's keeps its default).
            let _ = wr.set(videoio::VIDEOWRITER_PROP_QUALITY, 75.0);
            return Ok((Sink::OpenCv(wr), tmp, fin, "MJPG (avi, OpenCV)".into()));
        }
    }
    bail!("neither ffmpeg nor OpenCV can write H.264 or MJPG")
}
