//! What the `ffmpeg` program says, read: its stream description (size, rate, frame
//! count), its clock times, and which of its log lines are complaints, and whose.

use super::VideoInfo;

/// A clock time `HH:MM:SS.ss` (ffmpeg's duration), s.
pub(super) fn parse_clock(text: &str) -> Option<f64> {
    let mut parts = text.trim().split(':');
    let (h, m, sec) = (parts.next()?, parts.next()?, parts.next()?);
    let t = h.parse::<f64>().ok()? * 3600.0
        + m.parse::<f64>().ok()? * 60.0
        + sec.parse::<f64>().ok()?;
    (t.is_finite() && t >= 0.0 && parts.next().is_none()).then_some(t)
}

/// The facts of ffmpeg's description of a video stream, as in
/// `Stream #0:0[0x1](und): Video: h264 (High) (avc1 / 0x31637661), yuv420p(tv,
/// progressive), 640x480 [SAR 1:1 DAR 4:3], 1010 kb/s, 30 fps, 30 tbr, 15360 tbn`: the
/// codec (the first word), the size and the nominal rate (items of the comma-separated
/// list outside parentheses). The expected frame count is the duration at that rate.
pub(super) fn parse_video_stream(line: &str, duration_s: Option<f64>) -> Option<VideoInfo> {
    let desc = line.split(": Video: ").nth(1)?;
    let mut items = Vec::new();
    let (mut depth, mut from) = (0i32, 0usize);
    for (i, c) in desc.char_indices() {
        match c {
            '(' | '[' => depth += 1,
            ')' | ']' => depth -= 1,
            ',' if depth == 0 => {
                items.push(desc[from..i].trim());
                from = i + 1;
            }
            _ => {}
        }
    }
    items.push(desc[from..].trim());
    let codec = items.first()?.split_whitespace().next()?.to_string();
    // The pixel format, `yuv420p(tv, ...)` or `rgb24`: planar YUV and grey keep a luma
    // plane.
    let pix = items
        .get(1)
        .map_or("", |p| p.split('(').next().unwrap_or("").trim());
    let luma_plane = pix.starts_with("yuv") || pix.starts_with("gray") || pix.is_empty();
    let (width, height) = items.iter().skip(1).find_map(|item| {
        let (w, h) = item.split_whitespace().next()?.split_once('x')?;
        let (w, h) = (w.parse::<u32>().ok()?, h.parse::<u32>().ok()?);
        (w > 0 && h > 0).then_some((w, h))
    })?;
    let fps = items.iter().find_map(|item| {
        let v = item.strip_suffix(" fps")?.trim();
        let f = match v.strip_suffix('k') {
            Some(k) => k.parse::<f64>().ok()? * 1000.0,
            None => v.parse::<f64>().ok()?,
        };
        (f.is_finite() && f > 0.0).then_some(f)
    });
    let frames_header = match (duration_s, fps) {
        (Some(d), Some(f)) => Some((d * f).round() as u64),
        _ => None,
    };
    Some(VideoInfo {
        width,
        height,
        frames_header,
        duration_s,
        codec,
        luma_plane,
    })
}

/// Whether an ffmpeg log line (with `-v level+...`) is an error the decoder reports:
/// its severity tag is `[error]`, `[fatal]` or `[panic]`. Nothing else is judged, so a
/// file named `mirror.mp4` (quoted on `[info]` lines) is not taken for a damaged one.
pub(super) fn decoder_complaint(line: &str) -> bool {
    ["[error] ", "[fatal] ", "[panic] "]
        .iter()
        .any(|tag| line.starts_with(tag) || line.contains(&format!("] {tag}")))
}

/// Whether a complaint comes from our side of the decoder (the filters we asked for,
/// the raw output's muxer), not from reading the video: it says nothing of the video,
/// and is told as the tool's own fault. A complaint is judged by who makes it, not only
/// by its level.
pub(super) fn own_side(line: &str) -> bool {
    let who = line.trim_start();
    [
        "[rawvideo @ ",
        "[Parsed_",
        "[AVFilterGraph @ ",
        "[graph ",
        "[out#",
        "[vost#",
    ]
    .iter()
    .any(|p| who.starts_with(p))
}
