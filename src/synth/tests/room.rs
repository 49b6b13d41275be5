//! The room's conditions: a board, static edges, a second pendulum, a walker, a lens.

use super::*;

/// Pixels of frames `a` and `b` that differ by more than 3 grey levels, among those
/// farther than `clear` px from the segment pivot-`end` of every angle in `thetas`.
fn changed_away_from(a: &Mat, b: &Mat, g: &plan::Geometry, thetas: &[f64], clear: f64) -> usize {
    let (fa, fb) = (a.data_bytes().unwrap(), b.data_bytes().unwrap());
    let w = a.cols() as usize;
    let mut n = 0;
    for y in 0..a.rows() as usize {
        for x in 0..w {
            let near = thetas.iter().any(|th| {
                let (dx, dy) = (x as f64 - g.pivot[0], y as f64 - g.pivot[1]);
                let along = (dx * th.cos() + dy * th.sin()).clamp(0.0, g.d_px);
                let (ex, ey) = (dx - along * th.cos(), dy - along * th.sin());
                ex.hypot(ey) < clear
            });
            if near {
                continue;
            }
            let j = 3 * (y * w + x);
            if (0..3).any(|c| (fa[j + c] as i32 - fb[j + c] as i32).abs() > 3) {
                n += 1;
            }
        }
    }
    n
}

#[test]
fn a_second_pendulum_moves_away_from_the_first_and_the_board_is_drawn() {
    let render = |extra: &str, frames: &[usize]| {
        let e = exp(&format!(", width: 640, height: 480, clean: true{extra}"));
        let mut twin = Twin::new(Plan::new(&e, Some(2.0)).unwrap()).unwrap();
        let mut out = Vec::new();
        for &i in frames {
            twin.render_frame(i).unwrap();
            out.push(twin.frame.clone());
        }
        let thetas: Vec<f64> = frames
            .iter()
            .map(|&i| twin.plan.theta(twin.plan.truth[i].t_s))
            .collect();
        (out, twin.plan.geo.clone(), thetas)
    };
    let (plain, g, th) = render("", &[0, 20]);
    let clear = 2.0 * g.ball_r + 6.0;
    // An empty room: away from the wire and ball, nothing moves.
    assert_eq!(changed_away_from(&plain[0], &plain[1], &g, &th, clear), 0);
    let (busy, g2, th2) = render(
        ", room: {board: grid, edges: 2, second_string: true}",
        &[0, 20],
    );
    assert_eq!(g2.pivot, g.pivot);
    // The second pendulum moves elsewhere: hundreds of pixels change.
    let moved = changed_away_from(&busy[0], &busy[1], &g, &th2, clear);
    assert!(
        moved > 100,
        "{moved} px changed away from the first pendulum"
    );
    // The board and the edges change the still scene almost everywhere they are.
    let drawn = changed_away_from(&plain[0], &busy[0], &g, &th, clear);
    assert!(
        drawn > 640 * 480 / 20,
        "{drawn} px differ from the empty room"
    );
}

#[test]
fn the_walker_covers_the_wire_for_about_a_second_and_the_truth_says_so() {
    let e = exp(", width: 640, height: 480, clean: true, room: {walker_s: 1}");
    let plan = Plan::new(&e, Some(7.0)).unwrap();
    let covered: Vec<usize> = plan
        .truth
        .iter()
        .enumerate()
        .filter(|(_, r)| r.spoiled == "walker")
        .map(|(i, _)| i)
        .collect();
    // One run of frames, within the crossing, 0.3 to 2 s long at 30 frames/s.
    assert!(
        (9..=60).contains(&covered.len()),
        "{} frames",
        covered.len()
    );
    assert_eq!(covered.last().unwrap() - covered[0] + 1, covered.len());
    let (t0, t1) = (
        plan.truth[covered[0]].t_s,
        plan.truth[*covered.last().unwrap()].t_s,
    );
    assert!(
        t0 > 1.0 && t1 < 1.0 + crate::synth::room::WALKER_S,
        "{t0} {t1}"
    );
    // In a covered frame, the wire's middle is dark as the walker.
    let mid = covered[covered.len() / 2];
    let mut twin = Twin::new(plan).unwrap();
    twin.render_frame(mid).unwrap();
    let g = twin.plan.geo.clone();
    let th = twin.plan.theta(twin.plan.truth[mid].t_s);
    let p = [
        g.pivot[0] + 0.5 * g.d_px * th.cos(),
        g.pivot[1] + 0.5 * g.d_px * th.sin(),
    ];
    let buf = twin.frame.data_bytes().unwrap();
    let j = 3 * (p[1].round() as usize * g.w + p[0].round() as usize);
    let covered_here =
        twin.plan
            .walker
            .as_ref()
            .unwrap()
            .alpha(p[0], p[1], twin.plan.truth[mid].t_s);
    if covered_here > 0.9 {
        assert!(buf[j + 1] < 90, "{}", buf[j + 1]);
    }
}

#[test]
fn the_lens_moves_the_pivot_as_it_distorts_the_view() {
    let plain = Plan::new(&exp(", width: 640, height: 480, clean: true"), Some(1.0)).unwrap();
    let wide = Plan::new(
        &exp(", width: 640, height: 480, clean: true, lens_k1: -0.3"),
        Some(1.0),
    )
    .unwrap();
    let (p, q) = (plain.image_pivot(), wide.image_pivot());
    let c = [319.5, 239.5];
    // Barrel, zoomed to fill the frame: a point inside the frame moves away from the
    // centre, along its own direction.
    let (r0, r1) = (
        (p[0] - c[0]).hypot(p[1] - c[1]),
        (q[0] - c[0]).hypot(q[1] - c[1]),
    );
    assert!(r1 > r0 + 1.0, "{r0} {r1}");
    let cross = (p[0] - c[0]) * (q[1] - c[1]) - (p[1] - c[1]) * (q[0] - c[0]);
    assert!(cross.abs() < 1e-6 * r0 * r1);
}
