//! The same build through Snakemake (`rollfric workflow snakemake`), on two twins, a
//! lab experiment whose video is missing and a file that does not load: from scratch it
//! gives reports byte-identical to `rollfric build`'s (the two failures fail only their
//! own experiments and are marked in the index and summary, as the build marks them);
//! a second run has nothing to do;
//! editing one experiment reruns only its jobs and the report; a run killed with
//! `kill -9` at a random moment and run again completes to the same bytes; the
//! cluster-generic executor (submit script running each job here) completes the DAG;
//! the Slurm executor's dry run lists one job per stage per experiment with the
//! profile's resources.
//!
//! Snakemake is the pinned one `make snakemake` installs under `target/snakemake`
//! (`ROLLFRIC_SNAKEMAKE` names another).

mod common;

use common::{rollfric_ok, root, same_tree};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;

const BIN: &str = env!("CARGO_BIN_EXE_rollfric");

fn snakemake_bin() -> Option<PathBuf> {
    let p = std::env::var_os("ROLLFRIC_SNAKEMAKE")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("target/snakemake/bin/snakemake"));
    let present = Command::new(&p).arg("--version").output().is_ok();
    common::require(
        &format!("snakemake ({})", p.display()),
        "run `make snakemake` (a pinned Snakemake in a virtual environment under target/)",
        present,
    )
    .then_some(p)
}

/// Two short twins (glass geometry, 20 s at 25 frames/s, 640x360) in a manifest.
fn setup(dir: &Path) {
    for (name, s_r) in [("one", "3.714e-6"), ("two", "5.0e-6")] {
        std::fs::write(
            dir.join(format!("{name}.yaml")),
            common::short_glass_twin(name, s_r, ""),
        )
        .unwrap();
    }
    // A lab experiment whose recording is not there, and a file that does not load:
    // each fails alone, and the report marks it.
    std::fs::write(
        dir.join("lab-run.yaml"),
        "name: lab-run
geometry:
  incline: { angle_deg: 5 }
  pendulum: { d_m: 0.2 }
  ball: { radius_m: 0.0127, mass_kg: 0.067 }
video: { path: videos/lab-run.mp4 }
",
    )
    .unwrap();
    std::fs::write(dir.join("broken.yaml"), "geometry: [not, a, mapping]\n").unwrap();
    std::fs::write(
        dir.join("manifest.yaml"),
        "title: Snakemake test\nexperiments:\n  - one.yaml\n  - two.yaml\n  - lab-run.yaml\n  - broken.yaml\n",
    )
    .unwrap();
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

struct Smk {
    bin: PathBuf,
    dir: PathBuf,
}

impl Smk {
    /// Snakemake in its own process group: on a failed job it signals its whole
    /// group, which must not be the test's.
    fn command(&self, args: &[&str]) -> Command {
        use std::os::unix::process::CommandExt;
        let mut c = Command::new(&self.bin);
        c.process_group(0);
        c.args(args)
            .args(["--config", &format!("rollfric={BIN}")])
            .current_dir(&self.dir)
            .stdin(Stdio::null());
        c
    }

    fn run(&self, args: &[&str]) -> String {
        let o = self.command(args).output().expect("run snakemake");
        let t = text(&o);
        assert!(o.status.success(), "snakemake {args:?} failed:\n{t}");
        t
    }
}

/// The rule and experiment of each job a run's log lists (`rule X:` and its
/// `wildcards: name=Y`).
fn jobs(log: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rule = None;
    for l in log.lines().map(str::trim) {
        if let Some(r) = l.strip_prefix("localrule ").or(l.strip_prefix("rule ")) {
            if let Some(prev) = rule.take() {
                out.push(prev);
            }
            rule = Some(r.trim_end_matches(':').to_string());
        } else if let Some(w) = l.strip_prefix("wildcards: name=") {
            if let Some(r) = rule.take() {
                out.push(format!("{r} {w}"));
            }
        }
    }
    out.extend(rule);
    out.sort();
    out
}

#[test]
fn snakemake_builds_the_same_reports_as_the_build() {
    let Some(bin) = snakemake_bin() else { return };
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    setup(dir);
    // The build marks the two failures and exits 1.
    let build = || {
        let o = common::rollfric(
            &[
                "build",
                "-q",
                "--manifest",
                "manifest.yaml",
                "--out",
                "built",
                "--cache",
                "cache-built",
            ],
            dir,
        );
        assert!(
            text(&o).contains("2 failed") && text(&o).contains("FAILED lab-run"),
            "{}",
            text(&o)
        );
    };
    build();
    let (said, _) = rollfric_ok(
        &[
            "workflow",
            "snakemake",
            "--manifest",
            "manifest.yaml",
            "--out",
            "reports",
            "--cache",
            "cache",
        ],
        dir,
    );
    assert!(said.contains("profiles/slurm/config.yaml"), "{said}");
    let smk = Smk {
        bin,
        dir: dir.to_path_buf(),
    };

    // From scratch: the build's bytes.
    let first = smk.run(&["--cores", "2"]);
    let want: Vec<String> = [
        "all",
        "report",
        "analyze broken",
        "analyze lab-run",
        "detect lab-run",
    ]
    .into_iter()
    .map(String::from)
    .chain(
        ["analyze", "detect", "synth"]
            .iter()
            .flat_map(|r| ["one", "two"].map(|e| format!("{r} {e}"))),
    )
    .collect::<std::collections::BTreeSet<_>>()
    .into_iter()
    .collect();
    assert_eq!(jobs(&first), want, "{first}");
    // The failures are the build's, in the index and the summary, byte for byte.
    same_tree(
        &dir.join("built"),
        &dir.join("reports"),
        "snakemake from scratch",
    );
    let summary = std::fs::read_to_string(dir.join("reports/summary.json")).unwrap();
    assert!(
        summary.contains("lab-run") && summary.contains("broken"),
        "{summary}"
    );
    // Again: nothing to do.
    let again = smk.run(&["--cores", "2"]);
    assert!(again.contains("Nothing to be done"), "{again}");
    // One experiment edited (a comment: its analysis key changes, not its video's):
    // only its jobs and the report run, and the result is the build's.
    let mut yaml = std::fs::read_to_string(dir.join("one.yaml")).unwrap();
    yaml.push_str("# edited\n");
    std::fs::write(dir.join("one.yaml"), yaml).unwrap();
    let edited = smk.run(&["--cores", "2"]);
    // (A failed experiment's jobs run again too: its stages are not done for rollfric,
    // only recorded for Snakemake.)
    let edited_jobs: Vec<String> = jobs(&edited)
        .into_iter()
        .filter(|j| !j.ends_with("lab-run") && !j.ends_with("broken"))
        .collect();
    assert_eq!(
        edited_jobs,
        ["all", "analyze one", "detect one", "report", "synth one"],
        "{edited}"
    );
    build();
    same_tree(&dir.join("built"), &dir.join("reports"), "after an edit");

    // kill -9 of the whole run at a random moment of a fresh run, then a rerun.
    for p in ["cache", "reports"] {
        std::fs::remove_dir_all(dir.join(p)).unwrap();
    }
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .subsec_nanos();
    let wait = Duration::from_millis(800 + u64::from(nanos % 3000));
    let mut child = {
        smk.command(&["--cores", "2"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap()
    };
    std::thread::sleep(wait);
    let finished = child.try_wait().unwrap().is_some();
    let pgid = child.id() as i32;
    // The whole group: snakemake and the rollfric jobs it started. (`--` first: procps'
    // kill may take a bare negative number for an option, and `-1` is every process.)
    assert!(pgid > 1, "{pgid}");
    let _ = Command::new("kill")
        .args(["-s", "KILL", "--", &format!("-{pgid}")])
        .status();
    let _ = child.wait();
    println!(
        "killed the run after {} ms{}",
        wait.as_millis(),
        if finished {
            " (it had already finished)"
        } else {
            ""
        }
    );
    let _ = smk.command(&["--unlock"]).output();
    smk.run(&["--cores", "2", "--rerun-incomplete"]);
    same_tree(
        &dir.join("built"),
        &dir.join("reports"),
        "after kill -9 and a rerun",
    );

    // The cluster-generic executor, each job submitted to a script that runs it here.
    for p in ["cache", "reports", ".snakemake"] {
        std::fs::remove_dir_all(dir.join(p)).unwrap();
    }
    std::fs::write(
        dir.join("submit.sh"),
        "#!/bin/bash\n# Run the job here, in the background; its id is the process id.\n\
         bash \"$@\" >> submit.log 2>&1 &\necho $!\n",
    )
    .unwrap();
    let cluster = smk.run(&[
        "--executor",
        "cluster-generic",
        "--cluster-generic-submit-cmd",
        "bash submit.sh",
        "--jobs",
        "2",
    ]);
    assert!(cluster.contains("steps (100%) done"), "{cluster}");
    same_tree(&dir.join("built"), &dir.join("reports"), "cluster-generic");

    // Slurm: a dry run of the generated profile, with nothing cached.
    std::fs::remove_dir_all(dir.join("cache")).unwrap();
    let dry = smk.run(&["--dry-run", "--profile", "profiles/slurm"]);
    let listed = jobs(&dry);
    assert_eq!(listed, want, "{dry}");
    // One job per stage per experiment: the twins' three stages, the lab run's detect
    // and analyze, the broken file's analyze.
    for (rule, jobs, mem, runtime) in [
        ("synth", 2, 1000, 30),
        ("detect", 3, 1000, 30),
        ("analyze", 4, 500, 5),
    ] {
        let n = dry
            .split("rule ")
            .filter(|b| b.starts_with(&format!("{rule}:")))
            .filter(|b| {
                b.contains(&format!("mem_mb={mem},")) && b.contains(&format!("runtime={runtime}"))
            })
            .count();
        assert_eq!(
            n, jobs,
            "{rule}: {jobs} jobs with mem_mb={mem}, runtime={runtime}:\n{dry}"
        );
    }
}
