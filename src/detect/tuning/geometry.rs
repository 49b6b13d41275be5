//! Knobs of the geometry: the wire's lines and pivot in the first look.

use super::Knob;

knobs! {
    table GEOMETRY_KNOBS, stage "geometry";

    // From geometry.rs.
    /// At most this many threads look for the first look's lines (one per processor).
    GEOMETRY_THREADS: usize = 4, "threads",
        what "most threads that look for the first look's lines",
        chosen_by "83f0959 (then on every processor): geometry of the 960x540 bench twin 0.25 -> 0.14 s, angles byte-identical; the cap of 4 not measured";

    /// A second pendulum (`WireGeometry::second`) counts when its pivot lies this share of
    /// the look's larger side away from the first's at least,
    SECOND_APART: f64 = 0.1, "share",
        what "a second pendulum's pivot lies this share of the larger side away at least",
        chosen_by "dcaed79: the split-screen real clip refused as two pendulums; not swept";

    /// and as many directions of lines (half-degree bins) point at it, and half the
    /// first's at least (a ball's or a hand's edges meet in many points, each with a few).
    SECOND_MIN_DIRECTIONS: usize = 10, "directions",
        what "fewest line directions (0.5 deg bins) through a second pendulum's pivot",
        chosen_by "dcaed79: the split-screen real clip refused as two pendulums; not swept";

    /// Widest sweep of a pendulum's wire seen in the first look: lines that fan out over
    /// more than this are an outline (a bob's trail), not a wire.
    MAX_SWEEP_DEG: f64 = 120.0, "deg",
        what "widest fan of first-look lines a wire may make (wider: an outline)",
        chosen_by "bf532b5: the off-screen-pivot clip finds its pivot (988, -629), 0 frames missing";

    /// Lines through one pivot that make a wire (with `video.pivot` given, three do).
    MIN_WIRE_LINES: usize = 6, "lines",
        what "lines through one pivot that make a wire",
        chosen_by "034348f: hand-picked; no figure in the history";

    /// A line through the pivot in as many of the look's frames with such lines as this
    /// share ...
    STATIC_LINE_SHARE: f64 = 0.4, "share",
        what "share of the look's frames a static edge through the pivot lies in",
        chosen_by "a static ruler edge through the pivot, a 0.61 px sway unseen: seed 7 sweep scene 38";

    /// ... within this many degrees of one direction is a static edge, not the wire,
    /// when the wire is seen beside it.
    STATIC_LINE_DEG: f64 = 0.5, "deg",
        what "spread of a static edge's direction through the pivot",
        chosen_by "with STATIC_LINE_SHARE: seed 7 sweep scene 38";

    /// Lines through the pivot within this many degrees of one direction, seen on both
    /// sides of it ...
    STATIC_EDGE_DEG: f64 = 2.0, "deg",
        what "spread of an edge's direction through the pivot, seen on both sides",
        chosen_by "seed 31 sweep scene 18: a ruler's edge through the pivot read at 50.8 to 53.7 deg under a steadied sway";

    /// ... each side in this share of those lines or more (and in two frames), are an
    /// edge running through the pivot, not taken even alone in a frame: a wire ends at
    /// its pivot.
    STATIC_EDGE_SIDE_SHARE: f64 = 0.1, "share",
        what "least share of an edge's lines on each side of the pivot",
        chosen_by "seed 31 sweep scenes 13 and 18 (a protractor's ruler through the pivot under a sway): refused before; hand-picked";

    /// Jumps a first look may show and still be a pendulum's wire (`jumps`).
    MAX_JUMPS: usize = 1, "jumps",
        what "jumps a first look may show and still be a wire",
        chosen_by "034348f: lines that jump refused as no pendulum's; no figure";

    /// The roughness a first look may show and still be a pendulum's wire (`roughness`).
    MAX_ROUGHNESS: f64 = 0.35, "ratio",
        what "roughness a first look may show and still be a wire",
        chosen_by "034348f: lines that jitter refused as no pendulum's; no figure";

    /// The first look's first try: pixels this many noise sigmas over each pixel's
    /// noise ...
    LOOK_SIGMAS: f64 = 4.0, "sigmas",
        what "the first look's first threshold, noise sigmas",
        chosen_by "034348f: the look at the first threshold; not swept";

    /// ... and at least this many grey levels ...
    LOOK_FLOOR: f64 = 6.0, "grey levels",
        what "the first threshold's floor",
        chosen_by "034348f: not swept";

    /// ... whatever directions its lines take.
    LOOK_DIRECTIONS: usize = 0, "directions",
        what "directions the first try's lines must take",
        chosen_by "034348f: none asked of the first threshold";

    /// The second try, for a faint wire, at this many sigmas ...
    LOW_SIGMAS: f64 = 2.0, "sigmas",
        what "the second, lower threshold, noise sigmas",
        chosen_by "034348f: a faint wire (a second look at a lower threshold); not swept";

    /// ... and this floor ...
    LOW_FLOOR: f64 = 4.0, "grey levels",
        what "the lower threshold's floor",
        chosen_by "034348f: not swept";

    /// ... its lines turning through this many directions (half-degree bins): a low
    /// threshold lets the noise make lines too, and those do not turn with a pendulum.
    LOW_DIRECTIONS: usize = 8, "directions",
        what "directions the lower threshold's lines must take",
        chosen_by "034348f: noise lines do not turn with a pendulum; not swept";

    /// The streaming pass's threshold floor (grey levels), under half the first
    /// threshold's sigmas (`video.threshold_sigma`).
    PASS_FLOOR: f64 = 6.0, "grey levels",
        what "the streaming pass's threshold floor",
        chosen_by "034348f: not swept";

    // From geometry/faint.rs.
    /// The faint look's threshold: this many noise sigmas above the median (no allowance
    /// for the running extreme's own offset), at least one grey level.
    FAINT_SIGMAS: f64 = 1.5, "sigmas",
        what "the faint look's threshold over the median",
        chosen_by "90a2d18: a pixel-wide wire a few levels dark under flicker found; videos detected before unchanged";

    /// Directions the faint look's lines must take (its threshold lets the noise through).
    FAINT_MIN_DIRECTIONS: usize = 8, "directions",
        what "directions the faint look's lines must take",
        chosen_by "90a2d18: hand-picked; not swept";

    /// A faint line's votes, as a share of the shortest wire: its pixels over the faint
    /// threshold along it.
    FAINT_VOTES: f64 = 0.5, "share",
        what "a faint line's votes, as a share of the shortest wire",
        chosen_by "90a2d18: hand-picked; not swept";

    /// The strongest lines of a frame the faint look weighs, and the widest gap (px) along
    /// one between pixels over its threshold that still joins them into one wire: the
    /// noise that passes the faint threshold (a few pixels in a hundred) leaves wider gaps.
    FAINT_CANDIDATES: usize = 12, "lines",
        what "strongest lines of a frame the faint look weighs",
        chosen_by "90a2d18: hand-picked; not swept";

    FAINT_GAP: f64 = 3.0, "px",
        what "widest gap along a faint line that still joins one wire",
        chosen_by "90a2d18: noise over the faint threshold leaves wider gaps; not swept";

    // Lifted from geometry.rs and geometry/.

    HOUGH_VOTE_SHARE: f64 = 0.5, "share",
        what "a frame's Hough segment needs votes of this share of the shortest wire",
        chosen_by "297050c: the first detector's value; not measured";

    HOUGH_MIN_VOTES: f64 = 10.0, "votes",
        what "... and at least this many",
        chosen_by "297050c: the first detector's value; not measured";

    HOUGH_MAX_GAP_PX: f64 = 4.0, "px",
        what "widest gap a Hough segment bridges",
        chosen_by "297050c: the first detector's value; not measured";

    LINE_APART_DEG: f64 = 8.0, "deg",
        what "a frame's lines (up to three) differ in direction by this much at least",
        chosen_by "297050c: the first detector's value; not measured";

    LINE_PIXELS_PX: f64 = 1.5, "px",
        what "pixels within this of a segment's line are fitted to it",
        chosen_by "297050c: the first detector's value; not measured";

    /// A frame's line whose two ends both lie within this share of the video's smaller
    /// side (at least `EDGE_MIN_PX` of the look's px) of one edge of the video's frame
    /// runs along that edge: a stabilised or software-turned picture's empty border,
    /// which moves with the picture, not a wire (a wire meets the frame's edge only by
    /// crossing it).
    EDGE_MARGIN_SHARE: f64 = 0.01, "share",
        what "a line with both ends this near one edge of the frame runs along it, not a wire",
        chosen_by "the real off-screen pivot clip moved by ffmpeg (turned 0.3-0.4 deg, cropped 4 px): empty borders up to 8 px of 1072; hand-picked";

    /// See `EDGE_MARGIN_SHARE`.
    EDGE_MIN_PX: f64 = 2.0, "px",
        what "least margin along the frame's edges, px of the look",
        chosen_by "hand-picked: a border a pixel or two wide after shrinking";

    THRESHOLD_MAX_LEVELS: f64 = 250.0, "grey levels",
        what "highest a pixel's threshold may be",
        chosen_by "034348f: hand-picked; not measured";

    MIN_LEN_SHARE: f64 = 0.2, "share",
        what "shortest wire, as a share of the look's smaller side",
        chosen_by "297050c: the first detector's value; not measured";

    LOOK_CLOSE_FRAMES: usize = 60, "frames",
        what "about this many of the look's frames are searched for lines",
        chosen_by "895feef: hand-picked; not measured";

    BASE_TOL_PX: f64 = 2.0, "px",
        what "a line passes through a RANSAC pivot within this at least",
        chosen_by "297050c: the first detector's value; not measured";

    BASE_TOL_SHARE: f64 = 0.005, "share",
        what "... or this share of the look's larger side",
        chosen_by "297050c: the first detector's value; not measured";

    BAND_INNER_PCT: f64 = 0.08, "share",
        what "the band starts at this percentile of the lines' pixels' radii",
        chosen_by "297050c: the first detector's value; not measured";

    BAND_INNER_SLACK: f64 = 0.97, "ratio",
        what "... times this",
        chosen_by "297050c: the first detector's value; not measured";

    BAND_OUTER_PCT: f64 = 0.98, "share",
        what "the band ends at this percentile of the radii",
        chosen_by "297050c: the first detector's value; not measured";

    BAND_OUTER_SLACK: f64 = 1.02, "ratio",
        what "... times this",
        chosen_by "297050c: the first detector's value; not measured";

    ROI_MARGIN_DEG: f64 = 10.0, "deg",
        what "the region covers the angles seen in the look widened by this",
        chosen_by "297050c: the first detector's value; not measured";

    ROI_PAD_PX: f64 = 8.0, "px",
        what "and is padded by this",
        chosen_by "297050c: the first detector's value; not measured";

    RANSAC_TRIES: usize = 600, "pairs",
        what "pairs of lines the pivot's RANSAC tries",
        chosen_by "297050c: the first detector's value; not measured";

    /// The polarity that loses the first look is looked at to its end when its lines can
    /// still take this share of the winner's directions (it is given up as soon as they
    /// cannot: the look reads the loser further than when it was given up as soon as it
    /// could not win, and to its end only when it comes within this share) ...
    RIVAL_POLARITY_SHARE: f64 = 0.7, "share",
        what "the losing polarity is looked at to its end within this share of the winner's directions",
        chosen_by "issue 50: a light 1 px wire with its dark shadow took 26 and 27 directions (the shadow taken, 0.11 deg RMS); the red-apple clip's light lines 33 of 43";

    /// ... and its lines, swinging about the same pivot, rival the wire's when they lie
    /// this far from them at least (median over the frames both see; a wire's own
    /// highlight or edge of the other polarity lies along it).
    RIVAL_OFFSET_MIN_DEG: f64 = 1.0, "deg",
        what "lines of the other polarity this far from the wire's rival it",
        chosen_by "issue 50: a wire and its shadow 4.8 deg apart; hand-picked";

    /// ... and hold that angle, on one side: the spread between the quartiles of the
    /// signed angle over the frames is at most this share of its median (a shadow keeps its angle to the wire; a ghost or the
    /// scene's lines do not).
    RIVAL_OFFSET_STEADY: f64 = 0.25, "share",
        what "... and keep that angle within this share (quartiles' spread)",
        chosen_by "issue 50: a wire's shadow -4.71 to -4.40 deg off; the red-apple clip's light lines -1.4 to 30.7, a hand-held dark-wire twin's -3.6 to 7.6, a light wire's own shadow -5.5 to 8.1";
}
