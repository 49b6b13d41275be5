//! The unit tests of `detect/track/measure.rs`.

use super::ridge::full_width;
use super::*;
use crate::detect::tuning::CELLS;

#[test]
fn the_wedge_test_passes_over_only_pixels_outside_the_wedge_by_their_angle() {
    let mut rng = crate::rng::Rng::new(5);
    let (mut passed, mut kept) = (0, 0);
    for _ in 0..2000 {
        // Wedges at any direction, from 2 deg to wider than a half turn.
        let mid = 8.0 * rng.uniform() - 4.0;
        let half = (2.0 + 100.0 * rng.uniform()).to_radians();
        let (lo, hi) = (mid - half, mid + half);
        let test = WedgeTest::new(lo, hi);
        for _ in 0..50 {
            let d = Pt::new(
                (400.0 * rng.uniform() - 200.0).round(),
                (400.0 * rng.uniform() - 200.0).round(),
            );
            let r = d.norm();
            if r == 0.0 {
                continue;
            }
            let th = unwrap_near(d.y.atan2(d.x), 0.5 * (lo + hi));
            let inside = th >= lo && th <= hi;
            if test.surely(d, r) {
                assert!(!inside, "{d:?} inside {lo}..{hi} passed over");
                passed += 1;
            } else {
                kept += 1;
            }
        }
    }
    // It does pass over most of what lies outside.
    assert!(passed > kept / 2, "passed over {passed}, kept {kept}");
}

#[test]
fn a_pixel_on_the_wedge_s_edge_is_left_to_its_angle() {
    // The edge of a wedge from 0 to 30 deg, a pixel on it, and one just past it.
    let test = WedgeTest::new(0.0, 30f64.to_radians());
    let on = Pt::new(30f64.to_radians().cos(), 30f64.to_radians().sin()) * 100.0;
    assert!(!test.surely(on, on.norm()));
    let past = Pt::new(31f64.to_radians().cos(), 31f64.to_radians().sin()) * 100.0;
    assert!(test.surely(past, past.norm()));
    // Too wide to be tested so: nothing is passed over.
    let wide = WedgeTest::new(0.0, 3.2);
    assert!(!wide.surely(Pt::new(-1.0, -1.0), 2f64.sqrt()));
}

/// A 320x240 frame `index` of a 25 frames/s video.
fn frame(index: u64, data: Vec<u8>) -> crate::video::Frame {
    crate::video::Frame {
        index,
        t_s: index as f64 / 25.0,
        width: 320,
        height: 240,
        data,
    }
}

/// A 320x240 wall at 200 with a wire 45 grey levels dark (2 px wide) from (160, 20)
/// at `wire` rad, and a line 120 dark, a Gaussian of sigma 0.9 px across, at `other`:
/// the stronger ridge, and a little wider (not by the 30 % that outweighs a kept
/// track's strongest ridge, by more than the 8 % a starting track needs).
fn two_lines(index: u64, wire: Option<f64>, other: Option<f64>) -> crate::video::Frame {
    let (w, h) = (320usize, 240usize);
    let mut data = vec![200u8; w * h];
    for y in 0..h {
        for x in 0..w {
            let (vx, vy) = (x as f64 - 160.0, y as f64 - 20.0);
            let mut v = 200.0;
            for (th, depth, sharp) in [(wire, 45.0, true), (other, 120.0, false)] {
                let Some(th) = th else { continue };
                let along = vx * th.cos() + vy * th.sin();
                let across = (vx * th.sin() - vy * th.cos()).abs();
                if (0.0..=200.0).contains(&along) {
                    v -= depth
                        * if sharp {
                            (1.5 - across).clamp(0.0, 1.0)
                        } else {
                            (-0.5 * (across / 0.9).powi(2)).exp()
                        };
                }
            }
            data[y * w + x] = v.round() as u8;
        }
    }
    frame(index, data)
}

/// A 320x240 wall at 200 with a faint wire 20 grey levels dark (2 px wide) from
/// (160, 20) at `wire` rad, to a bob of radius 16 px centred on its line 190 px out
/// (the band's end), whose rim is 100 grey levels dark on one side of the wire only:
/// a crescent 5 px thick, from 1 px beside the wire's line outwards (an oblique view
/// lit from the side).
fn wire_and_rim(index: u64, wire: f64) -> crate::video::Frame {
    let (w, h) = (320usize, 240usize);
    let u = Pt::new(wire.cos(), wire.sin());
    let centre = Pt::new(160.0, 20.0) + u * 190.0;
    let mut data = vec![200u8; w * h];
    for y in 0..h {
        for x in 0..w {
            let q = Pt::new(x as f64, y as f64);
            let v = q - Pt::new(160.0, 20.0);
            let along = v.dot(&u);
            let across = v.x * u.y - v.y * u.x;
            let mut g = 200.0;
            if (0.0..=190.0).contains(&along) {
                g -= 20.0 * (1.5 - across.abs()).clamp(0.0, 1.0);
            }
            let d = (q - centre).norm();
            if (11.0..=16.0).contains(&d) && across > 1.0 {
                g -= 100.0;
            }
            data[y * w + x] = g.round() as u8;
        }
    }
    frame(index, data)
}

/// The rim's parts of the band weigh less in the histogram ([`covered_bins`]) and
/// stray from the wire's line in the fit ([`drop_stray_parts`]). Without either rule
/// the rim turned every frame's line by 0.16-0.20 deg (0.18 on average); with them
/// by 0.06-0.16 (0.09): what is left is the rim's share within the wire's own
/// parts, which neither rule can tell from the wire.
#[test]
fn the_bob_s_rim_beside_the_band_s_end_turns_the_line_less() {
    let deg = |d: f64| d.to_radians();
    let mut t = super::super::test_tracker((deg(78.0), deg(102.0)));
    let mut sum = 0.0;
    for k in 0..16u64 {
        let wire = deg(84.0 + 0.75 * k as f64);
        let row = t.step(&wire_and_rim(k, wire), None).unwrap();
        let got = row.angle_rad.expect("a line");
        assert!(
            (got - wire).abs() < deg(0.2),
            "frame {k}: {:.3} deg, the wire at {:.3}",
            got.to_degrees(),
            wire.to_degrees()
        );
        sum += (got - wire).abs();
    }
    let mean = (sum / 16.0).to_degrees();
    assert!(mean < 0.12, "the line turned by {mean:.3} deg on average");
}

/// A wall at 200 with a static tick 130 grey levels dark, 2 px wide, from the pivot's
/// direction at 90.9 deg between 70 and 150 px out (a protractor's); and a faint
/// black wire that darkens each pixel by 30 % of its coverage, whatever lies
/// behind, at `wire` rad: over the tick it shows a third of its evidence on the
/// plate.
fn wire_by_tick(index: u64, wire: Option<f64>) -> crate::video::Frame {
    let (w, h) = (320usize, 240usize);
    let tick = 90.9f64.to_radians();
    let mut data = vec![200u8; w * h];
    for y in 0..h {
        for x in 0..w {
            let v = Pt::new(x as f64 - 160.0, y as f64 - 20.0);
            let (t_along, t_across) = (
                v.x * tick.cos() + v.y * tick.sin(),
                v.x * tick.sin() - v.y * tick.cos(),
            );
            let mut g = 200.0;
            if (70.0..=150.0).contains(&t_along) && t_across.abs() <= 1.0 {
                g = 70.0;
            }
            if let Some(th) = wire {
                let along = v.x * th.cos() + v.y * th.sin();
                let across = v.x * th.sin() - v.y * th.cos();
                if (0.0..=200.0).contains(&along) {
                    g *= 1.0 - 0.3 * (1.5 - across.abs()).clamp(0.0, 1.0);
                }
            }
            data[y * w + x] = g.round() as u8;
        }
    }
    frame(index, data)
}

/// Beside the tick, the wire's flank over it shows less evidence than the other:
/// weighed as it came, the lines leaned away from the tick by 0.017 deg on average
/// and 0.045 at most. Weighed by the contrast behind it, with the tick and its
/// mirror image left out: 0.003 and 0.010.
#[test]
fn a_wire_beside_a_dark_tick_does_not_lean_away_from_it() {
    let deg = |d: f64| d.to_radians();
    let bg = wire_by_tick(0, None);
    let bg = opencv::core::Mat::new_rows_cols_with_data(240, 320, &bg.data)
        .unwrap()
        .try_clone()
        .unwrap();
    let mut t = super::super::test_tracker_over(bg, (deg(86.0), deg(95.0)));
    let (mut sum, mut worst) = (0.0f64, 0.0f64);
    for k in 0..16u64 {
        let wire = deg(89.0 + 0.25 * k as f64);
        let row = t.step(&wire_by_tick(k, Some(wire)), None).unwrap();
        let err = (row.angle_rad.expect("a line") - wire).abs().to_degrees();
        sum += err;
        worst = worst.max(err);
    }
    let mean = sum / 16.0;
    assert!(
        worst < 0.02 && mean < 0.01,
        "the line leaned by {mean:.4} deg on average, {worst:.4} at most"
    );
}

#[test]
fn a_bin_s_evidence_counts_by_the_share_of_the_band_it_reaches() {
    // Three bins: evidence 10 in every part of the band, 20 in each of its first
    // half's parts, and 40 in each of its last three parts. Half the band or more
    // counts whole; three parts of 24 count 3 / 12.
    let mut cells = vec![10.0; CELLS];
    cells.extend((0..CELLS).map(|c| if c < CELLS / 2 { 20.0 } else { 0.0 }));
    cells.extend((0..CELLS).map(|c| if c >= CELLS - 3 { 40.0 } else { 0.0 }));
    let mut histo = [0.0; 3];
    covered_bins(&cells, &mut histo);
    assert_eq!(histo, [240.0, 240.0, 120.0 * 3.0 / 12.0]);
}

#[test]
fn parts_of_a_strip_that_stray_from_its_line_are_dropped_the_rest_kept() {
    // A strip along the x axis from a pivot at the origin over the band 0..240 (ten
    // px a part): one pixel of weight 10 a part, 0.2 px either side in turn.
    let piv = Pt::new(0.0, 0.0);
    let along = Line {
        point: piv,
        dir: Pt::new(1.0, 0.0),
    };
    let strip: Vec<(Pt, f64)> = (0..CELLS)
        .map(|c| {
            (
                Pt::new(10.0 * c as f64 + 5.0, if c % 2 == 0 { 0.2 } else { -0.2 }),
                10.0,
            )
        })
        .collect();
    let mut kept = strip.clone();
    assert!(!drop_stray_parts(
        piv,
        (0.0, 240.0),
        along,
        &mut kept,
        &mut Vec::new()
    ));
    assert_eq!(kept, strip, "nothing strays");
    // The last two parts hold a blob 1.5 px to one side, 20 times as heavy: judged
    // against the line fitted with it made lighter, those two parts go.
    let mut with_blob = strip.clone();
    for c in [CELLS - 2, CELLS - 1] {
        with_blob.push((Pt::new(10.0 * c as f64 + 5.0, 1.5), 200.0));
    }
    let pulled = fit_line_through(piv, &with_blob).unwrap();
    let mut kept = with_blob.clone();
    assert!(drop_stray_parts(
        piv,
        (0.0, 240.0),
        pulled,
        &mut kept,
        &mut Vec::new()
    ));
    assert_eq!(kept, strip[..CELLS - 2].to_vec());
}

#[test]
fn a_strip_s_edge_pixels_count_by_their_share_inside() {
    // 2.5 px either side: a centre 2.0 px off counts whole, 2.5 px half, 2.75 px a
    // quarter, 3.0 px and beyond not at all.
    assert_eq!(edge_share(2.5, 2.0), 1.0);
    assert_eq!(edge_share(2.5, 2.5), 0.5);
    assert_eq!(edge_share(2.5, 2.75), 0.25);
    assert_eq!(edge_share(2.5, 3.0), 0.0);
    assert_eq!(edge_share(2.5, 0.0), 1.0);
}

#[test]
fn a_strip_holds_the_same_evidence_wherever_its_line_falls_between_pixels() {
    let deg = |d: f64| d.to_radians();
    let mut t = super::super::test_tracker((deg(78.0), deg(102.0)));
    // Evidence 10 everywhere: each row of the strip weighs its width times 10.
    t.ev = Mat::new_rows_cols_with_default(
        240,
        320,
        opencv::core::CV_8UC1,
        opencv::core::Scalar::all(10.0),
    )
    .unwrap();
    // A strip 1.75 px either side of a line 5 deg from vertical: 3.5 / cos 5 deg =
    // 3.513 px of each row, each weighing evidence 10 over the wall's 200.
    let want = 3.5 / deg(5.0).cos() * t.contrast.weight(10, 200);
    let mut px = Vec::new();
    // Through the pivot (160, 20), and moved across by tenths of a pixel (a line
    // given by a point along it, away from the pivot, as a free line is).
    let dir = Pt::new(deg(95.0).cos(), deg(95.0).sin());
    for k in 0..10 {
        let line = Line {
            point: Pt::new(160.0 + 0.1 * k as f64, 20.0) + dir * 100.0,
            dir,
        };
        t.strip_pixels(&line, 1.75, &mut px).unwrap();
        // The rows of the band's middle, away from its ends.
        for y in 80..140 {
            let row: f64 = px
                .iter()
                .filter(|(q, _)| q.y == y as f64)
                .map(|(_, w)| w)
                .sum();
            // Whole pixels only, a row would hold 3 or 4 of them.
            assert!(
                (row - want).abs() < 0.01 * want,
                "line {k}, row {y}: {row:.2}, want {want:.2}"
            );
        }
    }
}

#[test]
fn a_far_strip_taken_from_the_whole_walk_is_the_walk_from_its_radius() {
    // Random evidence with marks, and lines near the pivot's at every slope, steep
    // and not, through the pivot and beside it: the pixels of the walk from a radius
    // under the cut, from the cut out, are the walk's from the cut, in its order and
    // with its weights, to the bit.
    let mut rng = crate::rng::Rng::new(5);
    // A wall with dark specks the background's marks hold (and leave out of strips).
    let mut wall = vec![200u8; 240 * 320];
    for _ in 0..400 {
        let (x, y) = (
            (318.0 * rng.uniform()) as usize,
            (238.0 * rng.uniform()) as usize,
        );
        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            wall[(y + dy) * 320 + x + dx] = 100;
        }
    }
    let wall = Mat::new_rows_cols_with_data(240, 320, &wall)
        .unwrap()
        .try_clone()
        .unwrap();
    let mut t = super::super::test_tracker_over(wall, (0.0, std::f64::consts::TAU));
    assert!(
        t.contrast.marked_share() > 0.01,
        "{}",
        t.contrast.marked_share()
    );
    let ev: Vec<u8> = (0..240 * 320)
        .map(|_| {
            if rng.uniform() < 0.3 {
                0
            } else {
                (255.0 * rng.uniform()) as u8
            }
        })
        .collect();
    t.ev = Mat::new_rows_cols_with_data(240, 320, &ev)
        .unwrap()
        .try_clone()
        .unwrap();
    let (mut whole, mut far, mut walked) = (Vec::new(), Vec::new(), Vec::new());
    let mut compared = 0;
    for _ in 0..400 {
        let th = std::f64::consts::TAU * rng.uniform();
        let dir = Pt::new(th.cos(), th.sin());
        let normal = Pt::new(-dir.y, dir.x);
        let line = Line {
            point: t.piv + normal * (4.0 * rng.uniform() - 2.0) + dir * (50.0 * rng.uniform()),
            dir,
        };
        let from = t.r_lo + (t.r_hi - t.r_lo) * rng.uniform();
        let half = 1.0 + 2.0 * rng.uniform();
        t.strip_pixels_from(&line, half, t.r_lo, &mut whole)
            .unwrap();
        t.strip_beyond(&line, half, from, &whole, &mut far);
        t.strip_pixels_from(&line, half, from, &mut walked).unwrap();
        let bits = |v: &[(Pt, f64)]| -> Vec<[u64; 3]> {
            v.iter()
                .map(|(q, w)| [q.x.to_bits(), q.y.to_bits(), w.to_bits()])
                .collect()
        };
        assert_eq!(bits(&far), bits(&walked), "line at {th} rad from {from} px");
        compared += walked.len();
    }
    assert!(compared > 10_000, "{compared} pixels compared");
}

#[test]
fn a_lost_track_starts_again_on_the_sharper_ridge_not_the_stronger() {
    let deg = |d: f64| d.to_radians();
    let mut t = super::super::test_tracker((deg(78.0), deg(102.0)));
    // The wire alone, swinging 1 deg a frame: the track is on it.
    let wire = |k: u64| deg(80.0 + k as f64);
    for k in 0..8 {
        let row = t.step(&two_lines(k, Some(wire(k)), None), None).unwrap();
        assert!(row.flag.is_none(), "frame {k}: {:?}", row.flag);
    }
    // Gone for six frames: the track is lost (no prediction).
    for k in 8..14 {
        t.step(&two_lines(k, None, None), None).unwrap();
    }
    assert_eq!(t.predict(14.0 / 25.0), None, "the track is lost");
    // Back, with the stronger and wider line 15 deg off (past the wedge a track
    // keeps, within the sweep a lost track searches).
    let k = 14;
    let row = t
        .step(
            &two_lines(k, Some(wire(k)), Some(wire(k) - deg(15.0))),
            None,
        )
        .unwrap();
    let got = row.angle_rad.expect("an angle").to_degrees();
    assert!(
        (got - wire(k).to_degrees()).abs() < 0.5,
        "started again at {got:.2} deg: the wire is at {:.2}, the stronger line at {:.2}",
        wire(k).to_degrees(),
        wire(k).to_degrees() - 15.0
    );
}

#[test]
fn a_track_does_not_re_anchor_on_a_fixed_line_the_wire_moved_away_from() {
    let deg = |d: f64| d.to_radians();
    let mut t = super::super::test_tracker((deg(78.0), deg(102.0)));
    // A fixed line at 80 deg, and the wire 4 deg from it, leaving it 0.25 deg a
    // frame.
    let mark = Some(deg(80.0));
    let wire = |k: u64| deg(84.0 + 0.25 * k as f64);
    // A grey level of sensor noise, so that frames that show the same lines are not
    // taken for repeated ones.
    let frame = |k: u64, wire: Option<f64>| {
        let mut f = two_lines(k, wire, mark);
        for (i, v) in f.data.iter_mut().enumerate() {
            *v = (*v as usize + (i * 31 + k as usize * 17) % 3).saturating_sub(1) as u8;
        }
        f
    };
    let on_wire = |k: u64, row: crate::detect::AngleRow| {
        let got = row.angle_rad.expect("an angle").to_degrees();
        assert!(
            row.flag.is_none() && (got - wire(k).to_degrees()).abs() < 0.5,
            "frame {k}: {got:.2} deg, {:?}: the wire is at {:.2}",
            row.flag,
            wire(k).to_degrees()
        );
    };
    for k in 0..14 {
        on_wire(k, t.step(&frame(k, Some(wire(k))), None).unwrap());
    }
    // The wire unseen for four frames (too faint, too fast): only the fixed line,
    // 7.5 deg behind the track, which stands still there. It is in the track's
    // search from the second of them, and refused by the gate.
    for k in 14..18 {
        let row = t.step(&frame(k, None), None).unwrap();
        assert!(
            row.flag.is_some(),
            "frame {k}: the fixed line accepted at {:?} deg",
            row.angle_rad.map(f64::to_degrees)
        );
    }
    // Back: the track is still the wire's.
    on_wire(18, t.step(&frame(18, Some(wire(18))), None).unwrap());
}

#[test]
fn the_wire_s_side_is_known_once_the_sharper_ridge_leads_by_three_sigmas() {
    let deg = |d: f64| d.to_radians();
    // The narrower ridge (width 1.0 against 1.2) at the larger angle, 4 deg apart, or
    // at the smaller; either ridge may be the strongest (given first).
    // The pair at `k` deg along the swing (a vote needs the narrower ridge to have
    // moved 0.5 deg since the last).
    let wire_above = |r: &mut Ridges, k: f64| r.observe((deg(30.0 + k), 1.2), (deg(34.0 + k), 1.0));
    let wire_below = |r: &mut Ridges, k: f64| r.observe((deg(34.0 + k), 1.2), (deg(30.0 + k), 1.0));
    let mut r = Ridges::default();
    for k in 0..11 {
        wire_above(&mut r, k as f64);
    }
    assert_eq!(r.side(), None, "11 votes are too few");
    // A pair that has not moved does not vote.
    wire_above(&mut r, 10.2);
    assert_eq!(r.votes, 11);
    wire_above(&mut r, 11.0);
    let (side, sep) = r.side().expect("12 votes of one side");
    assert_eq!(side, 1.0);
    assert!((sep - deg(4.0)).abs() < 1e-12, "{}", sep.to_degrees());
    // Nearly equal widths (0.98 of the other's) do not vote.
    r.observe((deg(20.0), 1.0), (deg(16.0), 0.98));
    assert_eq!(r.votes, 12);
    // `n` votes, one in four for `fourth`'s side and the rest for `rest`'s.
    let mixed = |n: usize, fourth: &dyn Fn(&mut Ridges, f64), rest: &dyn Fn(&mut Ridges, f64)| {
        let mut r = Ridges::default();
        for k in 0..n {
            let vote = if k % 4 == 0 { fourth } else { rest };
            vote(&mut r, k as f64);
        }
        r
    };
    // 12 against 4: a lead of 8 is under 3 sqrt(16) = 12.
    assert_eq!(mixed(16, &wire_below, &wire_above).side(), None);
    // 27 against 9: a lead of 18 is 3 sqrt(36); the side is the wire's, below.
    let r = mixed(36, &wire_above, &wire_below);
    assert_eq!(r.side().map(|s| s.0), Some(-1.0));
    assert!((Ridges::reach(deg(4.0)) - deg(8.0)).abs() < 1e-12);
}

#[test]
fn every_byte_over_its_threshold_is_found_in_order() {
    let mut rng = crate::rng::Rng::new(5);
    for n in [0, 1, 31, 32, 33, 100, 257] {
        // Sparse and dense: a tenth, then half, of the bytes over.
        for share in [0.1, 0.5] {
            let t: Vec<u8> = (0..n).map(|_| (200.0 * rng.uniform()) as u8).collect();
            let e: Vec<u8> = t
                .iter()
                .map(|&v| {
                    if rng.uniform() < share {
                        v.saturating_add(1 + (50.0 * rng.uniform()) as u8)
                    } else {
                        v
                    }
                })
                .collect();
            let want: Vec<usize> = (0..n).filter(|&i| e[i] > t[i]).collect();
            let mut got = Vec::new();
            over_threshold(&e, &t, |i| got.push(i));
            assert_eq!(got, want, "{n} bytes, {share} over");
        }
    }
}

/// A light frame with two dark lines from `piv`: a sharp one (Gaussian sigma 0.5 px) at
/// `sharp` and a blurred one (sigma `blur` px) at `blurred`, radians.
fn sharp_and_blurred(piv: Pt, sharp: f64, blurred: f64, blur: f64) -> (Vec<u8>, usize, usize) {
    let (w, h) = (320, 240);
    let mut data = vec![0u8; w * h];
    for y in 0..h {
        for x in 0..w {
            let d = Pt::new(x as f64, y as f64) - piv;
            let dist = |th: f64| (d.x * th.sin() - d.y * th.cos()).abs();
            let ahead = |th: f64| d.x * th.cos() + d.y * th.sin() > 0.0;
            let mut g = 200.0;
            if ahead(sharp) {
                g -= 90.0 * (-0.5 * (dist(sharp) / 0.5).powi(2)).exp();
            }
            if ahead(blurred) {
                g -= 60.0 * (-0.5 * (dist(blurred) / blur).powi(2)).exp();
            }
            data[y * w + x] = g.round() as u8;
        }
    }
    (data, w, h)
}

#[test]
fn a_sharp_wire_measures_narrower_than_its_blurred_shadow_at_the_full_scale() {
    let piv = Pt::new(160.0, 10.0);
    let (wire, shadow) = (80f64.to_radians(), 86f64.to_radians());
    let (data, w, h) = sharp_and_blurred(piv, wire, shadow, 2.5);
    let full = Full { data: &data, w, h };
    let apart = shadow - wire;
    let band = (20.0, 220.0);
    let a = full_width(&full, piv, wire, band, apart, true).expect("the wire's width");
    let b = full_width(&full, piv, shadow, band, apart, true).expect("the shadow's width");
    // A Gaussian's spread above a quarter of its peak is about 0.6 of its sigma.
    assert!(a < 0.6, "the sharp line measures {a:.3} px");
    assert!(b > 1.2, "the blurred line measures {b:.3} px");
    // Looked for on the wrong polarity, or too near the other line to part them, none.
    assert!(full_width(&full, piv, wire, band, apart, false).is_none_or(|x| x > a));
    assert_eq!(
        full_width(&full, piv, wire, (20.0, 60.0), apart, true),
        None
    );
}

#[test]
fn a_strip_s_parabola_gives_its_middle_s_offset_and_how_much_of_a_shift_it_follows() {
    // A strip along x (the line through the origin pointing +x), its pixels on
    // v = 0.001 u^2 - 0.4 (v to the line's left: -y), u from -100 to 100: the middle
    // lies 0.001 * 100^2 = 10 px from the chord, to the chord's right (negative).
    let line = Line {
        point: Pt::zeros(),
        dir: Pt::new(1.0, 0.0),
    };
    let strip: Vec<(Pt, f64)> = (-100..=100)
        .map(|u| {
            let u = f64::from(u);
            (Pt::new(u, -(0.001 * u * u - 0.4)), 1.0)
        })
        .collect();
    let (mid, response, ends) =
        strip_parabola(&line, &strip, 50.0, &mut Vec::new(), &mut Vec::new()).unwrap();
    assert!((mid + 10.0).abs() < 1e-9, "{mid}");
    assert_eq!(ends, [-100.0, 100.0]);
    // Every pixel well inside the strip: a shift moves the centroid as far.
    assert!((response - 1.0).abs() < 1e-12, "{response}");
    // A flat profile reaching past the strip (1.75 px either side, its ramp from 1.25
    // to 2.25 px), sampled every half pixel: a shift leaves what the strip holds as it
    // is, and the centroid does not follow. By hand, per place along the line: the
    // shares 1 (0, 0.5 and 1 px), 0.75 (1.5 px) and 0.25 (2 px) weigh 1 + 2 * 3 = 7;
    // the ramp's places, |v| 1.5 and 2 at raw weight 1 over its width 1 px, each side,
    // 2 * 3.5 = 7: the response is 1 - 7 / 7 = 0.
    let flat: Vec<(Pt, f64)> = (-50..=50)
        .flat_map(|u| {
            (-4..=4).filter_map(move |k| {
                let v = 0.5 * f64::from(k);
                let share = edge_share(1.75, v.abs());
                (share > 0.0).then(|| (Pt::new(f64::from(u), v), share))
            })
        })
        .collect();
    let (_, response, _) =
        strip_parabola(&line, &flat, 1.75, &mut Vec::new(), &mut Vec::new()).unwrap();
    assert!(response.abs() < 1e-12, "{response}");
    assert!(strip_parabola(&line, &strip[..2], 50.0, &mut Vec::new(), &mut Vec::new()).is_none());
    // A static line crossing the wire pulls five steps 3 px aside: they are left out,
    // and the bow is the wire's (all in: 9.87 px).
    let crossed: Vec<(Pt, f64)> = strip
        .iter()
        .map(|&(q, w)| {
            let pulled = (40.0..45.0).contains(&q.x);
            (Pt::new(q.x, if pulled { q.y - 3.0 } else { q.y }), w)
        })
        .collect();
    let (mid, _, _) =
        strip_parabola(&line, &crossed, 50.0, &mut Vec::new(), &mut Vec::new()).unwrap();
    assert!((mid + 10.0).abs() < 1e-9, "{mid}");
}
