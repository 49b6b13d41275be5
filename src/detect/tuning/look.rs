//! Knobs of the first look: decoding, the working scale, a still start.

use super::Knob;

knobs! {
    table LOOK_KNOBS, stage "first look";

    // From input.rs.
    /// The largest frame a video may have, px: the detector's buffers (a region of a frame,
    /// a few kept for Figure 11) are sized from it before anything is decoded.
    MAX_FRAME_PIXELS: u64 = 8192 * 8192, "px",
        what "largest frame a video may have (8192 x 8192); larger ones are refused before decoding",
        chosen_by "48a2976: a bound on the buffers sized from the frame; not measured";

    // From mod.rs.
    /// Length of the first look at the video (geometry and background), s: more than half
    /// a swing of any pendulum up to a 5 s period.
    INIT_SECONDS: f64 = 2.5, "s",
        what "length of the first look at the video (geometry and background)",
        chosen_by "27ed403: 2.5 s, the setting every synthetic style and clip test passes with (4 s before)";

    /// The most frames a first look keeps (a high frame rate's `INIT_SECONDS`).
    LOOK_MAX_FRAMES: usize = 300, "frames",
        what "most frames a first look keeps",
        chosen_by "ca0056c: INIT_SECONDS at a high frame rate (120 frames/s); not measured";

    /// Of a still start (a held ball, see `still`), the first look keeps the last this
    /// many frames and starts its clock at the first of them. A release from an extreme
    /// without a hold moves the wire visibly within a few frames at any frame rate.
    STILL_KEEP: usize = 8, "frames",
        what "frames of a still start (a held ball) the first look keeps",
        chosen_by "cb79a79: the 8 experiments byte-identical; a 2 s hold of a faint wire, refused before, measured";

    /// A period that is not the experiment's pendulum's (the `length` check) may be
    /// another pendulum's, swinging while the ball was held through the first look: the
    /// detector looks again this many times, each look `INIT_SECONDS` after the one
    /// before, for a pendulum about another pivot (`SECOND_APART` away), and measures it
    /// when one is found (`detect::another_pendulum`).
    LENGTH_LOOKS: usize = 3, "looks",
        what "later looks for another pendulum after the `length` check failed",
        chosen_by "seed 1205's sweep scenes 31 and 54 (a ball held 2 s, a second string swinging): the look from 2.5 s finds the pendulum; three reach 10 s, STILL_MAX_SECONDS; not swept";

    /// A still start longer than this (s) is taken as the motion's start: the look does
    /// not wait for ever on a wire it cannot see move.
    STILL_MAX_SECONDS: f64 = 10.0, "s",
        what "a still start longer than this is taken as the motion's start",
        chosen_by "cb79a79: hand-picked; not measured";

    // From first_look.rs.
    /// The first look's decoder goes on into the streaming pass when the look is at full
    /// size and the frames asked for, at the look's region, amount to at most this many
    /// bytes (so that no decoder starts again, and the look's frames are not decoded
    /// twice); a longer video starts a decoder that crops to the region of interest, whose
    /// fewer bytes through the pipe then outweigh a second decoder's start. Measured with
    /// `make bench`: see docs/detector.md.
    DECODE_ONCE_MAX_BYTES: u64 = 256 << 20, "bytes",
        what "the look's decoder goes on into the pass up to this many bytes of frames",
        chosen_by "ea89746: make bench (docs/detector.md, decoding once)";

    /// The first look's frames, as decoded, held for the streaming pass at most to this
    /// many bytes: a look expected to need more (a high frame rate at a large region:
    /// 960x540 at 60 frames/s) is not decoded once, and one that comes to need more (a long
    /// still start) starts a decoder again for the streaming pass.
    HELD_MAX_BYTES: usize = 48 << 20, "bytes",
        what "the look's decoded frames held for the pass at most",
        chosen_by "ea89746, ca0056c: a memory bound (960x540 at 60 frames/s lies over it); not swept";

    /// The first look's frames kept for the geometry at most to about this many bytes: at a
    /// large working side (`--work-side 4096` on 4K, 8 MB a frame) the look keeps every
    /// `k`-th frame over the same `INIT_SECONDS` instead of every frame (1.4 GB at 60
    /// frames/s), and at least `LOOK_MIN_FRAMES` of them. At the default working side a
    /// look of `LOOK_MAX_FRAMES` frames of 640 x 640 px is 123 MB: every frame is kept.
    LOOK_MAX_BYTES: usize = 160 << 20, "bytes",
        what "the look's frames kept for the geometry at most (past it every k-th)",
        chosen_by "f64e3c0 (issue 52): 4K, 60 fps, --work-side 4096: peak 1458 -> 471 MiB, wall 32.2 -> 20.6 s, angles within 0.001 deg";

    /// The fewest frames a look thinned by `LOOK_MAX_BYTES` keeps: one every tenth of a
    /// second over `INIT_SECONDS`, as the geometry judges a line's jumps and roughness
    /// from step to step (`geometry::search`).
    LOOK_MIN_FRAMES: usize = 25, "frames",
        what "fewest frames a thinned look keeps",
        chosen_by "f64e3c0: one every tenth of a second over INIT_SECONDS; not swept";

    /// What the first look's decoder may decode ahead of the look, bytes: the frames after
    /// the look come while its geometry is worked out, so that the decoder does not wait on
    /// the geometry. A 960x540 look's geometry takes 0.2-0.3 s, in which the decoder gives
    /// about 150 frames of 0.5 MB; with 24 MiB it stopped after 48 of them, and the
    /// streaming pass waited 0.2 s for frames. Bounded: a video decoded once is at most
    /// `DECODE_ONCE_MAX_BYTES` in all, and its frames go as the streaming pass takes them.
    READ_AHEAD_BYTES: usize = 96 << 20, "bytes",
        what "how far the look's decoder may decode ahead of the look",
        chosen_by "761693f: 24 -> 96 MiB; the comment beside it: at 24 MiB a 960x540 look's decoder stopped after 48 of ~150 frames and the pass waited 0.2 s";

    /// The working side, px, by default (`video.work_side_px` asks for a larger one): a
    /// frame is shrunk by a whole factor towards this size for the first look, and the
    /// streaming pass works at the look's scale. A 1280x720 video is so measured at half
    /// size, its 2 px wire sampled as 1 px: at full size its angles err less, for about
    /// twice the detector's own processor time (docs/detector.md, "Working scale").
    WORK_SIDE_PX: f64 = 640.0, "px",
        what "default working side a frame is shrunk towards (whole factors)",
        chosen_by "e0cb6df, 75ce8a7: 640 px; a turned real 1920x1080 clip at 960x540 lost its turning points when measured at full size";

    /// The most pixels a frame (or its region of interest) holds at the working scale:
    /// a larger working side (`video.work_side_px`) is held to the finest whole factor
    /// that keeps a frame within this many, as the first look keeps at least
    /// `LOOK_MIN_FRAMES` of them whatever their size. 3840 x 2160 px (a 4K frame at
    /// full size): 8192 x 8192 at `--work-side 8192` is measured shrunk three times
    /// (2730 x 2730) instead of at full size (a look of 25 frames of 67 MB).
    WORK_MAX_PIXELS: u64 = 3840 * 2160, "px",
        what "most pixels of a frame at the working scale (a larger side is held to fit)",
        chosen_by "issue 52: peak memory at most 600 MB at any working side; measured in docs/detector.md";

    // From still.rs.
    /// Every `STILL_SAMPLE_STEP`-th pixel is compared (tens of thousands per frame).
    STILL_SAMPLE_STEP: usize = 7, "pixels",
        what "every n-th pixel is compared to tell a still start",
        chosen_by "cb79a79: tens of thousands of pixels a frame; not swept";

    /// A pixel has moved when it differs from the first frame by more than this many
    /// standard deviations of the two-frame noise ...
    MOVED_SIGMAS: f64 = 6.0, "sigmas",
        what "a pixel moved: its difference in two-frame noise sigmas",
        chosen_by "cb79a79: hand-picked; not measured";

    /// ... and by at least this many grey levels (compression noise is quantised: a
    /// still frame's differences are a few levels, a keyframe's up to about 9).
    MOVED_LEVELS: f64 = 16.0, "grey levels",
        what "a pixel moved: its least difference",
        chosen_by "cb79a79: over a keyframe's compression noise (up to about 9 levels); not swept";

    /// See `FirstLook::at`: a moving camera's look whose wire swept less than this, no
    /// still start dropped, is looked at again with the still start judged under the
    /// camera's motion (a held ball's wire sweeps none; a release angle of 3 deg or more
    /// sweeps more than this within a look's first swing).
    HELD_SWEEP_DEG: f64 = 6.0, "deg",
        what "a moving camera's look whose wire swept less is looked at again for a still start",
        chosen_by "hand-picked: a hand-held twin whose hand released the ball, 3.0 deg swept (the pivot 37 px off), 20 deg after";

    /// The scene moves when more than this share of the compared pixels moved (a still
    /// frame: a few in ten thousand; the ball and the wire leaving their place: several
    /// in a thousand) ...
    STILL_MOVING_SHARE: f64 = 5e-4, "share",
        what "share of the compared pixels that moved for the scene to move",
        chosen_by "cb79a79: a still frame a few in 10 000, ball and wire leaving several in 1000; not swept";

    /// ... and at least this many.
    MOVING_MIN: usize = 8, "pixels",
        what "fewest moved pixels for the scene to move",
        chosen_by "cb79a79: hand-picked; not measured";

    /// A frame compared under the camera's motion (a hand-held camera, the ball held)
    /// may differ by this many px times the first frame's gradient more than the noise
    /// allows: the motion is measured shrunk, to a tenth of a px or so, and a sharp
    /// edge's grey changes by its gradient per px.
    STILL_EDGE_PX: f64 = 0.5, "px",
        what "the camera's motion's allowed error at an edge, comparing a still start under it",
        chosen_by "issue 49: hand-picked (the alignment's own MEASURE_PX); measured on the sweep";

}
