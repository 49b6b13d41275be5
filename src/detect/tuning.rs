//! The detector's tuning in one place: its named knobs, their units and the figures that chose them.
//!
//! Every named threshold, limit, window and count of the detector is declared here.
//! Not yet: some literals of the streaming pass's gate and prediction in `track.rs`
//! (the weak-frame quality share, the innovations' factor of 4, the re-anchoring's
//! windows, the running means' weights).
//! Each knob is written once, in the file of its stage (`tuning/*.rs`), through
//! [`knobs!`]: that yields the `pub(crate) const` the detector reads and an entry of
//! [`KNOBS`], the table `rollfric tuning` prints and docs/tuning.md lists. A constant
//! that is no choice (a unit, a size fixed by an algorithm, a rounding guard) stays
//! beside its code; `tests::no_knob_outside_tuning` keeps the others here.

/// One knob of the detector: a named constant, its value, and why it has that value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Knob {
    /// The constant's name in the code.
    pub name: &'static str,
    /// Its value (as `f64`; integers exact).
    pub value: f64,
    /// Its unit: "deg", "px", "frames", "s", "share", "grey levels", ...
    pub unit: &'static str,
    /// The stage of the detector that reads it.
    pub stage: &'static str,
    /// What it sets, in one line.
    pub what: &'static str,
    /// The figure that chose it (sweep, scene, before and after; the commit), or that
    /// none did.
    pub chosen_by: &'static str,
}

/// Declares a stage's knobs: each entry is
/// `NAME: type = value, "unit", what "...", chosen_by "...";`, with its doc comment
/// above. Yields `pub(crate) const NAME: type = value;` and the stage's table.
macro_rules! knobs {
    (table $table:ident, stage $stage:literal;
     $( $(#[$doc:meta])* $name:ident : $ty:ty = $value:expr, $unit:literal,
        what $what:literal, chosen_by $chosen:literal; )*) => {
        $(
            $(#[$doc])*
            #[doc = ""]
            #[doc = concat!("Knob (", $unit, "): ", $what, ". Chosen by: ", $chosen, ".")]
            pub(crate) const $name: $ty = $value;
        )*
        /// This stage's knobs, in the order they are declared.
        #[allow(clippy::unnecessary_cast)]
        pub(super) const $table: &[Knob] = &[$(Knob {
            name: stringify!($name),
            value: $name as f64,
            unit: $unit,
            stage: $stage,
            what: $what,
            chosen_by: $chosen,
        }),*];
    };
}

mod geometry;
mod judge;
mod light;
mod look;
mod measure;
mod pass;
mod review;
mod steady;

pub(crate) use geometry::*;
pub(crate) use judge::*;
pub(crate) use light::*;
pub(crate) use look::*;
pub(crate) use measure::*;
pub(crate) use pass::*;
pub(crate) use review::*;
pub(crate) use steady::*;

/// The stages' tables, in the detector's order.
const STAGES: &[&[Knob]] = &[
    look::LOOK_KNOBS,
    light::LIGHT_KNOBS,
    steady::STEADY_KNOBS,
    geometry::GEOMETRY_KNOBS,
    pass::PASS_KNOBS,
    measure::MEASURE_KNOBS,
    judge::JUDGE_KNOBS,
    review::REVIEW_KNOBS,
];

const COUNT: usize = {
    let (mut n, mut s) = (0, 0);
    while s < STAGES.len() {
        n += STAGES[s].len();
        s += 1;
    }
    n
};

const fn joined() -> [Knob; COUNT] {
    let blank = Knob {
        name: "",
        value: 0.0,
        unit: "",
        stage: "",
        what: "",
        chosen_by: "",
    };
    let mut out = [blank; COUNT];
    let (mut k, mut s) = (0, 0);
    while s < STAGES.len() {
        let mut i = 0;
        while i < STAGES[s].len() {
            out[k] = STAGES[s][i];
            k += 1;
            i += 1;
        }
        s += 1;
    }
    out
}

/// Every knob of the detector, stage by stage.
pub const KNOBS: &[Knob] = &joined();

/// The table as aligned text (name, value, unit, stage, chosen by): `rollfric tuning`.
pub fn text() -> String {
    let rows: Vec<[String; 5]> = KNOBS
        .iter()
        .map(|k| {
            [
                k.name.to_string(),
                value(k.value),
                k.unit.to_string(),
                k.stage.to_string(),
                k.chosen_by.to_string(),
            ]
        })
        .collect();
    let head = ["name", "value", "unit", "stage", "chosen by"].map(String::from);
    let mut width = [0; 4];
    for r in std::iter::once(&head).chain(&rows) {
        for (w, c) in width.iter_mut().zip(r) {
            *w = (*w).max(c.chars().count());
        }
    }
    let mut out = String::new();
    for r in std::iter::once(&head).chain(&rows) {
        for (w, c) in width.iter().zip(r) {
            out += &format!("{c:<w$}  ");
        }
        out += &r[4];
        out += "\n";
    }
    out
}

/// The table as Markdown, one table per stage: docs/tuning.md.
pub fn markdown() -> String {
    let mut out = String::from(
        "# The detector's tuning\n\n\
         Every named threshold, limit, window and count the detector uses, with its unit and \
         the figure that chose it (a commit of the history, and the sweep, scene or clip it \
         measured, or the comment that stood beside it). Generated from the table in \
         `src/detect/tuning/`: `rollfric tuning --markdown > docs/tuning.md`. Constants that \
         are no choice (sizes fixed by the top-hat's 7x7 element, scan blocks, a rounding \
         guard, sqrt(70)) stay beside their code. Not in the table yet: some literals of the \
         streaming pass's gate and prediction in `track.rs` (the weak-frame quality share, \
         the innovations' factor of 4, the re-anchoring's windows, the running means' \
         weights).\n",
    );
    let mut stage = "";
    for k in KNOBS {
        if k.stage != stage {
            stage = k.stage;
            let first = stage[..1].to_uppercase() + &stage[1..];
            out += &format!(
                "\n## {first}\n\n| Knob | Value | Unit | What | Chosen by |\n|---|---|---|---|---|\n"
            );
        }
        out += &format!(
            "| `{}` | {} | {} | {} | {} |\n",
            k.name,
            value(k.value),
            k.unit,
            cell(k.what),
            cell(k.chosen_by)
        );
    }
    out
}

/// A value as the code writes it (shortest form that reads back the same).
fn value(v: f64) -> String {
    format!("{v}")
}

fn cell(s: &str) -> String {
    s.replace('|', "\\|")
}

#[cfg(test)]
mod tests;
