//! rollfric: rolling-friction coefficients from videos of a conical pendulum.
//!
//! The stages, one module each: [`config`] (experiment files) → [`physics`] (the
//! paper's model) → [`signal`] (turning points, equilibrium) → [`fit`] (`s_r` and its
//! uncertainty). [`simulate`] produces what a camera would record from the model,
//! [`synth`] renders it as video, [`detect`] measures the wire in a video, [`build`] runs
//! the stages for a manifest with a content-hash cache and [`report`] writes the pages.

pub mod build;
pub mod commands;
pub mod config;
pub mod detect;
pub mod fit;
pub mod fsutil;
pub mod numerics;
pub mod physics;
pub mod report;
pub mod rng;
pub mod series;
pub mod signal;
pub mod simulate;
pub mod stats;
pub mod synth;
pub mod video;
