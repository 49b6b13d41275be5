//! A sampled angle-versus-time series and its CSV form (`t_s,angle_rad`, as the paper's
//! detector writes it: time from each frame's timestamp, angle from the image x axis).

use crate::fsutil;
use anyhow::{bail, Context, Result};
use std::path::Path;

/// Angle of the wire sampled in time. Times strictly increase; every value is finite.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AngleSeries {
    /// Sample times, s.
    pub t: Vec<f64>,
    /// Angles, rad.
    pub angle: Vec<f64>,
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

    /// Read a CSV with (at least) the columns `t_s` and `angle_rad`; other columns are
    /// ignored, except that rows whose `status` column says `missing` are skipped.
    pub fn read_csv(path: &Path) -> Result<Self> {
        let text = fsutil::read_to_string(path)?;
        Self::parse_csv(&text).with_context(|| format!("{}", path.display()))
    }

    /// Parse CSV text; errors name the line and the column.
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
                    headers.iter().collect::<Vec<_>>().join(",")
                )
            })
        };
        let (ct, ca) = (col("t_s")?, col("angle_rad")?);
        let cs = headers.iter().position(|h| h == "status");
        let mut s = AngleSeries::default();
        for (i, rec) in rdr.records().enumerate() {
            let line = i + 2;
            let rec = rec.with_context(|| format!("line {line}: malformed CSV row"))?;
            if cs.and_then(|c| rec.get(c)) == Some("missing") {
                continue;
            }
            let num = |c: usize, name: &str| -> Result<f64> {
                let raw = rec.get(c).unwrap_or("");
                let v: f64 = raw
                    .parse()
                    .with_context(|| format!("line {line}: `{name}` = `{raw}` is not a number"))?;
                if !v.is_finite() {
                    bail!("line {line}: `{name}` = {raw} is not a finite number");
                }
                Ok(v)
            };
            let (t, a) = (num(ct, "t_s")?, num(ca, "angle_rad")?);
            if let Some(&prev) = s.t.last() {
                if t <= prev {
                    bail!("line {line}: `t_s` = {t} does not increase (previous {prev})");
                }
            }
            s.t.push(t);
            s.angle.push(a);
        }
        if s.is_empty() {
            bail!("no data rows after the header");
        }
        Ok(s)
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
            "frame,t_s,angle_rad,status\n0,0.0,1.5,ok\n1,0.1,1.6,missing\n2,0.2,1.7,ok\n",
        )
        .unwrap();
        assert_eq!(s.t, vec![0.0, 0.2]);
        assert_eq!(s.angle, vec![1.5, 1.7]);
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
        assert!(e("t,angle\n0,1\n").contains("no `t_s` column"));
        assert!(e("t_s,angle_rad\n0,1\n0.1,NaN\n").contains("line 3: `angle_rad` = NaN"));
        assert!(e("t_s,angle_rad\n0,1\n0,2\n").contains("line 3: `t_s` = 0 does not increase"));
        assert!(e("t_s,angle_rad\n0,x\n").contains("line 2: `angle_rad` = `x` is not a number"));
    }
}
