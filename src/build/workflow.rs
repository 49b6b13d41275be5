//! `rollfric workflow snakemake`: the manifest's stages as a Snakefile, for a cluster.
//!
//! One rule per stage (`synth`, `detect`, `analyze`) with the experiment's name as
//! wildcard, and `report`. Each rule runs `rollfric stage` (or `rollfric report`), whose
//! own content-hash key decides what is stale; the rule's output is that key file, which
//! the stage writes when it computes and touches when its key was already current, so
//! Snakemake reruns a job exactly when one of its inputs (the experiment file, a lab
//! video or angle CSV, the previous stage's key) is newer, and the job then does
//! nothing unless rollfric's key changed. Snakemake only schedules: the cache is the
//! source of truth, and `rollfric build` on the same folders gives the same reports.

use super::{Stage, REPORT_KEY};
use crate::config::{Experiment, Manifest};
use anyhow::Result;
use std::fmt::Write as _;
use std::path::Path;

/// The first line of every Snakefile written here (a file without it is not replaced).
pub const SNAKEFILE_MARK: &str = "# Written by `rollfric workflow snakemake`";

/// A local profile: `snakemake --profile profiles/local`.
pub const LOCAL_PROFILE: &str = "\
# rollfric on this machine: snakemake --profile profiles/local
cores: 2
rerun-incomplete: true
printshellcmds: true
";

/// A Slurm profile (snakemake-executor-plugin-slurm): `snakemake --profile profiles/slurm`.
pub const SLURM_PROFILE: &str = "\
# rollfric on a Slurm cluster: snakemake --profile profiles/slurm
# Needs snakemake-executor-plugin-slurm. Fill in your partition and account.
executor: slurm
# Jobs in the queue at once.
jobs: 100
rerun-incomplete: true
default-resources:
  # slurm_partition: main
  # slurm_account: my-lab
  mem_mb: 1000
  runtime: 30
# The analyze and report jobs take seconds: submit 20 of them as one cluster job.
group-components:
  short: 20
";

/// The Snakefile for `manifest`'s experiments, with rollfric's folders `cache` and
/// `out` (paths as Snakemake, run where this is called from, should see them).
pub fn snakefile(manifest: &Path, cache: &Path, out: &Path) -> Result<String> {
    let (_, files) = Manifest::load(manifest)?;
    let mut experiments = String::new();
    let mut twins = Vec::new();
    let mut videos = String::new();
    let mut csvs = String::new();
    let mut seen = std::collections::BTreeSet::new();
    for f in &files {
        let q = |p: &Path| py_str(&p.to_string_lossy());
        // An experiment that does not load (or repeats a name) is still a job: its
        // analyze stage fails and records why, and the report marks it as a build does.
        let stem = f.file_stem().map_or_else(
            || f.display().to_string(),
            |s| s.to_string_lossy().into_owned(),
        );
        let exp = match Experiment::load(f) {
            Ok(e) if seen.insert(e.name.clone()) => e,
            _ => {
                if seen.insert(stem.clone()) {
                    let _ = writeln!(experiments, "    {}: {},", py_str(&stem), q(f));
                    let _ = writeln!(csvs, "    {}: None,", py_str(&stem));
                }
                continue;
            }
        };
        let _ = writeln!(experiments, "    {}: {},", py_str(&exp.name), q(f));
        let name = py_str(&exp.name);
        // Where the angles come from, as `Source::of` decides, whether or not the file
        // is there yet (a missing one fails its job, not the workflow).
        match (
            &exp.file.angles,
            exp.file.video.as_ref().and_then(|v| v.path.as_ref()),
        ) {
            (Some(a), _) => {
                let _ = writeln!(csvs, "    {name}: {},", q(&exp.resolve(a)));
            }
            (None, Some(v)) => {
                let _ = writeln!(videos, "    {name}: {},", q(&exp.resolve(v)));
            }
            (None, None) => twins.push(name),
        }
    }
    let s = |p: &Path| py_str(&p.to_string_lossy());
    Ok(format!(
        r#"{SNAKEFILE_MARK} from {manifest_name}: write it again
# when the manifest's list of experiments changes.
#
#   snakemake --cores 2                       # here (or --profile profiles/local)
#   snakemake --profile profiles/slurm        # on a Slurm cluster
#
# Each job runs one cached stage of one experiment (`rollfric stage`); rollfric's own
# keys decide what is stale, and a job whose key is current does nothing but touch its
# key file (the rule's output). `rollfric build` on the same folders gives the same
# reports. Set config["rollfric"] to the binary when it is not on the PATH.

import os

ROLLFRIC = config.get("rollfric", "rollfric")
MANIFEST = {manifest}
CACHE = {cache}
OUT = {out}
# A failing experiment fails only its own jobs: the stage records the failure, which
# the report marks as a build does (and the next run tries the stage again).
ARGS = f"--manifest {{MANIFEST}} --cache {{CACHE}} --out {{OUT}} -q"
STAGE_ARGS = f"{{ARGS}} --record-failure"

# Experiment name -> its file.
EXPERIMENTS = {{
{experiments}}}
# Digital twins: rendered (synth), then measured (detect).
TWINS = [{twins}]
# Lab recordings: measured (detect).
VIDEOS = {{
{videos}}}
# Measured angle CSVs (None: an experiment file that does not load): analysed only.
CSVS = {{
{csvs}}}

wildcard_constraints:
    name="[A-Za-z0-9_-]+",


def present(*paths):
    return [p for p in paths if p is not None and os.path.exists(p)]


def detect_input(w):
    if w.name in VIDEOS:
        return [EXPERIMENTS[w.name]] + present(VIDEOS[w.name])
    return [EXPERIMENTS[w.name], f"{{CACHE}}/{{w.name}}/{twin_key}"]


def analyze_input(w):
    if w.name in CSVS:
        return [EXPERIMENTS[w.name]] + present(CSVS[w.name])
    return [EXPERIMENTS[w.name], f"{{CACHE}}/{{w.name}}/{detect_key}"]


localrules:
    all,


rule all:
    input:
        f"{{CACHE}}/{report_key}",


rule synth:
    input:
        lambda w: EXPERIMENTS[w.name],
    output:
        f"{{CACHE}}/{{{{name}}}}/{twin_key}",
    threads: 1
    resources:
        mem_mb=1000,
        runtime=30,
    shell:
        "{{ROLLFRIC}} stage synth {{wildcards.name}} {{STAGE_ARGS}}"


rule detect:
    input:
        detect_input,
    output:
        f"{{CACHE}}/{{{{name}}}}/{detect_key}",
    threads: 1
    resources:
        mem_mb=1000,
        runtime=30,
    shell:
        "{{ROLLFRIC}} stage detect {{wildcards.name}} {{STAGE_ARGS}}"


rule analyze:
    input:
        analyze_input,
    output:
        f"{{CACHE}}/{{{{name}}}}/{analysis_key}",
    threads: 1
    group: "short"
    resources:
        mem_mb=500,
        runtime=5,
    shell:
        "{{ROLLFRIC}} stage analyze {{wildcards.name}} {{STAGE_ARGS}}"


rule report:
    input:
        MANIFEST,
        expand(f"{{CACHE}}/{{{{name}}}}/{analysis_key}", name=EXPERIMENTS),
    output:
        f"{{CACHE}}/{report_key}",
    threads: 1
    group: "short"
    resources:
        mem_mb=500,
        runtime=5,
    shell:
        "{{ROLLFRIC}} report {{ARGS}}"
"#,
        manifest_name = manifest.display(),
        manifest = s(manifest),
        cache = s(cache),
        out = s(out),
        twins = twins.join(", "),
        report_key = REPORT_KEY,
        twin_key = Stage::Synth.key_name(),
        detect_key = Stage::Detect.key_name(),
        analysis_key = Stage::Analyze.key_name(),
    ))
}

/// `s` as a Python string literal (JSON's escapes are Python's for these characters).
fn py_str(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_else(|_| format!("{s:?}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_experiment_gets_the_stages_its_source_needs() {
        let d = tempfile::tempdir().unwrap();
        let geometry = "geometry:\n  incline: { angle_deg: 5 }\n  pendulum: { d_m: 0.2 }\n  \
                        ball: { radius_m: 0.0127, mass_kg: 0.067 }\n";
        let write = |name: &str, extra: &str| {
            std::fs::write(
                d.path().join(format!("{name}.yaml")),
                format!("name: {name}\n{geometry}{extra}"),
            )
            .unwrap();
        };
        write("twin", "synthetic: { s_r_m: 4e-6 }\n");
        write("lab", "video: { path: lab.mp4 }\n");
        write("csv", "angles: csv.csv\n");
        std::fs::write(d.path().join("lab.mp4"), b"not decoded here").unwrap();
        std::fs::write(d.path().join("csv.csv"), "t_s,angle_rad\n0,1\n").unwrap();
        let m = d.path().join("manifest.yaml");
        std::fs::write(
            &m,
            "title: t\nexperiments:\n  - twin.yaml\n  - lab.yaml\n  - csv.yaml\n",
        )
        .unwrap();
        let text = snakefile(&m, Path::new("cache"), Path::new("out")).unwrap();
        assert!(text.starts_with(SNAKEFILE_MARK), "{text}");
        let section = |start: &str| {
            let from = text
                .find(start)
                .unwrap_or_else(|| panic!("{start} in {text}"));
            text[from..]
                .lines()
                .take_while(|l| !l.is_empty() && *l != "}")
                .collect::<Vec<_>>()
                .join("\n")
        };
        assert!(
            section("TWINS = ").starts_with("TWINS = [\"twin\"]"),
            "{text}"
        );
        let videos = section("VIDEOS = {");
        assert!(
            videos.contains("\"lab\": ") && videos.contains("lab.mp4"),
            "{videos}"
        );
        assert!(
            !videos.contains("\"csv\"") && !videos.contains("\"twin\""),
            "{videos}"
        );
        let csvs = section("CSVS = {");
        assert!(
            csvs.contains("\"csv\": ") && csvs.contains("csv.csv"),
            "{csvs}"
        );
        assert!(text.contains("CACHE = \"cache\"") && text.contains("OUT = \"out\""));
        for rule in ["synth", "detect", "analyze", "report"] {
            assert!(text.contains(&format!("\nrule {rule}:\n")), "{rule}");
        }
    }
}
