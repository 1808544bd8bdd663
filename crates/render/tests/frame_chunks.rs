//! A batched frame is recorded into a few encoders (`FRAME_CHUNKS`), all but
//! the last handed to another thread that finishes them while the next
//! records: how many command buffers a frame submits, and a validation error
//! raised while finishing (on either thread) still drops the frame and is
//! named the frame after.

use spreadlight_render::frame_graph::{FRAME_CHUNKS, PassContext, PassName};
use spreadlight_render::renderer::{Recording, Timing, test_renderer};
use spreadlight_render::{FrameGraph, FrameReport, RenderError, Renderer, TextureDesc};

fn target() -> TextureDesc {
    TextureDesc::storage(wgpu::TextureFormat::Rgba16Float)
}

/// A copy whose size is not a multiple of 4: wgpu reports it when the
/// encoder is finished, on whichever thread finishes it.
pub(crate) fn misaligned_copy(cx: &mut PassContext<'_>) -> Result<(), RenderError> {
    let buffer = |label| {
        cx.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: 16,
            usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    };
    let (from, to) = (buffer("from"), buffer("to"));
    cx.encoder().copy_buffer_to_buffer(&from, 0, &to, 0, 3);
    Ok(())
}

/// `passes` independent passes (node ids 0..), the one at `broken` recording
/// an invalid copy; every output requested so none is culled.
pub(crate) fn frame(renderer: &Renderer, passes: usize, broken: Option<usize>) -> FrameReport {
    let mut fg = FrameGraph::new((4, 4));
    let names: Vec<String> = (0..passes).map(|i| format!("pass {i}")).collect();
    for (i, name) in names.iter().enumerate() {
        let run = move |cx: &mut PassContext<'_>| match broken == Some(i) {
            true => misaligned_copy(cx),
            false => Ok(()),
        };
        let mut pass = fg.pass(PassName::new(name.clone()), Some(i as u32));
        pass.write(name, target());
        pass.run(run);
        fg.request(name);
    }
    fg.execute(renderer).expect("the frame executes").0
}

#[test]
fn a_batched_frame_submits_a_few_command_buffers_finished_beside_its_recording() {
    let renderer = test_renderer();
    renderer.set_timing(Timing::Off);
    renderer.set_recording(Recording::Batched);
    let report = frame(&renderer, 8, None);
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.passes.len(), 8);
    assert_eq!(report.counter("command buffers"), FRAME_CHUNKS as u64);
    assert_eq!(
        report.counter("command encoders handed over"),
        FRAME_CHUNKS as u64 - 1
    );
    // Those the thread had not begun in time the recording thread finished.
    assert!(
        report.counter("command encoders taken back")
            <= report.counter("command encoders handed over"),
        "{:?}",
        report.counters
    );
    // A frame of one or two passes has one encoder a pass.
    let small = frame(&renderer, 2, None);
    assert_eq!(small.counter("command buffers"), 2);
    assert_eq!(small.counter("command encoders handed over"), 1);
    let single = frame(&renderer, 1, None);
    assert_eq!(single.counter("command buffers"), 1);
    assert_eq!(single.counter("command encoders handed over"), 0);
    // Isolated recording keeps one encoder a pass, all finished where recorded.
    renderer.set_recording(Recording::Isolated);
    let isolated = frame(&renderer, 8, None);
    assert_eq!(isolated.counter("command buffers"), 8);
    assert_eq!(isolated.counter("command encoders handed over"), 0);
    renderer.wait_idle().expect("drains");
}

#[test]
fn an_encoding_error_in_any_run_of_a_batched_frame_drops_it_and_the_next_names_the_pass() {
    let passes = 2 * FRAME_CHUNKS + 1;
    // The first pass lies in a run handed over, the last in the one
    // finished where it was recorded.
    let renderer = test_renderer();
    renderer.set_timing(Timing::Off);
    for broken in [0, passes / 2, passes - 1] {
        renderer.set_recording(Recording::Batched);
        let first = frame(&renderer, passes, Some(broken));
        assert_eq!(first.errors.len(), 1, "pass {broken}: {:?}", first.errors);
        assert_eq!(first.errors[0].0, None);
        assert!(
            first.errors[0]
                .1
                .contains("failed validation and was dropped"),
            "pass {broken}: {}",
            first.errors[0].1
        );
        assert_eq!(first.counter("command buffers"), 0, "nothing submitted");
        assert_eq!(renderer.settings().1, Recording::Isolated);
        let second = frame(&renderer, passes, Some(broken));
        assert_eq!(second.errors.len(), 1, "{:?}", second.errors);
        assert_eq!(second.errors[0].0, Some(broken as u32));
        assert!(
            second.errors[0]
                .1
                .contains(&format!("pass `pass {broken} #{broken}`")),
            "{}",
            second.errors[0].1
        );
        // The other passes still submit, one buffer each.
        assert_eq!(second.counter("command buffers"), passes as u64 - 1);
    }
    renderer.wait_idle().expect("drains");
}

#[test]
fn a_frame_that_panicked_while_recording_leaves_nothing_for_the_next() {
    let renderer = test_renderer();
    renderer.set_timing(Timing::Off);
    renderer.set_recording(Recording::Batched);
    let passes = 2 * FRAME_CHUNKS + 1;
    // The last pass panics after the runs before it were handed over.
    let panicked = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let mut fg = FrameGraph::new((4, 4));
        let names: Vec<String> = (0..passes).map(|i| format!("pass {i}")).collect();
        for (i, name) in names.iter().enumerate() {
            let mut pass = fg.pass(PassName::new(name.clone()), Some(i as u32));
            pass.write(name, target());
            pass.run(move |_| match i + 1 == passes {
                true => panic!("a pass that panics"),
                false => Ok(()),
            });
            fg.request(name);
        }
        fg.execute(&renderer)
    }));
    assert!(panicked.is_err());
    let report = frame(&renderer, passes, None);
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.counter("command buffers"), FRAME_CHUNKS as u64);
    renderer.wait_idle().expect("drains");
}
