//! `summary.json` (every result, check and input hash of a build) and `rollfric check`.

use super::{fmt_pct, fmt_sci};
use crate::config::CHECKS;
use crate::fsutil;
use crate::pipeline::ExperimentResult;
use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;

/// An experiment's outcome in a build.
#[derive(Clone, Debug)]
pub enum Outcome {
    Built(Box<ExperimentResult>),
    Failed {
        name: String,
        file: String,
        error: String,
    },
}

/// Whether an experiment was built.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum EntryStatus {
    Ok,
    Failed,
}

/// One experiment in `summary.json`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Entry {
    pub name: String,
    pub file: String,
    pub status: EntryStatus,
    pub error: Option<String>,
    pub result: Option<ExperimentResult>,
}

impl Entry {
    pub fn new(o: Outcome) -> Self {
        match o {
            Outcome::Built(r) => Entry {
                name: r.name.clone(),
                file: r.inputs.experiment_file.clone(),
                status: EntryStatus::Ok,
                error: None,
                result: Some(*r),
            },
            Outcome::Failed { name, file, error } => Entry {
                name,
                file,
                status: EntryStatus::Failed,
                error: Some(error),
                result: None,
            },
        }
    }

    pub fn failed(&self) -> bool {
        self.result.is_none()
    }

    /// Built, compared with an expected value, and every check within tolerance.
    pub fn passed(&self) -> bool {
        self.result.as_ref().is_some_and(ExperimentResult::passed)
    }
}

/// `reports/summary.json`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Summary {
    pub title: String,
    pub tool: String,
    pub manifest_sha256: String,
    pub experiments: Vec<Entry>,
    /// Repeat runs: the experiments that name the same material.
    #[serde(default)]
    pub groups: Vec<crate::uncertainty::Group>,
    /// `beta` from the runs of one pair at several normal forces (`pair`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub series: Vec<crate::fit::BetaSeries>,
}

impl Summary {
    /// Read a build's summary and check its invariants ([`Summary::validate`]); errors
    /// name the file.
    pub fn read(path: &Path) -> Result<Self> {
        let text = fsutil::read_to_string(path)?;
        let raw: serde_json::Value = serde_json::from_str(&text)
            .with_context(|| format!("{}: not a rollfric summary", path.display()))?;
        let s: Summary = serde_json::from_value(raw.clone())
            .with_context(|| format!("{}: not a rollfric summary", path.display()))?;
        if s.experiments.is_empty() {
            bail!("{}: the summary lists no experiment", path.display());
        }
        s.validate(&raw).map_err(|e| {
            anyhow::anyhow!(
                "{}: {e}: the summary is not as a build writes it (edited or damaged); \
                 build it again",
                path.display()
            )
        })?;
        Ok(s)
    }

    /// What a build's summary always holds, checked before `check` trusts it: a
    /// failed entry has an error and no result, a built one a result and no error; each
    /// result says its verdict, `suspect` exactly when it has warnings of known checks;
    /// its comparisons are exactly those its reference and synthetic truth call for, at
    /// its tolerances and with its own fitted values; a tolerance wider than its
    /// default carries its reason. `raw` is the JSON as read (a missing `verdict` would
    /// otherwise read as `ok`).
    pub fn validate(&self, raw: &serde_json::Value) -> Result<()> {
        use crate::verdict::{Against, Quantity, Status};
        for (i, e) in self.experiments.iter().enumerate() {
            let at = format!("experiments[{i}] (`{}`)", excerpt(&e.name));
            match (e.status, &e.result, &e.error) {
                (EntryStatus::Ok, Some(_), None) | (EntryStatus::Failed, None, Some(_)) => {}
                (s, r, err) => bail!(
                    "{at}: status `{}` with {} and {}",
                    if s == EntryStatus::Ok { "ok" } else { "failed" },
                    if r.is_some() { "a result" } else { "no result" },
                    if err.is_some() {
                        "an error"
                    } else {
                        "no error"
                    }
                ),
            }
            let Some(r) = &e.result else { continue };
            if r.name != e.name {
                bail!("{at}: its result is named `{}`", excerpt(&r.name));
            }
            if raw["experiments"][i]["result"].get("verdict").is_none() {
                bail!("{at}: its result has no `verdict`");
            }
            let v = &r.verdict;
            if (v.verdict == Status::Suspect) == v.warnings.is_empty() {
                bail!(
                    "{at}: verdict `{}` with {} warning(s)",
                    v.verdict.as_str(),
                    v.warnings.len()
                );
            }
            if let Some(w) = v
                .warnings
                .iter()
                .find(|w| !CHECKS.contains(&w.check.as_str()))
            {
                bail!(
                    "{at}: a warning of no known check (`{}`)",
                    excerpt(&w.check)
                );
            }
            let tol = &r.tolerances;
            if let Some((key, _, _)) = tol.widened().first() {
                if tol.reason.trim().is_empty() {
                    bail!("{at}: `tolerances.{key}` is wider than its default, with no reason");
                }
            }
            // The comparisons the result calls for: (quantity, against, value, expected,
            // tolerance).
            let f = &r.results;
            let mut wanted = Vec::new();
            if let Some(rf) = &r.reference {
                let src = if rf.source.is_empty() {
                    "reference"
                } else {
                    &rf.source
                };
                for (q, value, expected) in [
                    (Quantity::SR, f.s_r_m, rf.s_r_m),
                    (Quantity::MuR, f.mu_r, rf.mu_r),
                    (Quantity::A, f.a_rad_s, rf.a_rad_s),
                ] {
                    if let Some(x) = expected {
                        let against = Against::Reference(src.to_string());
                        wanted.push((q, against, value, x, tol.reference_rel));
                    }
                }
            }
            if let Some(x) = r.truth_s_r_m {
                let against = Against::SyntheticTruth;
                wanted.push((Quantity::SR, against, f.s_r_m, x, tol.truth_rel));
            }
            let got: Vec<_> = r
                .checks
                .iter()
                .map(|c| {
                    let (q, a) = (c.quantity, c.against.clone());
                    (q, a, c.value, c.expected, c.tolerance_rel)
                })
                .collect();
            if got.len() != wanted.len() {
                bail!(
                    "{at}: {} comparison(s) where its reference and synthetic truth call for {}",
                    got.len(),
                    wanted.len()
                );
            }
            if let Some((g, w)) = got.iter().zip(&wanted).find(|(g, w)| g != w) {
                bail!(
                    "{at}: its comparison of {} against {} is not the result's own (value {}, \
                     expected {}, tolerance {}; the result's: {}, {}, {})",
                    g.0.as_str(),
                    g.1.as_str(),
                    g.2,
                    g.3,
                    g.4,
                    w.2,
                    w.3,
                    w.4
                );
            }
        }
        Ok(())
    }
}

/// At most 60 characters of a name read from a summary.
fn excerpt(s: &str) -> String {
    crate::config::quoted(s, 60)
}

/// `rollfric check`: the reproduced values of a summary against their expected values
/// and tolerances (recomputed from the numbers), and each result's consistency verdict.
/// Returns the table and whether all pass: no failed experiment, no missed tolerance and
/// no `suspect` verdict with a warning the experiment does not accept. A result with no
/// expected value is "measured", neither a pass nor a miss.
pub fn check(s: &Summary) -> (String, bool) {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "{:<22} {:<6} {:<16} {:>11} {:>11} {:>9} {:>7}  verdict",
        "experiment", "value", "against", "reproduced", "expected", "dev", "tol"
    );
    let mut ok = true;
    for e in &s.experiments {
        let Some(r) = &e.result else {
            ok = false;
            let _ = writeln!(
                o,
                "{:<22} FAILED: {}",
                e.name,
                e.error.as_deref().unwrap_or("no result")
            );
            continue;
        };
        if r.checks.is_empty() {
            let _ = writeln!(
                o,
                "{:<22} measured: no reference or synthetic truth to compare with",
                e.name
            );
        }
        for c in &r.checks {
            let pass = c.verdict();
            ok &= pass;
            let _ = writeln!(
                o,
                "{:<22} {:<6} {:<16} {:>11} {:>11} {:>9} {:>6.1}%  {}",
                e.name,
                c.quantity.as_str(),
                c.against.as_str(),
                fmt_sci(c.value, 4),
                fmt_sci(c.expected, 4),
                fmt_pct((c.value - c.expected) / c.expected),
                100.0 * c.tolerance_rel,
                if pass { "pass" } else { "MISS" }
            );
        }
        let v = &r.verdict;
        ok &= !v.blocks();
        let _ = writeln!(o, "{:<22} verdict {}", e.name, v.label());
        for w in &v.warnings {
            let _ = writeln!(
                o,
                "{:<22}   {}{}: {} (value {}, limit {})",
                e.name,
                w.check,
                if w.accepted.is_some() {
                    " [accepted]"
                } else {
                    ""
                },
                w.reason,
                fmt_sci(w.value, 3),
                fmt_sci(w.limit, 3)
            );
            if let Some(why) = &w.accepted {
                let _ = writeln!(o, "{:<22}     accepted because: {why}", e.name);
            }
        }
    }
    let n = s.experiments.len();
    let results = || s.experiments.iter().filter_map(|e| e.result.as_ref());
    let good = s.experiments.iter().filter(|e| e.passed()).count();
    let compared = results().filter(|r| r.compared()).count();
    let suspect = results().filter(|r| r.verdict.blocks()).count();
    let failed = s.experiments.iter().filter(|e| e.failed()).count();
    let _ = writeln!(
        o,
        "{good}/{compared} compared experiments within their tolerances; {} measured only; \
         {suspect} suspect; {failed} failed; {n} in all",
        results().count() - compared
    );
    (o, ok)
}
