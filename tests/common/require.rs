//! Whether a test may skip when a tool or fixture it needs is missing: it may on a
//! developer's machine (saying SKIPPED), never under `make test` or CI, where the missing
//! tool fails the test. Std only: `tests/common` re-exports it and the library's unit
//! tests include it by path (`src/lib.rs`).
#![allow(dead_code)]

/// The variable `make test` sets (to 1) so that a missing tool fails the tests.
pub const REQUIRE_TOOLS: &str = "ROLLFRIC_REQUIRE_TOOLS";

/// How to get a tool the Makefile installs.
pub const MAKE_DEPS: &str = "`make deps` installs it";

/// Whether a missing tool fails the tests, given the values of `ROLLFRIC_REQUIRE_TOOLS`
/// and `CI`: the first set to anything but empty or `0`, or the second set to anything but
/// empty, `0` or `false` (CI services set `CI=true`).
pub fn strict_from(require_tools: Option<&str>, ci: Option<&str>) -> bool {
    let on = |v: Option<&str>, off: &[&str]| v.is_some_and(|v| !off.contains(&v.trim()));
    on(require_tools, &["", "0"]) || on(ci, &["", "0", "false"])
}

/// [`strict_from`] this process's environment.
pub fn strict() -> bool {
    let var = |k: &str| std::env::var(k).ok();
    strict_from(var(REQUIRE_TOOLS).as_deref(), var("CI").as_deref())
}

/// `true` when `what` is `present`. When it is missing: if `strict`, a panic naming it
/// and saying how to get it (`how`); otherwise a `SKIPPED: ...` line on stderr, and
/// `false` (the caller returns).
pub fn require_in(strict: bool, what: &str, how: &str, present: bool) -> bool {
    if present {
        return true;
    }
    if strict {
        panic!(
            "{what} is missing: {how} ({REQUIRE_TOOLS} or CI is set, so a missing tool \
             fails the test instead of skipping it)"
        );
    }
    eprintln!(
        "SKIPPED: {what} is missing: {how} (under `make test`, {REQUIRE_TOOLS}=1, or CI \
         this fails)"
    );
    false
}

/// [`require_in`] with the strictness of this process's environment ([`strict`]).
pub fn require(what: &str, how: &str, present: bool) -> bool {
    require_in(strict(), what, how, present)
}
