//! Damaged or unusable videos stop `rollfric detect` with one line naming the file (and
//! the last good frame where there was one), and no CSV is written: partial angles are
//! never passed off as complete.

mod common;

use common::{need_ffmpeg, rollfric, root};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn detect(video: &Path, csv: &Path) -> Output {
    rollfric(
        &[
            OsStr::new("detect"),
            video.as_os_str(),
            OsStr::new("-o"),
            csv.as_os_str(),
        ],
        &root(),
    )
}

fn assert_fails(out: &Output, csv: &Path, file: &str, needles: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "should fail: {err}");
    assert_eq!(
        err.trim_end().lines().count(),
        1,
        "one line expected:\n{err}"
    );
    assert!(err.contains(file), "names {file}: {err}");
    for n in needles {
        assert!(err.contains(n), "says `{n}`: {err}");
    }
    assert!(
        !csv.exists(),
        "no CSV may be written for a failed detection"
    );
}

/// A short H.264 clip with its index at the front, so that a cut keeps it decodable.
fn make_clip(dir: &Path, name: &str, source: &str) -> PathBuf {
    let p = dir.join(name);
    let st = Command::new("ffmpeg")
        .args(["-v", "error", "-y", "-f", "lavfi", "-i", source])
        .args([
            "-c:v",
            "libx264",
            "-pix_fmt",
            "yuv420p",
            "-movflags",
            "+faststart",
        ])
        .arg(&p)
        .status()
        .unwrap();
    assert!(st.success());
    p
}

#[test]
fn fails_when_video_is_empty_corrupt_or_truncated() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let csv = d.join("angles.csv");

    let empty = d.join("empty.mp4");
    std::fs::write(&empty, b"").unwrap();
    assert_fails(&detect(&empty, &csv), &csv, "empty.mp4", &["empty"]);

    let junk = d.join("junk.mp4");
    let bytes: Vec<u8> = (0..50_000u32)
        .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
        .collect();
    std::fs::write(&junk, bytes).unwrap();
    assert_fails(
        &detect(&junk, &csv),
        &csv,
        "junk.mp4",
        &["cannot open as a video"],
    );

    // A swinging dark line (a pendulum's wire from (160, 0), 0.3 rad at 1 Hz):
    // decodable, its wire found in the first seconds, then cut in the middle of its data.
    let clip = make_clip(
        d,
        "clip.mp4",
        "color=c=gray:size=320x240:rate=30:duration=6,format=gray,\
         geq=lum='if(lt(abs((X-160)*cos(0.3*sin(2*PI*T))-Y*sin(0.3*sin(2*PI*T))),1.5)\
         *lt(Y,200),40,200)'",
    );
    let full = std::fs::read(&clip).unwrap();
    let cut = d.join("cut.mp4");
    std::fs::write(&cut, &full[..full.len() * 6 / 10]).unwrap();
    assert_fails(
        &detect(&cut, &csv),
        &csv,
        "cut.mp4",
        &["truncated or damaged", "last good frame"],
    );
    // Cut within the first look (2.5 s): refused, naming the last good frame; the frames
    // up to the one before it are measured, the damage never read (the first look's
    // decoder, which goes on into the streaming pass of so short a video, stops at the
    // frame after the last one asked for, as a second decoder would).
    let early = d.join("early.mp4");
    std::fs::write(&early, &full[..full.len() * 3 / 10]).unwrap();
    let out = detect(&early, &csv);
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{said}");
    let good: u64 = said
        .split("last good frame ")
        .nth(1)
        .and_then(|s| s.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no last good frame in: {said}"));
    assert!(
        good > 10 && good < 75,
        "the cut lies within the first look: {said}"
    );
    let frames = format!("0,{}", good - 1);
    let out = rollfric(
        &[
            OsStr::new("detect"),
            early.as_os_str(),
            OsStr::new("--frames"),
            OsStr::new(&frames),
            OsStr::new("-o"),
            csv.as_os_str(),
        ],
        &root(),
    );
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "frames {frames}: {said}");
    assert!(
        said.contains(&format!("{good} frames")) && said.contains("decoded once"),
        "{said}"
    );
}

#[test]
fn fails_when_no_wire_can_be_found() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let still = make_clip(
        dir.path(),
        "still.mp4",
        "color=c=gray:size=320x240:rate=30:duration=3",
    );
    let csv = dir.path().join("angles.csv");
    assert_fails(&detect(&still, &csv), &csv, "still.mp4", &["no wire found"]);
    // Plenty of moving straight edges, none of them swinging about a pivot.
    let busy = make_clip(
        dir.path(),
        "busy.mp4",
        "testsrc2=size=320x240:rate=30:duration=3",
    );
    assert_fails(&detect(&busy, &csv), &csv, "busy.mp4", &["no wire found"]);
}

/// Decoding and rendering go through the `ffmpeg` program (OpenCV's video modules are not
/// linked): without it on `PATH`, `detect` and `synth` stop in one line naming the file
/// and the package to install, and write nothing.
#[test]
fn without_ffmpeg_videos_are_refused_naming_the_package() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let clip = make_clip(
        dir.path(),
        "clip.mp4",
        "color=c=gray:size=320x240:rate=30:duration=1",
    );
    let csv = dir.path().join("angles.csv");
    let empty = dir.path().join("no-tools");
    std::fs::create_dir(&empty).unwrap();
    let run = |args: &[&OsStr]| {
        common::command(&root())
            .env("PATH", &empty)
            .args(args)
            .output()
            .unwrap()
    };
    let out = run(&[
        OsStr::new("detect"),
        clip.as_os_str(),
        OsStr::new("-o"),
        csv.as_os_str(),
    ]);
    assert_fails(
        &out,
        &csv,
        "clip.mp4",
        &["needs the ffmpeg program", "apt-get install ffmpeg"],
    );
    let twin = dir.path().join("twin.avi");
    let out = run(&[
        OsStr::new("synth"),
        OsStr::new("glass"),
        OsStr::new("-o"),
        twin.as_os_str(),
        OsStr::new("--duration"),
        OsStr::new("1"),
    ]);
    assert_fails(
        &out,
        &twin,
        "twin.avi",
        &["needs the ffmpeg program", "apt-get install ffmpeg"],
    );
    // Nothing written, not even the twin's folder.
    let nested = dir.path().join("new").join("twin.avi");
    let out = run(&[
        OsStr::new("synth"),
        OsStr::new("glass"),
        OsStr::new("-o"),
        nested.as_os_str(),
    ]);
    assert_fails(&out, &nested, "twin.avi", &["needs the ffmpeg program"]);
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        2,
        "the clip and the empty folder only"
    );
    // `info` says what is missing.
    let out = run(&[OsStr::new("info")]);
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        said.contains("ffmpeg program: not found") && said.contains("apt-get install ffmpeg"),
        "{said}"
    );
}

/// A phone's variable frame rate is not damage: frames 6.7 and 26.7 ms apart in turn (in
/// whole milliseconds, at a nominal 60 frames/s) share ticks of a 1/60 s time base, which
/// ffmpeg's raw output refused as out of order ("non monotonically increasing dts"); the
/// reader read that as a damaged video. Every frame is read, at its own time.
#[test]
fn a_variable_frame_rate_is_read_frame_by_frame() {
    use rollfric::video::{Decoder, Frame, FrameSource};
    if !need_ffmpeg() {
        return;
    }
    let d = tempfile::tempdir().unwrap();
    let clip = d.path().join("vfr.mp4");
    let st = Command::new("ffmpeg")
        .args(["-v", "error", "-y", "-f", "lavfi", "-i"])
        .arg("testsrc2=size=160x120:rate=60:duration=2")
        .arg("-vf")
        .arg("settb=1/1000,setpts=round((N+0.3*(1-2*mod(N\\,2)))*1000/60)")
        .args(["-fps_mode", "passthrough", "-enc_time_base", "1/1000"])
        .args(["-c:v", "libx264", "-pix_fmt", "yuv420p"])
        .arg(&clip)
        .status()
        .unwrap();
    assert!(st.success());
    // The decoder describes the video before it is given its filters.
    let decoder = Decoder::start(&clip).unwrap();
    let info = decoder.info().clone();
    assert_eq!(
        (info.width, info.height, info.codec.as_str()),
        (160, 120, "h264")
    );
    let mut src = decoder.run(None, 1).unwrap();
    let mut f = Frame {
        index: 0,
        t_s: 0.0,
        width: 0,
        height: 0,
        data: Vec::new(),
    };
    let mut times = Vec::new();
    loop {
        match src.next_frame(&mut f) {
            Ok(true) => times.push(f.t_s),
            Ok(false) => break,
            Err(e) => panic!("after {} frames: {e:#}", times.len()),
        }
    }
    assert_eq!(times.len(), 120, "every frame read once");
    // Times from the first frame's (the container may start the clock at it).
    let written = |k: usize| {
        ((k as f64 + 0.3 * if k.is_multiple_of(2) { 1.0 } else { -1.0 }) / 60.0 * 1000.0).round()
            / 1000.0
    };
    for (k, t) in times.iter().enumerate() {
        let (got, want) = (t - times[0], written(k) - written(0));
        assert!(
            (got - want).abs() < 1e-6,
            "frame {k} at {got} s, written at {want} s"
        );
    }
}

/// ffmpeg's log is read as bytes: a tag in another encoding (a Latin-1 title, in the
/// file's header and on its video stream) neither stops the video being opened ("cannot
/// open as a video (no video stream)", when the description's reading stopped at the
/// header's title) nor the frames' times being read (the stream's title comes after its
/// description, where the times are read).
#[test]
fn tags_in_another_encoding_do_not_stop_the_reading() {
    use rollfric::video::{Decoder, Frame, FrameSource};
    use std::os::unix::ffi::OsStrExt;
    if !need_ffmpeg() {
        return;
    }
    let d = tempfile::tempdir().unwrap();
    let clip = d.path().join("latin1.avi");
    let title = [b"title=caf".as_slice(), &[0xe9]].concat();
    let st = Command::new("ffmpeg")
        .args(["-v", "error", "-y", "-f", "lavfi", "-i"])
        .arg("testsrc2=size=160x120:rate=25:duration=1")
        .arg("-metadata")
        .arg(OsStr::from_bytes(&title))
        .arg("-metadata:s:v:0")
        .arg(OsStr::from_bytes(&title))
        .args(["-c:v", "mjpeg"])
        .arg(&clip)
        .status()
        .unwrap();
    assert!(st.success());
    let decoder = Decoder::start(&clip).unwrap();
    assert_eq!((decoder.info().width, decoder.info().height), (160, 120));
    let mut src = decoder.run(None, 1).unwrap();
    let mut f = Frame::default();
    let mut times = Vec::new();
    while src.next_frame(&mut f).unwrap() {
        times.push(f.t_s);
    }
    assert_eq!(times.len(), 25, "every frame read");
    for (k, t) in times.iter().enumerate() {
        assert!((t - k as f64 / 25.0).abs() < 1e-6, "frame {k} at {t} s");
    }
}

/// A phone stores its frames as the sensor saw them and tags the video with the turn a
/// player applies. The frames are measured as stored: a real clip tagged as turned by
/// 90 degrees (the same frames, `-c copy`) gives the same angles, byte for byte, as the
/// clip untagged. Before, ffmpeg turned the frames while the region was cut from the
/// stored size, and the video was refused as "truncated or damaged".
#[test]
fn a_phone_rotation_tag_leaves_the_frames_as_stored() {
    if !need_ffmpeg() {
        return;
    }
    let Some(src) = common::fixture("bartekpacia_film1_fhd.mp4") else {
        return;
    };
    let d = tempfile::tempdir().unwrap();
    let cut = |name: &str, tag: &[&str]| {
        let out = d.path().join(name);
        let st = Command::new("ffmpeg")
            .args(["-nostdin", "-v", "error", "-y", "-i"])
            .arg(&src)
            .args(["-t", "8", "-an", "-c:v", "copy"])
            .args(tag)
            .arg(&out)
            .status()
            .unwrap();
        assert!(st.success(), "ffmpeg made {name}");
        out
    };
    let plain = cut("plain.mp4", &[]);
    let tagged = cut("tagged.mp4", &["-metadata:s:v:0", "rotate=90"]);
    let mut csvs = Vec::new();
    for video in [&plain, &tagged] {
        let csv = video.with_extension("csv");
        let out = detect(video, &csv);
        assert!(
            out.status.success(),
            "{}: {}",
            video.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        csvs.push(std::fs::read(&csv).unwrap());
    }
    assert!(csvs[0] == csvs[1], "the tagged clip's angles differ");
}

/// A working side whose frames would pass the bound on a frame's pixels at the working
/// scale (3840x2160) is held to a coarser whole factor, and `detect` says so before it
/// starts; a region within the bound is measured at the side asked for, unsaid.
#[test]
fn a_working_side_past_the_frame_bound_is_held_and_said() {
    if !need_ffmpeg() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let big = make_clip(
        dir.path(),
        "big.mp4",
        "color=c=gray:size=4200x2400:rate=25:duration=0.2",
    );
    let csv = dir.path().join("angles.csv");
    let run = |extra: &[&str]| {
        let mut args = vec![
            OsStr::new("detect"),
            big.as_os_str(),
            OsStr::new("-o"),
            csv.as_os_str(),
            OsStr::new("--work-side"),
            OsStr::new("8192"),
        ];
        args.extend(extra.iter().map(OsStr::new));
        let out = rollfric(&args, &root());
        assert!(!out.status.success(), "a grey picture has no wire");
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    // 10.1 Mpx at full size: half size, 2100x1200.
    let err = run(&[]);
    assert!(
        err.contains("big.mp4: working side 8192 px: the finer working scale shrinks the 4200x2400 px frame 2 times (2100x1200 px)"),
        "{err}"
    );
    // A 3840x2160 region of it: at full size, and nothing said of it.
    let err = run(&["--roi", "0,0,3840,2160"]);
    assert!(!err.contains("working scale shrinks"), "{err}");
    assert!(err.contains("no wire found"), "{err}");
}
