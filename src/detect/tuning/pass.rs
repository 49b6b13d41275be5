//! Knobs of the streaming pass: the track and its gate, the pivot, filling.

use super::Knob;

knobs! {
    table PASS_KNOBS, stage "streaming pass";

    // From track.rs.
    /// A re-anchoring's three raw measurements that move less than this (deg) and lie
    /// more than `REANCHOR_AWAY_GATES` gate from the last accepted angle are a fixed
    /// mark, not the wire (`Tracker::step`).
    REANCHOR_STILL_DEG: f64 = 0.25, "deg",
        what "a re-anchoring's measurements moving less than this are a fixed mark",
        chosen_by "1a89afa (issue 10): hand-picked; no figure";

    REANCHOR_AWAY_GATES: f64 = 1.0, "gates",
        what "... when they lie this many gates from the last accepted angle",
        chosen_by "1a89afa (issue 10): hand-picked; no figure";

    /// After a refused frame, the prediction is the least-squares quadratic of the
    /// accepted angles of the last `LONG_FIT_S` s, when there are `LONG_FIT_FRAMES` or
    /// more of them (`Tracker::predict_raw`).
    LONG_FIT_S: f64 = 0.3, "s",
        what "after a refused frame, predict from the accepted angles of the last this long",
        chosen_by "1a89afa (issue 10): replaces three noisy angles; no figure";

    LONG_FIT_FRAMES: usize = 6, "frames",
        what "fewest angles for that prediction",
        chosen_by "1a89afa (issue 10): hand-picked; no figure";

    /// Accepted frames that make a track: the quadratic prediction needs three.
    START_FRAMES: usize = 3, "frames",
        what "accepted frames that make a track",
        chosen_by "b04360b: the quadratic prediction needs three points";

    /// A frame whose mean grey moves from the running mean by more than this share of
    /// it (of at least `FLASH_MIN_LEVEL`) is a flash, kept out of the background.
    FLASH_SHARE: f64 = 0.2, "share",
        what "a frame whose mean grey moves more than this share is a flash",
        chosen_by "297050c: the first detector's value; not measured";

    FLASH_MIN_LEVEL: f64 = 20.0, "grey levels",
        what "... of a running mean of at least this",
        chosen_by "297050c: the first detector's value; not measured";

    /// A frame that differs from the previous one by less than this on average (grey
    /// levels, every 5th byte), or by less than `REPEAT_SHARE` of the typical change,
    /// is the previous one repeated.
    REPEAT_MAD: f64 = 0.02, "grey levels",
        what "a frame changing less than this on average repeats the previous one",
        chosen_by "297050c: the first detector's value; not measured";

    REPEAT_SHARE: f64 = 0.15, "share",
        what "... or less than this share of the typical change",
        chosen_by "297050c: the first detector's value; not measured";

    /// A frame that changes more than this many times the typical change (of at least
    /// `DISTURBED_MIN_MAD`) is disturbed (a hand, a bump).
    DISTURBED_TIMES: f64 = 4.0, "ratio",
        what "a frame changing this many times the typical change is disturbed",
        chosen_by "8ff29a6: the gate's disturbances flagged; not swept";

    DISTURBED_MIN_MAD: f64 = 0.5, "grey levels",
        what "... the typical change counted as at least this",
        chosen_by "8ff29a6: the gate's disturbances flagged; not swept";

    /// The background's running extreme moves one grey level back towards the scene
    /// every this many frames, so that slow changes of the light are followed.
    BG_DECAY_FRAMES: u64 = 120, "frames",
        what "the background decays by one grey level every this many frames",
        chosen_by "8ff29a6: hand-picked; not swept";

    /// A wire that has lain this long within half the strip's half width of where it lay
    /// (seen from the strip's far end) is at rest: at the background's lowering its whole
    /// strip keeps its level, not only its pixels over their threshold.
    BG_REST_S: f64 = 1.0, "s",
        what "a wire lying this long within its strip keeps its whole strip in the background",
        chosen_by "hand-picked: about a turning point, a swing of a 3.4 s period lies a second within the band only when under 2.5 times the strip's half width; not swept";

    /// A prediction is clamped to the first look's sweep widened by this each side.
    PREDICT_BEYOND_SWEEP_DEG: f64 = 15.0, "deg",
        what "predictions are kept within the first look's sweep widened by this",
        chosen_by "daae8f8: the first tracker's value; not measured";

    // From track/pivot.rs.
    /// Fewest accepted frames, and smallest spread of their angles, for `Tracker::swing_scale`.
    SWING_SCALE_FRAMES: usize = 20, "frames",
        what "fewest accepted frames for a swing scale",
        chosen_by "4883570: hand-picked; not measured";

    SWING_SCALE_SPREAD_DEG: f64 = 2.0, "deg",
        what "smallest spread of their angles for a swing scale",
        chosen_by "4883570: hand-picked; not measured";

    /// The windows `pivot_drift` takes the median of, s.
    DRIFT_WINDOW_S: f64 = 2.0, "s",
        what "windows the pivot's drift takes the median of",
        chosen_by "dcaed79: hand-picked; not measured";

    /// Fewest free lines, and the share of them whose directions must spread over
    /// `REFINE_SPREAD_DEG`, for `refined_pivot`.
    REFINE_LINES: usize = 20, "lines",
        what "fewest free lines for the pivot's refinement",
        chosen_by "09b4502 (issue 10): hand-picked; no figure";

    REFINE_CENTRAL: f64 = 0.8, "share",
        what "share of the free lines whose directions must spread (not the extremes)",
        chosen_by "09b4502 (issue 10): central 80 % instead of the extremes; no figure";

    REFINE_SPREAD_DEG: f64 = 2.0, "deg",
        what "spread of those directions the refinement needs",
        chosen_by "09b4502 (issue 10): hand-picked; no figure";

    /// When more than this share of the frames' far strips were not re-centred on the
    /// wire's free line (see `KeptMoments::free`: a wire blurred by its own speed), the
    /// pivot is refined from the re-centred lines of the slow frames alone
    /// (`REFINE_SLOW_SHARE`, see `refinement_lines`) ...
    REFINE_HELD_SHARE: f64 = 0.2, "share",
        what "share of lines kept about the pivot's line above which the slow frames' free lines refine the pivot",
        chosen_by "the green-screen real clip (25 fps, blurred mid-swing) held about half of its lines; a 640x480 twin and the film 1 and red apple clips none";

    /// ... those turning slower than this share of the pass's fast angular speed (its
    /// 95th percentile). The wire's lines in fast frames pass 1 to 5 px beside the
    /// pivot, on the side the wire moves to (the blur and the shutter), and those a
    /// pivot's line held come from one direction of swing more than the other.
    REFINE_SLOW_SHARE: f64 = 0.3, "share",
        what "slowest frames' share of the fast angular speed whose lines refine the pivot when many were held",
        chosen_by "the green-screen real clip from three starting pivots up to 4.4 px apart: refined 3.0 px apart with all lines, 1.1 px with the slow free lines (0.2 to 0.7 px from where the wire's lines at its turning points meet, by hand); its swing over 4 s moved by hand three ways +0.18 / +0.19 / +0.26 -> -0.00 / +0.14 / +0.07 deg from the still clip's; 0.2 and 0.5 not swept";

    // From mod.rs.
    /// A camera taken for still whose static scene two glances in a row find off (the `still`
    /// check failed) is measured again steadied, and that measurement kept when `ok` and,
    /// when `still` was the first's only failed check, when the steadying added at most
    /// this much noise from frame to frame, deg (in quadrature: `sqrt(noise2^2 -
    /// noise1^2)`). Three plain 320x240 walls whose glances
    /// misread 1.2 to 2.8 px of motion gained 0.038, 0.053 and 0.115 deg; three swaying
    /// sweep twins (seed 4 scene 4 at 40 and 12 s, scene 38) 0.005 to 0.007.
    STILL_AGAIN_NOISE_MAX_DEG: f64 = 0.01, "deg",
        what "noise the steadying may add for a second measurement after `still` alone failed to be kept",
        chosen_by "plain in-memory walls gained 0.038-0.115 deg (misread motions), swaying sweep twins 0.005-0.007";

    /// A swing scale (`Tracker::swing_scale`) further than this from 1 has the other
    /// working scale's look measured too (`detect_from`): the `pivot` check's limit
    /// (`PIVOT_SCALE_MAX`), so that no pass that check calls off is kept without the
    /// other look tried. On the robustness sweep's twins (both seeds, 126 measured) it
    /// lies within 0.002 of 1, and within 0.001 for 122 of them; a 960x540 twin whose
    /// shrunk look took a wire and its shadow for one line gave 1.09. At 0.02 a pass
    /// between the two limits was kept `suspect (pivot)` untried (seed 53 scene 42:
    /// 0.9845, `s_r` -0.86 %).
    SWING_SCALE_RETRY: f64 = super::PIVOT_SCALE_MAX, "ratio",
        what "a swing scale this far from 1 has the other working scale measured too",
        chosen_by "the pivot check's limit (PIVOT_SCALE_MAX); was 0.02 (8e7bd01: sweep both seeds, 126 twins within 0.002; seed 2 scene 16: 1.058 -> 1.0001, 2.1 -> 0.019 deg RMS)";

    /// Of two passes measured at the two working scales for their motion, one whose
    /// look swept within this ratio of its track's swing (twice its first amplitude) ...
    LOOK_SWING_AGREE: f64 = 1.5, "ratio",
        what "a look's sweep within this ratio of its pass's swing agrees with it",
        chosen_by "film 1 (real) moved by hand: the wire's look 24.3 deg, its swing 24.4; hand-picked";

    /// ... is kept over one whose look swept beyond this ratio of its swing, or under its
    /// inverse.
    LOOK_SWING_APART: f64 = 2.0, "ratio",
        what "a look's sweep beyond this ratio of its pass's swing saw something else",
        chosen_by "film 1 (real) moved by hand: the ball's beads' look 88 deg, their swing 7; hand-picked";

    /// A track that turned back fewer than `TURNS_MIN` times over a video this long did
    /// not follow a pendulum's wire: one whose period is 10 s turns back four times in 20
    /// s. Such a pass is measured again from a look against the median alone
    /// (`choose::against_median`); a shorter video's few turns may be a wire held first.
    TURNS_LONG_S: f64 = 20.0, "s",
        what "a video this long whose track turned back too seldom followed no wire",
        chosen_by "film 1 (real) under a jittery hand: 0 turning points in 25.6 s, a static line followed; an 8 s twin held 1.5 s turns back 3 times; the sweeps of seeds 1 and 1206: no scene fails turns";

    // From fill.rs.
    /// Good frames in a run shorter than this, between two losses of the wire, are
    /// flagged `Flag::Isolated`.
    ISOLATED_RUN: usize = 5, "frames",
        what "good runs shorter than this between two losses are flagged isolated",
        chosen_by "27c1bbf: a walker twin's two frames 7.5 deg off, called ok, now missing; not swept";

    /// A loss of the wire: at least this many frames in a row flagged or without an angle.
    /// A short run of found frames (under `ISOLATED_RUN`) whose angle lies beyond the
    /// range of the longer runs' angles by more than this share of that range is flagged
    /// `Flag::Beyond`: a swing never grows.
    BEYOND_SWING_SHARE: f64 = 0.2, "share",
        what "a short run this far beyond the longer runs' range (as a share of it) is flagged",
        chosen_by "issue 49, seed 7 scene 15 (a walker at a turning point, two frames 42 and 23 deg off called ok, the fit refused): those two frames, and none of the 250 other kept detections of seeds 1, 2 and 7 nor the real clips; at 0.1, 8 frames of one suspect scene, under 0.8 deg off";

    /// A track that stands still (its found angles within `STILL_BEYOND_BAND_DEG` of one
    /// another) for `STILL_BEYOND_S` or longer, beyond the swing of the
    /// `STILL_BEYOND_PRIOR_S` before it by more than `STILL_BEYOND_SHARE` of that swing's
    /// range (a swing over at least twice the band), is on something else: a wire comes
    /// to rest inside its last swing (`fill::flag_still_beyond`).
    STILL_BEYOND_S: f64 = 2.0, "s",
        what "a track standing still this long beyond the swing before it is flagged",
        chosen_by "seed 1's sweep scene 32 (640x480, hand-held, a walker at 11.5 s): the track took a static edge 14 deg beyond the swing and stood on it for 27 s, ok; hand-picked above a turning point's dwell within the band (0.3 s at 10 deg and a 2 s period; a turning point cannot lie beyond the swing about it); not swept";

    STILL_BEYOND_BAND_DEG: f64 = 1.0, "deg",
        what "... its found angles within this of one another",
        chosen_by "the same scene: the edge's angle crept 0.9 deg as the walker left it (at 0.5 deg the stretch broke, and its second part lay within the first's range); not swept";

    STILL_BEYOND_PRIOR_S: f64 = 8.0, "s",
        what "... beyond the range of the found angles this long before it",
        chosen_by "kept sweep angles (98 of seeds 1, 2, 7, 1205 and 163 more of seeds 1, 2 and 1205): at 4 s with a share of 0.2 a glass-fiber ball at rest 0.13 deg beyond its last 4 s, its last turning point misread; at 8 s or 0.5 only scene 32 (twice); with the swing's 5th to 95th percentiles, the same on 342 (seed 2's whole sweep added)";

    STILL_BEYOND_QUANTILE: f64 = 0.05, "share",
        what "... that swing from this quantile of its found angles to 1 minus it",
        chosen_by "scene 32 with a frame 1.3 deg off early in its stand: with the extremes, that frame widened the swing and none was flagged; the 5th and 95th percentiles of a sinusoid lie within 1.2 % of its amplitude of its extremes; not swept";

    STILL_BEYOND_SHARE: f64 = 0.5, "share",
        what "... by more than this share of that range",
        chosen_by "the same: scene 32 lies 3 deg beyond the 8 s range widened by 0.5 of it, the glass-fiber ball 2.2 deg inside the 4 s one";

    LOSS_FRAMES: usize = 3, "frames",
        what "a loss of the wire: this many frames in a row flagged or without an angle",
        chosen_by "27c1bbf: the same walker twin; not swept";

    /// See `flag_off_swing`: a found frame more than this off the swing's path fitted
    /// about it, deg, ...
    OFF_SWING_MIN_DEG: f64 = 1.0, "deg",
        what "a found frame this far off the swing's path fitted about it is flagged",
        chosen_by "issue 49: a walker's edge followed 2.8 to 16 deg off after a loss; as JUMP_MIN_DEG";

    /// ... or, within `LOSS_EDGE_S` of a loss of the wire, more than this, deg ...
    LOSS_EDGE_MIN_DEG: f64 = 0.3, "deg",
        what "a found frame beside a loss this far off the swing's path is flagged",
        chosen_by "issue 49, seed 1205 scene 36 (a walker over a still 960x540 twin): a frame on half the wire 0.91 deg off, ok; the sweep's bar for an occluded frame is 0.5 deg";

    /// ... where a loss is `LOSS_FRAMES` frames in a row without an unflagged angle and
    /// its edge reaches this far before its first frame and after its last, s.
    LOSS_EDGE_S: f64 = 0.2, "s",
        what "how far before and after a loss of the wire its edge reaches",
        chosen_by "issue 49, seed 1205 scene 36: the walker's edge crossed the wire over 4 frames at 25 fps (0.16 s)";

    /// ... and more than this many times the fit's robust scatter, is flagged.
    OFF_SWING_SIGMAS: f64 = 8.0, "times",
        what "... and more than this many times the fit's robust scatter",
        chosen_by "issue 50: seeds 1 and 2 (128 twins), prototyped on their CSVs: frames under 0.5 deg off flagged only in two scenes already suspect; hand-picked";

    /// Each fit of the swing's path is made again on the frames within this many times
    /// its robust scatter ...
    OFF_SWING_KEEP_SIGMAS: f64 = 4.0, "times",
        what "a fit of the swing's path is made again on the frames within this many times its scatter",
        chosen_by "hand-picked; not swept";

    /// ... so many times in all.
    OFF_SWING_ROUNDS: usize = 3, "fits",
        what "fits of the swing's path in all",
        chosen_by "hand-picked; not swept";

    /// A step of the swing is judged when at least this many found frames fix its path.
    OFF_SWING_MIN_FIT: usize = 20, "frames",
        what "found frames needed to judge a step of the swing",
        chosen_by "hand-picked; not swept";

    /// See `flag_pulled`: the found frames are put in bins of this width by their
    /// angle, deg ...
    PULL_BIN_DEG: f64 = 0.25, "deg",
        what "the bins of angle in which the residuals from the swing's path are averaged",
        chosen_by "issue 49, seed 1's sweep scene 57 (1280x720, a bright rod through the fulcrum at -61.4 deg inside the swing): its pull spans about 2 deg of measured angle; hand-picked to hold 3 or more frames of each direction of swing at 30 frames/s";

    /// ... and a bin is pulled when, in both directions of swing, its frames' mean
    /// residual from the swing's path, less the median of the same direction's frames
    /// `PULL_RING_FROM_DEG` to `PULL_BASE_DEG` away, lies beyond this (deg) ...
    PULL_MIN_DEG: f64 = 0.05, "deg",
        what "a bin's mean residual, less its surroundings', beyond this in both directions of swing is a pull",
        chosen_by "issue 49, 224 kept sweep detections (seeds 1, 2, 7, 1205) and the 21 real clips (the seven, cropped still and moved), prototyped on their CSVs: scene 57's pulled bins lie 0.07 to 0.45 deg off in both directions; the only other pulls found lie in seed 1's scene 23 (three static edges, 0.055 deg either side of -85.25 deg) and seed 2's scene 48 (0.21 deg scatter, suspect, 0.49 deg RMS)";

    /// ... and beyond this many times the swing's robust scatter over the square root
    /// of the frames averaged ...
    PULL_SIGMAS: f64 = 4.0, "times",
        what "... and beyond this many standard errors of the mean",
        chosen_by "the same; hand-picked";

    /// ... each direction averaging at least this many frames (and its surroundings
    /// holding as many) ...
    PULL_MIN_FRAMES: usize = 3, "frames",
        what "fewest frames of a direction of swing in a bin judged",
        chosen_by "the same: at 4, scene 57's pull loses its side below the rod (6 and 3 frames); hand-picked";

    /// ... from at least this many half periods (a bin only the first swings reach is
    /// not judged: the swing's path there rests on few frames).
    PULL_MIN_PASSES: usize = 3, "half periods",
        what "fewest half periods of a direction of swing in a bin judged",
        chosen_by "scene 57: the bins next to its release angle, reached in the first swing only, erred 0.2 to 0.9 deg from the path fitted over it before the swing's span bounded the fit";

    PULL_RING_FROM_DEG: f64 = 1.5, "deg",
        what "a bin's residual is judged against the same direction's frames from this far away in angle ...",
        chosen_by "scene 57: beyond its pull (2 deg of measured angle about the rod); hand-picked";

    PULL_BASE_DEG: f64 = 3.0, "deg",
        what "... to this far",
        chosen_by "the red-apple clip (a 25 deg swing at 60 frames/s): against the median of the bins within 2 deg, its bins of 3 or 4 frames at the same phase of every swing read 0.1 deg off the fitted path and were flagged, though each lay within 0.01 deg of its neighbours' local path; hand-picked";

    /// At least this many pulled bins, each within `PULL_JOIN_DEG` of the next, make a
    /// pull.
    PULL_MIN_BINS: usize = 2, "bins",
        what "fewest pulled bins that make a pull",
        chosen_by "the real clips: the red apple's and film 1's lone bins of a few frames each; a line pulls the wire towards it from either side (scene 57: +0.08 deg below the rod, -0.2 above; scene 23: +0.055 and -0.055)";

    /// Pulled bins this close (deg) are one pull, widened by `PULL_MARGIN_DEG` each
    /// side; its frames are flagged.
    PULL_JOIN_DEG: f64 = 1.0, "deg",
        what "pulled bins this close are one pull",
        chosen_by "scene 57: its pull changes sign across the rod (+0.12 deg at -62 deg, -0.19 at -61), and the bin between reads +0.03; joined, its angle RMS 0.056 -> 0.011 deg (prototype)";

    /// Pulls holding more than this share of the found frames are not flagged.
    PULL_MAX_SHARE: f64 = 0.2, "share",
        what "pulls holding more than this share of the found frames are left to the other checks",
        chosen_by "issue 49: the film-2 clip of the real fixtures (the rope unseen, a ball's edge followed) had 784 of its 1432 found frames in bins pulled the same way; scene 57's pull holds 8 %; hand-picked";

    PULL_MARGIN_DEG: f64 = 0.25, "deg",
        what "a pull is widened by this each side",
        chosen_by "scene 57: 0.25 and 0.5 leave the same RMS (0.0114 and 0.0115 deg, prototype); hand-picked";

    /// See `flag_leapt`: two found frames whose angles differ by more than this many
    /// times what the swing turns at its fastest over the time between them (and by
    /// `JUMP_MIN_DEG`) part the track into runs.
    LEAP_SPEED_TIMES: f64 = 2.0, "times",
        what "a change of angle more than this many times the swing's fastest parts the track",
        chosen_by "issue 50: seed 1 scene 32, a static edge held 16 frames then left by 19 deg (limit 11 deg there); hand-picked";

    /// ... and a run shorter than a run it leaps from or to is flagged when it lasts
    /// less than this share of the period.
    LEAP_RUN_PERIODS: f64 = 0.5, "periods",
        what "a run parted by leaps is flagged when shorter than its neighbour and this share of the period",
        chosen_by "issue 50: prototyped on seeds 1 and 2 (128 twins): without it a suspect scene (seed 2, 33) lost 570 frames, 490 within 0.5 deg; with it, frames flagged only in scene 32 and four scenes already suspect";

    /// A found frame whose angle leaves the smooth path of its found neighbours (a
    /// quadratic in time through up to three on each side, within `FILL_REACH_S`) by more
    /// than this, deg, ...
    JUMP_MIN_DEG: f64 = 1.0, "deg",
        what "a found frame this far off its neighbours' smooth path may be flagged a jump",
        chosen_by "issue 50, seed 4 and seed 2's first 32 scenes (97 detected twins): frames flagged in 8 scenes, six already suspect, a shadow's frame 5.3 deg off in one called ok (seed 2 scene 8) and a flicking track (seed 4 scene 48); none in the 89 others; the real clips measured ok: none at 0.5";

    /// ... and by more than this many times the angle's own motion over a frame there (a
    /// wire's path moves by a few degrees a frame at a fast swing's crossing, and a frame's
    /// time or the codec's blur put it off that path by a fraction of that), is flagged
    /// `Flag::Jump`: a wire cannot leave its path and come back in one frame.
    JUMP_STEPS: f64 = 2.0, "frames of motion",
        what "... and by this many times the angle's motion over a frame",
        chosen_by "issue 50: the green-screen clip (29 deg at 25 frames/s) leaves its path by up to 0.99 deg at its crossings, under one frame's motion; at two, none of the real clips measured ok has a frame flagged at 0.5 deg";

    FILL_REACH_S: f64 = 0.3, "s",
        what "a flagged frame is filled from good frames at most this far in time",
        chosen_by "297050c: the first detector's value; not measured";
}
