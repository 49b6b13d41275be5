//! One experiment through the cached stages. Each stage computes its key, returns its
//! cached outputs when the key is fresh, and otherwise calls the pipeline and records
//! what it produced.

use super::progress::Progress;
use super::writer::{relative, Writer};
use crate::config::Experiment;
use crate::detect::summary::{DetectionSummary, ReviewPicture};
use crate::detect::{self, FrameProgress};
use crate::fsutil;
use crate::hash::{self, Key};
use crate::pipeline::{self, Angles, ExperimentResult, Inputs, Source};
use crate::report;
use crate::series::AngleTable;
use crate::signal;
use crate::sources;
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// One cached stage of an experiment (`rollfric stage NAME`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Render the digital twin's video (nothing for a lab video or an angle CSV).
    Synth,
    /// Measure the angles in the video (nothing for an angle CSV).
    Detect,
    /// Fit, check, draw and write the experiment's pages.
    Analyze,
}

impl Stage {
    /// The stage's key file under `cache/<name>/` (written last by the stage).
    pub fn key_name(self) -> &'static str {
        match self {
            Stage::Synth => pipeline::TWIN_KEY,
            Stage::Detect => "detect.key",
            Stage::Analyze => "analysis.key",
        }
    }

    pub fn as_str(self) -> &'static str {
        match self {
            Stage::Synth => "synth",
            Stage::Detect => "detect",
            Stage::Analyze => "analyze",
        }
    }
}

/// Which stages may compute; any other must be current in the cache, or the experiment
/// stops, naming the stage command that makes it current.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Runs {
    /// Every stage (`rollfric build`).
    All,
    /// This one, after which the experiment stops (`rollfric stage`).
    Only(Stage),
    /// None: every result is read from the cache (`rollfric report`).
    Cached,
}

impl Runs {
    fn may(self, s: Stage) -> bool {
        match self {
            Runs::All => true,
            Runs::Only(o) => o == s,
            Runs::Cached => false,
        }
    }

    /// Whether the experiment stops after stage `s`.
    fn stops_after(self, s: Stage) -> bool {
        self == Runs::Only(s)
    }
}

/// The file whose content is stage `s`'s key for the experiment named `name` (written
/// last by the stage).
pub(super) fn key_file(cache: &Path, name: &str, s: Stage) -> PathBuf {
    cache.join(name).join(s.key_name())
}

/// Where `rollfric stage --record-failure` leaves an experiment's failure for `report`.
pub(super) fn failure_file(cache: &Path, name: &str) -> PathBuf {
    cache.join(name).join("failed.txt")
}

/// What every stage of one experiment needs.
pub(super) struct Ctx<'a> {
    /// The manifest's folder (report paths are relative to it).
    pub root: &'a Path,
    pub cache: &'a Path,
    pub progress: &'a Arc<Progress>,
    pub label: String,
    pub writer: &'a Writer,
    pub runs: Runs,
}

/// The error of a stage that may not run here and is not current in the cache.
#[derive(Debug)]
pub struct NotCurrent(String);

impl std::fmt::Display for NotCurrent {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for NotCurrent {}

impl Ctx<'_> {
    /// Stop: stage `s` is not current and may not run here.
    fn not_current(&self, exp: &Experiment, s: Stage) -> anyhow::Error {
        NotCurrent(format!(
            "{}: the {} stage is not current in {}: run `rollfric stage {} {}` first",
            self.label,
            s.as_str(),
            self.cache.display(),
            s.as_str(),
            exp.name
        ))
        .into()
    }
}

/// The video an experiment's angles are measured in.
struct Video {
    path: PathBuf,
    /// SHA-256 of a lab video; the render key of the twin.
    id: String,
    /// How the reports name it.
    label: String,
}

/// Where a stage left the experiment's angles.
struct CachedAngles {
    source: Source,
    csv: PathBuf,
    /// Identifies the angles for the analysis key (the CSV's hash or the detect key).
    id: String,
    detection: Option<DetectionSummary>,
    fig11: Option<PathBuf>,
    /// The review pictures' index (`review.json`; the PNGs in `review/` beside it).
    review: Option<PathBuf>,
}

/// The stages that ran (for the log line).
#[derive(Default)]
struct Ran(Vec<&'static str>);

impl Ran {
    fn how(&self) -> String {
        if self.0.is_empty() {
            "cached".to_string()
        } else {
            format!("{} ran", self.0.join(", "))
        }
    }
}

/// One experiment (loaded from `file`, whose bytes are `yaml`) through the stages
/// `ctx.runs` allows, reading the others from the cache. Returns its result (none when
/// it stops after one stage) and how it was obtained.
pub(super) fn run_experiment(
    file: &Path,
    exp: &Experiment,
    yaml: &[u8],
    ctx: &Ctx,
) -> Result<(Option<ExperimentResult>, String)> {
    let mut ran = Ran::default();
    let angles = match pipeline::Source::of(exp, None)? {
        Source::Csv(csv) => csv_stage(exp, csv)?,
        source => {
            let video = video_stage(exp, &source, ctx, &mut ran)?;
            if ctx.runs.stops_after(Stage::Synth) {
                return Ok((None, ran.how()));
            }
            detect_stage(exp, source, video, ctx, &mut ran)?
        }
    };
    if ctx.runs.stops_after(Stage::Synth) || ctx.runs.stops_after(Stage::Detect) {
        return Ok((None, ran.how()));
    }
    let result = analysis_stage(exp, file, yaml, angles, ctx, &mut ran)?;
    Ok((Some(result), ran.how()))
}

/// A measured angle CSV: nothing to compute, its hash identifies it.
fn csv_stage(exp: &Experiment, csv: PathBuf) -> Result<CachedAngles> {
    let id = hash::sha256_file(&csv).with_context(|| {
        format!(
            "{}: `angles` = {}",
            exp.path.display(),
            exp.file.angles.as_deref().unwrap_or_default()
        )
    })?;
    Ok(CachedAngles {
        source: Source::Csv(csv.clone()),
        csv,
        id,
        detection: None,
        fig11: None,
        review: None,
    })
}

/// How the reports name a twin's video.
fn twin_label(exp: &Experiment) -> String {
    format!("{}/twin.avi (rendered by the build)", exp.name)
}

/// The video to detect: the lab's recording (hashed), or the twin (rendered when stale,
/// if the synth stage may run).
fn video_stage(exp: &Experiment, source: &Source, ctx: &Ctx, ran: &mut Ran) -> Result<Video> {
    if let Source::LabVideo(path) = source {
        ctx.progress.stage(&ctx.label, "video", "hashing");
        return Ok(Video {
            id: hash::sha256_file(path)?,
            label: relative(ctx.root, path),
            path: path.clone(),
        });
    }
    if !ctx.runs.may(Stage::Synth) {
        let (path, id) = pipeline::twin_cached(exp, ctx.cache)?
            .ok_or_else(|| ctx.not_current(exp, Stage::Synth))?;
        return Ok(Video {
            path,
            id,
            label: twin_label(exp),
        });
    }
    let (label, progress) = (ctx.label.clone(), ctx.progress.clone());
    let (path, id, rendered) = pipeline::twin(exp, ctx.cache, &mut |done, total| {
        if done == 0 {
            progress.stage(&label, "synth", "rendering the digital twin's video");
        }
        progress.frames(&label, done, Some(total));
    })?;
    if rendered {
        ran.0.push("synth");
    }
    Ok(Video {
        path,
        id,
        label: twin_label(exp),
    })
}

/// The detect stage's files of one experiment under `cache/<name>/`.
struct DetectFiles {
    csv: PathBuf,
    summary: PathBuf,
    fig11: PathBuf,
    /// The review pictures: `review.json` lists the PNGs in `review/`.
    review: PathBuf,
    review_dir: PathBuf,
    key: PathBuf,
}

impl DetectFiles {
    fn of(cache: &Path, exp: &Experiment) -> Self {
        let dir = cache.join(&exp.name);
        Self {
            csv: dir.join("angles.csv"),
            summary: dir.join("detect.json"),
            fig11: dir.join("fig11.png"),
            review: dir.join("review.json"),
            review_dir: dir.join("review"),
            key: dir.join(Stage::Detect.key_name()),
        }
    }

    /// The stage's key: the detector's source, the video's content id, the
    /// experiment's `video:` settings, and its geometry and period tolerance (the
    /// detection's `length` check judges the period seen against them).
    fn key(exp: &Experiment, video_id: &str) -> String {
        Key::new("detect")
            .part("source", sources::hash("detect").as_bytes())
            .part("video", video_id.as_bytes())
            .json("settings", &pipeline::detect_settings(exp))
            .json("geometry", &exp.file.geometry)
            .json("period_rel", &exp.file.tolerances.period_rel)
            .hex()
    }

    /// The cached detection, when it was made under `key` and every file is there
    /// (each review picture too).
    fn fresh(&self, key: &str) -> Option<DetectionSummary> {
        let files: [&Path; 4] = [&self.csv, &self.summary, &self.fig11, &self.review];
        if !hash::fresh(&self.key, key, &files) {
            return None;
        }
        let pictures = read_review(&self.review).ok()?;
        if !pictures
            .iter()
            .all(|p| self.review_dir.join(&p.file).is_file())
        {
            return None;
        }
        std::fs::read(&self.summary)
            .ok()
            .and_then(|b| serde_json::from_slice::<DetectionSummary>(&b).ok())
    }

    /// Record a detection made under `key` (each file written whole; the key last).
    /// The review pictures are the kept flagged frames and the frame after a release
    /// from rest, found in `angles` as the fit finds it.
    fn record(
        &self,
        key: &str,
        d: &detect::Detection,
        angles: &AngleTable,
        summary: &DetectionSummary,
        video: &Path,
    ) -> Result<()> {
        let png =
            detect::figure11_png(d).with_context(|| format!("{}: Figure 11", video.display()))?;
        fsutil::write_atomic(&self.fig11, &png)?;
        let release = signal::find_release(&angles.series()).map(|(r, _)| r.t_s);
        let pictures = d.review.pictures(release);
        if self.review_dir.exists() {
            std::fs::remove_dir_all(&self.review_dir)
                .with_context(|| format!("{}: cannot clear", self.review_dir.display()))?;
        }
        let mut index = Vec::with_capacity(pictures.len());
        for f in pictures {
            let p = ReviewPicture::of(f);
            let png = f
                .png()
                .with_context(|| format!("{}: review pictures", video.display()))?;
            fsutil::write_atomic(&self.review_dir.join(&p.file), &png)?;
            index.push(p);
        }
        fsutil::write_atomic(&self.review, &serde_json::to_vec_pretty(&index)?)?;
        fsutil::write_atomic(&self.csv, d.to_csv().as_bytes())?;
        fsutil::write_atomic(&self.summary, &serde_json::to_vec_pretty(summary)?)?;
        hash::record(&self.key, key)
    }
}

/// Detect the angles of the video (cached): `angles.csv`, `detect.json`, `fig11.png`.
fn detect_stage(
    exp: &Experiment,
    source: Source,
    video: Video,
    ctx: &Ctx,
    ran: &mut Ran,
) -> Result<CachedAngles> {
    let key = DetectFiles::key(exp, &video.id);
    let files = DetectFiles::of(ctx.cache, exp);
    let cached = |detection, files: DetectFiles| CachedAngles {
        source: source.clone(),
        csv: files.csv,
        id: key.clone(),
        detection: Some(detection),
        fig11: Some(files.fig11),
        review: Some(files.review),
    };
    if let Some(s) = files.fresh(&key) {
        return Ok(cached(s, files));
    }
    if !ctx.runs.may(Stage::Detect) {
        return Err(ctx.not_current(exp, Stage::Detect));
    }
    ctx.progress.stage(
        &ctx.label,
        "detect",
        "measuring the wire angle in every frame",
    );
    let mut opts = pipeline::detect_options(exp);
    let (label, progress) = (ctx.label.clone(), ctx.progress.clone());
    opts.progress = Some(FrameProgress(Arc::new(move |d, t| {
        progress.frames(&label, d, t)
    })));
    let (angles, d) = pipeline::detect(
        &video.path,
        &opts,
        video.label,
        video.id.clone(),
        source.clone(),
    )?;
    let summary = angles.detection.clone().expect("a detection");
    files.record(&key, &d, &angles.table, &summary, &video.path)?;
    ran.0.push("detect");
    Ok(cached(summary, files))
}

/// The review pictures listed in `index` (`review.json`).
fn read_review(index: &Path) -> Result<Vec<ReviewPicture>> {
    let bytes =
        std::fs::read(index).with_context(|| format!("{}: cannot read", index.display()))?;
    serde_json::from_slice(&bytes)
        .with_context(|| format!("{}: not a review index", index.display()))
}

/// The review pictures of a cached detection and their PNGs (from `review/` beside
/// `index`).
fn review_pictures(index: &Path) -> Result<Vec<(ReviewPicture, Vec<u8>)>> {
    let dir = index.with_file_name("review");
    read_review(index)?
        .into_iter()
        .map(|p| {
            let file = dir.join(&p.file);
            let png =
                std::fs::read(&file).with_context(|| format!("{}: cannot read", file.display()))?;
            Ok((p, png))
        })
        .collect()
}

/// The angles a build measured in `exp`'s video and left in `cache`, when the video
/// (`video_id`: a lab video's SHA-256, the twin's render key) and the experiment's
/// `video:` settings are still those they were measured with: what `rollfric fit` reads
/// instead of decoding the video again. `None` when stale or missing.
pub fn cached_angles(
    exp: &Experiment,
    source: Source,
    video_id: &str,
    cache: &Path,
) -> Option<Angles> {
    let files = DetectFiles::of(cache, exp);
    let summary = files.fresh(&DetectFiles::key(exp, video_id))?;
    let table = AngleTable::read_csv(&files.csv).ok()?;
    Some(Angles {
        source,
        table,
        detection: Some(summary),
    })
}

/// Fit, check, draw and write the experiment's pages (cached with `result.json`).
fn analysis_stage(
    exp: &Experiment,
    file: &Path,
    yaml: &[u8],
    cached: CachedAngles,
    ctx: &Ctx,
    ran: &mut Ran,
) -> Result<ExperimentResult> {
    let key = Key::new("analysis")
        .part("source", sources::hash("pipeline").as_bytes())
        .part("source", sources::hash("report").as_bytes())
        .part("yaml", yaml)
        .part("angles", cached.id.as_bytes())
        .hex();
    let dir = ctx.cache.join(&exp.name);
    let result_file = dir.join("result.json");
    let key_file = dir.join(Stage::Analyze.key_name());
    if hash::fresh(&key_file, &key, &[&result_file]) {
        let r: Option<ExperimentResult> = std::fs::read(&result_file)
            .ok()
            .and_then(|b| serde_json::from_slice(&b).ok());
        if let Some(r) = r.filter(|r| ctx.writer.intact(r)) {
            return Ok(r);
        }
    }
    if !ctx.runs.may(Stage::Analyze) {
        return Err(ctx.not_current(exp, Stage::Analyze));
    }
    ctx.progress
        .stage(&ctx.label, "analysis", "fit, torsion, figures, pages");
    let angles = Angles {
        source: cached.source,
        table: AngleTable::read_csv(&cached.csv)?,
        detection: cached.detection,
    };
    let analysis = pipeline::analyze(exp, &angles, pipeline::Overrides::default())?;
    let inputs = Inputs {
        experiment_file: relative(ctx.root, file),
        experiment_sha256: hash::sha256(yaml),
        angles_sha256: hash::sha256_file(&cached.csv)?,
    };
    let mut result = ExperimentResult::new(exp, &angles, &analysis, inputs);
    let fig11 = match &cached.fig11 {
        Some(p) => Some(std::fs::read(p).with_context(|| format!("{}: cannot read", p.display()))?),
        None => None,
    };
    let review = cached.review.as_deref().map(review_pictures).transpose()?;
    let files = report::experiment_pages(
        exp,
        &analysis,
        &result,
        &angles.table.rows,
        fig11.as_deref(),
        review.as_deref(),
    )?;
    result.pages = ctx.writer.write(&files)?;
    fsutil::write_atomic(&result_file, &serde_json::to_vec_pretty(&result)?)?;
    hash::record(&key_file, &key)?;
    ran.0.push("analysis");
    Ok(result)
}
