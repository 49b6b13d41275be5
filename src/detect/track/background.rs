//! The background the evidence is taken against: each pixel's running extreme of the
//! scene, lowered slowly towards it but where the wire lies.

use super::Tracker;
use crate::detect::tuning::{BG_REST_S, STRIP_HALF};
use crate::detect::Pt;
use anyhow::Result;
use opencv::core;
use opencv::prelude::*;

impl Tracker {
    /// The background after frame `index` (the working frame in `small`): its running
    /// extreme, and every `decay_every` frames one grey level back towards the scene
    /// ([`decay_where_seen`]).
    pub(super) fn follow_scene(&mut self, index: u64) -> Result<()> {
        if self.geo.dark {
            core::max(&self.bg, &self.small, &mut self.tmp)?;
        } else {
            core::min(&self.bg, &self.small, &mut self.tmp)?;
        }
        std::mem::swap(&mut self.bg, &mut self.tmp);
        if index.is_multiple_of(self.decay_every) {
            // The strip about the last accepted line, px of the region.
            let (piv, band, cols) = (self.piv, (self.r_lo, self.r_hi), self.bg.cols());
            let wire = self.hist.last().map(|&(_, a)| Pt::new(a.cos(), a.sin()));
            let whole = self.wire_at_rest();
            let on_wire = |i: usize| {
                wire.is_some_and(|d| {
                    let cols = cols as usize;
                    let q = Pt::new((i % cols) as f64, (i / cols) as f64) - piv;
                    let along = q.dot(&d);
                    along >= band.0
                        && along <= band.1
                        && (q.x * d.y - q.y * d.x).abs() <= STRIP_HALF
                })
            };
            let (frame, tmap) = (self.small.data_bytes()?, self.tmap.data_bytes()?);
            decay_where_seen(
                self.bg.data_bytes_mut()?,
                frame,
                tmap,
                self.geo.dark,
                whole,
                on_wire,
            );
        }
        Ok(())
    }

    /// An accepted angle (before the counts of refused and repeated frames start
    /// again): the wire lies still from here when it left the strip about where it lay
    /// still (half its half width seen from the strip's far end, so that every line
    /// since lies within the strip about any other), or the track had been lost.
    pub(super) fn note_still(&mut self, t_s: f64, angle: f64) {
        let tol = 0.5 * STRIP_HALF / self.r_hi.max(1.0);
        let moved = |&(_, a): &(f64, f64)| (angle - a).abs() > tol;
        if !self.held() || self.still.as_ref().is_none_or(moved) {
            self.still = Some((t_s, angle));
        }
    }

    /// The wire has lain still for [`BG_REST_S`] up to its last accepted frame, and the
    /// track holds: its lines since lie within the strip about the last, which covered
    /// the same pixels all along. A swinging wire lies so long within so narrow a band
    /// only about the turning points of a swing under 2.5 times the strip's half width
    /// (seen from its far end, of a 3.4 s period; less at a shorter one): nearly at rest.
    pub(super) fn wire_at_rest(&self) -> bool {
        match (self.still, self.hist.last()) {
            (Some((t0, _)), Some(&(t, _))) => self.held() && t - t0 >= BG_REST_S,
            _ => false,
        }
    }
}

/// The background's decay of one grey level towards the scene, but where the wire lies:
/// a pixel `on_wire` (by its index in the region: the strip of `STRIP_HALF` px about
/// the last accepted line) whose grey level in `frame` stands over its noise threshold
/// (`tmap`) from the background `bg` keeps its level, so that a wire at rest is not
/// taken into the background. Decayed everywhere, a 1 px wire at rest under a 60 fps
/// camera lost half its evidence in 10 s, and the track its wire (a sweep twin: on its
/// shadow, then lost from 36 s). The test is the wire's strip's only: the running
/// extreme of a plain plate's noise lies a few thresholds from most frames, and held
/// wherever it did, the background crept up to the noise's extreme (two real clips'
/// tracks then took a line beside the wire).
///
/// With `whole` (the wire at rest, [`Tracker::wire_at_rest`]) every pixel of the strip
/// keeps its level: a faint wire's pixels under their threshold, lowered, faded it
/// unevenly, and its angle's scatter at rest grew from 0.03 to 0.07 deg (a 1 px wire
/// shrunk 1.5 times at 30 fps, a sweep twin). Held so while the wire swings, the whole
/// strip moved a real clip's `beside` figure over its limit.
pub(super) fn decay_where_seen(
    bg: &mut [u8],
    frame: &[u8],
    tmap: &[u8],
    dark: bool,
    whole: bool,
    on_wire: impl Fn(usize) -> bool,
) {
    let pixels = bg.iter_mut().zip(frame).zip(tmap).enumerate();
    for (i, ((b, f), t)) in pixels {
        let over = if dark {
            b.saturating_sub(*f) > *t
        } else {
            f.saturating_sub(*b) > *t
        };
        if !((whole || over) && on_wire(i)) {
            *b = if dark {
                b.saturating_sub(1)
            } else {
                b.saturating_add(1)
            };
        }
    }
}
