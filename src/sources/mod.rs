//! The source code behind each output, for the build's cache keys: `build.rs` hashes
//! every top-level module together with the modules it names and the templates it
//! embeds ([`scan`]); a stage's key takes the hash of the module that produces it.

pub mod scan;

include!(concat!(env!("OUT_DIR"), "/sources.rs"));

/// The closure hash of top-level module `name` (see [`scan::closure_hash`]).
///
/// # Panics
/// When `name` is not a module of `src/` (a programming error, caught by the tests).
pub fn hash(name: &str) -> &'static str {
    MODULE_HASHES
        .iter()
        .find(|(m, _)| *m == name)
        .map(|(_, h)| *h)
        .unwrap_or_else(|| panic!("no module `{name}` in src/"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn copy_tree(from: &Path, to: &Path) {
        std::fs::create_dir_all(to).unwrap();
        for e in std::fs::read_dir(from).unwrap() {
            let p = e.unwrap().path();
            let dst = to.join(p.file_name().unwrap());
            if p.is_dir() {
                copy_tree(&p, &dst);
            } else {
                std::fs::copy(&p, &dst).unwrap();
            }
        }
    }

    fn crate_copy() -> tempfile::TempDir {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let d = tempfile::tempdir().unwrap();
        copy_tree(&root.join("src"), &d.path().join("src"));
        copy_tree(&root.join("templates"), &d.path().join("templates"));
        std::fs::copy(root.join("Cargo.lock"), d.path().join("Cargo.lock")).unwrap();
        d
    }

    fn hash_in(dir: &Path, root: &str) -> String {
        let mods = scan::modules(&dir.join("src")).unwrap();
        scan::closure_hash(dir, &mods, root).unwrap()
    }

    #[test]
    fn the_compiled_in_hashes_are_those_of_the_tree() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        for m in ["synth", "detect", "pipeline", "report"] {
            assert_eq!(hash(m), hash_in(root, m), "module {m}");
        }
    }

    #[test]
    fn editing_the_integrator_invalidates_the_twin_render_key() {
        let d = crate_copy();
        let before = hash_in(d.path(), "synth");
        let video_before = hash_in(d.path(), "video");
        let ode = d.path().join("src/physics/ode.rs");
        let mut text = std::fs::read_to_string(&ode).unwrap();
        text.push_str("\n// an edit\n");
        std::fs::write(&ode, text).unwrap();
        assert_ne!(
            hash_in(d.path(), "synth"),
            before,
            "synth -> simulate -> physics::ode"
        );
        assert_eq!(
            hash_in(d.path(), "video"),
            video_before,
            "decoding does not depend on the model"
        );
    }

    #[test]
    fn a_template_edit_reaches_the_report_and_not_the_detector() {
        let d = crate_copy();
        let (rep, det) = (hash_in(d.path(), "report"), hash_in(d.path(), "detect"));
        let t = d.path().join("templates/experiment.md.tera");
        let mut text = std::fs::read_to_string(&t).unwrap();
        text.push('\n');
        std::fs::write(&t, text).unwrap();
        assert_ne!(hash_in(d.path(), "report"), rep);
        assert_eq!(hash_in(d.path(), "detect"), det);
    }

    #[test]
    fn closures_follow_grouped_and_plain_crate_paths() {
        let d = tempfile::tempdir().unwrap();
        let src = d.path().join("src");
        std::fs::create_dir_all(src.join("b")).unwrap();
        std::fs::write(src.join("a.rs"), "use crate::{b::x, c};\n").unwrap();
        std::fs::write(src.join("b/mod.rs"), "fn f() { crate::d::g() }\n").unwrap();
        std::fs::write(src.join("c.rs"), "// crate::e is only named in a comment\n").unwrap();
        std::fs::write(src.join("d.rs"), "").unwrap();
        std::fs::write(src.join("e.rs"), "").unwrap();
        let mods = scan::modules(&src).unwrap();
        let c: Vec<_> = scan::closure(&mods, "a").into_iter().collect();
        assert_eq!(c, ["a", "b", "c", "d"]);
        // A module's unit tests in a `tests.rs` of their own name no dependency (but
        // are hashed with it); the same words in code do.
        std::fs::write(src.join("b/tests.rs"), "use crate::e;\n").unwrap();
        let mods = scan::modules(&src).unwrap();
        assert!(mods["b"].files.contains(&src.join("b/tests.rs")));
        assert!(!mods["b"].uses.contains("e"));
        std::fs::create_dir_all(src.join("b/tests")).unwrap();
        std::fs::write(src.join("b/tests/more.rs"), "use crate::e;\n").unwrap();
        assert!(!scan::modules(&src).unwrap()["b"].uses.contains("e"));
        std::fs::write(src.join("b/other.rs"), "use crate::e;\n").unwrap();
        assert!(scan::modules(&src).unwrap()["b"].uses.contains("e"));
    }

    /// The module graph of the live tree, as `build.rs` reads it.
    fn live() -> std::collections::BTreeMap<String, scan::Module> {
        scan::modules(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src")).unwrap()
    }

    #[test]
    fn dependencies_point_one_way() {
        let mods = live();
        // A module in its own closure only through one of its dependencies is a cycle.
        for (name, m) in &mods {
            for dep in m
                .uses
                .iter()
                .filter(|d| *d != name && mods.contains_key(*d))
            {
                assert!(
                    !scan::closure(&mods, dep).contains(name),
                    "import cycle: {name} -> {dep} -> ... -> {name}"
                );
            }
        }
        let uses = |a: &str, b: &str| scan::closure(&mods, a).contains(b);
        assert!(!uses("config", "fit"), "config knows nothing of fit");
        for low in ["build", "cli"] {
            assert!(!uses("report", low), "report never calls {low}");
            assert!(!uses("pipeline", low), "pipeline never calls {low}");
        }
        assert!(!uses("pipeline", "report"), "the pipeline writes no page");
        assert!(
            !uses("build", "cli"),
            "the build knows nothing of the command line"
        );
    }

    #[test]
    fn the_cycle_check_can_fail() {
        let d = tempfile::tempdir().unwrap();
        let src = d.path().join("src");
        std::fs::create_dir_all(&src).unwrap();
        std::fs::write(src.join("a.rs"), "use crate::b::f;\n").unwrap();
        std::fs::write(src.join("b.rs"), "use crate::a::g;\n").unwrap();
        let mods = scan::modules(&src).unwrap();
        assert!(scan::closure(&mods, "b").contains("a"));
        assert!(scan::closure(&mods, "a").contains("b"));
    }
}
