//! Reading video frames: the slow, machine-dependent stage, behind the [`FrameSource`]
//! trait so that everything after it can be tested with frames made in memory.
//!
//! [`FfmpegSource`] is the fast path. It has the `ffmpeg` program decode, crop to the
//! region of interest and hand over only the luma plane (`extractplanes=y`): no colour
//! conversion at all, and only the pixels the detector looks at cross the pipe. Frame
//! times come from each decoded frame's own timestamp (`showinfo`), not from the
//! container's nominal rate. The `ffmpeg` program is required: OpenCV's `videoio` is
//! not linked (see [`crate::picture`] for why), and a video is refused, with the package
//! to install, when the program is missing.
//!
//! A [`Decoder`] is an `ffmpeg` process started before its filters are known: it loads
//! its libraries, opens the video and describes it (its size, for the filters to be
//! chosen), then waits for the filter graph on its standard input. So a video costs no
//! separate `ffprobe` run, and a decoder started early (the detector's streaming pass,
//! while the first look's geometry is worked out) has its start-up behind it when its
//! filters arrive.

mod said;

use anyhow::{bail, Context, Result};
use said::{decoder_complaint, own_side, parse_clock, parse_video_stream};
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStderr, ChildStdin, Command, Stdio};
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
    /// Frame count expected from the header (the duration at the nominal frame rate;
    /// it may be wrong: it only sizes progress reports, and frames are counted as
    /// decoded).
    pub frames_header: Option<u64>,
    pub duration_s: Option<f64>,
    pub codec: String,
    /// Whether the luma is stored as a plane of its own (YUV or grey pixels), to be
    /// taken as it is; an RGB video's (a PNG or QuickTime Animation stream) is computed.
    pub luma_plane: bool,
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

    /// A frame's buffer the caller is done with, for the source to fill again (a
    /// decoder's reader thread then allocates, and the system zeroes, no fresh pages for
    /// it). By default it is dropped.
    fn recycle(&mut self, _buf: Vec<u8>) {}
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

/// For the unit tests: whether a test that needs ffmpeg may go on (a missing one fails
/// it under `make test` and CI, and skips it otherwise).
#[cfg(test)]
pub(crate) fn need_ffmpeg() -> bool {
    crate::require::require("ffmpeg", crate::require::MAKE_DEPS, have_ffmpeg())
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

/// An `ffmpeg` process started on a video, which describes the video and then waits
/// for its filters (see the module's documentation). Dropped unused, the process is
/// stopped.
pub struct Decoder {
    path: PathBuf,
    /// The process, until [`Decoder::run`] hands it to its [`FfmpegSource`].
    child: Option<Child>,
    stdin: Option<ChildStdin>,
    /// The process's log, read up to the video stream's description.
    log: Option<BufReader<ChildStderr>>,
    /// The video, once the description is read ([`Decoder::describe`]).
    info: Option<VideoInfo>,
    /// Complaints logged before the description (kept for the decoding's verdict).
    early: Vec<String>,
}

impl Decoder {
    /// Start `ffmpeg` on `path` and read what it says of the video (refused when the
    /// file is empty or unreadable, when `ffmpeg` is not installed, or when the file
    /// holds no video stream).
    pub fn start(path: &Path) -> Result<Self> {
        let mut d = Self::spawn(path)?;
        d.describe()?;
        Ok(d)
    }

    /// Start `ffmpeg` on `path` without waiting for it: it loads, opens the video and
    /// describes it while the caller goes on ([`Decoder::describe`] reads that).
    pub fn spawn(path: &Path) -> Result<Self> {
        if crate::fsutil::regular_file(path)? == 0 {
            bail!(
                "{}: the file is empty (0 bytes); no frame to read",
                path.display()
            );
        }
        if !on_path("ffmpeg") {
            bail!(
                "{}: decoding needs the ffmpeg program, which is not on PATH (Debian: apt-get install ffmpeg)",
                path.display()
            );
        }
        let mut child = Command::new("ffmpeg")
            // `-nostdin`: standard input carries the filter script, not key presses.
            // `level+`: every line carries its severity as `[error]`, `[info]`, ...,
            // so complaints are told by the decoder's own level, not by their words.
            // `-noautorotate`: the frames as stored, of the size the description gives.
            // A phone's rotation tag would have ffmpeg turn them, and the region cut
            // from the stored size not fit ("Invalid too big ... size", read as a
            // damaged video); the wire's angle is measured at any roll anyway.
            .args([
                "-nostdin",
                "-hide_banner",
                "-nostats",
                "-v",
                "level+info",
                "-noautorotate",
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
                "-filter_script:v",
                "pipe:0",
                "-f",
                "rawvideo",
                "-",
            ])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .with_context(|| format!("{}: cannot start ffmpeg", path.display()))?;
        let stdin = child.stdin.take();
        let log = BufReader::new(child.stderr.take().expect("piped"));
        Ok(Self {
            path: path.to_path_buf(),
            child: Some(child),
            stdin,
            log: Some(log),
            info: None,
            early: Vec::new(),
        })
    }

    /// The video as the decoder describes it: read from its log the first time (the
    /// input's description comes first; then ffmpeg waits for its filters, so reading
    /// stops at the first video stream's line, or at the end of a refusal).
    pub fn describe(&mut self) -> Result<&VideoInfo> {
        if self.info.is_none() {
            let log = self.log.as_mut().expect("a decoder runs once");
            let mut duration_s = None;
            let mut line = Vec::new();
            let described = loop {
                line.clear();
                match log.read_until(b'\n', &mut line) {
                    Ok(0) | Err(_) => break None,
                    Ok(_) => {}
                }
                // A path or a tag in another encoding is no reason to stop reading.
                let text = String::from_utf8_lossy(&line);
                let l = text.trim_end();
                if let Some(rest) = l.split("Duration: ").nth(1) {
                    duration_s = parse_clock(rest.split(',').next().unwrap_or(""));
                } else if l.contains("Stream #0:") && l.contains(": Video: ") {
                    break Some(l.to_string());
                } else if decoder_complaint(l) {
                    self.early.push(l.trim().to_string());
                }
            };
            let info = described
                .as_deref()
                .and_then(|l| parse_video_stream(l, duration_s));
            let Some(info) = info else {
                if let Some(mut child) = self.child.take() {
                    let _ = child.kill();
                    let _ = child.wait();
                }
                let why = self
                    .early
                    .first()
                    .map(|l| l.rsplit("] ").next().unwrap_or(l).trim().to_string())
                    .filter(|w| !w.contains("matches no streams"))
                    .unwrap_or_else(|| "it holds no video stream".to_string());
                bail!(
                    "{}: cannot open as a video ({why}); no frame decoded",
                    self.path.display()
                );
            };
            self.info = Some(info);
        }
        Ok(self.info.as_ref().expect("described"))
    }

    /// The video as the decoder described it ([`Decoder::start`] reads that first).
    pub fn info(&self) -> &VideoInfo {
        self.info
            .as_ref()
            .expect("Decoder::info after Decoder::start or Decoder::describe")
    }

    /// Decode, cropped to `roi` (whole frame if `None`) and optionally scaled down by
    /// an integer `shrink` (for quick looks at large frames).
    pub fn run(self, roi: Option<Roi>, shrink: u32) -> Result<FfmpegSource> {
        self.run_ahead(roi, shrink, 0)
    }

    /// [`Decoder::run`], reading up to `ahead_bytes` of frames ahead of the caller (at
    /// least [`READ_AHEAD`] frames): a caller that stops to think between frames (the
    /// detector's geometry between its first look and the streaming pass) finds them
    /// decoded.
    pub fn run_ahead(
        mut self,
        roi: Option<Roi>,
        shrink: u32,
        ahead_bytes: usize,
    ) -> Result<FfmpegSource> {
        let info = self.describe()?.clone();
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
        // The luma plane as stored, whatever its range: the streaming pass reads it so
        // (unshrunk), and a look shrunk here must see the same grey levels. RGB pixels
        // have no such plane: their grey is computed from the three colours.
        filters.push_str(if info.luma_plane {
            ",extractplanes=y"
        } else {
            ",format=gray"
        });
        if shrink > 1 {
            width /= shrink as usize;
            height /= shrink as usize;
            // Each pixel the mean of a `shrink` x `shrink` block, rounded, as OpenCV's
            // `INTER_AREA` shrinks the streaming pass's frames (exactly at 2x; at 3x the
            // scaler's fixed point rounds a block now and then the other way, by one
            // grey level, without bias). A range of `full` in and out: the scaler would
            // otherwise stretch a limited-range (TV) luma, as H.264 usually stores it, to
            // full range (x 255/219, less 18.6 grey levels), and the look's background,
            // thresholds and brightness reference would not match the pass's frames.
            filters.push_str(&format!(
                ",scale={width}:{height}:flags=area:in_range=full:out_range=full"
            ));
        }
        // One byte a pixel, as the frames are read: a deeper luma (10-bit HEVC, as a
        // phone records HDR) is brought to 8 bits (8-bit luma passes untouched). Two
        // bytes a pixel would read as two frames per frame and wait forever for the
        // second one's time.
        filters.push_str(",format=gray");
        filters.push_str(",showinfo=checksum=0");
        // After the times are read, the raw output is numbered 0, 1, 2, ... seconds: the
        // muxer's time base (1/fps, or a variable rate's millisecond) is finer than a
        // second, so every frame lands on a tick of its own for any length and rate. A
        // finer numbering (N microseconds) put frames on one tick once the frame rate
        // times N passed half a million (past 2.3 minutes at 60 fps), and the muxer
        // dropped them.
        filters.push_str(",settb=1,setpts=N");
        // The script, then the end of the input: ffmpeg reads it to its end.
        if let Some(mut stdin) = self.stdin.take() {
            use std::io::Write;
            // A decoder that has stopped meanwhile says why on its log (read below).
            let _ = stdin.write_all(filters.as_bytes());
        }
        let mut child = self.child.take().expect("a decoder runs once");
        let mut stdout = child.stdout.take().expect("piped");
        let log = self.log.take().expect("a decoder runs once");
        let path = self.path.clone();
        let frame_len = width * height;
        // A pipe holds 64 KiB by default: a frame of the region crossed it in several
        // writes, each waking the reader and the decoder in turn. Room for a frame or
        // two (up to the system's limit for an unprivileged pipe) halves the handovers.
        // Best effort: a kernel that refuses keeps the default, and the data is the same.
        let _ = rustix::pipe::fcntl_setpipe_size(&stdout, (2 * frame_len).clamp(1 << 16, PIPE_MAX));
        let ahead = (ahead_bytes / frame_len.max(1)).max(READ_AHEAD);
        let (frames_tx, frames) = mpsc::sync_channel::<Chunk>(ahead);
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
        // Complaints logged while the video was opened count as the decoding's own.
        let mut early = std::mem::take(&mut self.early);
        early.truncate(8);
        let errors = std::sync::Arc::new(std::sync::Mutex::new(early));
        let errs = errors.clone();
        std::thread::spawn(move || {
            let mut tb = 0.0f64;
            // One line per frame: read into one buffer (bytes: a line in another
            // encoding must not end the reading, and with it every later frame's time).
            let mut reader = log;
            let mut bytes = Vec::new();
            loop {
                bytes.clear();
                match reader.read_until(b'\n', &mut bytes) {
                    Ok(0) | Err(_) => break,
                    Ok(_) => {}
                }
                let text = String::from_utf8_lossy(&bytes);
                let line = text.trim_end_matches(['\n', '\r']);
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
        Ok(FfmpegSource {
            path,
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
}

impl Drop for Decoder {
    fn drop(&mut self) {
        // Not run: stop the process waiting for its filters.
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
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
    pub fn open(path: &Path, roi: Option<Roi>, shrink: u32) -> Result<Self> {
        Decoder::start(path)?.run(roi, shrink)
    }

    fn fail_message(&self) -> String {
        let errors = self.errors.lock().map(|e| e.clone()).unwrap_or_default();
        // The first complaint about the video, else the first about our own side of the
        // decoder, each without its "[h264 @ 0x...]" prefix.
        let bare = |l: &String| l.rsplit("] ").next().unwrap_or(l).trim().to_string();
        let damage = errors.iter().find(|l| !own_side(l)).map(bare);
        let ours = errors.iter().find(|l| own_side(l)).map(bare);
        let last = if self.next_index == 0 {
            "no frame decoded".to_string()
        } else {
            format!("last good frame {}", self.next_index - 1)
        };
        let path = self.path.display();
        match (damage, ours) {
            (Some(w), _) => format!("{path}: truncated or damaged video ({last}): {w}"),
            (None, Some(w)) => format!(
                "{path}: the decoded frames could not be passed on ({last}): {w}; the video \
                 itself decoded without complaint: this is a fault of rollfric, please report it"
            ),
            (None, None) => format!("{path}: decoding failed ({last})"),
        }
    }
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

/// Frames read ahead of the detector (flat memory: a few frames of the cropped region),
/// unless [`Decoder::run_ahead`] asks for more.
pub const READ_AHEAD: usize = 6;

/// The largest pipe buffer asked of the kernel for the decoder's output, bytes: Linux's
/// default `/proc/sys/fs/pipe-max-size` (what an unprivileged process may ask).
const PIPE_MAX: usize = 1 << 20;

impl FrameSource for FfmpegSource {
    fn recycle(&mut self, buf: Vec<u8>) {
        // A reader that has stopped has no use for it.
        let _ = self.spent.send(buf);
    }

    fn next_frame(&mut self, frame: &mut Frame) -> Result<bool> {
        if self.finished {
            return Ok(false);
        }
        let chunk = self.frames.recv().unwrap_or(Chunk::End { partial: false });
        let partial = match chunk {
            Chunk::Frame(buf) => {
                let old = std::mem::replace(&mut frame.data, buf);
                self.recycle(old);
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
mod tests;
