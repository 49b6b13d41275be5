//! Knobs of the brightness: one gain per frame, and a covered frame.

use super::Knob;

knobs! {
    table LIGHT_KNOBS, stage "brightness";

    // From light.rs.
    /// Every `LIGHT_SAMPLE_STEP`-th pixel votes for the gain (a few thousand votes per frame).
    LIGHT_SAMPLE_STEP: usize = 7, "pixels",
        what "every n-th pixel votes for the frame's gain",
        chosen_by "034348f: a few thousand votes a frame; not swept";

    /// Ratios are counted in bins of `1 / RATIO_SCALE` (0.1 %) from 0 to 4.
    RATIO_SCALE: u32 = 1024, "bins per unit",
        what "ratios are counted in bins of 1/RATIO_SCALE (0.1 %)",
        chosen_by "034348f: hand-picked; not swept";

    RATIO_BINS: usize = 4 * RATIO_SCALE as usize, "bins",
        what "bins of the ratio histogram (ratios 0 to 4)",
        chosen_by "034348f: follows RATIO_SCALE";

    /// Reference pixels darker than this carry too little light for a ratio.
    MIN_REFERENCE: u8 = 16, "grey levels",
        what "reference pixels darker than this carry no ratio",
        chosen_by "034348f: hand-picked; not swept";

    /// Gains closer to 1 than this leave the frame as it is (bit for bit): steadily lit
    /// footage is not touched.
    DEAD_BAND: f64 = 0.004, "ratio",
        what "gains closer to 1 than this leave the frame untouched",
        chosen_by "034348f: steadily lit footage bit for bit as before; not swept";

    /// A frame is covered (a person in front of the plate) when more of its region than
    /// this many times the typical share, and than `COVERED_SHARE`, shows something else
    /// than the first look's reference (`Brightness::foreign`) ...
    COVERED_TIMES: f64 = 3.0, "times",
        what "a frame is covered when its foreign share is this many times the typical",
        chosen_by "300bdf1: a person in front of the plate; not swept";

    /// ... (see `COVERED_TIMES`) ...
    COVERED_SHARE: f64 = 0.35, "share",
        what "... and more than this share",
        chosen_by "300bdf1: a person in front of the plate; not swept";

    /// ... or when its brightness departs from the typical by more than this factor (a
    /// person covering most of the region: the gain follows it; flicker of 15 % and a
    /// slow drift stay well within).
    COVERED_GAIN: f64 = 1.35, "ratio",
        what "... or when its gain departs from the typical by this factor",
        chosen_by "300bdf1: flicker of 15 % and a slow drift stay within; not swept";

    /// How much of each frame not covered the typical foreign share and gain take in.
    COVERED_FOLLOW: f64 = 0.01, "share",
        what "how much of each uncovered frame the typical share and gain take in",
        chosen_by "300bdf1: hand-picked; not swept";

    /// A vote whose ratio lies beyond this factor of the frame's gain (either way) is
    /// foreign: the pixel shows something else than the reference did (the ball, or a
    /// person in front of the plate), not the same scene lit otherwise.
    FOREIGN_RATIO: f64 = 1.25, "ratio",
        what "a vote beyond this factor of the frame's gain is foreign",
        chosen_by "300bdf1: hand-picked; not swept";
}
