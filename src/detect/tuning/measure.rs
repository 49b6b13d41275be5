//! Knobs of the measurement in the wedge: strips, rivals, the band's parts, contrast.

use super::Knob;

knobs! {
    table MEASURE_KNOBS, stage "measurement in the wedge";

    // From track/measure.rs.
    /// Half the width of the strip the wire's line is fitted to, px of the working scale.
    STRIP_HALF: f64 = 2.5, "px",
        what "half width of the strip the wire's line is fitted to (working scale)",
        chosen_by "hand-picked; not swept (see FREE_STRIP_HALF for the narrower strip's figures)";

    /// Times the kept moments' strip is re-centred on the wire's free line
    /// (`Tracker::free_strip_moments`): a pivot 3 px off along or across the wire of a
    /// 960x540 twin is then refined to within 0.1 px.
    FREE_STRIP_PASSES: usize = 3, "passes",
        what "times the kept strip is re-centred on the wire's free line",
        chosen_by "011a017: aluminum twin's pivot 0.8 -> 0.0 px off, swing -0.46 -> -0.05 %, s_r -0.54 -> -0.14 %";

    /// Half the width of the re-centred strip, px of the working scale. Narrower than
    /// `STRIP_HALF`: at 2.5 px, a soft shadow diverging 4 deg from a faint wire pulled
    /// its free lines and the pivot 1.5 px off (angles 0.55 deg off), and on a 1280x720
    /// twin (thin dark wire, shrunk by two) rolled to 45 or 60 deg the swing came out
    /// 0.4 % small; at 1.75 px, 0.7 px and 0.27 deg, and 0.2 %. Narrower still (1.25 px)
    /// helps those two more but leaves a wider wire's pivot, given 4 px off along it,
    /// 0.3 px short of the wire (the aluminum twin, 960x540).
    FREE_STRIP_HALF: f64 = 1.75, "px",
        what "half width of the re-centred strip (working scale)",
        chosen_by "fda42d4: faint wire + shadow 0.55 -> 0.27 deg, pivot 1.5 -> 0.7 px; 1280x720 twin swing 0.4 -> 0.2 % small";

    /// The `bent` check's bow of each strip (`strip_parabola`): a step along the line
    /// whose centroid lies more than this many median deviations from the parabola is
    /// left out of its next fit ...
    BOW_OUTLIER_MADS: f64 = 4.0, "deviations",
        what "a strip's step this far from its parabola is left out of the bow's next fit",
        chosen_by "issue 49: seed 1's scene 23 (a protractor's ticks and cables across the wire) with its lens given read k1 +0.248 from whole-strip fits, -0.077 with the steps left out (drawn -0.196); the scenes without clutter within 0.01";
    /// ... the median deviation taken as at least this (px: a clean wire's steps lie
    /// within hundredths of a pixel of the parabola) ...
    BOW_MAD_FLOOR_PX: f64 = 0.05, "px",
        what "least median deviation of a strip's steps from its parabola",
        chosen_by "hand-picked with BOW_OUTLIER_MADS: a step 0.2 px off is kept";
    /// ... and a fit needs this many steps.
    BOW_MIN_STEPS: usize = 10, "steps",
        what "fewest steps along the line for a strip's bow",
        chosen_by "hand-picked: three parameters and the outliers left out";

    /// The radius, as a share of the band's outer radius, inside which the re-centred
    /// strip leaves the wire out. Near the pivot a soft shadow and the wire (and, at a
    /// shrunk working scale, the static edges crossing there) merge into one ridge whose
    /// middle lies off the wire's line; the free lines, pulled at their inner ends, meet
    /// off the pivot along the wire. On a 1280x720 twin worked at half size (a dark wire
    /// with a soft shadow 5.7 deg off, three static edges through the fulcrum) the pivot
    /// came 3.5 px short along the wire and the swing 1.09 % wide; from a quarter out,
    /// -0.07 % (the same twin without the edges: -0.05 % before). Measured from the
    /// pivot, not from the band's inner end: a pivot beyond the frame's edge, whose
    /// wire is seen far from it, keeps its whole band (a 1920x1080 twin cut from the
    /// band's inner end read its swing 0.39 % small).
    FREE_STRIP_FROM: f64 = 0.25, "share",
        what "radius (share of the band's outer one) inside which the re-centred strip leaves the wire out",
        chosen_by "one twin (shadow + static edges, 1280x720 at half size): swing +1.09 -> -0.07 %; checked on sweep seeds 1 and 2";

    /// Farthest a free line may lie from the line through the pivot at the band's ends, px
    /// of the working scale, for its strip to be kept.
    FREE_STRIP_DRIFT: f64 = 3.0, "px",
        what "farthest a free line may lie from the pivot's line at the band's ends",
        chosen_by "011a017: hand-picked; not swept";

    // From track/measure/ridge.rs.
    /// A rival peak must score this share of the strongest to be weighed at all.
    RIVAL_SCORE: f64 = 0.15, "share",
        what "least score of a rival peak, as a share of the strongest",
        chosen_by "324bfb2: a faint wire beside its darker soft shadow (test); not swept";

    /// ... cover this share of the band that the strongest covers (a wire runs the band's
    /// length; a scale's radial tick mark does not) ...
    RIVAL_COVER: f64 = 0.6, "share",
        what "share of the strongest's band a rival must cover",
        chosen_by "324bfb2: a radial tick mark does not run the band (test); not swept";

    /// ... and be this much narrower across than the strongest to win outright: a wire's soft
    /// shadow, diverging from the fulcrum beside it, can hold more evidence than a faint
    /// wire, but it is wide and the wire is a sharp ridge.
    RIVAL_SHARPER: f64 = 0.7, "ratio",
        what "width ratio for a rival to win outright",
        chosen_by "324bfb2: a faint wire beside its soft shadow (test); not swept";

    /// ... or this much narrower while the track begins (fewer than three frames accepted,
    /// the whole sweep searched) or starts again (lost: no prediction): there is no track
    /// to keep, and a wire beside a stronger shadow of a similar width (1.12 px against
    /// 1.40, 1.17 against 1.28 on 640x480 and 1280x720 twins) is told by its sharper
    /// ridge. On a 1280x720 twin with a 1 px wire (worked at half size), a lost track that
    /// took the strongest ridge took the numerals of a protractor the wire had left (their
    /// ridge 1.25 times as wide as the wire's), and stayed on them for 45 frames.
    RIVAL_SHARPER_START: f64 = 0.92, "ratio",
        what "width ratio for a rival to win while the track starts",
        chosen_by "1fe0711; the comment beside it: wire 1.12 vs shadow 1.40 px, 1.17 vs 1.28 (640x480, 1280x720 twins); numerals 1.25x as wide";

    /// A rival within the gate of the prediction, the strongest peak outside it, is the wire
    /// unless this much wider than the strongest.
    RIVAL_WIDER_GATED: f64 = 1.25, "ratio",
        what "a rival within the gate wins unless this much wider",
        chosen_by "1fe0711: a 640x480 sweep scene followed the shadow from frame 194 (1.92 deg RMS) before";

    /// Evidence within this many px of a peak's line counts towards its width.
    WIDTH_STRIP: f64 = 4.0, "px",
        what "evidence within this of a peak's line counts towards its width",
        chosen_by "324bfb2: hand-picked; not swept";

    /// Working shrunk, peaks' widths are measured across each at the full scale too, on
    /// profiles this many px either side of its line (see `full_width`).
    FULL_WIDTH_HALF_PX: f64 = 6.0, "px",
        what "half-length of a profile across a peak's line at the full scale",
        chosen_by "a 1920x1080 hand-held twin (seed 2 sweep scene 56): a 2 px wire beside its shadow blurred 2.2 px, both 1.07-1.11 px wide at a third of the scale; hand-picked to hold the shadow's flanks";

    /// ... on at most this many profiles, spread over the band.
    FULL_WIDTH_PROFILES: usize = 48, "profiles",
        what "profiles across a peak's line at the full scale",
        chosen_by "the same twin; hand-picked for cost";

    /// ... of which a profile counts only when its line's middle lies this near the
    /// profile's own: one across a ridge placed beside its line (a shadow's flank)
    /// catches the line's edge alone, and would measure it narrow.
    FULL_WIDTH_OFF_PX: f64 = 1.5, "px",
        what "how far a profile's middle may lie from the peak's line at the full scale",
        chosen_by "seed 2 sweep scene 8 (1920x1080, a shadow blurred 3.3 px, 5.5 deg off): a ridge 1.5 deg inside the shadow measured 0.6 px wide, narrower than the wire, and the side was never learnt; hand-picked";

    /// A rival this close in angle to the strongest peak (rad, 10 deg) makes a pair with
    /// it: a wire and its shadow, diverging from the fulcrum a few degrees apart.
    PAIR_MAX: f64 = 0.1745, "rad",
        what "a rival this close to the strongest (10 deg) makes a pair",
        chosen_by "599aeff: test wire + shadow followed on the shadow 450/450 frames -> 14 of the first 150";

    /// A pair votes for the side its narrower ridge lies on when that ridge is at most this
    /// share of the other's width (nearly equal widths say nothing).
    PAIR_VOTE_RATIO: f64 = 0.97, "ratio",
        what "a pair votes when its narrower ridge is this share of the other's width",
        chosen_by "599aeff: 3 % narrower or more; the same test";

    /// Votes before the side is known, and how far one side must lead, in standard
    /// deviations of a fair coin's lead (`sqrt(votes)`): ridges with no side of their own
    /// (a wire passing a fixed line) lead that far by chance at any one count about 3 times
    /// in 1000 (more often over a long video, as the lead is weighed at every vote).
    PAIR_MIN_VOTES: usize = 12, "votes",
        what "votes before a pair's side is known",
        chosen_by "599aeff: the same test; not swept";

    PAIR_LEAD_SIGMAS: f64 = 3.0, "sigmas",
        what "lead a side needs, in a fair coin's sigmas",
        chosen_by "599aeff: chance about 3 in 1000 at one count; not swept";

    /// Frames accepted on one ridge of a pair before the side is known are held, with the
    /// other ridge measured too, and restated once it is: at most this many (the other
    /// ridge's measurement costs as much as the wire's, and a pair whose side is never
    /// learnt would hold every frame).
    UNDECIDED_MAX_FRAMES: usize = 1000, "frames",
        what "frames held with a pair's other ridge until the side is known",
        chosen_by "a 1920x1080 sweep twin (seed 4 scene 11) followed the shadow for its first 32 frames, until the side was learnt; hand-picked cap";

    /// A frame held so that saw no pair is refused with its neighbour restated, within
    /// this many frames, when its angle lies nearer that neighbour's shadow ridge than its
    /// wire's: taken on the shadow too, with nothing to restate it by.
    RESTATE_BESIDE_FRAMES: u64 = 2, "frames",
        what "a held frame with no pair is refused beside a restated one this near, on its shadow's ridge",
        chosen_by "a 1920x1080 sweep twin (seed 2 scene 8): frame 1, on the shadow 5.3 deg off, no pair seen, called ok beside restated frame 0; hand-picked";

    /// A pair is the learnt one when its separation is within this share of the learnt
    /// separation.
    PAIR_SEP_TOL: f64 = 0.5, "share",
        what "a pair is the learnt one within this share of the learnt separation",
        chosen_by "599aeff: hand-picked; not swept";

    /// A pair votes again only once its narrower ridge has moved this far (rad, 0.5 deg)
    /// from where it last voted: a shadow moves with the wire, while a wire at rest beside
    /// a fixed line (a scale's tick the background does not quite hide) would otherwise
    /// vote for that line's side frame after frame.
    PAIR_MOVE: f64 = 0.0087, "rad",
        what "a pair votes again once its narrower ridge moved this far (0.5 deg)",
        chosen_by "599aeff: a wire at rest beside a fixed line; not swept";

    // From track/measure/band.rs.
    /// A histogram bin reaching this many of the band's parts counts whole
    /// (`covered_bins`). Counted by the share of all the parts, a faint wire (over its
    /// threshold in only some of them) lost frames to its soft shadow, which runs the band.
    COVERED_FULL: usize = CELLS / 2, "parts",
        what "a histogram bin reaching this many parts counts whole (half the band)",
        chosen_by "c818d97: by the share of all parts a faint wire lost frames to its shadow (shadow test)";

    /// Parts of the band, by distance from the pivot, that a histogram bin's evidence and a
    /// strip's pixels are counted in (`covered_bins`, `drop_stray_parts`).
    CELLS: usize = 24, "parts",
        what "parts of the band, by distance from the pivot",
        chosen_by "c818d97: seed 1 scene 12 angle RMS 0.101 -> 0.037 deg; seed 1 s_r within 0.5 %: 96.8 -> 98.4 %";

    /// A part of the band whose strip pixels lie, on the whole, this far from the fitted
    /// line (px of the working scale) ...
    STRAY_MIN_PX: f64 = 0.75, "px",
        what "a part of the band this far from the fitted line may be stray",
        chosen_by "c818d97: a bob's rim turned the fit 0.2-0.5 deg (seed 1 scene 12); not swept";

    /// ... and this many times as far as the median part's, is not the wire's
    /// (`drop_stray_parts`) ...
    STRAY_TIMES: f64 = 3.0, "times",
        what "... and this many times as far as the median part",
        chosen_by "c818d97: seed 1 scene 12; not swept";

    /// ... unless more than this share of the parts holding any pixel are.
    STRAY_MAX_SHARE: f64 = 0.25, "share",
        what "no part is stray when more than this share of them are",
        chosen_by "c818d97: seed 1 scene 12; not swept";

    /// A part holding more than this many times the evidence of the median part is heavy:
    /// the stray parts are judged against the line fitted with each heavy part counting as
    /// `HEAVY_COUNTS` times the median part.
    HEAVY_TIMES: f64 = 3.0, "times",
        what "a part with this many times the median part's evidence is heavy",
        chosen_by "c818d97: seed 1 scene 12; not swept";

    HEAVY_COUNTS: f64 = 1.5, "times",
        what "a heavy part counts as this many median parts in the judging fit",
        chosen_by "c818d97: seed 1 scene 12; not swept";

    // From track/contrast.rs.
    /// The evidence of a pixel of the background's level `b` is divided by its contrast
    /// (`b` for a dark wire, `255 - b` for a light one), at least this many grey levels.
    CONTRAST_FLOOR: f64 = 10.0, "grey levels",
        what "least contrast a pixel's evidence is divided by",
        chosen_by "741f6c7: sweep both seeds, angle RMS <= 0.02 deg 93.7 -> 95.2 % (seed 1 scene 39: 0.0276 -> 0.0069 deg)";

    /// The weights' common scale: a pixel of contrast 100 weighs its evidence.
    WEIGHT_SCALE: f64 = 100.0, "grey levels",
        what "the weights' common scale (a pixel of contrast 100 weighs its evidence)",
        chosen_by "741f6c7: a common scale; not swept";

    /// Static marks are found at this size, px: a closing (dark wire) or opening (light
    /// wire) of the background by an ellipse this wide fills ticks, numerals and edges
    /// narrower than it.
    MARK_SIZE: i32 = 9, "px",
        what "size at which static marks are found (closing or opening)",
        chosen_by "741f6c7: the same sweep (93.7 -> 95.2 %); value not swept";

    /// A pixel is a mark when the closing lifts it (or the opening lowers it) by more than
    /// this many grey levels ...
    MARK_MIN_LEVELS: f64 = 8.0, "grey levels",
        what "a pixel is a mark when the closing lifts it by more than this",
        chosen_by "741f6c7: the same sweep; value not swept";

    /// ... and more than this share of the surroundings' level.
    MARK_SHARE: f64 = 0.1, "share",
        what "... and by more than this share of its surroundings' level",
        chosen_by "741f6c7: the same sweep; value not swept";

    /// Marks over more than this share of the region are a textured background (wood,
    /// cloth), not marks: then none is left out.
    MARKS_MAX_SHARE: f64 = 0.25, "share",
        what "marks over more than this share of the region are a texture: none left out",
        chosen_by "741f6c7: the same sweep; value not swept";

    // From track/evidence.rs.
    /// Around the wedge's rectangle, the evidence is exact this far (px of the working
    /// scale): the strips of the line fit (2.5 px either side of a line in the wedge, 4 px
    /// when rival peaks are weighed, each with its half-pixel edge) and a fitted line's
    /// tilt within the strip.
    EVIDENCE_MARGIN: f64 = 8.0, "px",
        what "evidence is exact this far around the wedge's rectangle",
        chosen_by "0aba8e2: from the strips' widths and a line's tilt; angles byte-identical on 27 videos";

    // Lifted from track/measure.rs.

    HIST_BIN_PX: f64 = 0.75, "px",
        what "width of a histogram bin of angles at the band's middle radius",
        chosen_by "297050c: the first detector's value; not measured";

    HIST_MIN_BINS: usize = 8, "bins",
        what "fewest bins of the histogram of angles",
        chosen_by "297050c: the first detector's value; not measured";

    HIST_MAX_BINS: usize = 20_000, "bins",
        what "most bins of the histogram of angles",
        chosen_by "297050c: the first detector's value; not measured";

    MAX_CANDIDATES: usize = 200_000, "pixels",
        what "most pixels over the threshold a wedge's histogram takes",
        chosen_by "297050c: the first detector's value; not measured";

    MIN_LINE_PIXELS: usize = 5, "pixels",
        what "fewest pixels a frame's line is fitted to (else no angle)",
        chosen_by "297050c: the first detector's value; not measured";

    PEAK_STEP_BINS: usize = 4, "bins",
        what "a peak is scored against the bins 3 times this far on each side",
        chosen_by "297050c: the first detector's value; not measured";

    SELECT_STRIP_WIDE: f64 = 4.0, "px",
        what "first strip about the histogram's line the pixels are taken from",
        chosen_by "297050c: the first detector's value; not measured";

    SELECT_STRIP_NARROW: f64 = 2.5, "px",
        what "second, tighter strip of that selection",
        chosen_by "297050c: the first detector's value; not measured";

    STRIP_REFITS: usize = 2, "passes",
        what "refits of the line to every pixel of the strip",
        chosen_by "297050c: the first detector's value; not measured";

    RIVAL_REACH_BINS: usize = 4, "bins",
        what "a rival peak lies this far from the strongest and tops its neighbours this far",
        chosen_by "324bfb2: hand-picked; not swept";

    PAIR_REACH_MARGIN_DEG: f64 = 2.0, "deg",
        what "room past a learnt pair's separation the search reaches on the wire's side",
        chosen_by "599aeff: hand-picked; not swept";
}
