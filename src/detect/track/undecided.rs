//! Frames accepted while the side of a wire-and-shadow pair the wire lies on was not
//! yet known, restated once it is.

use super::{Restated, Tracker};
use crate::detect::tuning::{PAIR_SEP_TOL, RESTATE_BESIDE_FRAMES};

impl Tracker {
    /// Once the side a wire lies on beside its shadow is learnt, the frames accepted
    /// before on the ridge of a like pair on the shadow's side are restated with the
    /// other ridge's measurement, and the history the prediction reads with them. Until
    /// then, a track begun on a shadow stronger than its wire and barely wider (0.96 px
    /// against 1.01 on a 1920x1080 twin, too close for [`RIVAL_SHARPER_START`]) stays
    /// on it, the wire a rival outside the gate, until the votes decide (its first 32
    /// frames there, 2.8 deg off, `ok`).
    ///
    /// [`RIVAL_SHARPER_START`]: crate::detect::tuning::RIVAL_SHARPER_START
    pub(super) fn restate_undecided(&mut self) {
        if self.undecided.is_empty() {
            return;
        }
        let Some((side, along)) = self.ridges.side() else {
            return;
        };
        let held = std::mem::take(&mut self.undecided);
        // Each pair frame: restated (its ridge on the shadow's side of a like pair)?
        let restate: Vec<Option<bool>> = held
            .iter()
            .map(|u| {
                u.other.map(|o| {
                    let sep = u.taken - o.0;
                    // `side`: where the wire lies against the other ridge (+1: larger).
                    (sep.abs() - along).abs() <= PAIR_SEP_TOL * along && sep * side < 0.0
                })
            })
            .collect();
        for (i, u) in held.iter().enumerate() {
            let restated = match restate[i] {
                Some(r) => r,
                // A frame that saw no pair, between two restated, or beside one and
                // nearer its shadow's ridge than its wire's: taken on the shadow's track,
                // with nothing to restate it by.
                None => {
                    let before = restate[..i].iter().rev().find_map(|r| *r);
                    let after = restate[i + 1..].iter().find_map(|r| *r);
                    let beside = |j: usize| {
                        let n = &held[j];
                        restate[j] == Some(true)
                            && n.frame.abs_diff(u.frame) <= RESTATE_BESIDE_FRAMES
                            && n.other
                                .is_some_and(|o| (u.taken - n.taken).abs() < (u.taken - o.0).abs())
                    };
                    (before == Some(true) && after == Some(true))
                        || (i > 0 && beside(i - 1))
                        || (i + 1 < held.len() && beside(i + 1))
                }
            };
            if !restated {
                continue;
            }
            self.still = None;
            if let Some(o) = u.other {
                for h in self.hist.iter_mut().filter(|h| h.0 == u.t_s) {
                    h.1 = o.0;
                }
            } else {
                self.hist.retain(|h| h.0 != u.t_s);
            }
            self.restated.push(Restated {
                frame: u.frame,
                other: u.other,
            });
        }
    }
}
