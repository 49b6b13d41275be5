//! Knobs of steadying a moving camera: the alignment and whether the camera moves.

use super::Knob;

knobs! {
    table STEADY_KNOBS, stage "steadying a moving camera";

    // From steady.rs.
    /// The frame is measured shrunk to at most this side, px (block means).
    EST_SIDE: f64 = 480.0, "px",
        what "a frame is measured shrunk to at most this side",
        chosen_by "f48638b: hand-picked; not swept";

    /// The measured frames are brought to this spread of their grey levels between the
    /// quartiles (whatever the exposure and the scene's own contrast) ...
    LEVEL_SPREAD: f64 = 40.0, "grey levels",
        what "measured frames are brought to this spread between the quartiles",
        chosen_by "96db5d0: an exposure drift no longer reads as motion; moved real clips within 0.2 deg";

    /// ... by a gain of at most this (or at least its inverse): a plain wall's noise is not
    /// made a texture.
    MAX_GAIN: f64 = 4.0, "ratio",
        what "most gain that levelling may apply",
        chosen_by "96db5d0: a plain wall's noise not made a texture; not swept";

    /// The smoothing of the measured frames (a Gaussian's standard deviation, px of the
    /// shrunk frame): it widens the basin the alignment converges from to a few px.
    SMOOTH_PX: f64 = 1.2, "px",
        what "smoothing of the measured frames (Gaussian sigma)",
        chosen_by "f48638b: hand-picked; not swept";

    /// At most this many iterations of the alignment at each of the two scales ...
    ITERATIONS: usize = 10, "iterations",
        what "most iterations of the alignment at each scale",
        chosen_by "f48638b: hand-picked; not swept";

    /// A frame steadied goes further along a run of steps whose directions differ by
    /// less than the angle of this cosine: Tukey's weights, refitted at each step, keep
    /// the pixels that agree with where the step started, and the steps crawl (a 1080p
    /// hand-held twin of a plain plate, each step a fifth of the way left, or the same
    /// small step ten times). Seed 1206's scene 14, its scale widened for the noise:
    /// 0.126 -> 0.086 deg RMS. Where going further leaves more pixels off than where the
    /// step started, it is taken back.
    AHEAD_COS: f64 = 0.9, "cosine",
        what "a steadied frame's alignment goes further along steps whose directions agree this well",
        chosen_by "seed 1206's scene 14: 0.126 -> 0.086 deg RMS; hand-picked, not swept";

    /// Steps shrinking by less than this ratio are extrapolated to the end of their
    /// geometric run ...
    AHEAD_RATIO: f64 = 0.95, "ratio",
        what "steps shrinking faster than this are extrapolated to their run's end",
        chosen_by "hand-picked, not swept";

    /// ... at most this many times the last step ...
    AHEAD_AITKEN: f64 = 4.0, "steps",
        what "most extrapolation of a shrinking run of steps, times the last step",
        chosen_by "hand-picked, not swept";

    /// ... and steps that do not shrink go twice as far as the last went, at most this
    /// many times further than themselves.
    AHEAD_MAX: f64 = 8.0, "steps",
        what "most a steady run of steps is taken further, times the step",
        chosen_by "hand-picked, not swept";

    /// ... which stop when a step moves the frame's corners less than this, px of the
    /// scale aligned.
    CONVERGED_PX: f64 = 0.01, "px",
        what "the alignment stops when a step moves the corners less than this",
        chosen_by "f48638b: hand-picked; not swept";

    /// The first frame's pixels with a gradient below this (grey levels per px, on the
    /// measuring scale, smoothed) are not read: they hold no information on the motion.
    MIN_GRADIENT: f32 = 0.5, "grey levels/px",
        what "first-frame pixels with a weaker gradient are not read",
        chosen_by "96db5d0: a sixth of the time; angles unchanged";

    /// At most this many pixels are read (the strongest gradients).
    MAX_POINTS: usize = 12_000, "pixels",
        what "most pixels read (the strongest gradients)",
        chosen_by "96db5d0: hand-picked; not swept";

    /// On the coarser scale (a quarter of the pixels), at most this many: every k-th, in
    /// the frame's order, of its strongest [`MAX_POINTS`], so that they lie as spread as
    /// those do, and each counts for k in the information the scene holds (`MIN_INFO`).
    /// The coarser scale brings the alignment near, and fixes the turn the measuring
    /// scale may keep; it took as many pixels as the measuring scale, and twice its
    /// steps (5.4 a frame against 2.5 on a hand-held 640x480 twin).
    MAX_COARSE_POINTS: usize = 6_000, "pixels",
        what "most pixels read on the coarser scale (evenly among its strongest)",
        chosen_by "hand-held seed-53 sweep scenes at 3000: 0.75 of the CPU, the same shares within 0.02 deg and 0.5 %, but a released ball under a swaying camera (tests/synthetic_video.rs) lost its wire; 6000 keeps it";

    /// See `Steady::measure`.
    RESTART: f64 = 1.2, "ratio",
        what "restart from no motion when the previous start aligns this much worse",
        chosen_by "96db5d0: hand-picked; not swept";

    /// Whether the camera moved is judged with Tukey's scale widened by what this much
    /// misalignment changes a pixel's grey by along its gradient, px: an edge a little
    /// misaligned is not yet an outlier.
    EXPLAIN_PX: f32 = 0.5, "px",
        what "Tukey's scale widening for whether the camera moved",
        chosen_by "96db5d0: half a pixel; not swept";

    /// The same for the measurement. On the hand-held twin the angles err 0.015 deg RMS at
    /// 0 px, 0.033 at 0.3 and 0.08 at 0.5; but on real clips moved by ffmpeg (two rods; a
    /// split screen with an exposure drift) 0 px lets the alignment follow the rods or
    /// drift, and at 0.3 the rods of the still two-rod clip measure as a camera moving 4.5
    /// px: 0.5 is the one that errs on none of them.
    MEASURE_PX: f32 = 0.5, "px",
        what "Tukey's scale widening for the measurement",
        chosen_by "hand-held twin 0 / 0.3 / 0.5 px: 0.015 / 0.033 / 0.08 deg RMS; real two-rod clip at 0.3 px read 4.5 px of camera motion";

    /// A pixel differing from the first frame by more than this (grey levels), once
    /// aligned, weighs nothing (Tukey's biweight): it sees something that moved.
    TUKEY_LEVELS: f32 = 10.0, "grey levels",
        what "a pixel off by more than this, aligned, weighs nothing",
        chosen_by "f48638b: hand-picked; not swept";

    /// A steadied frame's pixels, aligned, differ from the first frame's by a median
    /// share of their Tukey scale (`TUKEY_LEVELS` widened by `MEASURE_PX`); past this
    /// share the scale of the frames after widens in proportion: the noise of the scene,
    /// not something that moved, leaves the pixels off. The noise the scale was set for
    /// (`TUKEY_LEVELS` at Tukey's 95 % efficiency, 4.685 standard deviations; a Gaussian
    /// noise's median size 0.6745 of one) gives at most 0.144, and the moving twins of
    /// `make test` and seed 1206 give 0.14 to 0.17: past 0.2 the noise is more than the
    /// scale was set for. A 1080p hand-held twin of a plain plate (CRF 34) gives 0.49,
    /// its alignment crawling to the iterations' cap and its angles 0.314 deg RMS off
    /// (0.126 widened). At 0.144 it read 0.091, but a rolling shutter's twin at 0.17,
    /// widened a few hundredths, lost its readout's fit (0.048 -> 0.125 deg RMS).
    NOISE_SHARE: f32 = 0.2, "share of Tukey's scale",
        what "the steadied frames' median difference, aligned, past which Tukey's scale widens",
        chosen_by "the noise the scale was set for gives at most 0.144, the moving twins 0.14-0.17; seed 1206's scene 14 (0.49): 0.314 -> 0.126 deg RMS";

    /// ... at most this many times ...
    MAX_WIDEN: f32 = 4.0, "ratio",
        what "most widening of Tukey's scale for a noisy scene",
        chosen_by "seed 1206's scene 14 asks 3.4 at its median frame; hand-picked";

    /// ... the share taken as its lower quartile over the last this many frames: a
    /// person walking through lifts a frame's share (to 5 on a 1080p twin), not the
    /// scene's noise. Averaged over 10 frames, the scale widened 4 times while they
    /// passed and let them pull the alignment (two hand-held twins with a walker, 0.004
    /// and 0.011 deg RMS, went to 0.024 and 0.038); the median over 101 frames still
    /// widened it 4 times while one passed for 100 frames.
    NOISE_FRAMES: usize = 301, "frames",
        what "the steadied frames' median difference is the lower quartile over this many frames",
        chosen_by "seed 1206's scenes 43 and 58 (a person walking through); hand-picked";

    /// A direction of motion along which the scene's pixels hold less information than
    /// this (the weighted mean of the squared gradient along it, grey levels squared per px
    /// squared, on the measuring scale) is not measured: the frame is not moved along it. A
    /// textured scene holds 4 to 50 along every direction, the twin's plate 0.2 to 12 (its
    /// turn the least: at 0.3 the turn of a hand-held twin was mostly left in, 0.26 deg
    /// angle RMS, at 0.15 0.05 deg), a plain wall 0.04 to 0.13 along its least.
    MIN_INFO: f64 = 0.15, "grey levels^2/px^2",
        what "a direction of motion with less information is not measured",
        chosen_by "hand-held twin: 0.3 -> 0.26 deg RMS, 0.15 -> 0.05 deg; plain wall 0.04-0.13, texture 4-50";

    /// See `shutter`: a rolling shutter's readout fitted to the angles is taken out of them
    /// when it stands this many standard errors from none ...
    READOUT_SIGNIFICANCE: f64 = 6.0, "standard errors",
        what "a rolling shutter's readout is taken out of the angles when this many standard errors from none",
        chosen_by "hand-picked: a hand-held 640x480 twin read out over 0.8 of the interval fits 19.6 ms at 46 standard errors (0.134 -> 0.047 deg RMS), the same twin with a global shutter 0.2";

    /// ... and within this share of the frame's interval (the rows are read within one
    /// frame's time).
    MAX_READOUT: f64 = 1.0, "share",
        what "longest rolling shutter readout taken, a share of the frame's interval",
        chosen_by "the rows of a frame are read within its interval";

    /// See `shutter::wire`: the readout fitted to how the moving wire bows compares each
    /// frame's bow with the other frames' at the same angle, in bins this wide (a lens's
    /// bow changes little over it) ...
    WIRE_READOUT_BIN_DEG: f64 = 0.5, "deg",
        what "bins of angle whose frames' bows are compared for a rolling shutter's readout",
        chosen_by "hand-picked: a lens's bow changes little over it, and a swing of a few deg fills each bin from both directions; not swept";

    /// ... it is taken when it stands this many standard errors from none, the rows read
    /// top to bottom (and within a frame's interval, [`MAX_READOUT`]) ...
    WIRE_READOUT_SIGNIFICANCE: f64 = 10.0, "standard errors",
        what "a rolling shutter's readout fitted to the wire's bows is taken when this many standard errors from none",
        chosen_by "hand-picked: the sweep's rolling shutters fit at 11.8 to 120 standard errors; twins of a 1 px wire with a global shutter (seed 8897's scene 23 and its variants) at 5.2, 5.6 and 12.9 (the last 89 ms, five times the interval)";

    /// ... its uncertainty is the jackknife over this many contiguous blocks of frames (a
    /// bow's noise follows the swing) ...
    WIRE_READOUT_BLOCKS: usize = 10, "blocks",
        what "contiguous blocks of frames of the readout's jackknife",
        chosen_by "as the lens's fit from the wire's bows (lens::bow); not swept";

    /// ... it is fitted to at least this many frames with a bow ...
    WIRE_READOUT_MIN_FRAMES: usize = 200, "frames",
        what "fewest frames with a bow a rolling shutter's readout is fitted to",
        chosen_by "hand-picked: a few swings at 25 frames/s; not swept";

    /// ... each of whose strips follows at least this share of an offset (see
    /// `Bowed::response`).
    WIRE_READOUT_MIN_RESPONSE: f64 = 0.2, "share",
        what "least share of an offset a frame's strip must follow for its bow to count",
        chosen_by "as the lens's fit from the wire's bows (lens::bow); not swept";

    /// A frame whose alignment leaves the static scene's pixels (weighted) this far off on
    /// average (grey levels RMS, each pixel's weight its Tukey weight) is not taken as
    /// measured.
    MAX_RESIDUAL: f64 = 40.0, "grey levels",
        what "a frame aligned this far off on average is not taken as measured",
        chosen_by "f48638b: hand-picked; not swept";

    /// A frame measured farther from the first than this share of the video's side (a
    /// glance at the streaming pass's region: of the region's; see `Steady::within`), or
    /// turned by more than `MAX_TURN_DEG`, is not taken as measured: a camera held still
    /// by hand or on a tripod does not go so far, and an alignment that did has followed
    /// something that moves (on a plain wall, the ball) rather than the scene.
    MAX_SHIFT: f64 = 0.02, "share",
        what "farthest shift, as a share of the video's side (a glance: the region's), taken as measured",
        chosen_by "96db5d0: motions beyond 2 % of the side refused; not swept. Followed frames judged by the video's side: a drift of 8.6 px in a 228x256 region 0.29 -> 0.11 deg RMS";

    /// See `MAX_SHIFT`, degrees.
    MAX_TURN_DEG: f64 = 3.0, "deg",
        what "largest turn taken as measured",
        chosen_by "f48638b: hand-picked; not swept";

    /// A frame of the first look counts as moved only when its pixels, aligned, differ from
    /// the first frame's (Tukey's loss) by less than this share of what they differ
    /// unaligned (see `Steady::explains`).
    EXPLAINS: f64 = 0.6, "share",
        what "a look frame counts as moved when aligned it differs less than this share",
        chosen_by "96db5d0: hand-picked; not swept";

    /// A camera the first look took for still that the streaming pass finds moving from
    /// its start is measured again steadied only when the look's glances hinted it: more
    /// than `MOVING_SHARE` of them aligned to a motion that explains the frame by this
    /// share. A hand-held camera shrunk four times or more explains 0.42 to 0.83 of a
    /// glance's pixels (the moving wire and ball keep the loss high); a plain synthetic
    /// scene of a still camera, whose glances align to nothing, 0.90 to 0.99 (one 0.34).
    LOOK_HINT_EXPLAINS: f64 = 0.85, "share",
        what "a look glance hints the camera moved when aligned it differs less than this share",
        chosen_by "issue 49: 2560x1440 to 7680x4320 hand-held twins 4 to 9 of 10-12 glances under it; a still plain scene 1 of 11";

    /// The camera is taken as moving when a frame of the first look is displaced, at its
    /// farthest corner, by more than this many px of the frame as measured ...
    MOVING_PX: f64 = 0.4, "px",
        what "a look frame displaced more than this at its farthest corner moved",
        chosen_by "f48638b: a still camera measures within a few hundredths of a px; not swept";

    /// The first look measures every this many frames to tell whether the camera moves
    /// (all of them once it does): a still camera's look costs a third of the measurement.
    LOOK_EVERY: u64 = 6, "frames",
        what "the first look measures every this many frames",
        chosen_by "b57b00c: with the 0.2 s floor (LOOK_EVERY_S) a still 60 fps clip's CPU 1.16 -> 1.08 of unsteadied; the 6 itself not swept";

    /// ... and `LOOK_EVERY_S` apart at least: 13 glances over the look at 30 frames/s or
    /// less, not 25 at 60 (a still 60 fps clip's detection took a fifth more of the
    /// processor than without them). A glance every 0.24 s whatever the rate left the
    /// two-rod clip, moved, 2 glances of 10 that found it moved, and unsteadied.
    LOOK_EVERY_S: f64 = 0.2, "s",
        what "... and this far apart at least",
        chosen_by "b57b00c: 0.24 s whatever the rate left the moved two-rod clip unsteadied";

    /// ... in more than this share of the first look's frames: a still camera's frames
    /// measure within a few hundredths of a pixel of the first.
    MOVING_SHARE: f64 = 0.2, "share",
        what "the camera moves when more than this share of look frames moved",
        chosen_by "f48638b: hand-picked; not swept";

    /// The pass does not read the part of the frame the pendulum sweeps: out to this many
    /// times the farthest the wire was seen from the pivot (the ball at its end) ...
    SWEEP_REACH: f64 = 1.4, "ratio",
        what "the pass's steadying skips the sweep out to this times the wire's reach",
        chosen_by "hand-held twin with a visible ball: pulled 2.4 deg round the pivot without it";

    /// ... and this much beyond the angles it was seen at on either side (the ball's own
    /// width, the wire's and the ball's shadows).
    SWEEP_MARGIN_DEG: f64 = 15.0, "deg",
        what "... and this far beyond the angles the wire was seen at",
        chosen_by "a ball of a seventh of the wire's length, a shadow 5 deg off; not swept";

    /// A moving camera's first look measures its frames twice: the first time it counts,
    /// for each pixel of the first frame, the frames that do not show it alike once
    /// aligned, and drops those that differ in more than this share of them (the
    /// pendulum's: a visible ball near where the first frame has it pulls the alignment
    /// round the pivot).
    PRUNE_SHARE: f64 = 0.5, "share",
        what "the look drops first-frame pixels that differ in more than this share of its frames",
        chosen_by "hand-picked; not swept";

    /// ... when at least this many frames were counted ...
    PRUNE_MIN_FRAMES: u32 = 8, "frames",
        what "... when at least this many frames were counted",
        chosen_by "hand-picked; not swept";

    /// ... and at least this share of the pixels is kept, percent.
    PRUNE_MIN_KEPT: usize = 25, "percent",
        what "... and at least this share of pixels is kept",
        chosen_by "hand-picked; not swept";

    /// The streaming pass, steadying every frame, counts the same over its first this
    /// many frames measured, and drops the pixels that differed in more than
    /// `PRUNE_SHARE` of them: what the pass reads is its own region at its own scale, not
    /// the look's, and a second pendulum swinging there pulled its alignment. Dropped
    /// this early, what a person passing in the first second hid is dropped too: the
    /// static scene keeps the rest.
    PASS_FIRST_PRUNE_FRAMES: usize = 30, "frames",
        what "the pass drops what moved over its first this many measured frames, then counts again",
        chosen_by "issue 49, seed 1 scene 0 (640x480, a drift found at 10.1 s, a second pendulum): counted over 100 frames, from 11.1 s the second pendulum pulled the motion 12 px and 2 deg off and the angles 5 deg, 40 frames `ok`; 0.87 -> 0.12 deg RMS, none `ok` over 0.5 deg; 30 hand-picked";

    /// ... then counts again up to this many frames measured, and drops what differed in
    /// more than `PRUNE_SHARE` of those since the first drop (each drop keeps at least
    /// `PRUNE_MIN_KEPT` of what it finds).
    PASS_PRUNE_FRAMES: usize = 100, "frames",
        what "... and again after this many measured frames",
        chosen_by "issue 49: a second pendulum beside a hand-held twin's wire, 0.082 -> 0.049 deg RMS; 100 frames hand-picked";

    /// A frame's light against the first's (see `Light`) is first fitted in this many
    /// rounds ...
    LIGHT_ROUNDS: usize = 3, "rounds",
        what "rounds of the light's first fit",
        chosen_by "hand-picked; not swept";

    /// ... on the pixels within this many grey levels of the fit (Tukey's biweight).
    LIGHT_LEVELS: f32 = 30.0, "grey levels",
        what "tolerance of the light's first fit",
        chosen_by "hand-picked; not swept";

    // From steady/follow.rs.
    /// See `Late`: so many glances in a row must find the camera moved.
    LATE_GLANCES: usize = 2, "glances",
        what "glances in a row that must find a still-seen camera moved",
        chosen_by "5d8c5fd: drift twin (8 px over 20 s) angle RMS 0.55 -> 0.067 deg";

    /// See `Late::drifts`: a glance that does not explain the frame by `EXPLAINS` still
    /// counts when it does by this share ...
    LATE_EXPLAINS: f64 = 0.95, "share",
        what "a glance explaining the frame by this share may still be a drift",
        chosen_by "a drift of 11 px under CRF 35: glances at 0.82 to 0.91; hand-picked";

    /// ... and, measured afresh, lies within this share of its reach of the glance
    /// before ...
    LATE_AGREE: f64 = 0.5, "share",
        what "a drift's glances agree within this share of their reach",
        chosen_by "hand-picked; not swept";

    /// ... so many times in a row.
    LATE_DRIFT_GLANCES: usize = 2, "glances",
        what "glances in a row that must agree for a drift",
        chosen_by "hand-picked; not swept";

    /// See `Late`, s: a drift or a bump is caught within two of these; a still camera pays
    /// one measurement each (at 1 s, a 22 s 60 fps clip took 4 % more of the processor than
    /// at 2 s; the drift twin's angles erred the same).
    LATE_EVERY_S: f64 = 2.0, "s",
        what "a camera seen still is glanced at this often on the pass",
        chosen_by "010dc75: at 1 s a 22 s 60 fps clip took 4 % more CPU; the drift twin errs the same at 2 s";

    /// See `Followed::next`: a steadied frame whose pixels, aligned, are off (Tukey's
    /// loss) more than this many times the typical frame's ...
    HIDDEN_TIMES: f64 = 3.0, "times",
        what "a steadied frame whose aligned loss is this many times the typical has its scene hidden",
        chosen_by "issue 49: a walker over a 640x480 sway twin 0.13 -> 0.87, the motion read 8 px and 3 deg off; seed 1's 14 steadied scenes: 172 frames found, 168 spoiled (walker, hand, flash) and 4 beside a walker; no other above 2.7 times after the first twenty but two beside a walker under 0.3";

    /// ... and more than this loss (a share of the pixels) has its static scene hidden
    /// (a person in front): its motion is not measured, but held.
    HIDDEN_MIN_LOSS: f64 = 0.3, "share",
        what "... and more than this loss",
        chosen_by "issue 49: steadied frames of the moved real clips 0.04 to 0.07; hand-picked";

    /// A run of hidden frames this long is a scene that changed (see `Followed::hidden`):
    /// the first frame's pixels off in more than `SCENE_CHANGE_SHARE` of its frames
    /// are dropped from the static scene.
    SCENE_CHANGE_S: f64 = 2.0, "s",
        what "a run of frames hidden from the steadying this long is a changed scene",
        chosen_by "issue 49, seed 7 scene 52: a releasing hand in the first frame, every frame after hidden (pixels off 0.35 against 0.03); the twin's walker hides a pixel for under 1 s";

    /// ... and the pixels off in more than this share of the run's frames are dropped.
    SCENE_CHANGE_SHARE: f64 = 0.9, "share",
        what "share of a hidden run's frames a pixel must be off in to leave the static scene",
        chosen_by "issue 49: the walker (a third of the frame wide, 4 s to cross) covers a pixel for under half of a 2 s run; a hand gone, all of it";

    /// How much of each steadied frame not hidden the typical loss takes in (at first,
    /// the mean of those so far).
    HIDDEN_FOLLOW: f64 = 0.01, "share",
        what "how fast the typical loss of a steadied frame follows",
        chosen_by "hand-picked; not swept";

    // From steady/jitter.rs.
    /// The steadying's noise in the angles is read in each frame's departure from the
    /// cubic fitted to a window of this many frames (odd) ...
    JITTER_FRAMES: usize = 9, "frames",
        what "frames of the window whose cubic the motions' and angles' departures are taken from",
        chosen_by "seed 8897's sweep scene 55 (960x540, 60 fps, hand-held, plain room): 5 / 7 / 9 / 15 frames 0.0236 / 0.0215 / 0.0200 / 0.0180 deg RMS from 0.0295; a unit test shaking at 3 Hz dilutes the regression at 15 (0.0164 -> 0.0154 deg RMS; 0.0098 at 9); a 25 fps swing departs from the cubic by 0.0002 deg RMS at 9";

    /// ... and taken out of the angles when one of the regression's coefficients stands
    /// this many standard errors from none ...
    JITTER_SIGNIFICANCE: f64 = 10.0, "standard errors",
        what "the steadying's noise is taken out of the angles when this many standard errors from none",
        chosen_by "as the rolling shutter's readout from the wire's bows (WIRE_READOUT_SIGNIFICANCE); not swept";

    /// ... (a jackknife over this many contiguous blocks of frames) ...
    JITTER_BLOCKS: usize = 10, "blocks",
        what "contiguous blocks of frames of the steadying noise's jackknife",
        chosen_by "as the rolling shutter's readout (WIRE_READOUT_BLOCKS); not swept";

    /// ... fitted to at least this many frames ...
    JITTER_MIN_FRAMES: usize = 200, "frames",
        what "fewest steadied frames the steadying's noise is fitted to",
        chosen_by "hand-picked: a few swings at 25 frames/s; not swept";

    /// ... and explaining at least this share of the angles' departures' sum of squares.
    JITTER_MIN_SHARE: f64 = 0.05, "share",
        what "least share of the angles' departures the steadying's noise must explain",
        chosen_by "hand-picked; not swept";
}
