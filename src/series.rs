//! A sampled angle-versus-time series and its CSV form (`t_s,angle_rad`, as the paper's
//! detector writes it: time from each frame's timestamp, angle from the image x axis).
//!
//! [`AngleTable::parse_csv`] is the one reader of angle CSVs: the detector's output
//! (`t_s,angle_rad,status,quality`) and a lab's measured series (`t_s,angle_rad`) alike.
//! It refuses what no series can be: times that do not strictly increase, angles that
//! are not finite numbers, a status it does not know; each error names the line.

use crate::config::quoted;
use crate::fsutil;
use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Angle of the wire sampled in time. Times strictly increase; every value is finite.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AngleSeries {
    /// Sample times, s.
    pub t: Vec<f64>,
    /// Angles, rad.
    pub angle: Vec<f64>,
}

/// Per-frame status, as the CSV writes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Measured and accepted.
    Ok,
    /// Measured, refused by the gate or flagged, and replaced by the prediction.
    Corrected,
    /// Set by an operator's mark in the experiment file.
    Manual,
    /// No angle.
    Missing,
}

impl Status {
    pub fn as_str(&self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Corrected => "corrected",
            Status::Manual => "manual",
            Status::Missing => "missing",
        }
    }

    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "ok" => Status::Ok,
            "corrected" => Status::Corrected,
            "manual" => Status::Manual,
            "missing" => Status::Missing,
            _ => return None,
        })
    }
}

/// The first time from which a series' times are taken for clock times, s (eleven
/// days: no recording of a pendulum starts that long after its clock's zero).
pub const CLOCK_TIME_S: f64 = 1e6;

/// One row of an angle CSV.
#[derive(Clone, Debug, PartialEq)]
pub struct AngleRow {
    pub t_s: f64,
    /// `None` when the frame is `missing`.
    pub angle_rad: Option<f64>,
    pub status: Status,
}

/// Every row of an angle CSV, missing frames included (the figures show them).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AngleTable {
    pub rows: Vec<AngleRow>,
}

impl AngleTable {
    /// Read an angle CSV; errors name the file and the line.
    pub fn read_csv(path: &Path) -> Result<Self> {
        let text = fsutil::read_text_limited(path, fsutil::MAX_CSV_BYTES)?;
        Self::parse_csv(&text).with_context(|| format!("{}", path.display()))
    }

    /// Parse CSV text with (at least) the columns `t_s` and `angle_rad`, and optionally
    /// `status` (`ok`, `corrected`, `manual` or `missing`; `ok` when absent). Other
    /// columns are ignored. A `missing` row may leave its angle empty; every other row
    /// needs a finite angle, and times strictly increase over all rows.
    pub fn parse_csv(text: &str) -> Result<Self> {
        if text.trim().is_empty() {
            bail!("the file is empty (expected a header with `t_s` and `angle_rad`)");
        }
        let mut rdr = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        let headers = rdr.headers().context("cannot read the CSV header")?.clone();
        let col = |name: &str| {
            headers.iter().position(|h| h == name).with_context(|| {
                format!(
                    "no `{name}` column (header is `{}`)",
                    quoted(&headers.iter().collect::<Vec<_>>().join(","), 120)
                )
            })
        };
        let (ct, ca) = (col("t_s")?, col("angle_rad")?);
        let cs = headers.iter().position(|h| h == "status");
        let mut rows: Vec<AngleRow> = Vec::new();
        for (i, rec) in rdr.records().enumerate() {
            let line = i + 2;
            let rec = rec.with_context(|| format!("line {line}: malformed CSV row"))?;
            let status = match cs.and_then(|c| rec.get(c)) {
                None => Status::Ok,
                Some(raw) => Status::parse(raw).with_context(|| {
                    format!(
                        "line {line}: `status` = `{}` is not one of ok, corrected, manual, missing",
                        quoted(raw, 60)
                    )
                })?,
            };
            let num = |c: usize, name: &str| -> Result<f64> {
                let raw = rec.get(c).unwrap_or("");
                let v: f64 = raw.parse().with_context(|| {
                    format!(
                        "line {line}: `{name}` = `{}` is not a number",
                        quoted(raw, 60)
                    )
                })?;
                if !v.is_finite() {
                    bail!(
                        "line {line}: `{name}` = {} is not a finite number",
                        quoted(raw, 60)
                    );
                }
                Ok(v)
            };
            let t = num(ct, "t_s")?;
            let angle_rad = match status {
                Status::Missing => None,
                _ => Some(num(ca, "angle_rad")?),
            };
            if let Some(prev) = rows.last() {
                if t <= prev.t_s {
                    bail!(
                        "line {line}: `t_s` = {t} does not increase (previous {})",
                        prev.t_s
                    );
                }
            }
            rows.push(AngleRow {
                t_s: t,
                angle_rad,
                status,
            });
        }
        let table = Self { rows };
        if table.series().is_empty() {
            bail!("no data rows after the header");
        }
        Ok(table)
    }

    /// The usable angles (every row but `missing`).
    pub fn series(&self) -> AngleSeries {
        let mut s = AngleSeries::default();
        for r in &self.rows {
            if let Some(a) = r.angle_rad {
                s.t.push(r.t_s);
                s.angle.push(a);
            }
        }
        s
    }

    /// Rows with this status.
    pub fn count(&self, st: Status) -> usize {
        self.rows.iter().filter(|r| r.status == st).count()
    }
}

impl AngleSeries {
    pub fn new(t: Vec<f64>, angle: Vec<f64>) -> Self {
        assert_eq!(t.len(), angle.len(), "one angle per time");
        Self { t, angle }
    }

    pub fn len(&self) -> usize {
        self.t.len()
    }

    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Read an angle CSV (see [`AngleTable::parse_csv`]); `missing` rows are skipped.
    pub fn read_csv(path: &Path) -> Result<Self> {
        Ok(AngleTable::read_csv(path)?.series())
    }

    /// Parse CSV text (see [`AngleTable::parse_csv`]); `missing` rows are skipped.
    pub fn parse_csv(text: &str) -> Result<Self> {
        Ok(AngleTable::parse_csv(text)?.series())
    }

    /// The series with its times counted from its first frame when they are clock
    /// times (a first time of [`CLOCK_TIME_S`] or more: seconds since 1970, say); other
    /// series are returned as they are. A fit of clock times would lose their digits
    /// (and its turning points their order) to the offset.
    pub fn from_clock_start(mut self) -> Self {
        if let Some(&t0) = self.t.first() {
            if t0 >= CLOCK_TIME_S {
                for t in &mut self.t {
                    *t -= t0;
                }
            }
        }
        self
    }

    /// CSV text with the header `t_s,angle_rad`.
    pub fn to_csv(&self) -> String {
        let mut out = String::with_capacity(32 * self.len() + 16);
        out.push_str("t_s,angle_rad\n");
        for (t, a) in self.t.iter().zip(&self.angle) {
            out.push_str(&format!("{t:.6},{a:.9}\n"));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_extra_columns_and_skips_missing_frames() {
        let s = AngleSeries::parse_csv(
            "frame,t_s,angle_rad,status\n0,0.0,1.5,ok\n1,0.1,,missing\n2,0.2,1.7,corrected\n",
        )
        .unwrap();
        assert_eq!(s.t, vec![0.0, 0.2]);
        assert_eq!(s.angle, vec![1.5, 1.7]);
        let t = AngleTable::parse_csv("t_s,angle_rad,status\n0,1,ok\n0.1,,missing\n").unwrap();
        assert_eq!(t.rows.len(), 2);
        assert_eq!(t.count(Status::Missing), 1);
        assert_eq!(t.rows[1].angle_rad, None);
    }

    #[test]
    fn round_trips_through_csv() {
        let s = AngleSeries::new(vec![0.0, 0.016667], vec![1.234567891, -0.25]);
        assert_eq!(AngleSeries::parse_csv(&s.to_csv()).unwrap(), s);
    }

    #[test]
    fn errors_name_the_line_and_the_problem() {
        let e = |text: &str| format!("{:#}", AngleSeries::parse_csv(text).unwrap_err());
        assert!(e("").contains("empty"));
        assert!(e("t_s,angle_rad\n").contains("no data rows"));
        assert!(e("t_s,angle_rad,status\n0,,missing\n").contains("no data rows"));
        assert!(e("t,angle\n0,1\n").contains("no `t_s` column"));
        assert!(e("t_s,angle_rad\n0,1\n0.1,NaN\n").contains("line 3: `angle_rad` = NaN"));
        assert!(e("t_s,angle_rad\n0,1\n0,2\n").contains("line 3: `t_s` = 0 does not increase"));
        assert!(e("t_s,angle_rad\n0,x\n").contains("line 2: `angle_rad` = `x` is not a number"));
        assert!(e("t_s,angle_rad,status\n0,1,ok\n0.1,,ok\n").contains("line 3: `angle_rad` = ``"));
        assert!(e("t_s,angle_rad,status\n0,1,fine\n").contains("line 2: `status` = `fine`"));
        assert!(
            e("t_s,angle_rad,status\n0,1,ok\n0.1,,missing\n0.05,1,ok\n")
                .contains("line 4: `t_s` = 0.05 does not increase"),
            "missing rows count for the order too"
        );
    }
}
