//! Frames submitted on a submission thread (`Submission::Thread`,
//! `SPREADLIGHT_SUBMIT=thread`, frame_graph/submitter.rs): the recording
//! thread returns before the frame's tail; a frame that fails validation is
//! still dropped and named, in its own report when it waits for its
//! timestamps, else once submitted; the submission gate still holds the
//! submission back; a renderer dropped with a frame still owed submits it
//! and ends. (Images and readback against inline submission: the cli
//! crate's `submission_thread.rs` renders post.ron's sequence both ways.)

use std::sync::mpsc;
use std::time::Duration;

use spreadlight_render::renderer::{Recording, Submission, Timing, test_renderer};

use crate::frame_chunks::frame;

/// Long enough for any machine; reached only if something deadlocks.
const HUNG: Duration = Duration::from_secs(120);

const FAILED: &str = "failed validation and was dropped";

#[test]
fn a_frame_on_the_thread_counts_the_threads_time_and_submits_its_buffers() {
    let renderer = test_renderer();
    renderer.set_recording(Recording::Batched);
    renderer.set_submission(Submission::Thread);
    // Timed: the frame waits for its own submission, whose outcome is its
    // report's (these passes dispatch nothing, so write no timestamps).
    renderer.set_timing(Timing::Frame);
    let timed = frame(&renderer, 8, None);
    assert!(timed.errors.is_empty(), "{:?}", timed.errors);
    assert!(timed.submission_thread_ms.is_some_and(|ms| ms > 0.0));
    assert_eq!(timed.counter("command encoders handed over"), 2);
    // The frame's runs and the timestamps' copy, submitted there.
    assert_eq!(timed.counter("command buffers"), 3);
    // Frames in flight: each frame carries the time of the one before,
    // which its first use of the queue waited for.
    renderer.set_timing(Timing::Off);
    let first = frame(&renderer, 8, None);
    let second = frame(&renderer, 8, None);
    assert!(first.errors.is_empty() && second.errors.is_empty());
    assert!(second.submission_thread_ms.is_some_and(|ms| ms > 0.0));
    assert!(second.submission_wait_ms >= 0.0);
    // Its own buffers are counted where it waits for its submission only.
    assert_eq!(second.counter("command buffers"), 0);
    renderer.wait_idle().expect("drains");
    // Inline: no thread, no time of its.
    renderer.set_submission(Submission::Inline);
    let inline = frame(&renderer, 8, None);
    assert_eq!(inline.submission_thread_ms, None);
    assert_eq!(inline.counter("command buffers"), 3);
    renderer.wait_idle().expect("drains");
}

#[test]
fn a_frame_that_fails_on_the_thread_is_dropped_and_named_and_the_next_names_the_pass() {
    let passes = 7;
    let renderer = test_renderer();
    renderer.set_submission(Submission::Thread);
    for (timing, broken) in [(Timing::Frame, 0), (Timing::Off, passes - 1)] {
        renderer.set_timing(timing);
        renderer.set_recording(Recording::Batched);
        let first = frame(&renderer, passes, Some(broken));
        let errors = match timing {
            // Timed: its own report.
            Timing::Frame => first.errors.clone(),
            // In flight: once submitted (wait_idle waits for it), the last report.
            _ => {
                assert!(first.errors.is_empty(), "{:?}", first.errors);
                renderer.wait_idle().expect("drains");
                renderer.last_errors()
            }
        };
        assert_eq!(errors.len(), 1, "{timing:?}: {errors:?}");
        assert_eq!(errors[0].0, None);
        assert!(errors[0].1.contains(FAILED), "{}", errors[0].1);
        assert_eq!(renderer.settings().1, Recording::Isolated);
        let second = frame(&renderer, passes, Some(broken));
        assert_eq!(second.errors.len(), 1, "{:?}", second.errors);
        assert_eq!(second.errors[0].0, Some(broken as u32));
        assert!(
            second.errors[0]
                .1
                .contains(&format!("pass `pass {broken} #{broken}`"))
        );
        renderer.wait_idle().expect("drains");
    }
    // Nobody read the failing frame's report: the next frame's says it,
    // and that frame is already recorded pass by pass.
    renderer.set_recording(Recording::Batched);
    renderer.set_timing(Timing::Off);
    frame(&renderer, passes, Some(1));
    let next = frame(&renderer, passes, None);
    assert_eq!(next.errors.len(), 1, "{:?}", next.errors);
    assert!(
        next.errors[0]
            .1
            .starts_with("the frame before, at its submission: ")
            && next.errors[0].1.contains(FAILED),
        "{}",
        next.errors[0].1
    );
    assert_eq!(renderer.settings().1, Recording::Isolated);
    renderer.wait_idle().expect("drains");
}

#[test]
fn the_gate_holds_a_threads_submission_back_without_holding_the_recording() {
    let renderer = test_renderer();
    renderer.set_recording(Recording::Batched);
    renderer.set_timing(Timing::Off);
    renderer.set_submission(Submission::Thread);
    let gate = renderer.gpu.submission_gate().clone();
    let (woke, wakes) = mpsc::channel();
    gate.set_waker(move || {
        let _ = woke.send(());
    });
    gate.close();
    let before = gate.counts();
    // The frame returns while its submission waits at the closed gate.
    let (done, returned) = mpsc::channel();
    let recorder = renderer.clone();
    std::thread::spawn(move || {
        let report = frame(&recorder, 8, None);
        let _ = done.send(report);
    });
    let report = returned.recv_timeout(HUNG).expect("the frame returns");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    wakes
        .recv_timeout(HUNG)
        .expect("the submission asks to be let in");
    assert_eq!(gate.counts().since(before).submissions, 0, "held back");
    gate.open();
    renderer.wait_idle().expect("drains");
    let passed = gate.counts().since(before);
    assert_eq!(passed.submissions, 1);
    assert!(passed.waits >= 1);
}

#[test]
fn a_renderer_dropped_with_a_frame_owed_submits_it_and_ends() {
    let renderer = test_renderer();
    renderer.set_recording(Recording::Batched);
    renderer.set_timing(Timing::Off);
    renderer.set_submission(Submission::Thread);
    let gate = renderer.gpu.submission_gate().clone();
    let before = gate.counts();
    let (dropped, ended) = mpsc::channel();
    std::thread::spawn(move || {
        for _ in 0..3 {
            frame(&renderer, 8, None);
        }
        // The last frame's submission is likely still owed here.
        drop(renderer);
        let _ = dropped.send(());
    });
    ended.recv_timeout(HUNG).expect("the drop ends");
    assert_eq!(
        gate.counts().since(before).submissions,
        3,
        "every frame submitted"
    );
}

#[test]
fn a_write_between_frames_reaches_the_next_frames_submission_not_the_one_owed() {
    const FRAMES: u64 = 6;
    let renderer = test_renderer();
    renderer.set_recording(Recording::Batched);
    renderer.set_timing(Timing::Off);
    renderer.set_submission(Submission::Thread);
    let device = &renderer.gpu.device;
    let buffer = |label, size, usage| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage,
            mapped_at_creation: false,
        })
    };
    use wgpu::BufferUsages as U;
    let value = buffer("value", 4, U::COPY_SRC | U::COPY_DST);
    let slots = buffer("slots", 4 * FRAMES, U::COPY_SRC | U::COPY_DST);
    let readback = buffer("readback", 4 * FRAMES, U::MAP_READ | U::COPY_DST);
    for k in 0..FRAMES {
        // As a node's evaluation writes a uniform before its frame records,
        // while the frame before may still be owed: wgpu applies the write
        // at the next submit, which must be this frame's.
        renderer
            .gpu
            .queue
            .write_buffer(&value, 0, &(k as u32).to_le_bytes());
        let mut fg = spreadlight_render::FrameGraph::new((4, 4));
        let names: Vec<String> = (0..8).map(|i| format!("pass {i}")).collect();
        for (i, name) in names.iter().enumerate() {
            let mut pass = fg.pass(
                spreadlight_render::frame_graph::PassName::new(name.clone()),
                Some(i as u32),
            );
            pass.write(name, spreadlight_render::TextureDesc::token());
            let (value, slots) = (&value, &slots);
            pass.run(move |cx| {
                if i == 7 {
                    cx.encoder()
                        .copy_buffer_to_buffer(value, 0, slots, 4 * k, 4);
                }
                Ok(())
            });
            fg.request(name);
        }
        let report = fg.execute(&renderer).expect("the frame executes").0;
        assert!(report.errors.is_empty(), "{:?}", report.errors);
    }
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(&slots, 0, &readback, 0, 4 * FRAMES);
    renderer.gpu.submit([encoder.finish()]);
    let slice = readback.slice(..);
    slice.map_async(wgpu::MapMode::Read, |r| r.expect("maps"));
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("drains");
    let bytes = slice.get_mapped_range().expect("mapped").to_vec();
    let seen: Vec<u32> = bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    assert_eq!(seen, (0..FRAMES as u32).collect::<Vec<_>>());
}
