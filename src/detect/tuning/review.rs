//! Knobs of figure 11's frame and the review page's frames.

use super::Knob;

knobs! {
    table REVIEW_KNOBS, stage "figure 11 and review";

    // From figure11.rs.
    /// Seconds after the first `ok` frame in which Figure 11's frame is chosen.
    EARLY_S: f64 = 4.0, "s",
        what "Figure 11's frame is chosen in this long after the first ok frame",
        chosen_by "e2014fb: the first 4 s; not measured";

    /// Frames kept for each side (highest and lowest angles) while streaming.
    PER_SIDE: usize = 4, "frames",
        what "frames kept for each side (highest, lowest angles) for Figure 11",
        chosen_by "e2014fb: hand-picked; not measured";

    // From review.rs.
    /// Flagged frames kept at most.
    MAX_FLAGGED: usize = 48, "frames",
        what "flagged frames the review page keeps at most",
        chosen_by "c69cd66: the review page's size; not measured";

    /// Frames of the start kept at most (the release frame is looked for among them).
    HOLD_FRAMES: usize = 32, "frames",
        what "frames of the start kept at most (the release is looked for in them)",
        chosen_by "c69cd66: hand-picked; not measured";

    /// The start's frames are kept until the wire leaves its first angle by this, degrees.
    HOLD_DEG: f64 = 1.0, "deg",
        what "the start's frames are kept until the wire leaves its first angle by this",
        chosen_by "c69cd66: hand-picked; not measured";

    /// Longer side of a picture at most, px.
    MAX_SIDE: usize = 512, "px",
        what "longer side of a review picture at most",
        chosen_by "c69cd66: the review page's size; not measured";
}
