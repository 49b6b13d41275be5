//! Reading video frames: the slow, machine-dependent stage, behind the [`FrameSource`]
//! trait so that everything after it can be tested with frames made in memory.
//!
//! [`FfmpegSource`] is the fast path. It has the `ffmpeg` program decode, crop to the
//! region of interest and hand over only the luma plane (`extractplanes=y`): no colour
//! conversion at all, and only the pixels the detector looks at cross the pipe. Frame
//! times come from each decoded frame's own timestamp (`showinfo`), not from the
//! container's nominal rate. The `ffmpeg` program (and its `ffprobe`) is required:
//! OpenCV's `videoio` is not linked (see [`crate::picture`] for why), and a video is
//! refused, with the package to install, when the program is missing.

use anyhow::{bail, Context, Result};
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;

/// A rectangle of the frame, px.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Roi {
    pub x: u32,
    pub y: u32,
    pub w: u32,
    pub h: u32,
}

/// What a video is, as the container tells it.
#[derive(Clone, Debug)]
pub struct VideoInfo {
    pub width: u32,
    pub height: u32,
    /// Frame count from the header (may be wrong; frames are counted as decoded).
    pub frames_header: Option<u64>,
    pub duration_s: Option<f64>,
    pub codec: String,
}

/// One decoded grey frame (row-major, `width` bytes per row). `Frame::default()` is an
/// empty one for a [`FrameSource`] to fill.
#[derive(Clone, Debug, Default)]
pub struct Frame {
    /// 0-based index among decoded frames.
    pub index: u64,
    /// Timestamp of the frame, s.
    pub t_s: f64,
    pub width: usize,
    pub height: usize,
    pub data: Vec<u8>,
}

/// A stream of grey frames.
pub trait FrameSource {
    /// Fill `frame` with the next frame; `Ok(false)` at the end of the video.
    fn next_frame(&mut self, frame: &mut Frame) -> Result<bool>;
}

/// Whether the `ffmpeg` program is installed: an executable file of that name in a
/// folder of `PATH` (looked up once per process). Not by running it: ffmpeg loads about
/// 200 shared libraries, 50 ms a start, which a workflow running one process per stage
/// would pay on every job; a program that is found but cannot run fails where it is
/// used, with its own message.
pub fn have_ffmpeg() -> bool {
    static HAVE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *HAVE.get_or_init(|| on_path("ffmpeg"))
}

/// Whether an executable file `name` is in a folder of `PATH` as the program would be
/// found when started (an empty entry is the working folder; without `PATH`, the
/// system's default `/bin:/usr/bin`).
pub fn on_path(name: &str) -> bool {
    use std::os::unix::fs::PermissionsExt;
    let path = std::env::var_os("PATH").unwrap_or_else(|| "/bin:/usr/bin".into());
    std::env::split_paths(&path).any(|dir| {
        std::fs::metadata(dir.join(name))
            .is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
    })
}

/// Probe a video's size and header facts (`ffprobe`; no decoding).
pub fn probe(path: &Path) -> Result<VideoInfo> {
    let meta =
        std::fs::metadata(path).with_context(|| format!("{}: cannot read", path.display()))?;
    if meta.len() == 0 {
        bail!(
            "{}: the file is empty (0 bytes); no frame to read",
            path.display()
        );
    }
    for program in ["ffmpeg", "ffprobe"] {
        if !on_path(program) {
            bail!(
                "{}: decoding needs the {program} program, which is not on PATH (Debian: apt-get install ffmpeg)",
                path.display()
            );
        }
    }
    probe_ffprobe(path)
}

fn probe_ffprobe(path: &Path) -> Result<VideoInfo> {
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-select_streams", "v:0", "-show_entries"])
        .arg("stream=width,height,nb_frames,codec_name,duration")
        .args(["-of", "default=noprint_wrappers=1"])
        .arg(path)
        .stdin(Stdio::null())
        .output()
        .with_context(|| format!("{}: cannot run ffprobe", path.display()))?;
    let text = String::from_utf8_lossy(&out.stdout);
    let field = |k: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(&format!("{k}=")))
            .map(str::trim)
            .filter(|v| !v.is_empty() && *v != "N/A")
    };
    let (Some(w), Some(h)) = (
        field("width").and_then(|v| v.parse::<u32>().ok()),
        field("height").and_then(|v| v.parse::<u32>().ok()),
    ) else {
        let err = String::from_utf8_lossy(&out.stderr);
        let why = err
            .lines()
            .map(|l| l.rsplit("] ").next().unwrap_or(l).trim())
            .find(|l| !l.is_empty())
            .unwrap_or("no video stream");
        bail!(
            "{}: cannot open as a video ({why}); no frame decoded",
            path.display()
        );
    };
    Ok(VideoInfo {
        width: w,
        height: h,
        frames_header: field("nb_frames").and_then(|v| v.parse().ok()),
        duration_s: field("duration").and_then(|v| v.parse().ok()),
        codec: field("codec_name").unwrap_or("?").to_string(),
    })
}

/// Decoding by the `ffmpeg` program: luma only, cropped, with per-frame timestamps.
pub struct FfmpegSource {
    path: PathBuf,
    child: Child,
    /// Frames read ahead by a reader thread, so that decoding goes on while a frame is
    /// processed (a pipe buffer holds less than one frame).
    frames: mpsc::Receiver<Chunk>,
    /// Spent buffers going back to the reader (no allocation per frame).
    spent: mpsc::Sender<Vec<u8>>,
    times: mpsc::Receiver<f64>,
    errors: std::sync::Arc<std::sync::Mutex<Vec<String>>>,
    width: usize,
    height: usize,
    next_index: u64,
    finished: bool,
}

impl FfmpegSource {
    /// Start decoding `path`, cropped to `roi` (whole frame if `None`) and optionally
    /// scaled down by an integer `shrink` (for quick looks at large frames).
    pub fn open(path: &Path, info: &VideoInfo, roi: Option<Roi>, shrink: u32) -> Result<Self> {
        let roi = roi.unwrap_or(Roi {
            x: 0,
            y: 0,
            w: info.width,
            h: info.height,
        });
        // `exact`: without it a subsampled (4:2:0) video is cropped at even x and y,
        // one pixel off the region the caller maps coordinates with.
        let mut filters = format!("crop={}:{}:{}:{}:exact=1", roi.w, roi.h, roi.x, roi.y);
        let (mut width, mut height) = (roi.w as usize, roi.h as usize);
        if shrink > 1 {
            width /= shrink as usize;
            height /= shrink as usize;
            filters.push_str(&format!(",scale={width}:{height}:flags=area,format=gray"));
        } else {
            filters.push_str(",extractplanes=y");
        }
        filters.push_str(",showinfo=checksum=0");
        // After the times are read, the raw output is numbered 0, 1, 2, ...: a variable
        // frame rate's frames (millisecond times from a phone) could otherwise land on
        // one tick of the output's coarser time base, which the muxer refuses as out of
        // order (and that refusal would read as a damaged video).
        filters.push_str(",settb=1/1000000,setpts=N");
        let mut child = Command::new("ffmpeg")
            // `level+`: every line carries its severity as `[error]`, `[info]`, ...,
            // so complaints are told by the decoder's own level, not by their words.
            .args([
                "-nostdin",
                "-hide_banner",
                "-nostats",
                "-v",
                "level+info",
                "-i",
            ])
            .arg(path)
            .args([
                "-map",
                "0:v:0",
                "-an",
                "-sn",
                "-fps_mode",
                "passthrough",
                "-vf",
            ])
            .arg(&filters)
            .args(["-f", "rawvideo", "-"])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .with_context(|| format!("{}: cannot start ffmpeg", path.display()))?;
        let mut stdout = child.stdout.take().expect("piped");
        let stderr = child.stderr.take().expect("piped");
        let frame_len = width * height;
        // A pipe holds 64 KiB by default: a frame of the region crossed it in several
        // writes, each waking the reader and the decoder in turn. Room for a frame or
        // two (up to the system's limit for an unprivileged pipe) halves the handovers.
        // Best effort: a kernel that refuses keeps the default, and the data is the same.
        let _ = rustix::pipe::fcntl_setpipe_size(&stdout, (2 * frame_len).clamp(1 << 16, PIPE_MAX));
        let (frames_tx, frames) = mpsc::sync_channel::<Chunk>(READ_AHEAD);
        let (spent, spent_rx) = mpsc::channel::<Vec<u8>>();
        std::thread::spawn(move || loop {
            let mut buf = spent_rx.try_recv().unwrap_or_default();
            buf.resize(frame_len, 0);
            let mut got = 0;
            while got < frame_len {
                match stdout.read(&mut buf[got..]) {
                    Ok(0) => break,
                    Ok(k) => got += k,
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                    Err(e) => {
                        let _ = frames_tx.send(Chunk::Failed(e.to_string()));
                        return;
                    }
                }
            }
            let chunk = if got == frame_len {
                Chunk::Frame(buf)
            } else {
                Chunk::End { partial: got > 0 }
            };
            let end = !matches!(chunk, Chunk::Frame(_));
            if frames_tx.send(chunk).is_err() || end {
                return;
            }
        });
        let (tx, times) = mpsc::channel();
        let errors = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        let errs = errors.clone();
        std::thread::spawn(move || {
            let mut tb = 0.0f64;
            // One line per frame: read into one buffer.
            let mut reader = BufReader::new(stderr);
            let mut line = String::new();
            loop {
                line.clear();
                match reader.read_line(&mut line) {
                    Ok(0) | Err(_) => break,
                    Ok(_) => {}
                }
                let line = line.trim_end_matches(['\n', '\r']);
                if let Some(rest) = line.split("config in time_base: ").nth(1) {
                    let frac = rest.split(',').next().unwrap_or("");
                    if let Some((a, b)) = frac.split_once('/') {
                        if let (Ok(a), Ok(b)) = (a.trim().parse::<f64>(), b.trim().parse::<f64>()) {
                            if b != 0.0 {
                                tb = a / b;
                            }
                        }
                    }
                } else if line.contains("showinfo") && line.contains(" pts:") {
                    let pts = line
                        .split(" pts:")
                        .nth(1)
                        .and_then(|s| s.split_whitespace().next())
                        .and_then(|s| s.parse::<f64>().ok());
                    let pts_time = line
                        .split("pts_time:")
                        .nth(1)
                        .and_then(|s| s.split_whitespace().next())
                        .and_then(|s| s.parse::<f64>().ok());
                    let t = match (pts, pts_time) {
                        (Some(p), _) if tb > 0.0 => p * tb,
                        (_, Some(t)) => t,
                        _ => f64::NAN,
                    };
                    if tx.send(t).is_err() {
                        break;
                    }
                } else if decoder_complaint(line) {
                    if let Ok(mut e) = errs.lock() {
                        if e.len() < 8 {
                            e.push(line.trim().to_string());
                        }
                    }
                }
            }
        });
        Ok(Self {
            path: path.to_path_buf(),
            child,
            frames,
            spent,
            times,
            errors,
            width,
            height,
            next_index: 0,
            finished: false,
        })
    }

    fn fail_message(&self) -> String {
        // The decoder's first complaint, without its "[h264 @ 0x...]" prefix.
        let why = self
            .errors
            .lock()
            .ok()
            .and_then(|e| e.first().cloned())
            .map(|l| l.rsplit("] ").next().unwrap_or(&l).trim().to_string());
        let last = if self.next_index == 0 {
            "no frame decoded".to_string()
        } else {
            format!("last good frame {}", self.next_index - 1)
        };
        match why {
            Some(w) => format!(
                "{}: truncated or damaged video ({last}): {w}",
                self.path.display()
            ),
            None => format!("{}: decoding failed ({last})", self.path.display()),
        }
    }
}

/// Whether an ffmpeg log line (with `-v level+...`) is an error the decoder reports:
/// its severity tag is `[error]`, `[fatal]` or `[panic]`. Nothing else is judged, so a
/// file named `mirror.mp4` (quoted on `[info]` lines) is not taken for a damaged one.
fn decoder_complaint(line: &str) -> bool {
    ["[error] ", "[fatal] ", "[panic] "]
        .iter()
        .any(|tag| line.starts_with(tag) || line.contains(&format!("] {tag}")))
}

/// What the reader thread hands over.
enum Chunk {
    Frame(Vec<u8>),
    /// The stream ended; `partial` if it ended inside a frame.
    End {
        partial: bool,
    },
    Failed(String),
}

/// Frames read ahead of the detector (flat memory: a few frames of the cropped region).
const READ_AHEAD: usize = 6;

/// The largest pipe buffer asked of the kernel for the decoder's output, bytes: Linux's
/// default `/proc/sys/fs/pipe-max-size` (what an unprivileged process may ask).
const PIPE_MAX: usize = 1 << 20;

impl FrameSource for FfmpegSource {
    fn next_frame(&mut self, frame: &mut Frame) -> Result<bool> {
        if self.finished {
            return Ok(false);
        }
        let chunk = self.frames.recv().unwrap_or(Chunk::End { partial: false });
        let partial = match chunk {
            Chunk::Frame(buf) => {
                let old = std::mem::replace(&mut frame.data, buf);
                let _ = self.spent.send(old);
                let t = self.times.recv().unwrap_or(f64::NAN);
                frame.index = self.next_index;
                frame.t_s = t;
                frame.width = self.width;
                frame.height = self.height;
                self.next_index += 1;
                return Ok(true);
            }
            Chunk::Failed(e) => {
                self.finished = true;
                let _ = self.child.kill();
                let _ = self.child.wait();
                bail!("{}: reading frames from ffmpeg: {e}", self.path.display());
            }
            Chunk::End { partial } => partial,
        };
        self.finished = true;
        let status = self.child.wait()?;
        if partial || !status.success() {
            bail!("{}", self.fail_message());
        }
        // A clean end; a decoder that met damage but carried on still says so.
        let errs = self.errors.lock().map(|e| e.clone()).unwrap_or_default();
        if !errs.is_empty() {
            bail!("{}", self.fail_message());
        }
        Ok(false)
    }
}

impl Drop for FfmpegSource {
    fn drop(&mut self) {
        if !self.finished {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// Tool version, OpenCV version and the `ffmpeg` program's version (or its absence).
pub fn info() -> Result<String> {
    let ffmpeg = Command::new("ffmpeg")
        .args(["-hide_banner", "-version"])
        .stdin(Stdio::null())
        .stderr(Stdio::null())
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| {
            String::from_utf8_lossy(&o.stdout)
                .lines()
                .next()
                .map(|l| l.split(" Copyright").next().unwrap_or(l).trim().to_string())
        });
    Ok(format!(
        "rollfric {}\nOpenCV {} (core, imgproc)\nffmpeg program: {}\n",
        env!("CARGO_PKG_VERSION"),
        opencv::core::CV_VERSION,
        ffmpeg.as_deref().unwrap_or(
            "not found: videos cannot be decoded or rendered (Debian: apt-get install ffmpeg)"
        )
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn complaints_are_told_by_their_level_not_their_words() {
        assert!(decoder_complaint(
            "[h264 @ 0x55] [error] Invalid NAL unit size (1210 > 415)."
        ));
        assert!(decoder_complaint(
            "[error] cut.mp4: Invalid data found when processing input"
        ));
        assert!(!decoder_complaint(
            "[info] Input #0, mov,mp4,m4a,3gp,3g2,mj2, from 'mirror_error_invalid_truncated.mp4':"
        ));
        assert!(!decoder_complaint("[warning] deprecated pixel format used"));
    }
}
