//! rollfric: rolling-friction coefficients from videos of a conical pendulum.
//!
//! The stages, one module each, dependencies pointing down this list's data flow:
//! [`config`] (experiment files) and [`physics`] (the paper's model); [`video`]
//! (decoding) and [`detect`] (the wire angle in every frame), [`series`] (angle CSVs),
//! [`signal`] (turning points, equilibrium) and [`fit`] (over [`numerics`]) (`s_r` and its uncertainty),
//! with [`verdict`] for the checks; [`simulate`] and [`synth`] for the digital twin;
//! [`plane`] and [`lens`] map image angles to the plate's; [`pipeline`] takes one experiment through them; [`report`] renders pages as bytes;
//! [`picture`] encodes PNGs; [`usage`] reads this process's processor time and memory;
//! [`build`] runs the pipeline for a manifest with a content-hash cache ([`hash`],
//! [`sources`]) and writes the reports; [`cli`] is the command line.

pub mod build;
pub mod cli;
pub mod clobber;
pub mod config;
pub mod detect;
pub mod fit;
pub mod fsutil;
pub mod hash;
pub mod lens;
pub mod numerics;
pub mod physics;
pub mod picture;
pub mod pipeline;
pub mod plane;
pub mod report;
pub mod rng;
pub mod series;
pub mod signal;
pub mod simulate;
pub mod sources;
pub mod stats;
pub mod synth;
pub mod uncertainty;
pub mod usage;
pub mod verdict;
pub mod video;

/// For the unit tests: whether a test may skip when a tool it needs is missing (not
/// under `make test` or CI); the integration tests' own copy, included by path.
#[cfg(test)]
#[path = "../tests/common/require.rs"]
mod require;
