//! Comparisons of a reproduced value with an expected one, and their verdicts.
//!
//! A check's verdict is always recomputed from its numbers ([`Check::verdict`]), so a
//! summary edited by hand cannot claim a pass its numbers do not support.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// The value a result is compared with.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Against {
    /// A published value (the experiment's `reference.source`, `reference` if unnamed).
    Reference(String),
    /// The `s_r` the digital twin was rendered with.
    SyntheticTruth,
}

impl Against {
    const TRUTH: &'static str = "synthetic truth";

    pub fn as_str(&self) -> &str {
        match self {
            Against::Reference(s) => s,
            Against::SyntheticTruth => Self::TRUTH,
        }
    }
}

impl Serialize for Against {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

impl<'de> Deserialize<'de> for Against {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        Ok(if s == Self::TRUTH {
            Against::SyntheticTruth
        } else {
            Against::Reference(s)
        })
    }
}

/// The quantity a check compares.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Quantity {
    /// The rolling-friction coefficient, m.
    #[serde(rename = "s_r")]
    SR,
    /// The dimensionless coefficient `s_r N_0^(beta-1) / r`.
    #[serde(rename = "mu_r")]
    MuR,
    /// The envelope slope, rad/s.
    #[serde(rename = "a")]
    A,
}

impl Quantity {
    pub fn as_str(&self) -> &'static str {
        match self {
            Quantity::SR => "s_r",
            Quantity::MuR => "mu_r",
            Quantity::A => "a",
        }
    }
}

/// One comparison of a reproduced value with an expected one.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Check {
    pub quantity: Quantity,
    pub against: Against,
    pub value: f64,
    pub expected: f64,
    pub tolerance_rel: f64,
    pub deviation_rel: f64,
    pub pass: bool,
}

impl Check {
    pub fn new(quantity: Quantity, against: Against, value: f64, expected: f64, tol: f64) -> Self {
        let dev = (value - expected) / expected;
        Self {
            quantity,
            against,
            value,
            expected,
            tolerance_rel: tol,
            deviation_rel: dev,
            pass: dev.abs() <= tol,
        }
    }

    /// Recompute the verdict from the numbers (a summary's `pass` is not trusted).
    pub fn verdict(&self) -> bool {
        let dev = (self.value - self.expected) / self.expected;
        dev.is_finite() && dev.abs() <= self.tolerance_rel
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_verdict_comes_from_the_numbers() {
        let mut c = Check::new(Quantity::SR, Against::SyntheticTruth, 1.01, 1.0, 0.02);
        assert!(c.pass && c.verdict());
        c.value = 1.05;
        assert!(c.pass && !c.verdict(), "a stale pass flag is not trusted");
        let nan = Check::new(Quantity::A, Against::SyntheticTruth, f64::NAN, 1.0, 0.02);
        assert!(!nan.verdict());
    }

    #[test]
    fn serialises_as_the_plain_names() {
        let c = Check::new(
            Quantity::MuR,
            Against::Reference("Table 1".into()),
            1.0,
            1.0,
            0.1,
        );
        let j = serde_json::to_string(&c).unwrap();
        assert!(
            j.starts_with(r#"{"quantity":"mu_r","against":"Table 1","#),
            "{j}"
        );
        let back: Check = serde_json::from_str(&j).unwrap();
        assert_eq!(back.against, Against::Reference("Table 1".into()));
        let t: Against = serde_json::from_str(r#""synthetic truth""#).unwrap();
        assert_eq!(t, Against::SyntheticTruth);
    }
}
