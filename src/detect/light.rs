//! Brightness normalisation: each frame is scaled to the brightness of a reference
//! frame before anything judges it, so that mains flicker (lamps pulse at twice the
//! mains frequency, sampled by the camera at 25-60 frames/s as a beat) and slow
//! lighting changes move neither the background, nor the noise estimate, nor the gate.
//!
//! Flicker and drift scale the whole scene: a pixel of the frame is `g` times the
//! same pixel of the reference, whatever its grey level. The gain `g` is the median,
//! over a sparse grid of pixels, of the ratio frame / reference: the moving wire and
//! ball change a minority of the pixels and do not move the median.

use crate::detect::tuning::{
    COVERED_FOLLOW, COVERED_GAIN, COVERED_SHARE, COVERED_TIMES, DEAD_BAND, FOREIGN_RATIO,
    LIGHT_SAMPLE_STEP, MIN_REFERENCE, RATIO_BINS, RATIO_SCALE,
};

/// The gain of frames against one reference frame, with buffers reused from frame to
/// frame.
pub(super) struct Brightness {
    /// Per sampled pixel: its offset, and `2^20 / reference` (the reference's reciprocal
    /// in fixed point, so that a ratio costs a multiplication).
    samples: Vec<(u32, u32)>,
    hist: Vec<u32>,
    lut: [u8; 256],
    /// The same division as `lut` in fixed point, when it gives every grey level as
    /// `lut` does ([`fixed_point_of`]): `(v * m + 2^15) >> 16`, which the compiler
    /// runs on many pixels at once (a table lookup is one pixel at a time).
    fixed: Option<u32>,
    /// Of the last frame's votes, the share far from its gain ([`FOREIGN_RATIO`]).
    foreign: f64,
    /// Typical foreign share and gain of the frames not covered
    /// ([`Brightness::covered`]).
    foreign_ref: Option<f64>,
    gain_ref: Option<f64>,
}

impl Brightness {
    /// Gains against `reference` (the bytes of one frame; later frames have the same
    /// size).
    pub(super) fn new(reference: &[u8]) -> Self {
        let samples = reference
            .iter()
            .enumerate()
            .step_by(LIGHT_SAMPLE_STEP)
            .filter(|(_, &v)| v >= MIN_REFERENCE)
            .map(|(i, &v)| (i as u32, (1u32 << 20) / v as u32))
            .collect();
        Self {
            samples,
            hist: vec![0; RATIO_BINS],
            lut: [0; 256],
            fixed: None,
            foreign: 0.0,
            foreign_ref: None,
            gain_ref: None,
        }
    }

    /// The frame's brightness against the reference's: the median ratio (`None` when
    /// too few pixels of the reference are lit to tell, or the frame has another size).
    pub(super) fn gain(&mut self, frame: &[u8]) -> Option<f64> {
        self.foreign = 0.0;
        if self.samples.len() < 50
            || self
                .samples
                .last()
                .is_some_and(|s| s.0 as usize >= frame.len())
        {
            return None;
        }
        self.hist.fill(0);
        for &(i, inv) in &self.samples {
            // ratio * RATIO_SCALE = v * 2^20 / ref / 2^10
            let q = (frame[i as usize] as u32 * inv) >> 10;
            self.hist[(q as usize).min(RATIO_BINS - 1)] += 1;
        }
        let half = self.samples.len() as u32 / 2;
        let mut seen = 0u32;
        for (b, &n) in self.hist.iter().enumerate() {
            if seen + n > half {
                // Within the bin, where the median falls (its votes spread evenly).
                let within = (half - seen) as f64 + 0.5;
                let g = (b as f64 + within / n as f64) / RATIO_SCALE as f64;
                let lo = (g / FOREIGN_RATIO * RATIO_SCALE as f64) as usize;
                let hi = ((g * FOREIGN_RATIO * RATIO_SCALE as f64) as usize).min(RATIO_BINS);
                let near: u32 = self.hist[lo.min(hi)..hi].iter().sum();
                self.foreign = 1.0 - f64::from(near) / self.samples.len() as f64;
                return Some(g);
            }
            seen += n;
        }
        None
    }

    /// Of the last frame measured, the share of its votes far from its gain (beyond
    /// [`FOREIGN_RATIO`] either way): what of it shows something else than the
    /// reference frame did.
    pub(super) fn foreign(&self) -> f64 {
        self.foreign
    }

    /// Whether the frame last measured, of gain `gain`, is covered (see
    /// [`COVERED_TIMES`] and [`COVERED_GAIN`]), from its foreign share and gain; the typical ones follow the frames that are not.
    pub(super) fn covered(&mut self, gain: f64) -> bool {
        let foreign = self.foreign;
        let covered = self
            .foreign_ref
            .is_some_and(|r| foreign > (COVERED_TIMES * r).max(COVERED_SHARE))
            || self
                .gain_ref
                .is_some_and(|g| gain > 0.0 && (gain / g).ln().abs() > COVERED_GAIN.ln());
        // Slowly (a hundred frames or so): a person stepping in over half a second
        // does not become the typical.
        if !covered {
            let k = COVERED_FOLLOW;
            self.foreign_ref = Some(
                self.foreign_ref
                    .map_or(foreign, |r| (1.0 - k) * r + k * foreign),
            );
            self.gain_ref = Some(self.gain_ref.map_or(gain, |g| (1.0 - k) * g + k * gain));
        }
        covered
    }

    /// Bring `frame` to the reference's brightness (divide by its gain), in place.
    /// Returns the gain (1 when unknown or within the dead band, and the frame is left
    /// as it was).
    pub(super) fn normalise(&mut self, frame: &mut [u8]) -> f64 {
        let (g, divide) = self.plan(frame);
        if divide {
            self.divide(frame.iter_mut().map(|v| {
                let level = *v;
                (v, level)
            }));
        }
        g
    }

    /// [`Brightness::normalise`] of `frame` written into `out` (of the same size): the
    /// bytes of a copy normalised in place, in one pass over the frame.
    pub(super) fn normalise_into(&mut self, frame: &[u8], out: &mut [u8]) -> f64 {
        let (g, divide) = self.plan(frame);
        if divide {
            self.divide(out.iter_mut().zip(frame.iter().copied()));
        } else {
            out.copy_from_slice(frame);
        }
        g
    }

    /// Each pixel's grey level divided by the planned gain into its place: in fixed
    /// point when a multiplier matches the table ([`fixed_point_of`]), else by the table.
    fn divide<'a>(&self, pixels: impl Iterator<Item = (&'a mut u8, u8)>) {
        match self.fixed {
            Some(m) => pixels.for_each(|(o, v)| *o = divided(v, m)),
            None => pixels.for_each(|(o, v)| *o = self.lut[v as usize]),
        }
    }

    /// The frame's gain (1 when unknown), and whether the frame is to be divided by it
    /// (outside the dead band: `lut` then divides a grey level).
    fn plan(&mut self, frame: &[u8]) -> (f64, bool) {
        let Some(g) = self.gain(frame).filter(|g| *g > 0.05) else {
            return (1.0, false);
        };
        if (g - 1.0).abs() < DEAD_BAND {
            return (g, false);
        }
        for (v, out) in self.lut.iter_mut().enumerate() {
            *out = (v as f64 / g).round().min(255.0) as u8;
        }
        self.fixed = fixed_point_of(&self.lut, g);
        (g, true)
    }
}

/// `v` divided as the multiplier `m` of [`fixed_point_of`] divides it.
#[inline]
fn divided(v: u8, m: u32) -> u8 {
    ((u32::from(v) * m + (1 << 15)) >> 16).min(255) as u8
}

/// A multiplier `m` (near `2^16 / g`) with which [`divided`] gives every grey level
/// exactly as `lut` does (the division by `g`, rounded, at most 255), or `None` when no
/// multiplier near it does (a quotient within a rounding of a half): the table is then
/// read as it is, and the frame is the same to the byte either way.
fn fixed_point_of(lut: &[u8; 256], g: f64) -> Option<u32> {
    let m0 = (65536.0 / g).round();
    if !(1.0..=f64::from(u32::MAX / 512)).contains(&m0) {
        return None;
    }
    let m0 = m0 as u32;
    [m0, m0 - 1, m0 + 1]
        .into_iter()
        .find(|&m| (0..=255u8).all(|v| divided(v, m) == lut[v as usize]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A textured scene (grey levels 40..220), scaled by `g`, with a dark bar over
    /// `cover` of its pixels.
    fn scene(g: f64, cover: f64) -> Vec<u8> {
        let n = 200 * 150;
        (0..n)
            .map(|i| {
                let base = 40.0 + ((i * 37 % 181) as f64);
                if (i as f64) < cover * n as f64 {
                    20
                } else {
                    (base * g).round().min(255.0) as u8
                }
            })
            .collect()
    }

    #[test]
    fn the_gain_is_the_scene_s_scale_whatever_moves_over_a_minority_of_it() {
        let mut b = Brightness::new(&scene(1.0, 0.0));
        for g in [0.85, 0.97, 1.0, 1.12] {
            // A dark object over 30 % of the frame does not move the median ratio.
            let got = b.gain(&scene(g, 0.3)).unwrap();
            assert!((got - g).abs() < 0.004, "gain {g}: measured {got}");
        }
    }

    #[test]
    fn the_share_that_shows_something_else_is_foreign_whatever_the_light() {
        let mut b = Brightness::new(&scene(1.0, 0.0));
        for (g, cover) in [
            (1.0, 0.0),
            (0.88, 0.0),
            (1.0, 0.3),
            (1.12, 0.3),
            (0.9, 0.45),
        ] {
            b.gain(&scene(g, cover)).unwrap();
            // The dark bar's pixels (a few of the darkest reference pixels are as dark
            // as the bar, and vote as the scene).
            assert!(
                (b.foreign() - cover).abs() < 0.02,
                "gain {g}, {cover} covered: foreign {}",
                b.foreign()
            );
        }
    }

    #[test]
    fn normalising_undoes_a_flicker_and_leaves_a_steady_frame_alone() {
        let reference = scene(1.0, 0.0);
        let mut b = Brightness::new(&reference);
        let mut dim = scene(0.88, 0.0);
        let g = b.normalise(&mut dim);
        assert!((g - 0.88).abs() < 0.004, "{g}");
        let worst = dim
            .iter()
            .zip(&reference)
            .map(|(a, r)| a.abs_diff(*r))
            .max()
            .unwrap();
        assert!(worst <= 2, "worst difference after normalising: {worst}");
        // Steady light: untouched, bit for bit.
        let mut same = reference.clone();
        b.normalise(&mut same);
        assert_eq!(same, reference);
    }

    #[test]
    fn normalising_into_another_buffer_gives_the_bytes_normalised_in_place() {
        let mut b = Brightness::new(&scene(1.0, 0.0));
        for g in [0.88, 1.001, 1.12] {
            let frame = scene(g, 0.2);
            let mut in_place = frame.clone();
            let g1 = b.normalise(&mut in_place);
            let mut out = vec![7u8; frame.len()];
            let g2 = b.normalise_into(&frame, &mut out);
            assert_eq!(g1, g2);
            assert_eq!(out, in_place, "gain {g}");
        }
    }

    #[test]
    fn a_dark_reference_or_a_wrong_size_gives_no_gain() {
        let mut b = Brightness::new(&vec![3u8; 10_000]);
        assert_eq!(b.gain(&vec![100u8; 10_000]), None);
        let mut b = Brightness::new(&scene(1.0, 0.0));
        assert_eq!(b.gain(&[100u8; 10]), None);
    }

    #[test]
    fn the_fixed_point_division_gives_every_grey_level_as_the_table_or_is_not_used() {
        // Gains across flicker's and a dimming's range, finely: where a multiplier is
        // found it divides all 256 levels as the table does, and one is found for most.
        let mut found = 0;
        let n = 4000;
        for k in 0..n {
            let g = 0.5 + 1.5 * k as f64 / n as f64;
            let mut lut = [0u8; 256];
            for (v, out) in lut.iter_mut().enumerate() {
                *out = (v as f64 / g).round().min(255.0) as u8;
            }
            if let Some(m) = fixed_point_of(&lut, g) {
                found += 1;
                for v in 0..=255u8 {
                    assert_eq!(divided(v, m), lut[v as usize], "gain {g}, level {v}");
                }
            }
        }
        assert!(found > n * 9 / 10, "a multiplier for {found} of {n} gains");
        // A gain whose quotients fall on a half is left to the table: 2 gives 1/2,
        // 3/2, ... exactly, which the table rounds up (away from zero) and so does the
        // fixed point; a multiplier off by one would round them down.
        let mut lut = [0u8; 256];
        for (v, out) in lut.iter_mut().enumerate() {
            *out = (v as f64 / 2.0).round().min(255.0) as u8;
        }
        let m = fixed_point_of(&lut, 2.0).expect("2^15 divides exactly");
        assert_eq!(m, 1 << 15);
    }
}
