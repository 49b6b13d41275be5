//! The index: Table 1 reproduced, the torsion table, Figures 2 and 19, provenance,
//! and `summary.json`.

use super::summary::{Entry, Outcome, Summary};
use super::{figures, fmt_pct, fmt_sci, kv, render_pair, Kv, OutputFile};
use crate::config::Manifest;
use crate::uncertainty::{self, Group, Run};
use crate::verdict::{Against, Quantity};
use anyhow::Result;
use serde::Serialize;
use std::fmt::Write as _;

#[derive(Serialize)]
struct IndexView {
    title: String,
    tool: &'static str,
    manifest_sha256: String,
    rows: Vec<TableRow>,
    groups: Vec<GroupView>,
    series: Vec<super::series::SeriesView>,
    failures: Vec<Kv>,
    torsion: Vec<TorsionRow>,
    provenance: Vec<Kv>,
    synthetic: Vec<String>,
    measured: Vec<String>,
    fig19: bool,
    fig2: bool,
    fig2_note: String,
    passed: usize,
    compared: usize,
    measured_only: usize,
    suspect: usize,
    /// Suspect, but every warning accepted with a written reason.
    accepted: usize,
    total: usize,
}

#[derive(Serialize)]
struct TableRow {
    name: String,
    material: String,
    synthetic: bool,
    s_r: String,
    s_r_paper: String,
    s_r_dev: String,
    mu_r: String,
    mu_r_paper: String,
    mu_r_dev: String,
    a: String,
    a_paper: String,
    a_dev: String,
    truth_dev: String,
    pass: bool,
    /// `pass`, `FAIL` or `measured` (nothing to compare with).
    standing: &'static str,
    verdict: String,
    suspect: bool,
}

#[derive(Serialize)]
struct GroupView {
    material: String,
    runs: String,
    n: usize,
    mean: String,
    sd: String,
    u_mean: String,
    u_geometry: String,
    expanded: String,
    birge: String,
    consistent: bool,
}

fn group_view(g: &Group) -> GroupView {
    let rel = |v: f64| format!("{v:.2e} m ({:.2} %)", 100.0 * v / g.mean_m.abs());
    GroupView {
        material: g.material.clone(),
        runs: g
            .runs
            .iter()
            .map(|r| format!("{} (d = {:.3} m: {:.4e})", r.name, r.d_m, r.s_r_m))
            .collect::<Vec<_>>()
            .join(", "),
        n: g.runs.len(),
        mean: format!(
            "{:.4e} ± {:.2e} m (k = {:.2}, ν = {})",
            g.mean_m,
            g.expanded_m,
            g.k,
            super::figures::dof(g.nu_eff)
        ),
        sd: rel(g.sd_m),
        u_mean: rel(g.u_mean_m),
        u_geometry: rel(g.u_geometry_m),
        expanded: rel(g.expanded_m),
        birge: format!(
            "{:.2} (limit {:.2}; chi² {:.2} on {} dof)",
            g.birge_ratio,
            g.birge_limit,
            g.chi2,
            g.runs.len() - 1
        ),
        consistent: g.consistent,
    }
}

/// The repeat runs: the built experiments that name the same material, two or more, in
/// the manifest's order.
fn groups(entries: &[Entry]) -> Vec<Group> {
    let mut out: Vec<(String, Vec<Run>)> = Vec::new();
    // A pair's runs at several normal forces are a series, not repeats.
    for r in entries
        .iter()
        .filter_map(|e| e.result.as_ref())
        .filter(|r| r.pair.is_none())
    {
        let run = Run {
            name: r.name.clone(),
            d_m: r.geometry.d_m,
            s_r_m: r.results.s_r_m,
            u_angles_m: r.results.s_r_u_m,
            u_c_m: r.budget.u_c_m,
        };
        match out.iter_mut().find(|(m, _)| *m == r.material) {
            Some((_, runs)) => runs.push(run),
            None => out.push((r.material.clone(), vec![run])),
        }
    }
    out.into_iter()
        .filter(|(_, runs)| runs.len() >= 2)
        .map(|(m, runs)| uncertainty::group(&m, runs))
        .collect()
}

#[derive(Serialize)]
struct TorsionRow {
    material: String,
    k_t: String,
    m_t: String,
    m_r: String,
    ratio: String,
}

/// The index pages, their figures and `summary.json`, from the experiments' outcomes.
pub fn index_pages(
    manifest: &Manifest,
    outcomes: Vec<Outcome>,
) -> Result<(Summary, Vec<OutputFile>)> {
    let manifest_sha256 = crate::hash::sha256(
        serde_json::to_string(manifest)
            .unwrap_or_default()
            .as_bytes(),
    );
    let entries: Vec<Entry> = outcomes.into_iter().map(Entry::new).collect();
    // A material with repeat runs names each run's experiment beside it in Table 1.
    let runs_of = |material: &str| {
        entries
            .iter()
            .filter_map(|e| e.result.as_ref())
            .filter(|r| r.material == material)
            .count()
    };
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    let mut torsion = Vec::new();
    let mut provenance = Vec::new();
    let (mut synthetic, mut measured) = (Vec::new(), Vec::new());
    let mut f19 = Vec::new();
    for e in &entries {
        let Some(r) = &e.result else {
            failures.push(kv(&e.name, e.error.clone().unwrap_or_default()));
            provenance.push(kv(&e.file, "failed: no output".into()));
            continue;
        };
        let find = |q: Quantity| {
            r.checks
                .iter()
                .find(|c| c.quantity == q && c.against != Against::SyntheticTruth)
        };
        let paper = |q| find(q).map_or("-".into(), |c| fmt_sci(c.expected, 3));
        let dev = |q| find(q).map_or("-".into(), |c| fmt_pct(c.deviation_rel));
        let truth = r
            .checks
            .iter()
            .find(|c| c.against == Against::SyntheticTruth)
            .map_or("-".into(), |c| fmt_pct(c.deviation_rel));
        let f = &r.results;
        rows.push(TableRow {
            name: r.name.clone(),
            material: if runs_of(&r.material) > 1 {
                format!("{} ({})", r.material, r.name)
            } else {
                r.material.clone()
            },
            synthetic: r.synthetic,
            s_r: format!("{} ± {:.1e}", fmt_sci(f.s_r_m, 4), r.budget.expanded_m),
            s_r_paper: paper(Quantity::SR),
            s_r_dev: dev(Quantity::SR),
            mu_r: fmt_sci(f.mu_r, 3),
            mu_r_paper: paper(Quantity::MuR),
            mu_r_dev: dev(Quantity::MuR),
            a: fmt_sci(f.a_rad_s, 3),
            a_paper: paper(Quantity::A),
            a_dev: dev(Quantity::A),
            truth_dev: truth,
            pass: r.passed(),
            standing: if !r.compared() {
                "measured"
            } else if r.passed() {
                "pass"
            } else {
                "FAIL"
            },
            verdict: r.verdict.label(),
            suspect: !r.verdict.warnings.is_empty(),
        });
        if let Some(c) = r.torsion {
            torsion.push(TorsionRow {
                material: r.material.clone(),
                k_t: fmt_sci(c.k_t_n_m_per_rad, 3),
                m_t: fmt_sci(c.m_t_max_n_m, 3),
                m_r: fmt_sci(c.m_r_model_n_m, 3),
                ratio: format!("{:.2} %", c.ratio_pct),
            });
        }
        let mut p = format!("experiment {}", r.inputs.experiment_sha256);
        let _ = write!(p, "; angles {}", r.inputs.angles_sha256);
        if let Some(d) = &r.detection {
            let _ = write!(
                p,
                "; video {} {}",
                if d.synthetic { "render key" } else { "SHA-256" },
                d.video_id
            );
        }
        provenance.push(kv(&r.inputs.experiment_file, p));
        if r.synthetic {
            synthetic.push(r.material.clone());
        } else {
            measured.push(r.material.clone());
        }
        f19.push(figures::Fig19Point {
            label: r.material.clone(),
            a_rad_s: f.a_rad_s,
            mu_r: f.mu_r,
            mu_r_expanded: f.mu_r * r.budget.expanded_m / f.s_r_m.abs(),
            model_ratio: r.model_mu_r_per_a_s,
            d_m: r.geometry.d_m,
        });
    }
    let groups = groups(&entries);
    let series = super::series::series_of(&entries);
    let mut files: Vec<OutputFile> = Vec::new();
    for (i, s) in series.iter().enumerate() {
        files.push(OutputFile::new(
            super::series::figure_file(i),
            super::series::figure(s)?,
        ));
    }
    if !f19.is_empty() {
        files.push(OutputFile::new("fig19.svg", figures::figure19(&f19)?.svg));
    }
    // Figure 2 on the first built experiment's pendulum and fitted s_r.
    let mut fig2_note = String::new();
    if let Some(r) = entries.iter().find_map(|e| e.result.as_ref()) {
        let g = &r.geometry;
        let p = crate::physics::Pendulum::new(
            g.r_m,
            g.m_kg,
            g.j_z_kg_m2,
            g.d_m,
            g.alpha_deg.to_radians(),
            g.g_m_s2,
        )?;
        for fg in figures::figure2(&p, r.results.s_r_m, 10f64.to_radians())? {
            files.push(OutputFile::new(fg.file, fg.svg));
        }
        fig2_note = format!(
            "{} pendulum (d = {:.4} m), released at 10 deg; s_r = {:.3e} m for beta = 1, and the s_r giving the same torque at rest for beta = 3/2.",
            r.material, g.d_m, r.results.s_r_m
        );
    }
    let summary = Summary {
        title: manifest.title.clone(),
        tool: crate::hash::TOOL.into(),
        manifest_sha256: manifest_sha256.clone(),
        experiments: entries,
        groups,
        series,
    };
    let results = || summary.experiments.iter().filter_map(|e| e.result.as_ref());
    let view = IndexView {
        title: manifest.title.clone(),
        tool: crate::hash::TOOL,
        manifest_sha256,
        passed: summary.experiments.iter().filter(|e| e.passed()).count(),
        compared: results().filter(|r| r.compared()).count(),
        measured_only: results().filter(|r| !r.compared()).count(),
        suspect: results().filter(|r| !r.verdict.warnings.is_empty()).count(),
        accepted: results()
            .filter(|r| !r.verdict.warnings.is_empty() && !r.verdict.blocks())
            .count(),
        total: summary.experiments.len(),
        rows,
        groups: summary.groups.iter().map(group_view).collect(),
        series: summary
            .series
            .iter()
            .enumerate()
            .map(|(i, s)| super::series::series_view(i, s))
            .collect(),
        failures,
        torsion,
        provenance,
        synthetic,
        measured,
        fig19: !f19.is_empty(),
        fig2: !fig2_note.is_empty(),
        fig2_note,
    };
    files.extend(render_pair("index", "index", &view)?);
    files.push(OutputFile::new(
        "summary.json",
        serde_json::to_string_pretty(&summary)? + "\n",
    ));
    Ok((summary, files))
}
