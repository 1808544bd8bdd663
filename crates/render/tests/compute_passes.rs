//! Consecutive dispatches share one wgpu compute pass (frame_graph/compute_pass.rs):
//! wgpu encodes every compute pass into command buffers of its own, so a
//! batched frame opens one a run of dispatching passes instead of one a pass.
//! What they render stays as with a pass each, and each pass is still timed.
//! (Lavapipe runs dispatches in order, so a missing barrier would not show in
//! these images: that wgpu places them inside a pass is read from its source,
//! compute_pass.rs says where.)

use std::sync::Arc;

use spreadlight_render::frame_graph::{Bindings, COMPUTE_PASSES, FRAME_CHUNKS, PassName};
use spreadlight_render::post::CopyKey;
use spreadlight_render::readback::render_and_read;
use spreadlight_render::renderer::{Recording, Timing, test_renderer};
use spreadlight_render::shaders::Permutation;
use spreadlight_render::static_texture::StaticTexture;
use spreadlight_render::{FrameGraph, FrameReport, GpuContext, Renderer, TextureDesc};

const SIZE: (u32, u32) = (8, 8);

fn target() -> TextureDesc {
    let mut desc = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float);
    desc.usage |= wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::COPY_SRC;
    desc
}

/// A ramp, the chain's start (imported: no pass of its own).
fn seed(renderer: &Renderer) -> Arc<StaticTexture> {
    let pixels: Vec<[f32; 4]> = (0..SIZE.0 * SIZE.1)
        .map(|i| {
            let v = i as f32 / 64.0;
            [v, v, v, 1.0]
        })
        .collect();
    StaticTexture::from_rgba32f(&renderer.gpu, SIZE.0, SIZE.1, &pixels, "seed")
}

/// The seed, then `hops` passes that each copy the one before through a
/// dispatch (post/copy.wgsl: the last image is the seed only if every hop saw
/// the one before it), with a texture copy through the encoder before the
/// hop after `copy_after`, and hop `failing` returning an error after its
/// dispatch, when asked.
struct Chain {
    seed: Arc<StaticTexture>,
    hops: usize,
    copy_after: Option<usize>,
    failing: Option<usize>,
}

impl Chain {
    fn last(&self) -> String {
        format!("h{}", self.hops)
    }
}

impl spreadlight_render::Recipe for Chain {
    fn declare<'a>(&'a self, _: &'a Renderer, fg: &mut FrameGraph<'a>) {
        fg.import("h0", self.seed.texture.texture.clone());
        for hop in 1..=self.hops {
            let (from, to) = (format!("h{}", hop - 1), format!("h{hop}"));
            let copied = self.copy_after == Some(hop - 1);
            let fails = self.failing == Some(hop);
            let mut pass = fg.pass(PassName::new("hop").step(hop.to_string()), Some(hop as u32));
            let (input, output) = (pass.read(&from), pass.write(&to, target()));
            pass.run(move |cx| {
                let bindings = Bindings::new().texture("output", output);
                let bindings = if copied {
                    // Through the encoder: the open compute pass must end first
                    // (wgpu refuses an encoder with a pass open on it).
                    let from = cx.texture(input)?.clone();
                    let scratch = cx.gpu.device.create_texture(&wgpu::TextureDescriptor {
                        label: Some("copy"),
                        size: from.size(),
                        mip_level_count: 1,
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        format: from.format(),
                        usage: wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::TEXTURE_BINDING,
                        view_formats: &[],
                    });
                    cx.encoder().copy_texture_to_texture(
                        from.as_image_copy(),
                        scratch.as_image_copy(),
                        from.size(),
                    );
                    bindings.view("source", scratch.create_view(&Default::default()))
                } else {
                    bindings.texture("source", input)
                };
                cx.dispatch_image("hop", &CopyKey.key(), bindings, SIZE)?;
                match fails {
                    true => Err(spreadlight_render::RenderError::Graph(
                        "a deliberate error after the dispatch".into(),
                    )),
                    false => Ok(()),
                }
            });
        }
    }
}

fn render(renderer: &Renderer, chain: &Chain) -> (FrameReport, Vec<[f32; 4]>) {
    let (report, image) = render_with_errors(renderer, chain);
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    (report, image)
}

fn render_with_errors(renderer: &Renderer, chain: &Chain) -> (FrameReport, Vec<[f32; 4]>) {
    let last = chain.last();
    let (report, images) = render_and_read(renderer, chain, SIZE, &[&last]).expect("renders");
    (report, images[0].pixels.clone())
}

/// 12 hops from the seed, none failing.
fn chain(renderer: &Renderer, copy_after: Option<usize>) -> Chain {
    Chain {
        seed: seed(renderer),
        hops: 12,
        copy_after,
        failing: None,
    }
}

/// The hops' reports, in order.
fn hops(report: &FrameReport) -> Vec<&spreadlight_render::frame_graph::PassReport> {
    report.passes.iter().filter(|p| p.kind == "hop").collect()
}

/// A renderer on a device opened without timestamps inside passes (as a host
/// that opened its own device may hand over: `GpuContext::from_parts`).
fn renderer_without_timestamps_inside_passes() -> Renderer {
    pollster::block_on(async {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions::default())
            .await
            .expect("GPU tests need a GPU adapter");
        let features = adapter.features()
            & (wgpu::Features::TIMESTAMP_QUERY
                | wgpu::Features::SHADER_INT64
                | wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX);
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                required_features: features,
                required_limits: adapter.limits(),
                ..Default::default()
            })
            .await
            .expect("a device");
        assert!(
            !device
                .features()
                .contains(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES)
        );
        Renderer::new(GpuContext::from_parts(device, queue, adapter.get_info())).expect("renderer")
    })
}

#[test]
fn a_batched_frame_opens_one_compute_pass_a_run_and_renders_what_a_pass_each_renders() {
    let renderer = test_renderer();
    let plain = chain(&renderer, None);
    // Isolated: an encoder a pass, so a compute pass a dispatching pass.
    renderer.set_recording(Recording::Isolated);
    let (report, reference) = render(&renderer, &plain);
    assert_eq!(report.counter(COMPUTE_PASSES), 12);
    assert!(
        reference.iter().any(|p| p[0] > 0.5),
        "the ramp went through every hop"
    );

    renderer.set_recording(Recording::Batched);
    for timing in [Timing::PerPass, Timing::Frame, Timing::Off] {
        renderer.set_timing(timing);
        let (report, image) = render(&renderer, &plain);
        assert_eq!(image, reference, "{timing:?}");
        // One a run of the frame: every run of the 12 passes holds hops.
        assert_eq!(
            report.counter(COMPUTE_PASSES),
            FRAME_CHUNKS as u64,
            "{timing:?}"
        );
        if timing == Timing::Frame {
            // The first and the last pass only.
            let timed: Vec<bool> = hops(&report).iter().map(|p| p.gpu_ms.is_some()).collect();
            let mut ends = vec![false; 12];
            (ends[0], ends[11]) = (true, true);
            assert_eq!(timed, ends);
            assert!(report.gpu_frame_ms.is_some());
        }
    }

    // A copy through the encoder ends the open compute pass, and the copy
    // reads what the dispatch before it wrote.
    let copied = chain(&renderer, Some(2));
    let (report, image) = render(&renderer, &copied);
    assert_eq!(image, reference);
    assert_eq!(report.counter(COMPUTE_PASSES), FRAME_CHUNKS as u64 + 1);
    renderer.set_recording(Recording::Isolated);
    let (_, image) = render(&renderer, &copied);
    assert_eq!(image, reference);
    renderer.wait_idle().expect("drains");
}

#[test]
fn passes_sharing_a_compute_pass_are_each_timed() {
    let renderer = test_renderer();
    assert!(
        renderer.gpu.has_timestamps(),
        "the test adapter times passes"
    );
    renderer.set_recording(Recording::Batched);
    renderer.set_timing(Timing::PerPass);
    let (report, _) = render(&renderer, &chain(&renderer, Some(5)));
    assert!(report.counter(COMPUTE_PASSES) < 12);
    let hops = hops(&report);
    assert_eq!(hops.len(), 12);
    // Each hop's own two timestamps, written inside the shared pass, around its dispatch.
    for pass in &hops {
        let ms = pass
            .gpu_ms
            .unwrap_or_else(|| panic!("{} untimed", pass.name));
        assert!(ms > 0.0, "{}: {ms}", pass.name);
        assert!(pass.idle_ms.is_some(), "{}", pass.name);
    }
    let (span, sum) = (
        report.gpu_frame_ms.expect("a span"),
        report.gpu_ms.expect("a sum"),
    );
    // The passes follow each other, so their times fit in the frame's span.
    assert!(sum <= span * 1.001 + 1e-6, "sum {sum} > span {span}");
    renderer.wait_idle().expect("drains");
}

#[test]
fn without_timestamps_inside_passes_a_timed_pass_gets_a_compute_pass_of_its_own() {
    let renderer = renderer_without_timestamps_inside_passes();
    assert!(
        renderer.gpu.has_timestamps(),
        "the test adapter times passes"
    );
    let chain = chain(&renderer, Some(2));
    renderer.set_recording(Recording::Isolated);
    renderer.set_timing(Timing::Off);
    let (_, reference) = render(&renderer, &chain);
    renderer.set_recording(Recording::Batched);

    renderer.set_timing(Timing::PerPass);
    let (report, image) = render(&renderer, &chain);
    assert_eq!(image, reference);
    assert_eq!(report.counter(COMPUTE_PASSES), 12);
    assert!(hops(&report).iter().all(|p| p.gpu_ms.is_some()));
    // Untimed passes still share.
    renderer.set_timing(Timing::Off);
    let (report, image) = render(&renderer, &chain);
    assert_eq!(image, reference);
    assert_eq!(report.counter(COMPUTE_PASSES), FRAME_CHUNKS as u64 + 1);
    renderer.wait_idle().expect("drains");
}

#[test]
fn a_pass_that_fails_after_its_dispatch_is_reported_and_the_passes_after_it_still_run() {
    let renderer = test_renderer();
    renderer.set_recording(Recording::Isolated);
    let (_, reference) = render(&renderer, &chain(&renderer, None));
    renderer.set_recording(Recording::Batched);
    renderer.set_timing(Timing::PerPass);
    let failing = Chain {
        failing: Some(4),
        ..chain(&renderer, None)
    };
    let (report, image) = render_with_errors(&renderer, &failing);
    assert_eq!(report.errors.len(), 1, "{:?}", report.errors);
    let (owner, message) = &report.errors[0];
    assert_eq!(*owner, Some(4));
    assert!(message.contains("deliberate"), "{message}");
    // Its dispatch was recorded, and the hops after it read it and are timed
    // (a failed pass reports no time, as with a compute pass of its own).
    assert_eq!(image, reference);
    let timed: Vec<bool> = hops(&report).iter().map(|p| p.gpu_ms.is_some()).collect();
    let mut all_but_the_failed = vec![true; 12];
    all_but_the_failed[3] = false;
    assert_eq!(timed, all_but_the_failed);
    // A pass's own error is no validation error: the frame stays batched.
    assert_eq!(renderer.settings().1, Recording::Batched);
    renderer.wait_idle().expect("drains");
}
