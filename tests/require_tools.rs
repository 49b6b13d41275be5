//! A missing tool or fixture fails the tests under `make test` (`ROLLFRIC_REQUIRE_TOOLS=1`)
//! and CI (`CI=true`), and skips, saying so, elsewhere. The rule and its effect are pure
//! functions of their arguments: no test here changes the process's environment.

mod common;

use common::{require_in, strict_from, MAKE_DEPS};

#[test]
fn strictness_follows_rollfric_require_tools_and_ci() {
    for (require_tools, ci, strict) in [
        (None, None, false),
        (Some(""), None, false),
        (Some("0"), None, false),
        (Some("1"), None, true),
        (Some("yes"), None, true),
        (Some("false"), None, true),
        (None, Some("true"), true),
        (None, Some("1"), true),
        (None, Some(""), false),
        (None, Some("0"), false),
        (None, Some("false"), false),
        (Some("0"), Some("true"), true),
        (Some("1"), Some("false"), true),
    ] {
        assert_eq!(
            strict_from(require_tools, ci),
            strict,
            "ROLLFRIC_REQUIRE_TOOLS={require_tools:?} CI={ci:?}"
        );
    }
}

#[test]
fn a_present_tool_runs_the_test_either_way() {
    assert!(require_in(true, "ffmpeg", MAKE_DEPS, true));
    assert!(require_in(false, "ffmpeg", MAKE_DEPS, true));
}

#[test]
fn a_missing_tool_skips_when_not_strict() {
    assert!(!require_in(false, "nothing", MAKE_DEPS, false));
}

#[test]
#[should_panic(expected = "nothing is missing: `make deps` installs it (ROLLFRIC_REQUIRE_TOOLS")]
fn a_missing_tool_fails_when_strict() {
    require_in(true, "nothing", MAKE_DEPS, false);
}
