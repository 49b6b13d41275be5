//! Knobs of the judge: the checks of the verdict on what was followed.

use super::Knob;

knobs! {
    table JUDGE_KNOBS, stage "judge";

    // From judge.rs.
    /// Least share of frames found (`ok`) for a detection to be trusted.
    FOUND_MIN: f64 = 0.6, "share",
        what "least share of frames ok for a trusted detection",
        chosen_by "dcaed79: real clips (tests/real_verdicts.rs) and sweep seed 1, 56 scenes: none within 0.02 deg called suspect, 8 of 19 over 0.05 deg called suspect";

    /// The swing's end, for `found`: the last found angle off the rest angle by more
    /// than this share of the amplitude's scale ...
    STOP_SHARE: f64 = 0.1, "share",
        what "a swing over: every later found angle within this share of the amplitude of rest",
        chosen_by "issue 50, seeds 1 and 2: 24 of 120 twins swing out halfway; their wire at rest fades into the still scene (seed 2 scene 51: 59 % of frames found, 86 % up to the swing's end, 0.014 deg RMS)";

    /// ... when at least this many found angles follow it, all at rest ...
    AT_REST_MIN: usize = 20, "frames",
        what "fewest found frames at rest that show a swing over",
        chosen_by "issue 50, seeds 1 and 2: the swung-out twins 64-1174 found frames at rest, a track that lost the wire mid-swing (seed 2 scene 11, 0.16 deg RMS) 4";

    /// ... and the found angles of the period before it all lie within this share of the
    /// scale of rest (the swing was seen dying out, not lost mid-swing).
    DYING_SHARE_MAX: f64 = 0.5, "share",
        what "largest swing in the period before a swing's end, as a share of the amplitude",
        chosen_by "issue 50, seeds 1 and 2: the swung-out twins 0.24-0.31 of the scale in the 2 s before; a swing lost mid-way keeps its size";

    /// Frames whose intervals all lie within this share of their mean are evenly timed:
    /// their fourth difference takes the plain weights, not their times'.
    EVEN_TIMES: f64 = 0.01, "share",
        what "largest spread of five frames' intervals taken as evenly timed",
        chosen_by "issue 50, seed 7 scene 32 (variable frame times, 0.38 of a frame): its noise read 0.030 deg at even weights, 0.0014 at its times; a constant frame rate's intervals differ by rounding only";

    /// Fewest turning points of a detection trusted: the fit needs four, and the checks on
    /// the motion judge none without them.
    TURNS_MIN: usize = 4, "turning points",
        what "fewest turning points of a trusted detection (the fit's least)",
        chosen_by "sweep seed 1 scene 32 (hand-held, 640x480): 11.7 deg RMS off, no turning point, called ok; the fit's own minimum";

    /// Largest growth of the swing's amplitude from its first two turning points to its
    /// last two, as a share of the first: a pendulum left to itself only loses amplitude.
    GROWTH_MAX: f64 = 0.05, "share",
        what "largest growth of the amplitude seen from start to end (a pendulum's only shrinks)",
        chosen_by "issue 50: 175 kept sweep detections (seeds 2, 7, 31) shrink by 11 % to 32 % over 40 s, but seed 31 scene 8 (0.77 deg RMS, called ok) grows by 31 %; real clips shrink by 0.6-14 %, a 10 s carbon-fiber twin by 4.6 %";

    /// Least share of the swing's crossings of its rest angle seen (a found frame either
    /// side), once it has crossed `TURNS_MIN` times or more.
    CROSSED_MIN: f64 = 0.45, "share",
        what "least share of the rest angle's crossings seen",
        chosen_by "issue 50: 240 kept sweep detections (seeds 1, 2, 4): 0.83 or more, but seed 2 scene 20 (2.2 deg RMS, called ok) 0.1 and a suspect one 0.32-0.36; real clips 0.74-1.0, film 1 turned 180 deg 0.52; between";

    /// Fewest periods timed (from a crossing of the rest angle to the next in the same
    /// sense, within one run of found frames) for the period's spread to be judged.
    PERIODS_MIN: usize = 4, "periods",
        what "fewest periods timed for their spread to be judged",
        chosen_by "dcaed79: hand-picked with PERIOD_SPREAD_MAX; not swept";

    /// A swing that turned back this often, whose period was timed fewer than
    /// `PERIODS_MIN` times, had its track lost once a swing or more: `period` fails.
    UNTIMED_TURNS_MIN: usize = 10, "turning points",
        what "turning points from which a swing must have its period timed",
        chosen_by "issue 49: seed 53 scene 48 (lost 0.2 s or more in every swing: 21 turning points, no period timed, 0.65 deg RMS off) was called ok; the real clips measured ok time 14-35 periods from 17-49 turning points, the 220-frame clip 3 from 4; five periods";

    /// Largest spread of the periods from swing to swing (robust, relative to their median).
    PERIOD_SPREAD_MAX: f64 = 0.05, "share",
        what "largest spread of the periods swing to swing (of the median)",
        chosen_by "dcaed79: real clips (tests/real_verdicts.rs) and sweep seed 1, 56 scenes: none within 0.02 deg called suspect, 8 of 19 over 0.05 deg called suspect";

    /// Largest factor between the time from turning point to turning point and the half
    /// period the crossings of the rest angle give (either way).
    RHYTHM_MAX: f64 = 1.25, "times",
        what "largest factor between the turning points' pace and the crossings' half period",
        chosen_by "issue 50, 94 twins of seeds 4 and 2 with a period and 4 turning points: within 0.984-1.021 but five, all off by over 0.29 deg RMS: 6.8 (seed 4 scene 48, 6.1 deg RMS, called ok), 3.3, 2.3, 1.24, 0.96; the real clips measured ok 0.997-0.999";

    /// Largest noise from frame to frame, as a share of the swing's amplitude.
    NOISE_SHARE_MAX: f64 = 0.0045, "share",
        what "largest frame-to-frame noise, as a share of the amplitude",
        chosen_by "issue 50, seeds 1 and 2 (120 kept sweep detections): within 0.02 deg RMS 0.28 % or less; the two over 0.05 deg called ok for their noise 0.55 % (seed 2 scene 55, 0.11 deg) and 1.09 % (seed 1 scene 61, 0.22 deg); real clips measured ok 0.02-0.35 % (film 1 the most); between. Was 2 % (dcaed79)";

    /// A stall: the angle stays within this share of the amplitude over `STALL_WINDOW` of
    /// a period (a turning point moves by 5 % of the amplitude over a tenth of a period
    /// centred on it, more off centre).
    STALL_RANGE: f64 = 0.02, "share",
        what "a stall: the angle stays within this share of the amplitude",
        chosen_by "dcaed79; the comment beside it: a turning point moves 5 % over a tenth of a period; the real-clip verdicts";

    /// The stretch a stall is judged over, in periods.
    STALL_WINDOW: f64 = 0.1, "periods",
        what "the stretch a stall is judged over",
        chosen_by "dcaed79: real clips (tests/real_verdicts.rs) and sweep seed 1, 56 scenes: none within 0.02 deg called suspect, 8 of 19 over 0.05 deg called suspect";

    /// Largest share of frames in stalls.
    STALL_SHARE_MAX: f64 = 0.02, "share",
        what "largest share of frames in stalls",
        chosen_by "dcaed79: real clips (tests/real_verdicts.rs) and sweep seed 1, 56 scenes: none within 0.02 deg called suspect, 8 of 19 over 0.05 deg called suspect";

    /// Largest wander of the rest angle about its trend from turning point to turning point
    /// (RMS), deg, at a low noise,
    REST_WANDER_MAX_DEG: f64 = 0.04, "deg",
        what "largest wander of the rest angle about its trend at low noise",
        chosen_by "dcaed79: real clips (tests/real_verdicts.rs) and sweep seed 1, 56 scenes: none within 0.02 deg called suspect, 8 of 19 over 0.05 deg called suspect";

    /// and in multiples of what the angle noise alone gives it.
    REST_NOISE_FACTOR: f64 = 4.0, "times",
        what "... or this many times what the noise alone gives",
        chosen_by "dcaed79: real clips (tests/real_verdicts.rs) and sweep seed 1, 56 scenes: none within 0.02 deg called suspect, 8 of 19 over 0.05 deg called suspect";

    /// Largest scatter of the swings from turning point to turning point about a smooth
    /// decay (RMS), deg, at a low noise,
    ENVELOPE_MAX_DEG: f64 = 0.1, "deg",
        what "largest scatter of the swings about a smooth decay at low noise",
        chosen_by "dcaed79: real clips (tests/real_verdicts.rs) and sweep seed 1, 56 scenes: none within 0.02 deg called suspect, 8 of 19 over 0.05 deg called suspect";

    /// or this share of the mean swing (real strings scatter so: a swing of 47 deg by 0.08
    /// deg, one of 21 deg at 480x360 and 30 frames/s by 0.07: a ball that swings a little
    /// out of the plane; the sweep's worst twin measured well, by 0.04),
    ENVELOPE_SHARE: f64 = 0.003, "share",
        what "... or this share of the mean swing",
        chosen_by "dcaed79; the comment beside it: real strings 0.08 deg at 47 deg, 0.07 at 21 deg; the sweep's worst twin 0.04";

    /// or this many times what the angle noise alone gives it.
    ENVELOPE_NOISE_FACTOR: f64 = 4.0, "times",
        what "... or this many times what the noise alone gives",
        chosen_by "dcaed79: real clips (tests/real_verdicts.rs) and sweep seed 1, 56 scenes: none within 0.02 deg called suspect, 8 of 19 over 0.05 deg called suspect";

    /// The longest gap between found frames a crossing of the rest angle is timed across,
    /// s (a person passing hides the wire for a second or two).
    MAX_GAP_S: f64 = 0.2, "s",
        what "longest gap between found frames a rest crossing is timed across",
        chosen_by "dcaed79: hand-picked; not measured";

    /// The hysteresis of a crossing of the rest angle, as a share of the amplitude.
    HYSTERESIS: f64 = 0.3, "share",
        what "hysteresis of a rest crossing, as a share of the amplitude",
        chosen_by "dcaed79: hand-picked; not measured";

    /// `still`: the farthest a still-taken camera's static scene may lie from the first
    /// frame's (or the first glance's) at two of the pass's glances in a row (px at the
    /// region's farthest corner); a first glance lying further than this from the first
    /// frame, by a motion that explains it, is a bump (see `Late::unfollowed`).
    STILL_MAX_PX: f64 = 0.5, "px",
        what "largest displacement of a still-taken camera's static scene at two glances in a row",
        chosen_by "seed 4: a still CRF 34 twin read 0.40 px, oblique sways seen still 0.54 (0.27 deg RMS, ok at 0.6) and 0.83; 26 older still scenes 0.005-0.31";

    /// `turn`: the most of a moving camera's angle noise that may move with the turn
    /// each frame was steadied by, deg ...
    TURN_FOLLOW_MAX_DEG: f64 = 0.01, "deg",
        what "most of a steadied angle's noise that may move with the measured turn",
        chosen_by "issue 50, seed 4's 21 hand-held scenes: within 0.02 deg RMS 0.0001-0.0018, a plain plate's 0.17 deg RMS called ok 0.043; the moved green-screen clip 0.0011";
    /// ... judged when the regression's slope stands this many standard errors from 0.
    TURN_FOLLOW_SIGNIFICANCE: f64 = 4.0, "standard errors",
        what "the turn's share is judged when this many standard errors from 0",
        chosen_by "hand-picked: a share that noise alone gives is not judged; not swept";

    /// `wander`: the most the found angles may stray from the swing's own path (their
    /// robust scatter about it, step by step), in times their noise from frame to frame ...
    WANDER_NOISE_FACTOR: f64 = 3.5, "times",
        what "most steadied angles may stray from the swing's own path, in times their frame-to-frame noise",
        chosen_by "issue 50, seed 7's sweep (its first 28 scenes, from their kept angles): the 8 with a moving camera within 0.02 deg RMS 1.1-2.0 times, scene 2 (0.093 deg RMS, ok) 3.85, scene 18 (0.115, ok) about 10; the splitscreen clip moved by ffmpeg (swing as still's) 2.94: little room";
    /// ... and in degrees: a scatter under this passes whatever the noise.
    WANDER_MIN_DEG: f64 = 0.02, "deg",
        what "a scatter about the swing's own path under this passes",
        chosen_by "issue 50's angle RMS that counts as good (0.02 deg); a still twin (seed 7 scene 14, 0.006 deg RMS) strayed 4.8 times its small noise, 0.013 deg";

    /// `lens`: the largest relative uncertainty a lens given with the video (`video.lens`,
    /// its `u_k1`) may leave on the swing's scale: the fit's `scale` limit (`scale_rel`'s
    /// default), so that the angles and `s_r` are judged alike.
    LENS_SCALE_MAX: f64 = 0.005, "share",
        what "largest share of the swing a lens's uncertainty may leave uncertain",
        chosen_by "the fit's scale_rel default; issue 50: seed 2 scene 40 (lens declared unknown) and seed 7 scene 60 (sheet fit -0.131 +- 0.062) read 3.21 and 2.97 %, their swings 2.07 and 1.41 % wide, called ok before";

    /// `bent`: the lens the wire's bows give differs from the one given with the video
    /// (none: 0) by more than this many times their uncertainties ...
    BENT_SIGMAS: f64 = 3.5, "uncertainties",
        what "the wire's lens must differ from the one given by this many uncertainties for its effect to be judged",
        chosen_by "issue 49, seed 1's 14 sweep scenes rendered again (10 with a lens, none given): the three whose swing is 1.2 to 10 % wide 3.8 to 4.2; the real clips: the red-apple clip 2.9, cropped by 8 px and re-encoded 3.0 (+0.114, read as a swing 0.96 % narrow: its string bends as it swings), the green-screen clip 3.5 (0.42 %)";
    /// ... the wire's own counting this share of its coefficient besides its scatter
    /// (the strip's response to a bow is reckoned from its profile, not measured) ...
    BENT_REL_U: f64 = 0.2, "share",
        what "relative uncertainty of the lens the wire's bows give, besides their scatter",
        chosen_by "issue 49, seed 1's 10 sweep scenes with a lens, none given: the wire's k1 within 21 % of the twin's on 7 (-0.179 for -0.170, -0.241 for -0.240, -0.167 for -0.194), 34 % on a 960x540 oblique view, -0.55 +- 0.24 for -0.14 on a 1920x1080 oblique one at CRF 39";
    /// ... and at least this much of it (a bend of the wire's own, static lines
    /// crossing the strip, the ball's rim at its end).
    BENT_MIN_U: f64 = 0.03, "k1",
        what "least uncertainty of the lens the wire's bows give",
        chosen_by "issue 49: seed 1's scene 25 (no lens, a grid behind a 1 px wire) read +0.032 with a jackknife of 0.010; the real clips' strings, which bend as they swing, up to +0.16 (the green-screen clip)";

    /// `pivot`: the most the wire's own direction may swing more or less than its angle
    /// about the pivot (`Tracker::swing_scale`, as a share off 1).
    PIVOT_SCALE_MAX: f64 = 0.0075, "share",
        what "largest share the wire's own direction may swing more or less than its angle about the pivot",
        chosen_by "issue 50, seed 7's sweep: a steadied drift through a lens read 1.08 % (0.115 deg RMS, ok) and a hand-held view 0.91 % (0.44 deg); every other scene 0.49 % or less, those within 0.02 deg 0.15 % or less; the real clips measured ok 0.12-0.41 %, the report twins 0.04 % or less; a twin following a light wire's dark shadow 0.78 %";

    /// `beside`: the pass looks across the followed line at the first frame it accepts
    /// this long after its last look (`track::beside::sharper_beside`) ...
    BESIDE_EVERY_S: f64 = 1.0, "s",
        what "time between the pass's looks beside the followed line",
        chosen_by "for cost: a look takes about 0.35 ms on a 640x480 twin (a band of 217 px), 6 us a frame at 60 frames/s, under 2 % of the pass's own work; a 12 s clip gets 12 looks; not swept";
    /// ... at directions this far apart at the band's middle ...
    BESIDE_STEP_PX: f64 = 0.5, "px",
        what "step between the directions looked at beside the followed line, at the band's middle",
        chosen_by "hand-picked: a wire 1 px wide is crossed by two; not swept";
    /// ... summing each direction's contrasts every this many px along it ...
    BESIDE_RADIAL_STEP_PX: f64 = 2.0, "px",
        what "step along each direction looked at beside the followed line",
        chosen_by "hand-picked for cost: half the work of every px, and a line's contrast holds along it; not swept";
    /// ... up to this far either side of it ...
    BESIDE_REACH_DEG: f64 = 10.0, "deg",
        what "how far either side of the followed line the pass looks",
        chosen_by "PAIR_MAX's 10 deg: a wire and its shadow diverge a few degrees apart";
    /// ... from this far off it (px at the band's middle; nearer is the followed line's own
    /// ridge) ...
    BESIDE_MIN_APART_PX: f64 = 3.0, "px",
        what "nearest a line beside the followed one may lie, at the band's middle",
        chosen_by "hand-picked: twice the 2 px contrast's reach; not swept";
    /// ... for a ridge whose 2 px contrast holds at least this share of the followed
    /// line's ...
    BESIDE_MIN_SHARE: f64 = 0.05, "share",
        what "least 2 px contrast of a ridge beside the followed line, as a share of its own",
        chosen_by "seed 53's sweep scene 31 (960x540, a 1 px wire 3.4 deg from its shadow, the shadow followed): the wire's 0.07-0.34; noise peaks are told by their scattered offsets";
    /// ... and sharper across than the followed line by this factor (the share of its
    /// 3.5 px contrast its 1 px contrast holds) ...
    BESIDE_SHARPER: f64 = 2.0, "times",
        what "how much sharper across a ridge beside must be than the followed line",
        chosen_by "seed 53's sweep: the wires beside followed shadows 2.3 (scene 62, 640x480), 9 to 36 (scene 31) and 5 to 36 (scene 55) times as sharp; the shadows beside followed wires (scenes 22, 47) 0.4 to 1 times";
    /// ... and at least this sharp.
    BESIDE_SHARP_MIN: f64 = 0.2, "share",
        what "least share of its 3.5 px contrast a sharper ridge's 1 px contrast holds",
        chosen_by "seed 53's sweep scene 62: the wire beside the followed shadow 0.21-0.28; hand-picked";
    /// The check judges at least this many looks ...
    BESIDE_MIN_SAMPLES: usize = 10, "looks",
        what "fewest looks beside the followed line the check judges",
        chosen_by "hand-picked: 10 s at 30 frames/s; not swept";
    /// ... and counts the looks that find a sharper ridge within this of one offset (on
    /// one side only: a wide rod's two edges lie either side) ...
    BESIDE_TOL_DEG: f64 = 0.5, "deg",
        what "spread of the offsets of a sharper ridge counted as one line",
        chosen_by "hand-picked: a shadow turns with its wire; a noise peak's offset scatters over the 20 deg looked at; not swept";
    /// ... which may be at most this share of them.
    BESIDE_MAX_SHARE: f64 = 0.35, "share",
        what "largest share of the looks that may find one sharper line beside the followed one",
        chosen_by "seeds 53 and 31's sweeps: the shadows followed 0.41 to 0.82 (seed 53 scenes 62, 55, 31, 48 at the finer scale; seed 31 scenes 28 and 63, 0.41 and 0.49, missed at 0.5); the passes kept that follow the wire 0.30 at most (seed 53 scenes 11, 22, 34: 0.30, 0.28, 0.25); the real clips 0 to 0.23 a pass, film 2 (no wire seen, already suspect) 0.45";
}
