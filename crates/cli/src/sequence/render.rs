//! The `render` command: plans which frames to render (skipping complete
//! ones), evaluates them in order with the preroll each needs, and writes
//! each output's files atomically or streams them to ffmpeg.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use serde_json::json;
use spreadlight_graph::{Memory, format};

use super::BadInput;
use super::evaluate::{Evaluator, Timing};
use super::exr_pixels::ExrPixels;
use super::fault::KillAt;
use super::files::{commit, is_complete, sweep_partials};
use super::frames::{FrameRange, Preroll, Span};
use super::names::{Target, VideoKind};
use super::outputs::{Declared, declared};
use super::pipeline::{Finished, Job, Pipeline};
use super::progress::{Progress, Status};
use super::stages::RunStages;
use super::video::Video;
use crate::session::{Session, parse_size};

#[derive(clap::Args)]
pub struct Args {
    /// The patch to render; it needs an `Output` node.
    pub patch: PathBuf,
    /// Where frames go: `out/shot_####.exr` (the `#`s pad the frame number; or `{frame}`), PNG or
    /// EXR (32-bit float) by extension; `out.png` for one frame; `out.mp4` or `out.mov` (ProRes) for
    /// a video through ffmpeg. `{name}` is the Output's Name; with several Outputs and no `{name}`,
    /// each sequence goes in a folder named for its Output.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Output size.
    #[arg(long, default_value = "640x360", value_parser = parse_size)]
    pub size: (u32, u32),
    /// The frames to render: FIRST-LAST (inclusive, e.g. 0-239) or one frame.
    #[arg(long, default_value = "0")]
    pub frames: Span,
    /// Render every STEP-th frame of the range (the clock moves STEP frames at a time).
    #[arg(long, default_value_t = 1)]
    pub step: u64,
    /// Frames per second of the clock.
    #[arg(long, default_value_t = 60.0)]
    pub fps: f64,
    /// Frames evaluated, not written, before the first frame rendered, so temporal effects and
    /// simulations are as in a run from frame 0: a number, or `all` (from frame 0). Default: the
    /// largest Preroll of the patch's Outputs; without one, what its nodes remember (all, from
    /// frame 0, when a node keeps state: particles, feedback, filters, TAA...). 0 skips it.
    #[arg(long)]
    pub preroll: Option<Preroll>,
    /// Sub-frame renders averaged per frame: each at its own instant across the shutter (motion
    /// blur) with its own sub-pixel camera offset (anti-aliasing).
    #[arg(long, default_value_t = 1)]
    pub samples: u32,
    /// How long the shutter is open with --samples, as a fraction of a frame (0.5: 180 degrees).
    #[arg(long, default_value_t = 0.5)]
    pub shutter: f64,
    /// Write only sub-frame K (0-based) of --samples, not averaged: one of the images a frame
    /// averages, at its own instant and sub-pixel offset (every sub-frame is still evaluated).
    #[arg(long, value_name = "K")]
    pub sub_frame: Option<u32>,
    /// Render frames of a sequence whose files are complete already (they are skipped
    /// otherwise; one image and a video are always rendered).
    #[arg(long)]
    pub overwrite: bool,
    /// Render nothing: list which frames are complete and which would be rendered.
    #[arg(long)]
    pub dry_run: bool,
    /// JSON lines on stdout (start, one per frame, errors, done) instead of the progress bar.
    #[arg(long)]
    pub json: bool,
    /// Only the `Output` node of this Name.
    #[arg(long = "output-name")]
    pub output_name: Option<String>,
    /// Run a patch even though an unknown node type (misspelled, or a shader
    /// or subpatch file that is missing) feeds its Output or a Probe: that
    /// node's work is left out. Without it such a patch is an error.
    #[arg(long)]
    pub allow_unknown: bool,
    /// Threads that read frames back, encode and write them while the GPU renders the next ones
    /// (default: one a core). Frames are written in order whatever the number.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Say where the cold start went (opening the GPU, loading the patch, composing shaders,
    /// making pipelines, the rest of the first frame). `--json` has it in `done` always.
    #[arg(long)]
    pub timings: bool,
    /// EXR pixels: `float` (32-bit, uncompressed) or `half` (16-bit, ZIP-compressed: lossless over
    /// the halves, about a quarter of the bytes).
    #[arg(long, value_enum, default_value_t)]
    pub exr: ExrPixels,
}

/// Exit codes: 0 every frame written or complete, 1 some frames failed (or
/// no GPU), 2 bad input (nothing rendered).
pub fn run(args: &Args) -> anyhow::Result<ExitCode> {
    match render(args) {
        Ok(false) => Ok(ExitCode::SUCCESS),
        Ok(true) => Ok(ExitCode::from(1)),
        Err(e) if e.downcast_ref::<BadInput>().is_some() => {
            eprintln!("error: {e:#}");
            if args.json {
                println!(
                    "{}",
                    json!({"event": "error", "frame": null, "message": format!("{e:#}"), "bad_input": true})
                );
            }
            Ok(ExitCode::from(2))
        }
        Err(e) => Err(e),
    }
}

fn bad(message: impl Into<String>) -> anyhow::Error {
    BadInput(message.into()).into()
}

/// What to render: the checked arguments and the patch's outputs.
struct Plan {
    range: FrameRange,
    target: Target,
    outputs: Vec<Declared>,
    preroll: Preroll,
    /// Why the preroll is from frame 0 when nothing asked for it: the nodes that keep state.
    stateful: Option<String>,
    timing: Timing,
}

impl Plan {
    fn new(args: &Args) -> anyhow::Result<Plan> {
        if !(args.fps.is_finite() && args.fps > 0.0) {
            return Err(bad("--fps must be a positive number"));
        }
        if !(0.0..=1.0).contains(&args.shutter) {
            return Err(bad("--shutter is a fraction of a frame, from 0 to 1"));
        }
        if args.samples == 0 {
            return Err(bad("--samples must be at least 1"));
        }
        if let Some(k) = args.sub_frame.filter(|&k| k >= args.samples) {
            return Err(bad(format!(
                "--sub-frame {k} is past the last of --samples {} (they count from 0)",
                args.samples
            )));
        }
        let range = FrameRange::new(args.frames, args.step).map_err(bad)?;
        let target = Target::parse(&args.output).map_err(bad)?;
        if matches!(target, Target::Image(_)) && range.len() > 1 {
            return Err(bad(format!(
                "`{}` names one image but --frames {range} is {} frames: add `####` or `{{frame}}` to the name",
                args.output.display(),
                range.len()
            )));
        }
        let patch = format::load(&args.patch).map_err(|e| bad(format!("{e:#}")))?;
        let mut outputs =
            declared(&patch).map_err(|e| bad(format!("{}: {e}", args.patch.display())))?;
        let all: Vec<String> = outputs.iter().map(|o| o.name.clone()).collect();
        if let Some(only) = &args.output_name {
            outputs.retain(|o| &o.name == only);
            if outputs.is_empty() {
                return Err(bad(format!(
                    "no Output node is named `{only}` (outputs: {})",
                    all.join(", ")
                )));
            }
        }
        if outputs.is_empty() {
            return Err(bad(format!(
                "{}: the patch has no `Output` node: nothing to render",
                args.patch.display()
            )));
        }
        let declared = outputs.iter().map(|o| o.preroll).max().unwrap_or(0);
        let (preroll, stateful) = match args.preroll {
            Some(preroll) => (preroll, None),
            None if declared > 0 => (Preroll::Frames(declared), None),
            // Nothing declared: what the nodes remember decides, so a chunk is what a run
            // from frame 0 gives (a simulation, a feedback or a filter started late is not).
            None => match crate::session::memory(&patch, &args.patch) {
                (Memory::None, _) => (Preroll::Frames(0), None),
                (Memory::Frames(n), _) => (Preroll::Frames(u64::from(n)), None),
                (Memory::Unbounded, types) => (Preroll::All, Some(types.join(", "))),
            },
        };
        let timing = Timing {
            fps: args.fps,
            step: args.step,
            samples: args.samples,
            shutter: args.shutter,
        };
        Ok(Plan {
            range,
            target,
            outputs,
            preroll,
            stateful,
            timing,
        })
    }

    /// Each output's file of `frame` (the video, for a video).
    fn files(&self, frame: u64) -> Vec<(String, PathBuf)> {
        let several = self.outputs.len() > 1;
        self.outputs
            .iter()
            .map(|o| {
                (
                    o.name.clone(),
                    self.target.template().path(&o.name, several, frame),
                )
            })
            .collect()
    }

    fn names(&self) -> Vec<String> {
        self.outputs.iter().map(|o| o.name.clone()).collect()
    }

    fn start_info(&self, args: &Args, todo: usize) -> serde_json::Value {
        json!({
            "patch": args.patch.display().to_string(),
            "first": self.range.first, "last": self.range.last, "step": self.range.step,
            "size": format!("{}x{}", args.size.0, args.size.1),
            "fps": args.fps, "samples": args.samples,
            "preroll": match self.preroll {
                Preroll::Frames(n) => json!(n),
                Preroll::All => json!("all"),
            },
            "outputs": self.names(), "to_render": todo,
        })
    }
}

fn shown(files: &[(String, PathBuf)]) -> Vec<(String, String)> {
    files
        .iter()
        .map(|(n, p)| (n.clone(), p.display().to_string()))
        .collect()
}

/// Returns whether some frames failed.
fn render(args: &Args) -> anyhow::Result<bool> {
    let plan = Plan::new(args)?;
    match plan.target {
        Target::Video(_, kind) => render_video(args, &plan, kind),
        Target::Frames(_) | Target::Image(_) => render_frames(args, &plan),
    }
}

/// Open the patch on a GPU; a patch that loads with errors is bad input.
fn open(args: &Args, plan: &Plan) -> anyhow::Result<Evaluator> {
    let session = Session::open(&args.patch, true, Some(args.size), args.allow_unknown)?;
    if session.load_errors {
        return Err(bad(format!(
            "{}: the patch has errors (above); fix them first (`spreadlight check`)",
            args.patch.display()
        )));
    }
    Ok(Evaluator::new(
        session,
        plan.timing,
        args.sub_frame,
        plan.names(),
        args.size,
        args.patch.clone(),
    ))
}

fn render_frames(args: &Args, plan: &Plan) -> anyhow::Result<bool> {
    let frames: Vec<u64> = plan.range.frames().collect();
    let targets: Vec<PathBuf> = frames
        .iter()
        .flat_map(|&f| plan.files(f).into_iter().map(|(_, p)| p))
        .collect();
    let kill = KillAt::from_env().map_err(bad)?;
    let swept = sweep_partials(&targets);
    // One image is always rendered anew: only a sequence resumes.
    let overwrite = args.overwrite || matches!(plan.target, Target::Image(_));
    let (todo, done): (Vec<u64>, Vec<u64>) = frames.iter().partition(|&&f| {
        overwrite
            || plan
                .files(f)
                .iter()
                .any(|(_, p)| !is_complete(p, args.size))
    });
    let progress = Progress::new(args.json, todo.len() as u64);
    progress.start(plan.start_info(args, todo.len()));
    if swept > 0 {
        progress.note(&format!(
            "removed {swept} partial file(s) left by killed runs"
        ));
    }
    for &f in &done {
        progress.frame(f, Status::Skipped, 0.0, &shown(&plan.files(f)));
    }
    if args.dry_run || todo.is_empty() {
        for &f in &todo {
            progress.frame(f, Status::Missing, 0.0, &shown(&plan.files(f)));
        }
        progress
            .finish(json!({"written": 0, "skipped": done.len(), "failed": [], "missing": todo}));
        return Ok(false);
    }
    let mut evaluator = open(args, plan)?;
    progress.note(&format!(
        "rendering {} frame(s) of {} at {}x{} on {}",
        todo.len(),
        args.patch.display(),
        args.size.0,
        args.size.1,
        evaluator.adapter()
    ));
    note_preroll(&progress, plan, &todo);
    let mut failed = Vec::new();
    let mut next: Option<u64> = None;
    let threads = args.threads.unwrap_or_else(default_threads).max(1);
    let mut pipeline = Pipeline::new(threads)?;
    let mut stages = RunStages::new(threads);
    // With --samples: the output images summed on the GPU, and those averaged on the CPU.
    let mut summed = (0u64, 0u64);
    for &frame in &todo {
        let prerolling = Instant::now();
        let prerolled = preroll(&mut evaluator, plan, &mut next, frame);
        stages.prerolled(prerolled, prerolling.elapsed());
        let started = Instant::now();
        let evaluated = evaluator.frame(frame);
        stages.evaluated(started.elapsed());
        match evaluated {
            Ok(captured) => {
                let (gpu, cpu) = captured.combined();
                summed = (summed.0 + gpu, summed.1 + cpu);
                let submitting = Instant::now();
                pipeline.submit(Job {
                    frame,
                    captured,
                    files: plan.files(frame).into_iter().map(|(_, p)| p).collect(),
                    started,
                    exr: args.exr,
                });
                stages.submitted(submitting.elapsed());
            }
            Err(errors) => pipeline.fail(frame, errors, started),
        }
        for finished in pipeline.finished(false) {
            place(finished, plan, &progress, kill, &mut failed, &mut stages);
        }
    }
    for finished in pipeline.finish() {
        place(finished, plan, &progress, kill, &mut failed, &mut stages);
    }
    let written = todo.len() - failed.len();
    let mut summary = json!({
        "written": written, "skipped": done.len(), "failed": failed, "stages": stages.json(),
    });
    if args.samples > 1 {
        summary["sub_frames"] = json!({"summed_on_gpu": summed.0, "averaged_on_cpu": summed.1});
    }
    cold_start(args, &evaluator, &progress, &mut summary);
    progress.finish(summary);
    evaluator.leave();
    Ok(!failed.is_empty())
}

/// The cold start into the `done` line, and for people with `--timings`.
fn cold_start(
    args: &Args,
    evaluator: &Evaluator,
    progress: &Progress,
    summary: &mut serde_json::Value,
) {
    if let Some(cold) = evaluator.cold_start() {
        if args.timings {
            progress.note(&cold.line());
        }
        summary["cold_start"] = cold.json();
    }
}

/// Writer threads default to one a core: encoding is most of a frame's CPU time.
fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(4, |n| n.get())
}

/// A frame's turn: its temporary files renamed into place (in frame order,
/// so the files on disk are always the run's first frames), and reported.
fn place(
    finished: Finished,
    plan: &Plan,
    progress: &Progress,
    kill: KillAt,
    failed: &mut Vec<u64>,
    stages: &mut RunStages,
) {
    let frame = finished.frame;
    let committing = Instant::now();
    let result = finished.result.and_then(|written| {
        let mut errors = Vec::new();
        for (partial, path) in written {
            if !errors.is_empty() {
                let _ = std::fs::remove_file(&partial);
                continue;
            }
            kill.after_write(frame);
            if let Err(e) = commit(&partial, &path) {
                errors.push(format!("cannot write {}: {e}", path.display()));
            }
        }
        if errors.is_empty() {
            Ok(())
        } else {
            Err(errors)
        }
    });
    stages.placed(result.is_ok(), &finished.stages, committing.elapsed());
    let seconds = finished.started.elapsed().as_secs_f64();
    let files = plan.files(frame);
    if let Err(errors) = result {
        for e in &errors {
            progress.error(
                Some(frame),
                &format!("frame {frame}: {}", e.trim_start_matches("error: ")),
            );
        }
        failed.push(frame);
        progress.frame(frame, Status::Failed, seconds, &shown(&files));
    } else {
        progress.frame(frame, Status::Written, seconds, &shown(&files));
    }
    kill.between_frames(frame);
}

/// Say why a render starts evaluating at frame 0 when nothing asked for it:
/// it costs those frames, and `--preroll` bounds or skips them.
fn note_preroll(progress: &Progress, plan: &Plan, todo: &[u64]) {
    let Some(types) = &plan.stateful else { return };
    let Some(&first) = todo.first() else { return };
    let start = plan.range.start_for(first, plan.preroll.frames());
    if start < first {
        progress.note(&format!(
            "prerolling frames {start} to {} before frame {first}: {types} keep state from frame to frame and no \
             Output declares a Preroll (`--preroll N` or a Preroll pin bounds it, `--preroll 0` skips it)",
            first - plan.range.step
        ));
    }
}

/// Evaluate, without writing, the frames `frame` needs before it: its
/// preroll, or the frames since the last one rendered when that is nearer
/// (the run stays continuous, as a full run would be). Returns how many.
fn preroll(evaluator: &mut Evaluator, plan: &Plan, next: &mut Option<u64>, frame: u64) -> u64 {
    let start = plan.range.start_for(frame, plan.preroll.frames());
    let from = match *next {
        Some(n) if n >= start && n <= frame => n,
        _ => start,
    };
    let mut f = from;
    let mut count = 0;
    while f < frame {
        // A preroll frame that fails is not this frame's failure: its own evaluation says.
        let _ = evaluator.frame(f);
        f += plan.range.step;
        count += 1;
    }
    *next = Some(frame + plan.range.step);
    count
}

fn render_video(args: &Args, plan: &Plan, kind: VideoKind) -> anyhow::Result<bool> {
    // A video is one file, made in one go: it is always rendered anew.
    let files = plan.files(plan.range.first);
    let frames: Vec<u64> = plan.range.frames().collect();
    let progress = Progress::new(args.json, frames.len() as u64);
    progress.start(plan.start_info(args, frames.len()));
    if args.dry_run {
        for &f in &frames {
            progress.frame(f, Status::Missing, 0.0, &shown(&files));
        }
        progress.finish(json!({"written": 0, "skipped": 0, "failed": []}));
        return Ok(false);
    }
    let rate = args.fps / plan.range.step as f64;
    let mut videos = Vec::new();
    for (_, path) in &files {
        match Video::open(path, kind, args.size, rate) {
            Ok(v) => videos.push(v),
            Err(e) => {
                videos.into_iter().for_each(Video::abort);
                return Err(bad(format!("{e:#}")));
            }
        }
    }
    let mut evaluator = match open(args, plan) {
        Ok(e) => e,
        Err(e) => {
            videos.into_iter().for_each(Video::abort);
            return Err(e);
        }
    };
    note_preroll(&progress, plan, &frames);
    let mut next = None;
    for &frame in &frames {
        preroll(&mut evaluator, plan, &mut next, frame);
        let started = Instant::now();
        let pushed = evaluator.frame(frame).and_then(|captured| {
            let resolved = captured.resolve()?;
            for (rendered, video) in resolved.images.into_iter().zip(videos.iter_mut()) {
                video
                    .push(&rendered.pixels.into_f32(), rendered.encoding)
                    .map_err(|e| vec![format!("{e:#}")])?;
            }
            Ok(())
        });
        let seconds = started.elapsed().as_secs_f64();
        if let Err(errors) = pushed {
            for e in &errors {
                progress.error(
                    Some(frame),
                    &format!("frame {frame}: {}", e.trim_start_matches("error: ")),
                );
            }
            progress.error(
                Some(frame),
                "a video cannot skip a frame: the video was not written",
            );
            videos.into_iter().for_each(Video::abort);
            progress.frame(frame, Status::Failed, seconds, &shown(&files));
            progress.finish(json!({"written": 0, "skipped": 0, "failed": [frame]}));
            return Ok(true);
        }
        progress.frame(frame, Status::Written, seconds, &shown(&files));
    }
    for video in videos {
        video.finish().context("the video")?;
    }
    let mut summary = json!({"written": frames.len(), "skipped": 0, "failed": []});
    cold_start(args, &evaluator, &progress, &mut summary);
    progress.finish(summary);
    evaluator.leave();
    Ok(false)
}
