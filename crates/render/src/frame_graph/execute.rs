//! Executing a frame graph on the renderer: allocate each pass's textures
//! (pooled temporaries, persistent histories), record the passes in order,
//! time them, submit, and hand the requested (and watched) textures back.
//! A host may add commands that read those textures to the frame's own
//! submission ([`FrameGraph::execute_on_then`]).
//!
//! Two choices are the renderer's settings ([`Recording`], [`Timing`]):
//! - `Recording::Isolated` records each pass into its own command encoder
//!   inside a validation error scope, so an error names its pass and the
//!   rest of the frame still renders. `Batched` records the whole frame into
//!   a few encoders ([`FRAME_CHUNKS`](super::FRAME_CHUNKS), each a run of
//!   passes, all but the last finished on another thread while the next
//!   records: finisher.rs) under one scope a thread (fewer command buffers
//!   and transitions for wgpu to stitch than one a pass); an error there
//!   drops that frame and switches the renderer to `Isolated` for good,
//!   which then names the failing pass. In both, consecutive dispatches of
//!   one encoder share a compute pass (compute_pass.rs).
//! - `Timing::PerPass` writes timestamps around every pass and waits for
//!   them (the per-pass figures of `stats` and `bench`); `Frame` only around
//!   the first and the last pass; `Off` writes none and never waits, so the
//!   CPU records the next frame while the GPU works on this one (at most
//!   [`FRAMES_IN_FLIGHT`] frames ahead).

use std::collections::HashMap;

use rustc_hash::{FxHashMap, FxHashSet};

use super::executor::{Executor, MAX_QUERIES, PERSISTENT_IDLE_GRAPHS, Recording, Timing};
use super::finisher::chunk_of;
use super::submitter::{Job, Outcome, Submission};
use super::{FrameGraph, Lifetime, PassContext, PassOrder, Recorded};
use crate::allocation_count;
use crate::context::GpuContext;
use crate::error::RenderError;
use crate::report::{FrameReport, PassReport};
use crate::texture_pool::create_texture;

/// Frames the CPU may run ahead of the GPU when nothing is read back.
pub const FRAMES_IN_FLIGHT: usize = 2;

impl FrameGraph<'_> {
    /// Cull, allocate, record and submit the frame on `executor`; `counters`
    /// adds the host's own to the report once the passes have recorded.
    /// Returns its report and the requested textures.
    pub fn execute_on(
        self,
        executor: &Executor,
        gpu: &GpuContext,
        counters: impl FnOnce() -> Vec<(&'static str, u64)>,
    ) -> Result<(FrameReport, HashMap<String, wgpu::Texture>), RenderError> {
        execute(executor, gpu, self, counters, |_| Vec::new())
    }

    /// [`FrameGraph::execute_on`], with `then`'s commands in the frame's own
    /// submission, after its passes: `then` gets the textures the frame
    /// hands back (requested and watched) before the submit, and records
    /// what the host does with them (an editor's blits into egui's
    /// textures). One submission a frame instead of two: on a host that
    /// gates submissions behind its UI frames, one wait instead of two.
    pub fn execute_on_then(
        self,
        executor: &Executor,
        gpu: &GpuContext,
        counters: impl FnOnce() -> Vec<(&'static str, u64)>,
        then: impl FnOnce(&HashMap<String, wgpu::Texture>) -> Vec<wgpu::CommandBuffer>,
    ) -> Result<(FrameReport, HashMap<String, wgpu::Texture>), RenderError> {
        execute(executor, gpu, self, counters, then)
    }
}

fn execute(
    executor: &Executor,
    gpu: &GpuContext,
    mut graph: FrameGraph<'_>,
    counters: impl FnOnce() -> Vec<(&'static str, u64)>,
    then: impl FnOnce(&HashMap<String, wgpu::Texture>) -> Vec<wgpu::CommandBuffer>,
) -> Result<(FrameReport, HashMap<String, wgpu::Texture>), RenderError> {
    // The frame before, if the submission thread still owes its submission,
    // is submitted before this one records (submitter.rs); what it found
    // out goes into this frame's report.
    executor.submitter().wait();
    let before = executor.submitter().take();
    if before.as_ref().is_some_and(|o| o.validation_failed) {
        executor.set_recording(Recording::Isolated);
    }
    let submission_wait = executor.submission_wait_since_last_frame();
    let started = std::time::Instant::now();
    let allocations_started = allocation_count::now();
    let (timing, recording) = executor.settings();
    let output_size = graph.output_size();
    let device = &gpu.device;
    // The pipelines the passes announced and the cache lacks: made on
    // threads from here, while the frame plans and records (gather.rs).
    let announced = graph.take_pipelines();
    if !announced.is_empty() {
        executor.shaders().make_ahead(device, announced);
    }
    let announced_if_run = graph.take_pipelines_if_run();
    let announced_if_read = graph.take_pipelines_if_read();
    let mut textures = executor.texture_pool();
    let lent = std::mem::take(&mut textures.lent);
    for (key, texture) in lent {
        textures.give_back(key, texture);
    }
    // Which names have a persistent texture (asked, not collected: no names
    // cloned a frame). The plan is last frame's when the graph declares what
    // it did then (plan.rs): then nothing below is worked out again.
    let pass_order = executor.pass_order().on(gpu.adapter_class());
    // In waves: which passes asked for the encoder last frame (first in
    // their wave, so part of what a kept plan must match).
    let mut encoder_passes = (pass_order == PassOrder::Waves).then(|| executor.encoder_passes());
    let planned = graph.plan(
        executor.plans(),
        &|name| textures.persistent.contains_key(name),
        pass_order,
        &|name| encoder_passes.as_ref().is_some_and(|e| e.contains(name)),
    )?;
    let plan = &*planned.plan;
    // Those announced for passes that may be culled or merged, now that the
    // plan says which run (gather.rs).
    if !announced_if_run.is_empty() || !announced_if_read.is_empty() {
        let mut run = super::gather::run_by(plan, announced_if_run);
        run.extend(super::gather::read_by(plan, announced_if_read));
        if !run.is_empty() {
            executor.shaders().make_ahead(device, run);
        }
    }
    let mut runs = planned.runs;
    let last_use = &plan.last_use;
    let requested = &plan.requested_set;
    // In waves, a temporary goes back to the pool after its last reader's
    // wave, not after its last reader: a pass beside that reader must not be
    // handed its memory (waves.rs). In declaration order, after the reader.
    let wave_end = &plan.wave_end;
    let released_after = |step: usize| wave_end.get(step).copied().unwrap_or(step);
    // A wave of two passes or more begins a compute pass of its own, so
    // every first use in it is prepared before it and no barrier parts its
    // dispatches (waves.rs).
    let begins_wave = |step: usize| {
        wave_end
            .get(step)
            .is_some_and(|&end| end > step && (step == 0 || wave_end[step - 1] < step))
    };
    // Watched textures are kept to the end of the frame, nothing else
    // (`FrameGraph::watch`); those made and read are handed back.
    let watched = &plan.watched_set;
    let mut watched_made: Vec<String> = Vec::new();
    let tradable = &plan.tradable;
    // A temporary whose history took its texture gives back the one the history had.
    let mut release_instead: FxHashMap<String, wgpu::Texture> = FxHashMap::default();

    // The plan's map of live textures, its names kept from the last frame
    // that took the plan (live.rs); put back, emptied, at the end.
    let mut live = std::mem::take(&mut *plan.live.lock().unwrap_or_else(|e| e.into_inner()));
    for (name, texture) in planned.imports {
        live.insert(&name, texture);
    }
    for (name, (_, texture)) in &textures.persistent {
        live.insert(name, texture.clone());
    }
    let mut fresh = FxHashSet::default();
    let mut report = FrameReport {
        adapter: gpu.adapter_name(),
        submission_wait_ms: submission_wait.as_secs_f64() * 1e3,
        ..Default::default()
    };
    if let Some(before) = before {
        // Its time only where this frame goes to the thread too (an inline frame reports none).
        let threaded = executor.submission().on(gpu.adapter_class()) == Submission::Thread;
        land(
            executor,
            &mut report,
            before,
            "the frame before, at its submission: ",
        );
        if !threaded {
            report.submission_thread_ms = None;
        }
    }
    for (name, n) in planned.counters {
        add_counter(&mut report, name, n);
    }
    let plans = if planned.reused {
        "plans reused"
    } else {
        "plans made"
    };
    add_counter(&mut report, plans, 1);
    // A kept plan runs under its own names; the caller gets this frame's.
    let frame_names = planned.frame_names;
    let frame_name = |name: &'_ str| -> String {
        super::plan::frame_name(plan, frame_names.as_deref(), name).to_owned()
    };
    report.passes.reserve(plan.order.len());
    // Pool textures this frame took, by pass and output (the name is
    // `plan.writes[p][output]`: not cloned a texture a frame), with the step
    // after which a temporary goes back to the pool (None: at the frame's
    // end), found once when it is taken: each pass then compares numbers,
    // not every texture's name hashed three times.
    let mut owned: Vec<(usize, usize, _, Option<usize>, _)> = Vec::new();
    let mut commands = Vec::new();
    let mut pass_queries: Vec<(usize, super::PassQueries)> = Vec::with_capacity(plan.order.len());
    let mut next_query = 0u32;
    let timestamps = executor.timestamps().filter(|_| timing != Timing::Off);
    let capacity = if timestamps.is_some() { MAX_QUERIES } else { 0 };
    let mut shaders = executor.shaders();
    shaders.begin_frame();
    let mut kept = executor.kept_bindings();
    kept.begin(
        plan.id,
        plan.names.len(),
        shaders.generation,
        planned.reused,
    );
    let compiled_before = shaders.pipelines_compiled;
    let looked_up_before = shaders.compute_pipelines_used().len();
    let groups_before = (shaders.bind_groups_created, shaders.bind_groups_reused);
    let views = std::cell::RefCell::new(std::mem::take(&mut textures.views));
    let views_before = {
        let v = views.borrow();
        (v.created, v.reused)
    };
    let batched = recording == Recording::Batched;
    let new_encoder = |label: &str| {
        device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) })
    };
    let frame_scope = batched.then(|| device.push_error_scope(wgpu::ErrorFilter::Validation));
    let mut shared = batched.then(|| new_encoder("frame"));
    // The compute pass open on `shared`, which the next pass's dispatches join (compute_pass.rs).
    let mut open_compute = None;
    let inside_passes = device
        .features()
        .contains(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES);
    let mut finishing = batched.then(|| executor.finisher().begin());
    let steps = plan.order.len();

    let max_side = device.limits().max_texture_dimension_2d;
    report.allocations_before_passes = allocation_count::since(allocations_started);
    for (step, &p) in plan.order.iter().enumerate() {
        let pass_started = std::time::Instant::now();
        let pass_allocations = allocation_count::now();
        // A texture past the adapter's limit fails its pass before anything
        // is allocated (wgpu would refuse it with an error outside any scope).
        let mut too_large = too_large(&plan.writes[p], &plan.keys[p], max_side, output_size);
        let writes = if too_large.is_some() {
            &[][..]
        } else {
            &plan.writes[p][..]
        };
        for (output, ((name, desc), key)) in writes.iter().zip(&plan.keys[p]).enumerate() {
            // An output only a reader needs, and nothing reads: not made
            // (the same test as `PassContext::is_read`, which the pass asks).
            if desc.only_if_read
                && !requested.contains(name.as_str())
                && last_use.get(name.as_str()).is_none_or(|&s| s <= step)
            {
                add_counter(&mut report, super::TARGETS_NOT_MADE, 1);
                continue;
            }
            let texture = match desc.lifetime {
                Lifetime::Persistent => match textures.persistent.get(name) {
                    Some((k, t)) if k == key => t.clone(),
                    _ => {
                        let t = create_texture(device, key, name);
                        report.textures_created += 1;
                        if let Some((_, old)) =
                            textures.persistent.insert(name.clone(), (*key, t.clone()))
                        {
                            views.borrow_mut().forget(&old);
                        }
                        fresh.insert(name.clone());
                        t
                    }
                },
                Lifetime::Temporary | Lifetime::Permanent => {
                    let slot = plan.slots[p][output];
                    let release = (desc.lifetime == Lifetime::Temporary
                        && !requested.contains(name.as_str())
                        && !watched.contains(name.as_str()))
                    .then(|| last_use.get(name.as_str()).map(|&s| released_after(s)))
                    .flatten();
                    owned.push((p, output, *key, release, slot));
                    textures.take(device, key, (slot, name), &mut report.textures_created)
                }
            };
            if desc.lifetime == Lifetime::Persistent {
                match textures.idle.get_mut(name.as_str()) {
                    Some(idle) => *idle = 0,
                    None => {
                        textures.idle.insert(name.clone(), 0);
                    }
                }
            }
            live.insert(name, texture);
        }

        // Batched: the encoder of the pass's run; isolated: one named for the pass.
        let encoder = shared.take().unwrap_or_else(|| new_encoder(&plan.names[p]));
        let scope = (!batched).then(|| device.push_error_scope(wgpu::ErrorFilter::Validation));
        // Timing::Frame times the first and the last pass: the frame's span.
        let timed = match timing {
            Timing::PerPass => true,
            Timing::Frame => step == 0 || step + 1 == steps,
            Timing::Off => false,
        };
        if begins_wave(step) {
            add_counter(&mut report, super::PASS_WAVES, 1);
            // Ended here: wgpu encodes what the wave first uses before the next one.
            drop(open_compute.take());
        }
        let run = runs[p].take();
        let mut cx = PassContext {
            gpu,
            encoder,
            compute: open_compute.take(),
            timestamps_inside_passes: inside_passes,
            shaders: &mut shaders,
            kept: kept.pass(p),
            textures: &mut live,
            texture_names: &plan.texture_names,
            reads: &plan.reads[p],
            writes: &plan.writes[p],
            tradable,
            last_use,
            requested,
            step,
            handovers: Vec::new(),
            views: &views,
            fresh: &fresh,
            timestamps: timestamps.filter(|_| timed).map(|t| &t.set),
            queries: Default::default(),
            next_query: &mut next_query,
            query_capacity: capacity,
            draws: 0,
            output_size,
            counters: Default::default(),
            used_encoder: false,
        };
        let result = match (too_large.take(), run) {
            (Some(error), _) => Err(error),
            (None, Some(run)) => run(&mut cx),
            (None, None) => Ok(()),
        };
        let Recorded {
            encoder,
            used_encoder,
            compute,
            queries,
            draws,
            counters,
            handovers,
        } = cx.finish();
        if let Some(passes) = &mut encoder_passes {
            // Remembered by name for the next frame's order; a name cloned only when it changes.
            if used_encoder && !passes.contains(&plan.names[p]) {
                passes.insert(plan.names[p].clone());
            } else if !used_encoder && passes.contains(&plan.names[p]) {
                passes.remove(&plan.names[p]);
            }
        }
        for handover in handovers {
            if let (Some((_, kept)), Some(texture)) = (
                textures.persistent.get_mut(&handover.persistent),
                live.get(&handover.persistent),
            ) {
                *kept = texture.clone();
            }
            release_instead.insert(handover.temporary, handover.release);
        }
        for (name, n) in counters {
            add_counter(&mut report, name, n);
        }
        let error = if batched {
            // The end of a run of passes: wgpu encodes it beside the next.
            match &mut finishing {
                Some(finishing)
                    if step + 1 < steps && chunk_of(step + 1, steps) != chunk_of(step, steps) =>
                {
                    // A finished encoder holds no open pass.
                    drop(compute);
                    finishing.send(encoder);
                    shared = Some(new_encoder("frame"));
                }
                _ => {
                    shared = Some(encoder);
                    open_compute = compute;
                }
            }
            result.err().map(|e| e.to_string())
        } else {
            drop(compute);
            let buffer = encoder.finish();
            let validation = scope.and_then(|s| pollster::block_on(s.pop()));
            match (result, validation) {
                (Err(e), _) => Some(e.to_string()),
                (Ok(()), Some(e)) => Some(
                    RenderError::Validation {
                        pass: plan.names[p].clone(),
                        message: e.to_string(),
                    }
                    .to_string(),
                ),
                (Ok(()), None) => {
                    commands.push(buffer);
                    None
                }
            }
        };
        if error.is_none() && !watched.is_empty() {
            // Made: written by this pass and read by a later one (a pass may
            // leave an output nobody reads unwritten, `PassContext::is_read`).
            for (name, _) in &plan.writes[p] {
                if watched.contains(name.as_str())
                    && last_use.get(name.as_str()).is_some_and(|&s| s > step)
                {
                    watched_made.push(name.clone());
                }
            }
        }
        match error {
            Some(message) => {
                let message = format!("pass `{}`: {message}", plan.names[p]);
                // A merged pass's error is both nodes' (merge.rs).
                if let Some(partner) = plan.partners[p] {
                    report.errors.push((Some(partner), message.clone()));
                }
                report.errors.push((plan.owners[p], message));
            }
            None => pass_queries.push((report.passes.len(), queries)),
        }
        report.draws += draws;
        report.passes.push(PassReport {
            name: plan.names[p].clone(),
            kind: plan.labels[p].kind.clone(),
            step: plan.labels[p].step.clone(),
            owner: plan.owners[p],
            partner: plan.partners[p],
            gpu_ms: None,
            idle_ms: None,
            draws,
            cpu_ms: 0.0,
            allocations: None,
        });
        let pass_report = report.passes.len() - 1;

        // Temporaries whose last reader has recorded go back to the pool, and
        // leave the live textures: no later pass can reach memory the pool
        // may hand to another.
        owned.retain(|&(pass, output, ref key, release, ref slot)| {
            let done = release.is_some_and(|r| r <= step);
            if done {
                let name = &plan.writes[pass][output].0;
                let texture = live.remove(name);
                match release_instead.remove(name) {
                    // Next frame the output takes the texture it gives back now.
                    Some(t) => textures.hold_for(*slot, *key, t),
                    None => {
                        if let Some(t) = texture {
                            textures.give_back(*key, t);
                        }
                    }
                }
            }
            !done
        });
        report.passes[pass_report].cpu_ms = pass_started.elapsed().as_secs_f64() * 1e3;
        report.passes[pass_report].allocations = allocation_count::since(pass_allocations);
    }
    let passes_recorded = started.elapsed();
    let tail_allocations = allocation_count::now();
    report.culled = plan.culled.iter().map(|&p| plan.names[p].clone()).collect();
    report.pipelines_compiled = shaders.pipelines_compiled - compiled_before;
    // Frames announce their pipelines while a frame still looks new ones up.
    super::gather::frame_made_pipelines(shaders.compute_pipelines_used().len() > looked_up_before);
    shaders.end_frame_ahead();
    let mut views = views.into_inner();
    let (pipelines_kept, groups_kept) = kept.counted();
    for (name, n) in counters().into_iter().chain([
        (
            "bind groups created",
            shaders.bind_groups_created - groups_before.0,
        ),
        // Kept ones too: reused without a look-up (kept_bindings.rs).
        (
            "bind groups reused",
            shaders.bind_groups_reused - groups_before.1 + groups_kept,
        ),
        (super::PIPELINES_KEPT, pipelines_kept),
        (super::BIND_GROUPS_KEPT, groups_kept),
        ("texture views created", views.created - views_before.0),
        ("texture views reused", views.reused - views_before.1),
    ]) {
        if n > 0 {
            add_counter(&mut report, name, n);
        }
    }
    views.end_frame();
    textures.end_frame();
    textures.views = views;
    drop(kept);
    drop(shaders);

    // The last run's compute pass ends before its encoder resolves the timestamps and finishes.
    drop(open_compute);
    if let (Some(ts), true) = (timestamps, next_query > 0) {
        let mut encoder = shared.take().unwrap_or_else(|| new_encoder("timestamps"));
        encoder.resolve_query_set(&ts.set, 0..next_query, &ts.resolve, 0);
        encoder.copy_buffer_to_buffer(&ts.resolve, 0, &ts.readback, 0, u64::from(next_query) * 8);
        if batched {
            shared = Some(encoder);
        } else {
            commands.push(encoder.finish());
        }
    }
    // The textures handed back, known before the submit so the host's own
    // commands that read them (the editor's blits into its viewport and
    // thumbnails) go in the frame's submission: each submission may wait
    // at the gate for a UI frame (submission_gate.rs).
    let mut outputs = HashMap::new();
    for name in &plan.requested {
        if let Some(t) = live.get(name) {
            outputs.insert(frame_name(name), t.clone());
        }
    }
    // A watched texture is handed back only if it can be sampled: a watch
    // changes no texture's usage.
    for name in watched_made {
        if let Some(t) = live.get(&name)
            && t.usage().contains(wgpu::TextureUsages::TEXTURE_BINDING)
        {
            outputs.insert(frame_name(&name), t.clone());
        }
    }
    let host_commands = then(&outputs);
    if !host_commands.is_empty() {
        add_counter(
            &mut report,
            "host command buffers",
            host_commands.len() as u64,
        );
    }
    // Whether this frame's timestamps are read back (it waits for the GPU).
    let timed = timestamps.is_some() && next_query > 0;
    // With a submission thread, the tail goes there (submitter.rs).
    let threaded = executor.submission().on(gpu.adapter_class()) == Submission::Thread;
    let mut job = None;
    if let (Some(encoder), Some(scope), Some(finishing)) = (shared, frame_scope, finishing) {
        if threaded {
            // Scopes are per thread: this one ends here, with what the
            // recording raised; the last run's `finish` gets its own there.
            let recording_error = pollster::block_on(scope.pop());
            let sent = finishing.sent() as u64;
            if sent > 0 {
                add_counter(&mut report, "command encoders handed over", sent);
            }
            job = Some(Job {
                finishing: Some(finishing),
                last: Some(encoder),
                finished: Vec::new(),
                recording_error,
                host: Vec::new(),
                throttle: None,
            });
        } else {
            let dropped = finish_here(
                executor,
                &mut report,
                (encoder, scope, finishing),
                &mut commands,
            );
            if dropped {
                pass_queries.clear();
                next_query = 0;
            }
        }
    } else if threaded {
        job = Some(Job {
            finishing: None,
            last: None,
            finished: std::mem::take(&mut commands),
            recording_error: None,
            host: Vec::new(),
            throttle: None,
        });
    }
    let mut submission = None;
    // The frame's own outcome, where it was submitted on the thread and
    // waits for it, or submitted here for want of a thread.
    let mut own = None;
    match job {
        Some(mut job) => {
            job.host = host_commands;
            job.throttle = (!timed).then_some(FRAMES_IN_FLIGHT);
            if let Some(mut job) = executor.submitter().send(gpu, job) {
                // No thread could start: the same tail, here.
                job.throttle = None;
                let outcome = super::submitter::submit(gpu, job, &mut Default::default());
                submission = outcome.submission.clone();
                own = Some(outcome);
            }
        }
        None => {
            if !commands.is_empty() {
                add_counter(&mut report, "command buffers", commands.len() as u64);
            }
            commands.extend(host_commands);
            let submitting = std::time::Instant::now();
            submission = Some(gpu.submit(commands));
            report.queue_submit_ms = submitting.elapsed().as_secs_f64() * 1e3;
        }
    }
    report.record_ms = started.elapsed().as_secs_f64() * 1e3;
    report.submit_ms = (started.elapsed() - passes_recorded).as_secs_f64() * 1e3;
    // A timed frame waits for its own submission, whose timestamps it
    // reads, and whose outcome is its report's (on an adapter without
    // timestamps too, so a timed frame's report is whole everywhere).
    if threaded && timing != Timing::Off && own.is_none() {
        executor.submitter().wait();
        own = executor.submitter().take();
    }
    if let Some(outcome) = own {
        if outcome.dropped {
            pass_queries.clear();
            next_query = 0;
        }
        land(executor, &mut report, outcome, "");
    }

    if let (Some(ts), true) = (timestamps, next_query > 0) {
        let ticks = crate::context::read_buffer(gpu, &ts.readback, u64::from(next_query) * 8)?;
        let ticks: Vec<u64> = ticks
            .chunks_exact(8)
            .map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
            .collect();
        let period_ns = f64::from(gpu.queue.get_timestamp_period());
        let written: Vec<u64> = pass_queries
            .iter()
            .flat_map(|(_, q)| {
                q.iter()
                    .flat_map(|&(b, e)| [ticks[b as usize], ticks[e as usize]])
            })
            .collect();
        if let (Some(first), Some(last)) = (written.iter().min(), written.iter().max()) {
            report.gpu_frame_ms = Some(last.saturating_sub(*first) as f64 * period_ns / 1e6);
        }
        let to_ms = |ticks: u64| ticks as f64 * period_ns / 1e6;
        let mut total = 0.0;
        // The end of the previous timed part, to measure the idle gap before each.
        let mut previous_end: Option<u64> = None;
        for (index, queries) in pass_queries {
            if queries.is_empty() {
                continue;
            }
            let (mut ms, mut idle) = (0.0, 0.0);
            for &(b, e) in &queries {
                let (begin, end) = (ticks[b as usize], ticks[e as usize]);
                ms += to_ms(end.saturating_sub(begin));
                if let Some(previous) = previous_end {
                    idle += to_ms(begin.saturating_sub(previous));
                }
                previous_end = Some(end);
            }
            report.passes[index].gpu_ms = Some(ms);
            if timing == Timing::PerPass {
                report.passes[index].idle_ms = Some(idle);
            }
            total += ms;
        }
        // Timing::Frame measures the span only: a sum of two passes means nothing.
        report.gpu_ms = (timing == Timing::PerPass).then_some(total);
    } else if let Some(submission) = submission {
        executor.throttle(submission, FRAMES_IN_FLIGHT)?;
    }

    // History exists only for effects that run: a persistent texture no pass
    // has written for a while (its node deleted, culled, or switched to
    // another mode) is dropped.
    // In place: the names were cloned (twice) for every persistent texture, every frame.
    let mut dropped = 0;
    let pool = &mut *textures;
    let idle = &mut pool.idle;
    let views = &mut pool.views;
    pool.persistent.retain(|name, (_, texture)| {
        if plan
            .order
            .iter()
            .any(|&p| plan.writes[p].iter().any(|(n, _)| n == name))
        {
            return true;
        }
        let frames = match idle.get_mut(name.as_str()) {
            Some(frames) => frames,
            None => idle.entry(name.clone()).or_insert(0),
        };
        *frames += 1;
        if *frames > PERSISTENT_IDLE_GRAPHS {
            idle.remove(name.as_str());
            views.forget(texture);
            dropped += 1;
            return false;
        }
        true
    });
    if dropped > 0 {
        add_counter(&mut report, "histories dropped", dropped);
    }

    // Requested outputs go to the caller and come back to the pool next frame;
    // other permanent textures return now.
    for (pass, output, key, _, _) in owned {
        let name = &plan.writes[pass][output].0;
        let texture = release_instead
            .remove(name)
            .or_else(|| live.get(name).cloned());
        if let Some(texture) = texture {
            if requested.contains(name.as_str()) || watched.contains(name.as_str()) {
                textures.lent.push((key, texture));
            } else {
                textures.give_back(key, texture);
            }
        }
    }
    live.clear();
    *plan.live.lock().unwrap_or_else(|e| e.into_inner()) = live;
    report.wait_ms = (started.elapsed().as_secs_f64() * 1e3 - report.record_ms).max(0.0);
    // A timed frame's wait for its own submission is in `wait_ms`, not the next frame's.
    executor.submission_wait_since_last_frame();
    report.allocations_after_passes = allocation_count::since(tail_allocations);
    // Errors outside every pass's scope (allocating the frame's textures,
    // or work done before it that no host took): the frame's, not a panic.
    for error in gpu.take_uncaptured_errors() {
        report
            .errors
            .push((None, format!("GPU error outside any pass: {error}")));
    }
    executor.set_last_report(&report);
    Ok((report, outputs))
}

/// A batched frame's tail on the recording thread: finish the last run's
/// encoder, close the frame's error scope and collect the runs the finishing
/// thread encoded, into `commands`. A frame that fails is dropped whole:
/// true, with its error in the report and `commands` empty.
fn finish_here(
    executor: &Executor,
    report: &mut FrameReport,
    (encoder, scope, finishing): (
        wgpu::CommandEncoder,
        wgpu::ErrorScopeGuard,
        super::finisher::Finishing,
    ),
    commands: &mut Vec<wgpu::CommandBuffer>,
) -> bool {
    let last = encoder.finish();
    let here = pollster::block_on(scope.pop());
    let sent = finishing.sent() as u64;
    let collected = finishing.collect();
    for (name, n) in [
        ("command encoders handed over", sent),
        ("command encoders taken back", collected.taken_back as u64),
    ] {
        if n > 0 {
            add_counter(report, name, n);
        }
    }
    // The runs handed over come first: their errors are the earlier.
    let dropped = match collected.finished {
        Some(finished) => {
            let mut first = None;
            for (buffer, error) in finished {
                commands.push(buffer);
                first = first.or(error);
            }
            commands.push(last);
            first.or(here).map(|e| {
                // From now on passes record apart, so the next frame names the pass.
                executor.set_recording(Recording::Isolated);
                format!(
                    "the frame failed validation and was dropped; passes record separately from now on: {e}"
                )
            })
        }
        None => Some(
            "finishing a command encoder of the frame panicked; the frame was dropped".to_owned(),
        ),
    };
    match dropped {
        Some(message) => {
            report.errors.push((None, message));
            commands.clear();
            true
        }
        None => false,
    }
}

/// Put what a submission on the submission thread found out into `report`:
/// its errors (each after `about`: which frame's) and the thread's time;
/// its counters only where it is the report's own frame's (`about` empty:
/// the frame before's would be counted twice beside this frame's own); and
/// record apart from now on if its validation failed.
fn land(executor: &Executor, report: &mut FrameReport, outcome: Outcome, about: &str) {
    if outcome.validation_failed {
        executor.set_recording(Recording::Isolated);
    }
    for error in outcome.errors {
        report.errors.push((None, format!("{about}{error}")));
    }
    if about.is_empty() {
        for (name, n) in outcome.counters {
            add_counter(report, name, n);
        }
    }
    report.submission_thread_ms = Some(outcome.thread_ms);
}

/// Add `n` to the report's counter `name` (borrowed: no allocation a name).
fn add_counter(report: &mut FrameReport, name: &'static str, n: u64) {
    *report
        .counters
        .entry(std::borrow::Cow::Borrowed(name))
        .or_default() += n;
}

/// The error of a pass whose output would be larger than the adapter's
/// largest 2D texture, naming the texture, its size and the limit.
fn too_large(
    writes: &[(String, super::TextureDesc)],
    keys: &[crate::texture_pool::TextureKey],
    max_side: u32,
    output_size: (u32, u32),
) -> Option<RenderError> {
    let ((name, _), key) = writes
        .iter()
        .zip(keys)
        .find(|(_, key)| key.width > max_side || key.height > max_side)?;
    Some(RenderError::TooLarge {
        what: format!(
            "texture `{name}` ({}x{} for a {}x{} frame)",
            key.width, key.height, output_size.0, output_size.1
        ),
        limit: "max_texture_dimension_2d",
        max: u64::from(max_side),
    })
}
