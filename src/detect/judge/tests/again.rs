//! Whether a second measurement (steadied, or at another scale) replaces the first:
//! `DetectionVerdict::fails_a_part_of` and `steadied_fails_a_part_of`.

use super::*;

#[test]
fn a_second_measurement_fails_a_part_of_the_first_only_when_it_breaks_nothing_new() {
    let passing = judge(&swinging(), [100.0, 20.0], Some(0.3), None);
    assert!(failed(&passing).is_empty(), "{:?}", passing.checks);
    // The same checks, those named failed.
    let failing = |names: &[&str]| {
        let mut v = passing.clone();
        for c in &mut v.checks {
            c.passed = !names.contains(&c.check.as_str());
        }
        assert_eq!(failed(&v), names, "every named check is judged");
        v
    };
    let first = failing(&["rhythm", "stalls", "rest"]);
    // Fixed two, broke none: kept.
    assert!(failing(&["rest"]).fails_a_part_of(&first));
    // Fixed nothing, or broke one the first passed: not.
    assert!(!failing(&["rhythm", "stalls", "rest"]).fails_a_part_of(&first));
    assert!(!failing(&["rest", "envelope"]).fails_a_part_of(&first));
    // Against a first that failed nothing, nothing fails less.
    assert!(!passing.fails_a_part_of(&passing));
    assert!(passing.fails_a_part_of(&first));
}

#[test]
fn a_steadied_measurement_failing_turn_alone_replaces_one_whose_angles_showed_the_motion() {
    let passing = judge(&swinging(), [100.0, 20.0], Some(0.3), None);
    // The same checks, `still` and a steadied measurement's `turn`, those named failed.
    let failing = |names: &[&str]| {
        let mut v = passing.clone().with(still_check(0.1)).with(DetectionCheck {
            check: "turn".into(),
            value: 0.0,
            limit: 0.01,
            passed: true,
            reason: String::new(),
        });
        for c in &mut v.checks {
            c.passed = !names.contains(&c.check.as_str());
        }
        let mut got = failed(&v);
        got.sort();
        let mut want = names.to_vec();
        want.sort();
        assert_eq!(got, want, "every named check is judged");
        v
    };
    // A first measurement never steadied: no `turn` of its own.
    let unsteadied = |names: &[&str]| {
        let mut v = failing(names);
        v.checks.retain(|c| c.check != "turn");
        v
    };
    // Seed 53's scene 13: the first measurement's angles wandered with the sway.
    let first = unsteadied(&["rest", "envelope", "still"]);
    assert!(failing(&["turn"]).steadied_fails_a_part_of(&first));
    assert!(failing(&["turn", "rest"]).steadied_fails_a_part_of(&first));
    // `turn` is not set aside where the first's angles showed nothing but `still`.
    let only_still = unsteadied(&["still"]);
    assert!(!failing(&["turn"]).steadied_fails_a_part_of(&only_still));
    // A first, never steadied, whose angles showed the motion without `still`: set
    // aside too.
    let later = unsteadied(&["rhythm", "stalls", "envelope"]);
    assert!(failing(&["turn"]).steadied_fails_a_part_of(&later));
    assert!(!failing(&["turn"]).fails_a_part_of(&later));
    assert!(failing(&["turn"]).steadied_fails_a_part_of(&unsteadied(&["rest", "still"])));
    // Not where the first, steadied in part, was judged by `turn`: failed (seed 53's
    // scene 6) or passed (a camera found moving later, its frames steadied from then).
    assert!(!failing(&["turn"]).steadied_fails_a_part_of(&failing(&["turn"])));
    assert!(!failing(&["turn", "rest"]).steadied_fails_a_part_of(&failing(&["turn", "still"])));
    assert!(
        !failing(&["turn"]).steadied_fails_a_part_of(&failing(&["rhythm", "stalls", "envelope"]))
    );
    // Nor does it excuse a check the first passed, or fixing nothing.
    assert!(!failing(&["turn", "period"]).steadied_fails_a_part_of(&first));
    assert!(!failing(&["turn", "rest", "envelope", "still"]).steadied_fails_a_part_of(&first));
    // Without `turn` failed, the same as `fails_a_part_of`.
    for names in [
        &["rest"][..],
        &["rest", "period"],
        &["rest", "envelope", "still"],
    ] {
        let v = failing(names);
        assert_eq!(
            v.steadied_fails_a_part_of(&first),
            v.fails_a_part_of(&first),
            "{names:?}"
        );
    }
}
