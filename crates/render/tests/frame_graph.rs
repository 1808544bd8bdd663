//! The frame graph's contract: culling by what is requested, clear errors for
//! impossible graphs, persistent textures across frames, and a failing pass
//! reported against its node while the rest of the frame renders.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use spreadlight_render::frame_graph::{Bindings, PassContext, PassName, Tex};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::{FrameGraph, Lifetime, RenderError, SizeRule, TextureDesc};

fn target() -> TextureDesc {
    TextureDesc::storage(wgpu::TextureFormat::Rgba16Float)
}

/// Declare a pass by the names it reads and writes, for the tests of
/// scheduling, culling, merging and errors, whose runs resolve no texture
/// (a run that does takes the handles `FrameGraph::pass` gives).
fn declare_pass<'a>(
    fg: &mut FrameGraph<'a>,
    name: &'static str,
    owner: Option<u32>,
    reads: &[&str],
    writes: &[(&str, TextureDesc)],
    run: impl FnOnce(&mut PassContext<'_>) -> Result<(), RenderError> + 'a,
) {
    let mut pass = fg.pass(name, owner);
    for read in reads {
        pass.read(read);
    }
    for (write, desc) in writes {
        pass.write(write, *desc);
    }
    pass.run(run);
}

#[test]
fn only_passes_leading_to_a_request_run() {
    let renderer = test_renderer();
    let ran = Arc::new(AtomicUsize::new(0));
    let mut fg = FrameGraph::new((16, 16));
    let counter = |ran: &Arc<AtomicUsize>| {
        let ran = ran.clone();
        move |cx: &mut PassContext<'_>| {
            ran.fetch_add(1, Ordering::SeqCst);
            let _ = cx.output_size;
            Ok(())
        }
    };
    declare_pass(
        &mut fg,
        "a",
        Some(1),
        &[],
        &[("a", target())],
        counter(&ran),
    );
    declare_pass(
        &mut fg,
        "b",
        Some(2),
        &["a"],
        &[("b", target())],
        counter(&ran),
    );
    declare_pass(
        &mut fg,
        "unused c",
        Some(3),
        &["a"],
        &[("c", target())],
        counter(&ran),
    );
    declare_pass(
        &mut fg,
        "unused d",
        Some(4),
        &["c"],
        &[("d", target())],
        counter(&ran),
    );
    fg.request("b");
    let (report, outputs) = fg.execute(&renderer).expect("executes");
    assert_eq!(
        report
            .passes
            .iter()
            .map(|p| p.kind.as_ref())
            .collect::<Vec<_>>(),
        ["a", "b"]
    );
    assert_eq!(report.culled, ["unused c #3", "unused d #4"]);
    assert_eq!(ran.load(Ordering::SeqCst), 2, "culled passes never record");
    assert!(outputs.contains_key("b") && !outputs.contains_key("a"));
}

/// A pass runs when any of its outputs is read, and can ask which are: an
/// output no live pass reads (nor the caller) is not read this frame.
#[test]
fn a_pass_with_two_outputs_knows_which_the_frame_reads() {
    let renderer = test_renderer();
    let seen = Arc::new(Mutex::new(Vec::new()));
    for wanted in [vec!["left"], vec!["right user"], vec!["left", "right user"]] {
        let mut fg = FrameGraph::new((4, 4));
        let s = seen.clone();
        let mut pass = fg.pass("two", None);
        let (left, right) = (pass.write("left", target()), pass.write("right", target()));
        pass.run(move |cx| {
            s.lock()
                .expect("lock")
                .push((cx.is_read(left), cx.is_read(right)));
            Ok(())
        });
        declare_pass(
            &mut fg,
            "user",
            None,
            &["right"],
            &[("right user", target())],
            |_| Ok(()),
        );
        for name in &wanted {
            fg.request(name);
        }
        fg.execute(&renderer).expect("executes");
    }
    assert_eq!(
        *seen.lock().expect("lock"),
        [(true, false), (false, true), (true, true)]
    );
}

/// What the passes of a merging test ran, in order.
type Log = Arc<Mutex<Vec<&'static str>>>;

/// A pass that adds `what` to `log` when it runs.
fn logs(
    log: &Log,
    what: &'static str,
) -> impl FnOnce(&mut PassContext<'_>) -> Result<(), RenderError> + 'static {
    let log = log.clone();
    move |_| {
        log.lock().expect("log").push(what);
        Ok(())
    }
}

/// A pass named `name` that reads `reads`, writes `write` and logs its
/// name when it runs.
fn logged_pass<'a>(
    fg: &mut FrameGraph<'a>,
    log: &Log,
    name: &'static str,
    reads: &[&str],
    write: &str,
) {
    declare_pass(fg, name, None, reads, &[(write, target())], logs(log, name));
}

/// Two passes declared to run together: one pass when the frame needs both,
/// each alone when it needs one, and never merged when the second reads
/// what the first makes.
#[test]
fn a_pair_that_runs_together_is_one_pass_only_when_both_are_needed() {
    let renderer = test_renderer();
    let log: Log = Arc::default();
    let frame = |requests: &[&str], second_reads_first: bool| {
        let mut fg = FrameGraph::new((16, 16));
        let run = |what: &'static str| logs(&log, what);
        logged_pass(&mut fg, &log, "source", &[], "source");
        logged_pass(&mut fg, &log, "first", &["source"], "a");
        let reads: &[&str] = if second_reads_first {
            &["source", "a"]
        } else {
            &["source"]
        };
        logged_pass(&mut fg, &log, "second", reads, "b");
        fg.runs_together("both", run("both"));
        for r in requests {
            fg.request(r);
        }
        log.lock().expect("log").clear();
        let (report, outputs) = fg.execute(&renderer).expect("executes");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        for r in requests {
            assert!(outputs.contains_key(*r), "{r} is handed back");
        }
        let names: Vec<String> = report.passes.iter().map(|p| p.name.clone()).collect();
        (names, report.culled, log.lock().expect("log").clone())
    };
    let (names, culled, ran) = frame(&["a", "b"], false);
    assert_eq!(names, ["source", "both"]);
    assert!(culled.is_empty());
    assert_eq!(ran, ["source", "both"]);
    let (names, culled, ran) = frame(&["b"], false);
    assert_eq!(names, ["source", "second"]);
    assert_eq!(culled, ["first"]);
    assert_eq!(ran, ["source", "second"]);
    let (names, _, ran) = frame(&["a"], false);
    assert_eq!(names, ["source", "first"]);
    assert_eq!(ran, ["source", "first"]);
    let (names, _, ran) = frame(&["a", "b"], true);
    assert_eq!(names, ["source", "first", "second"]);
    assert_eq!(ran, ["source", "first", "second"]);
}

/// A pass chained into the one whose output it reads: one pass that never
/// makes the inner output, unless something else reads that output.
#[test]
fn a_chain_is_one_pass_only_when_nothing_else_reads_the_inner_output() {
    let renderer = test_renderer();
    let log: Log = Arc::default();
    let frame = |requests: &[&str], third_reads_inner: bool| {
        let mut fg = FrameGraph::new((16, 16));
        let run = |what: &'static str| logs(&log, what);
        logged_pass(&mut fg, &log, "source", &[], "source");
        logged_pass(&mut fg, &log, "inner", &["source"], "inner");
        logged_pass(&mut fg, &log, "outer", &["inner"], "outer");
        fg.chains_into("inner", "inner and outer", run("both"));
        if third_reads_inner {
            logged_pass(&mut fg, &log, "third", &["inner"], "third");
        }
        for r in requests {
            fg.request(r);
        }
        log.lock().expect("log").clear();
        let (report, outputs) = fg.execute(&renderer).expect("executes");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        let names: Vec<String> = report.passes.iter().map(|p| p.name.clone()).collect();
        (names, log.lock().expect("log").clone(), outputs.len())
    };
    let (names, ran, outputs) = frame(&["outer"], false);
    assert_eq!(names, ["source", "inner and outer"]);
    assert_eq!(ran, ["source", "both"]);
    assert_eq!(outputs, 1);
    let (names, ran, ..) = frame(&["outer", "inner"], false);
    assert_eq!(names, ["source", "inner", "outer"]);
    assert_eq!(ran, ["source", "inner", "outer"]);
    let (names, ..) = frame(&["outer", "third"], true);
    assert_eq!(names, ["source", "inner", "outer", "third"]);

    // A merged pass of two nodes that fails is reported to both.
    let mut fg = FrameGraph::new((16, 16));
    declare_pass(
        &mut fg,
        "source",
        None,
        &[],
        &[("source", target())],
        logs(&log, "source"),
    );
    declare_pass(
        &mut fg,
        "inner",
        Some(7),
        &["source"],
        &[("inner", target())],
        logs(&log, "inner"),
    );
    declare_pass(
        &mut fg,
        "outer",
        Some(8),
        &["inner"],
        &[("outer", target())],
        logs(&log, "outer"),
    );
    fg.chains_into("inner", "inner and outer", |_| {
        Err(RenderError::Graph("broken".to_owned()))
    });
    fg.request("outer");
    let (report, _) = fg.execute(&renderer).expect("executes");
    let mut blamed: Vec<Option<u32>> = report.errors.iter().map(|(owner, _)| *owner).collect();
    blamed.sort();
    assert_eq!(blamed, [Some(7), Some(8)], "{:?}", report.errors);
    let merged = report
        .passes
        .iter()
        .find(|p| p.kind == "inner and outer")
        .expect("ran");
    assert_eq!((merged.owner, merged.partner), (Some(7), Some(8)));
}

/// A watched texture (the editor's thumbnails) leaves the frame as it is:
/// the chain still merges and its inner output is not handed back, no pass
/// is kept from culling, usage is not widened; a texture the frame makes
/// and reads is handed back; one no pass of the frame needs is made for the
/// watch alone; an output no pass reads (left unwritten) is not handed back.
#[test]
fn a_watch_hands_back_what_the_frame_makes_and_changes_nothing_else() {
    let renderer = test_renderer();
    let log: Log = Arc::default();
    // Sampled and stored, not copied: a request would add COPY_SRC.
    let narrow = TextureDesc {
        usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
        ..target()
    };
    let frame = |watches: &[&str]| {
        let mut fg = FrameGraph::new((16, 16));
        let run = |what: &'static str| logs(&log, what);
        declare_pass(
            &mut fg,
            "source",
            None,
            &[],
            &[("source", narrow), ("unread", narrow)],
            run("source"),
        );
        logged_pass(&mut fg, &log, "inner", &["source"], "inner");
        logged_pass(&mut fg, &log, "outer", &["inner"], "outer");
        fg.chains_into("inner", "inner and outer", run("both"));
        logged_pass(&mut fg, &log, "aside", &["source"], "aside");
        fg.request("outer");
        for w in watches {
            fg.watch(w);
        }
        log.lock().expect("log").clear();
        let (report, outputs) = fg.execute(&renderer).expect("executes");
        assert!(report.errors.is_empty(), "{:?}", report.errors);
        let names: Vec<String> = report.passes.iter().map(|p| p.name.clone()).collect();
        let mut handed: Vec<String> = outputs.keys().cloned().collect();
        handed.sort();
        (names, handed, outputs)
    };
    let (alone, ..) = frame(&[]);
    assert_eq!(alone, ["source", "inner and outer"]);
    // Watching the chain's inner output and the first pass's outputs: the
    // same passes, merged as before; what was made and read comes back,
    // with its own usage.
    let (names, handed, outputs) = frame(&["inner", "source", "unread"]);
    assert_eq!(names, alone);
    assert_eq!(handed, ["outer", "source"]);
    assert!(
        !outputs["source"]
            .usage()
            .contains(wgpu::TextureUsages::COPY_SRC),
        "a watch widened the texture's usage"
    );
    assert_eq!(log.lock().expect("log").clone(), ["source", "both"]);
    // A texture no pass of the frame needs is made for the watch alone.
    let (names, handed, _) = frame(&["aside"]);
    assert_eq!(names, ["source", "inner and outer", "aside"]);
    assert_eq!(handed, ["aside", "outer"]);
}

#[test]
fn passes_run_in_dependency_order_whatever_the_declaration_order() {
    let renderer = test_renderer();
    let order = Arc::new(std::sync::Mutex::new(Vec::new()));
    let mut fg = FrameGraph::new((8, 8));
    for (name, reads) in [
        ("last", vec!["mid"]),
        ("mid", vec!["first"]),
        ("first", vec![]),
    ] {
        let order = order.clone();
        declare_pass(
            &mut fg,
            name,
            None,
            &reads,
            &[(name, target())],
            move |_| {
                order.lock().expect("lock").push(name);
                Ok(())
            },
        );
    }
    fg.request("last");
    fg.execute(&renderer).expect("executes");
    assert_eq!(*order.lock().expect("lock"), ["first", "mid", "last"]);
}

#[test]
fn impossible_graphs_are_clear_errors() {
    let renderer = test_renderer();
    let mut fg = FrameGraph::new((8, 8));
    declare_pass(
        &mut fg,
        "reader",
        None,
        &["nowhere"],
        &[("out", target())],
        |_| Ok(()),
    );
    fg.request("out");
    let err = fg
        .execute(&renderer)
        .map(|_| ())
        .expect_err("refused")
        .to_string();
    assert!(
        err.contains("pass `reader` reads `nowhere`, which no pass writes"),
        "{err}"
    );

    let mut fg = FrameGraph::new((8, 8));
    declare_pass(&mut fg, "one", None, &[], &[("x", target())], |_| Ok(()));
    declare_pass(&mut fg, "two", None, &[], &[("x", target())], |_| Ok(()));
    fg.request("x");
    let err = fg
        .execute(&renderer)
        .map(|_| ())
        .expect_err("refused")
        .to_string();
    assert!(
        err.contains("`x` is written by two passes, `one` and `two`"),
        "{err}"
    );

    let mut fg = FrameGraph::new((8, 8));
    fg.request("ghost");
    let err = fg
        .execute(&renderer)
        .map(|_| ())
        .expect_err("refused")
        .to_string();
    assert!(
        err.contains("`ghost` was requested, but no pass writes it"),
        "{err}"
    );
}

#[test]
fn persistent_textures_keep_their_history_across_frames() {
    let renderer = test_renderer();
    // One frame with a persistent texture; says whether the pass found it fresh (no history).
    let frame = || {
        let fresh = Arc::new(std::sync::Mutex::new(None));
        let seen = fresh.clone();
        let mut fg = FrameGraph::new((8, 8));
        let mut pass = fg.pass("history", None);
        let history = pass.write("history", target().lifetime(Lifetime::Persistent));
        pass.run(move |cx| {
            *seen.lock().expect("lock") = Some(cx.is_fresh(history));
            Ok(())
        });
        fg.request("history");
        let (report, _) = fg.execute(&renderer).expect("executes");
        assert!(report.errors.is_empty());
        fresh.lock().expect("lock").expect("the pass ran")
    };
    assert_eq!([frame(), frame(), frame()], [true, false, false]);
    renderer.reset_history();
    assert!(frame(), "a reset (camera cut) starts history again");
}

#[test]
fn relative_sizes_follow_the_output() {
    let fg = FrameGraph::new((1920, 1080));
    let quarter = fg.resolve(&target().size(SizeRule::Relative(0.25)));
    assert_eq!((quarter.width, quarter.height), (480, 270));
    let fixed = fg.resolve(&target().size(SizeRule::Absolute {
        width: 512,
        height: 512,
    }));
    assert_eq!((fixed.width, fixed.height), (512, 512));
    let tiny = fg.resolve(&target().size(SizeRule::Relative(0.0001)));
    assert_eq!((tiny.width, tiny.height), (1, 1), "never zero-sized");
}

/// A pass that makes a validation error: a buffer both MAP_READ and MAP_WRITE.
fn invalid_buffer(cx: &mut PassContext<'_>) -> Result<(), RenderError> {
    let _ = cx.gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("invalid"),
        size: 16,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::MAP_WRITE,
        mapped_at_creation: false,
    });
    Ok(())
}

#[test]
fn a_pass_with_a_validation_error_is_reported_on_its_node_and_the_rest_renders() {
    let renderer = test_renderer();
    let ran_after = Arc::new(AtomicUsize::new(0));
    let mut fg = FrameGraph::new((8, 8));
    declare_pass(
        &mut fg,
        "broken",
        Some(42),
        &[],
        &[("broken", target())],
        invalid_buffer,
    );
    let after = ran_after.clone();
    declare_pass(
        &mut fg,
        "healthy",
        Some(7),
        &[],
        &[("healthy", target())],
        move |_| {
            after.fetch_add(1, Ordering::SeqCst);
            Ok(())
        },
    );
    fg.request("broken");
    fg.request("healthy");
    let (report, outputs) = fg.execute(&renderer).expect("the frame still executes");
    assert_eq!(report.errors.len(), 1, "{:?}", report.errors);
    assert_eq!(
        report.errors[0].0,
        Some(42),
        "the error names the node whose pass caused it"
    );
    assert!(
        report.errors[0].1.contains("pass `broken #42`"),
        "{}",
        report.errors[0].1
    );
    assert_eq!(ran_after.load(Ordering::SeqCst), 1);
    assert!(outputs.contains_key("healthy"));
}

/// A texture one past the adapter's largest 2D side fails its pass before
/// anything is allocated (wgpu would refuse it outside any error scope: a
/// panic in its default handler), with an error naming the pass, the
/// texture, its size and the limit; the rest of the frame renders.
#[test]
fn a_texture_past_the_adapter_s_limit_fails_its_pass_naming_the_limit() {
    let renderer = test_renderer();
    let max = renderer.gpu.device.limits().max_texture_dimension_2d;
    let ran = Arc::new(AtomicUsize::new(0));
    let mut fg = FrameGraph::new((8, 8));
    let counted = ran.clone();
    declare_pass(
        &mut fg,
        "huge",
        Some(9),
        &[],
        &[(
            "huge",
            target().size(SizeRule::Absolute {
                width: max + 1,
                height: 1,
            }),
        )],
        move |_| {
            counted.fetch_add(1, Ordering::SeqCst);
            Ok(())
        },
    );
    declare_pass(&mut fg, "fine", Some(7), &[], &[("fine", target())], |_| {
        Ok(())
    });
    fg.request("huge");
    fg.request("fine");
    let (report, outputs) = fg.execute(&renderer).expect("the frame still executes");
    assert_eq!(
        report.errors,
        [(
            Some(9),
            format!(
                "pass `huge #9`: texture `huge` ({}x1 for a 8x8 frame) is past the adapter's limit \
                 max_texture_dimension_2d ({max})",
                max + 1
            )
        )]
    );
    assert_eq!(ran.load(Ordering::SeqCst), 0, "the pass never recorded");
    assert!(!outputs.contains_key("huge") && outputs.contains_key("fine"));
    assert!(renderer.gpu.take_uncaptured_errors().is_empty());
}

/// A device error outside every error scope does not panic (wgpu's default
/// handler would): it is kept, and the next frame reports it.
#[test]
fn an_error_outside_any_scope_is_reported_by_the_next_frame_not_a_panic() {
    let renderer = test_renderer();
    // A buffer both mapped for reading and for writing: invalid, and in no scope.
    let _ = renderer.gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("outside"),
        size: 16,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::MAP_WRITE,
        mapped_at_creation: false,
    });
    // A frame of one pass that does nothing wrong.
    let fine_frame = || {
        let mut fg = FrameGraph::new((4, 4));
        declare_pass(
            &mut fg,
            "fine",
            None,
            &[],
            &[("fine", target())],
            |_| Ok(()),
        );
        fg.request("fine");
        fg.execute(&renderer).expect("executes")
    };
    let (report, outputs) = fine_frame();
    assert!(outputs.contains_key("fine"));
    assert_eq!(report.errors.len(), 1, "{:?}", report.errors);
    assert_eq!(report.errors[0].0, None);
    assert!(
        report.errors[0]
            .1
            .starts_with("GPU error outside any pass: ")
            && report.errors[0].1.contains("outside"),
        "{}",
        report.errors[0].1
    );
    // Taken once: the next frame is clean.
    let (report, _) = fine_frame();
    assert!(report.errors.is_empty(), "{:?}", report.errors);
}

/// What a frame hands back can be read by any sink, whatever usage its
/// pass declared: copied (Output's readback) and sampled (the viewport).
#[test]
fn requested_textures_can_be_copied_and_sampled() {
    use spreadlight_render::readback::read_texture;
    let renderer = test_renderer();
    let mut fg = FrameGraph::new((4, 4));
    let bare = TextureDesc {
        usage: wgpu::TextureUsages::STORAGE_BINDING,
        ..target()
    };
    declare_pass(&mut fg, "bare", None, &[], &[("bare", bare)], |_| Ok(()));
    fg.request("bare");
    let planned = fg.planned("bare").expect("planned");
    assert!(
        planned
            .usage
            .contains(spreadlight_render::frame_graph::READABLE)
    );
    let (report, outputs) = fg.execute(&renderer).expect("executes");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let texture = &outputs["bare"];
    assert!(
        texture
            .usage()
            .contains(spreadlight_render::frame_graph::READABLE)
    );
    let image = read_texture(&renderer.gpu, texture).expect("reads back");
    assert_eq!((image.width, image.height), (4, 4));
}

/// A host's commands ride the frame's own submission
/// (`FrameGraph::execute_then`): they get the textures the frame hands back
/// before it submits, run after its passes (a copy of the frame's last
/// output holds what the passes wrote, not the cleared texture it was
/// before them), and the frame with them is one submission through the gate
/// (the editor's blits into its viewport and thumbnails: each submission of
/// its worker waits for a UI frame).
#[test]
fn a_host_s_commands_go_in_the_frame_s_submission_after_its_passes() {
    use spreadlight_render::post::CopyKey;
    use spreadlight_render::readback::read_texture;
    use spreadlight_render::shaders::Permutation;
    let renderer = test_renderer();
    let mut fg = FrameGraph::new((8, 8));
    let mut seeded = target();
    seeded.usage |= wgpu::TextureUsages::COPY_DST;
    let mut pass = fg.pass("seed", None);
    let s0 = pass.write("s0", seeded);
    pass.run(move |cx| {
        seed_ramp(cx, &cx.texture(s0)?.clone());
        Ok(())
    });
    let mut pass = fg.pass("copy", None);
    let (source, output) = (pass.read("s0"), pass.write("s1", target()));
    pass.run(move |cx| {
        cx.dispatch_image(
            "copy",
            &CopyKey.key(),
            Bindings::new()
                .texture("source", source)
                .texture("output", output),
            (8, 8),
        )
    });
    fg.request("s1");
    let device = &renderer.gpu.device;
    let copy = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("host copy"),
        size: wgpu::Extent3d {
            width: 8,
            height: 8,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba16Float,
        usage: wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let gate = renderer.gpu.submission_gate().clone();
    let before = gate.counts();
    let mut handed = Vec::new();
    let (report, outputs) = fg
        .execute_then(&renderer, |outputs| {
            handed = outputs.keys().cloned().collect();
            let mut encoder = device.create_command_encoder(&Default::default());
            encoder.copy_texture_to_texture(
                outputs["s1"].as_image_copy(),
                copy.as_image_copy(),
                copy.size(),
            );
            vec![encoder.finish()]
        })
        .expect("executes");
    let counts = gate.counts().since(before);
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(handed, ["s1"], "the host gets what the frame hands back");
    assert_eq!(
        counts.submissions, 1,
        "the frame and the host's copy: one submission"
    );
    assert_eq!(report.counters.get("host command buffers"), Some(&1));
    let made = read_texture(&renderer.gpu, &outputs["s1"]).expect("reads back");
    let copied = read_texture(&renderer.gpu, &copy).expect("reads back");
    assert_eq!(made.pixels[9][0], 9.0 / 64.0, "the frame's passes ran");
    assert_eq!(copied.pixels, made.pixels, "after them, the host's copy");
}

/// A readback whose buffer would be one byte past the adapter's largest is
/// refused before anything is allocated, naming the size and the limit.
#[test]
fn a_readback_past_the_adapter_s_largest_buffer_is_refused_naming_the_limit() {
    use spreadlight_render::readback::readback_layout;
    use spreadlight_render::texture_pool::TextureKey;
    let renderer = test_renderer();
    let max = renderer.gpu.device.limits().max_buffer_size;
    // R32Float rows of 16384 pixels are 64 KiB, aligned already: the
    // largest whole number of rows that fits, and one row more.
    let rows = u32::try_from(max / 65536).expect("a largest buffer under 256 TiB");
    let key = |height: u32| TextureKey {
        format: wgpu::TextureFormat::R32Float,
        width: 16384,
        height,
        usage: wgpu::TextureUsages::COPY_SRC,
    };
    let (_, row, size) = readback_layout(&renderer.gpu, &key(rows), "it").expect("fits");
    assert_eq!((row, size), (65536, u64::from(rows) * 65536));
    let error = readback_layout(&renderer.gpu, &key(rows + 1), "the test's texture")
        .expect_err("one row too many");
    assert_eq!(
        error.to_string(),
        format!(
            "the readback of the test's texture (16384x{} R32Float: a {}-byte buffer) is past the \
             adapter's limit max_buffer_size ({max})",
            rows + 1,
            u64::from(rows + 1) * 65536
        )
    );
    // And what cannot be copied from is said so, not left to wgpu.
    let error = readback_layout(
        &renderer.gpu,
        &TextureKey {
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            ..key(1)
        },
        "it",
    )
    .expect_err("no COPY_SRC");
    assert!(error.to_string().contains("without COPY_SRC"), "{error}");
}

/// A frame of three dependent compute passes that fill, add to and scale an
/// image, so recording and timing modes can be compared on real work.
fn arithmetic_frame(renderer: &spreadlight_render::Renderer) -> Vec<[f32; 4]> {
    use spreadlight_render::post::CopyKey;
    use spreadlight_render::readback::render_and_read;
    use spreadlight_render::shaders::Permutation;
    struct Chain;
    impl spreadlight_render::Recipe for Chain {
        fn declare<'a>(&'a self, _: &'a spreadlight_render::Renderer, fg: &mut FrameGraph<'a>) {
            // A seeded image, then two hops of post/copy.wgsl.
            let mut seeded = target();
            seeded.usage |= wgpu::TextureUsages::COPY_DST;
            let mut pass = fg.pass("seed", None);
            let s0 = pass.write("s0", seeded);
            pass.run(move |cx| {
                seed_ramp(cx, &cx.texture(s0)?.clone());
                Ok(())
            });
            for (from, to) in [("s0", "s1"), ("s1", "s2")] {
                let mut pass = fg.pass(PassName::new("copy").step(to.to_string()), None);
                let (source, output) = (pass.read(from), pass.write(to, target()));
                pass.run(move |cx| {
                    cx.dispatch_image(
                        "copy",
                        &CopyKey.key(),
                        Bindings::new()
                            .texture("source", source)
                            .texture("output", output),
                        (8, 8),
                    )
                });
            }
        }
    }
    let (report, images) = render_and_read(renderer, &Chain, (8, 8), &["s2"]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    images[0].pixels.clone()
}

#[test]
fn batched_recording_and_every_timing_render_the_same_frame() {
    use spreadlight_render::renderer::{Recording, Timing};
    let renderer = test_renderer();
    let reference = arithmetic_frame(&renderer);
    assert!(
        reference.iter().any(|p| p[0] > 0.5),
        "the chain carried the seed"
    );
    let timed = renderer.last_report();
    for (timing, recording) in [
        (Timing::PerPass, Recording::Batched),
        (Timing::Frame, Recording::Isolated),
        (Timing::Frame, Recording::Batched),
        (Timing::Off, Recording::Batched),
        (Timing::Off, Recording::Isolated),
    ] {
        renderer.set_timing(timing);
        renderer.set_recording(recording);
        assert_eq!(
            arithmetic_frame(&renderer),
            reference,
            "{timing:?} {recording:?}"
        );
        let report = renderer.last_report();
        assert_eq!(report.passes.len(), 3);
        if timing == Timing::Off {
            assert!(report.passes.iter().all(|p| p.gpu_ms.is_none()));
            assert_eq!(report.gpu_frame_ms, None);
        }
        if timing == Timing::Frame && timed.gpu_frame_ms.is_some() {
            // First and last pass only; the span is still measured.
            assert!(report.passes[1].gpu_ms.is_none());
            assert!(report.gpu_frame_ms.is_some() && report.gpu_ms.is_none());
        }
    }
    renderer.wait_idle().expect("drains");
}

#[test]
fn a_batched_frame_that_fails_validation_is_dropped_and_the_next_names_the_pass() {
    use spreadlight_render::renderer::Recording;
    let renderer = test_renderer();
    renderer.set_recording(Recording::Batched);
    let frame = || {
        let mut fg = FrameGraph::new((8, 8));
        declare_pass(
            &mut fg,
            "broken",
            Some(42),
            &[],
            &[("broken", target())],
            invalid_buffer,
        );
        declare_pass(
            &mut fg,
            "healthy",
            Some(7),
            &[],
            &[("healthy", target())],
            |_| Ok(()),
        );
        fg.request("broken");
        fg.request("healthy");
        fg.execute(&renderer).expect("the frame still executes").0
    };
    let first = frame();
    assert_eq!(first.errors.len(), 1, "{:?}", first.errors);
    assert!(
        first.errors[0].1.contains("dropped"),
        "{}",
        first.errors[0].1
    );
    assert_eq!(renderer.settings().1, Recording::Isolated);
    let second = frame();
    assert_eq!(second.errors.len(), 1);
    assert_eq!(second.errors[0].0, Some(42));
    // What hosts check each frame: the report's errors, without the report.
    assert_eq!(renderer.last_errors(), second.errors);
}

/// Every graph executed since the timings were last taken counts in them
/// (a frame of a patch with several Outputs executes one for each); the
/// last report holds only the last graph's.
#[test]
fn the_timings_of_every_graph_executed_are_kept_until_taken() {
    let renderer = test_renderer();
    renderer.take_graph_timings();
    arithmetic_frame(&renderer);
    arithmetic_frame(&renderer);
    arithmetic_frame(&renderer);
    let timings = renderer.take_graph_timings();
    assert_eq!(timings.graphs, 3);
    assert!(timings.record_ms >= renderer.last_report().record_ms);
    assert_eq!(renderer.take_graph_timings().graphs, 0, "taken once");
}

#[test]
fn a_repeated_frame_reuses_its_bind_groups_and_texture_views() {
    let renderer = test_renderer();
    let first = arithmetic_frame(&renderer);
    let report = renderer.last_report();
    assert!(
        report.counter("bind groups created") >= 2,
        "{:?}",
        report.counters
    );
    assert!(
        report.counter("texture views created") >= 3,
        "{:?}",
        report.counters
    );
    // Pooled textures may trade places once (a lent output comes back);
    // from then on the frame binds what it bound before.
    for _ in 0..3 {
        assert_eq!(arithmetic_frame(&renderer), first);
    }
    let report = renderer.last_report();
    assert_eq!(
        report.counter("bind groups created"),
        0,
        "{:?}",
        report.counters
    );
    assert_eq!(
        report.counter("texture views created"),
        0,
        "{:?}",
        report.counters
    );
    assert!(report.counter("bind groups reused") >= 2);
    assert!(report.counter("texture views reused") >= 3);
    // The plan was kept: each copy's groups and pipeline came from its last
    // frame's call without a look-up (and count as reused).
    assert!(
        report.counter("bind groups kept") >= 2,
        "{:?}",
        report.counters
    );
    assert!(
        report.counter("pipelines kept") >= 2,
        "{:?}",
        report.counters
    );
}

/// [`arithmetic_frame`] as a re-made recipe declares it: its textures named
/// after a new id each frame (`frame`), its passes named as before.
fn renamed_frame(renderer: &spreadlight_render::Renderer, frame: u32) -> Vec<[f32; 4]> {
    use spreadlight_render::post::CopyKey;
    use spreadlight_render::readback::render_and_read;
    use spreadlight_render::shaders::Permutation;
    struct Chain([String; 3]);
    impl spreadlight_render::Recipe for Chain {
        fn declare<'a>(&'a self, _: &'a spreadlight_render::Renderer, fg: &mut FrameGraph<'a>) {
            let [s0, s1, s2] = &self.0;
            let mut seeded = target();
            seeded.usage |= wgpu::TextureUsages::COPY_DST;
            let mut pass = fg.pass("seed", Some(7));
            let seed = pass.write(s0, seeded);
            pass.run(move |cx| {
                seed_ramp(cx, &cx.texture(seed)?.clone());
                Ok(())
            });
            // Two passes of one name (as SSSS declares its three blurs).
            for (from, to) in [(s0, s1), (s1, s2)] {
                let mut pass = fg.pass("copy", Some(7));
                let (source, output) = (pass.read(from), pass.write(to, target()));
                pass.run(move |cx| {
                    cx.dispatch_image(
                        "copy",
                        &CopyKey.key(),
                        Bindings::new()
                            .texture("source", source)
                            .texture("output", output),
                        (8, 8),
                    )
                });
            }
        }
    }
    let chain = Chain([0, 1, 2].map(|i| format!("s{i} of recipe {frame}")));
    let requested = chain.0[2].clone();
    let (report, images) =
        render_and_read(renderer, &chain, (8, 8), &[requested.as_str()]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    images[0].pixels.clone()
}

#[test]
fn a_re_made_recipe_binds_the_textures_its_passes_had_last_frame() {
    let renderer = test_renderer();
    let first = renamed_frame(&renderer, 0);
    assert!(renderer.last_report().counter("bind groups created") >= 2);
    // Each frame names its textures anew; the passes (by name and order)
    // get last frame's textures back, so nothing new is bound from frame 2 on.
    for frame in 1..5 {
        assert_eq!(renamed_frame(&renderer, frame), first);
        let report = renderer.last_report();
        if frame >= 2 {
            assert_eq!(
                report.counter("bind groups created"),
                0,
                "frame {frame}: {:?}",
                report.counters
            );
            assert_eq!(report.counter("texture views created"), 0);
            assert!(report.counter("bind groups reused") >= 2);
        }
    }
}

/// Write an 8x8 grey ramp (0, 1/64, ... 63/64; alpha 1) into the seed texture.
fn seed_ramp(cx: &PassContext<'_>, t: &wgpu::Texture) {
    let data: Vec<u8> = (0..8 * 8)
        .flat_map(|i| {
            let v = half::f16::from_f32(i as f32 / 64.0).to_le_bytes();
            [v, v, v, half::f16::ONE.to_le_bytes()].concat()
        })
        .collect();
    cx.gpu.queue.write_texture(
        t.as_image_copy(),
        &data,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(8 * 8),
            rows_per_image: None,
        },
        t.size(),
    );
}

/// A frame of two temporal passes as the built-in effects declare them,
/// seeded with `value`: "previous" (copy_history, as AO and SSGI do) and
/// "kept" (keep_as_history, as TAA and SSR do). Returns what the frame read
/// as last frame's history through each, then this frame's result.
fn temporal_frame(renderer: &spreadlight_render::Renderer, value: f32) -> [f32; 3] {
    temporal_frame_requesting(renderer, value, &[])
}

/// [`temporal_frame`], also handing `more` textures to the caller.
fn temporal_frame_requesting(
    renderer: &spreadlight_render::Renderer,
    value: f32,
    more: &[&str],
) -> [f32; 3] {
    use spreadlight_render::post::CopyKey;
    use spreadlight_render::readback::render_and_read;
    use spreadlight_render::shaders::Permutation;
    fn copy(cx: &mut PassContext<'_>, from: Tex, to: Tex) -> Result<(), RenderError> {
        cx.dispatch_image(
            "copy",
            &CopyKey.key(),
            Bindings::new()
                .texture("source", from)
                .texture("output", to),
            (8, 8),
        )
    }
    struct Temporal(f32);
    impl spreadlight_render::Recipe for Temporal {
        fn declare<'a>(&'a self, _: &'a spreadlight_render::Renderer, fg: &mut FrameGraph<'a>) {
            let rgba = wgpu::TextureFormat::Rgba16Float;
            let mut seeded = target();
            seeded.usage |= wgpu::TextureUsages::COPY_DST;
            let value = self.0;
            let mut pass = fg.pass("seed", None);
            let now = pass.write("now", seeded);
            pass.run(move |cx| {
                let texel = [half::f16::from_f32(value).to_le_bytes(); 4].concat();
                let t = cx.texture(now)?.clone();
                cx.gpu.queue.write_texture(
                    t.as_image_copy(),
                    &texel.repeat(64),
                    wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(8 * 8),
                        rows_per_image: None,
                    },
                    t.size(),
                );
                Ok(())
            });
            // AO's shape: last frame's history into "previous", then the
            // history written anew.
            let mut pass = fg.pass("ao-like", None);
            let now = pass.read("now");
            let history = pass.write("history", TextureDesc::history(rgba));
            let previous = pass.write("previous", TextureDesc::history_twin(rgba));
            let read_previous = pass.write("read previous", target());
            pass.run(move |cx| {
                cx.copy_history(history, previous)?;
                copy(cx, previous, read_previous)?;
                copy(cx, now, history)
            });
            // TAA's shape: the history read, the output written, and the
            // output kept as next frame's history; a later pass reads it.
            let mut pass = fg.pass("taa-like", None);
            let now = pass.read("now");
            let output = pass.write("output", TextureDesc::history_twin(rgba));
            let kept = pass.write("kept", TextureDesc::history(rgba));
            let read_kept = pass.write("read kept", target());
            pass.run(move |cx| {
                copy(cx, kept, read_kept)?;
                copy(cx, now, output)?;
                cx.keep_as_history(output, kept)
            });
            let mut pass = fg.pass("after", None);
            let (output, shown) = (pass.read("output"), pass.write("shown", target()));
            pass.run(move |cx| copy(cx, output, shown));
        }
    }
    let mut requested = vec!["read previous", "read kept", "shown"];
    requested.extend(more);
    let (report, images) =
        render_and_read(renderer, &Temporal(value), (8, 8), &requested).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    let at = |k: usize| {
        let p = &images[k].pixels;
        assert!(p.iter().all(|t| *t == p[0]), "one value in every texel");
        p[0][0]
    };
    [at(0), at(1), at(2)]
}

#[test]
fn temporal_histories_trade_textures_instead_of_copying_and_read_last_frames_result() {
    use spreadlight_render::frame_graph::{HISTORIES_COPIED, HISTORIES_HANDED_OVER};
    let renderer = test_renderer();
    temporal_frame(&renderer, 0.25);
    for (frame, value) in [0.5f32, 0.75, 1.0, 1.25, 1.5, 1.75].into_iter().enumerate() {
        let last = 0.25 * (frame + 1) as f32;
        // Both shapes read exactly last frame's result, and later passes
        // this frame's, though no texture was copied.
        assert_eq!(temporal_frame(&renderer, value), [last, last, value]);
        let report = renderer.last_report();
        assert_eq!(
            report.counter(HISTORIES_HANDED_OVER),
            2,
            "{:?}",
            report.counters
        );
        assert_eq!(report.counter(HISTORIES_COPIED), 0);
        // The two textures of each history alternate (the two histories
        // share a format and size, and so a pool): nothing new is made or
        // bound once both have been seen.
        if frame >= 2 {
            assert_eq!(report.textures_created, 0, "frame {frame}");
            assert_eq!(
                report.counter("bind groups created"),
                0,
                "frame {frame}: {:?}",
                report.counters
            );
            assert_eq!(report.counter("texture views created"), 0);
        }
    }
}

#[test]
fn a_history_whose_twin_the_caller_takes_is_copied_and_still_right() {
    use spreadlight_render::frame_graph::{HISTORIES_COPIED, HISTORIES_HANDED_OVER};
    // TAA's output as the frame's final image: it goes to the caller (a
    // viewport shows it), so it cannot become the history; the history is
    // copied from it, and AO's pair still trades.
    let renderer = test_renderer();
    temporal_frame_requesting(&renderer, 0.25, &["output"]);
    for (frame, value) in [0.5f32, 0.75, 1.0].into_iter().enumerate() {
        let last = 0.25 * (frame + 1) as f32;
        assert_eq!(
            temporal_frame_requesting(&renderer, value, &["output"]),
            [last, last, value]
        );
        let report = renderer.last_report();
        assert_eq!(report.counter(HISTORIES_COPIED), 1, "{:?}", report.counters);
        assert_eq!(report.counter(HISTORIES_HANDED_OVER), 1);
    }
}

/// One pass's errors after a frame of `declare`, requesting `wanted`.
fn frame_errors(declare: impl FnOnce(&mut FrameGraph<'_>), wanted: &str) -> Vec<String> {
    let renderer = test_renderer();
    let mut fg = FrameGraph::new((8, 8));
    declare(&mut fg);
    fg.request(wanted);
    let (report, _) = fg.execute(&renderer).expect("executes");
    report.errors.into_iter().map(|(_, e)| e).collect()
}

/// A pass resolves only the handles of what it declared: another pass's
/// texture, even one alive at that moment, is an error naming it.
#[test]
fn a_pass_reaches_only_the_textures_it_declared() {
    let errors = frame_errors(
        |fg| {
            let mut pass = fg.pass("a", None);
            let a = pass.write("a", target());
            pass.run(|_| Ok(()));
            let mut pass = fg.pass("b", None);
            pass.read("a");
            pass.write("b", target());
            pass.run(|_| Ok(()));
            let mut pass = fg.pass("c", Some(3));
            pass.read("b");
            pass.write("c", target());
            pass.run(move |cx| cx.view(a).map(|_| ()));
        },
        "c",
    );
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].contains("pass `c #3`") && errors[0].contains("`a`, which it did not declare"),
        "{errors:?}"
    );
}

/// Bindings by name: a name the shader never declares (a typo) and a
/// variable the shader uses that the pass left unbound are errors naming
/// the variable, not a validation error about binding numbers.
#[test]
fn bindings_by_name_name_a_typo_and_a_missing_variable() {
    use spreadlight_render::post::CopyKey;
    use spreadlight_render::shaders::Permutation;
    let copy = |typo: bool| {
        move |fg: &mut FrameGraph<'_>| {
            let mut pass = fg.pass("source", None);
            pass.write("s", target());
            pass.run(|_| Ok(()));
            let mut pass = fg.pass("copy", Some(5));
            let (source, output) = (pass.read("s"), pass.write("o", target()));
            pass.run(move |cx| {
                let bindings = Bindings::new().texture("output", output);
                let bindings = match typo {
                    true => bindings.texture("sourc", source),
                    false => bindings,
                };
                cx.dispatch_image("copy", &CopyKey.key(), bindings, (8, 8))
            });
        }
    };
    let errors = frame_errors(copy(true), "o");
    assert!(
        errors.len() == 1 && errors[0].contains("binds `sourc`, which the shader does not declare"),
        "{errors:?}"
    );
    let errors = frame_errors(copy(false), "o");
    assert!(
        errors.len() == 1
            && errors[0].contains(
                "`source` (group 0, binding 0) is used by the shader but no pass binds it"
            ),
        "{errors:?}"
    );
}

/// The size an image effect takes from its source (`FrameGraph::effect_size`):
/// an imported texture's pixels, a pass output's size rule as declared, and
/// the frame's size for a texture nothing declared.
#[test]
fn an_image_effect_takes_its_sources_size() {
    let renderer = test_renderer();
    let file = spreadlight_render::static_texture::StaticTexture::from_rgba32f(
        &renderer.gpu,
        64,
        36,
        &[[0.5; 4]; 64 * 36],
        "file",
    );
    let mut fg = FrameGraph::new((96, 54));
    fg.import("file", file.texture.texture.clone());
    let half = SizeRule::Relative(0.5);
    let fixed = SizeRule::Absolute {
        width: 20,
        height: 10,
    };
    declare_pass(
        &mut fg,
        "writer",
        None,
        &[],
        &[
            ("frame", target()),
            ("half", target().size(half)),
            ("fixed", target().size(fixed)),
        ],
        |_| Ok(()),
    );
    assert_eq!(
        fg.effect_size("file"),
        SizeRule::Absolute {
            width: 64,
            height: 36
        }
    );
    assert_eq!(fg.effect_size("frame"), SizeRule::Relative(1.0));
    assert_eq!(fg.effect_size("half"), half);
    assert_eq!(fg.effect_size("fixed"), fixed);
    assert_eq!(fg.effect_size("undeclared"), SizeRule::Relative(1.0));
}

/// A frame as a recipe re-made every frame declares it: pass "A" writes
/// `a{id}/out`, "B" reads it and writes `b{id}/out` (the names carry the
/// recipe's id, new each time it is made), "H" keeps a persistent
/// `history` (named `history_name`), and with `extra` a pass "C" reads B's
/// output. Returns the requested name.
fn re_made_frame<'a>(
    fg: &mut FrameGraph<'a>,
    id: u32,
    format: wgpu::TextureFormat,
    history_name: &str,
    extra: bool,
) -> String {
    let (a, b, c) = (
        format!("a{id}/out"),
        format!("b{id}/out"),
        format!("c{id}/out"),
    );
    let mut pass = fg.pass("A", Some(1));
    let written = pass.write(&a, TextureDesc::storage(format));
    pass.run(move |cx| cx.texture(written).map(|_| ()));
    let mut pass = fg.pass("B", Some(2));
    let read = pass.read(&a);
    let written = pass.write(&b, TextureDesc::storage(format));
    let history = pass.write(history_name, TextureDesc::history(format));
    pass.run(move |cx| {
        cx.texture(read)?;
        cx.texture(history)?;
        cx.texture(written).map(|_| ())
    });
    if extra {
        let mut pass = fg.pass("C", Some(3));
        let read = pass.read(&b);
        let written = pass.write(&c, TextureDesc::storage(format));
        pass.run(move |cx| {
            cx.texture(read)?;
            cx.texture(written).map(|_| ())
        });
        fg.request(&c);
        return c;
    }
    fg.request(&b);
    b
}

/// A graph declared again as it was (its recipes made again under new
/// names) runs on last frame's plan, and hands its output back under this
/// frame's name; a change to what was declared (a texture's format, as a
/// pin that changes a key does; the output size; a pass added; a
/// persistent texture's name) makes a new plan; with reuse off every frame
/// plans afresh. The passes, textures and outputs are the same either way.
#[test]
fn a_frame_declared_again_reuses_its_plan_and_any_change_makes_a_new_one() {
    let renderer = test_renderer();
    let rgba16 = wgpu::TextureFormat::Rgba16Float;
    // (output size, format, history name, extra pass, reused)
    let frames = [
        ((16, 16), rgba16, "history", false, false),
        ((16, 16), rgba16, "history", false, true),
        ((16, 16), rgba16, "history", false, true),
        ((24, 16), rgba16, "history", false, false),
        ((24, 16), rgba16, "history", false, true),
        (
            (24, 16),
            wgpu::TextureFormat::Rgba8Unorm,
            "history",
            false,
            false,
        ),
        (
            (24, 16),
            wgpu::TextureFormat::Rgba8Unorm,
            "history",
            true,
            false,
        ),
        (
            (24, 16),
            wgpu::TextureFormat::Rgba8Unorm,
            "history",
            true,
            true,
        ),
        (
            (24, 16),
            wgpu::TextureFormat::Rgba8Unorm,
            "other history",
            true,
            false,
        ),
        // Back to a frame seen before: its plan was kept.
        ((16, 16), rgba16, "history", false, true),
    ];
    let run = |reuse: bool| {
        renderer.set_plan_reuse(reuse);
        let mut seen = Vec::new();
        for (id, &(size, format, history, extra, reused)) in frames.iter().enumerate() {
            let mut fg = FrameGraph::new(size);
            let requested = re_made_frame(&mut fg, id as u32, format, history, extra);
            let (report, outputs) = fg.execute(&renderer).expect("executes");
            assert!(report.errors.is_empty(), "frame {id}: {:?}", report.errors);
            let reused = reuse && reused;
            assert_eq!(
                (report.counter("plans reused"), report.counter("plans made")),
                (u64::from(reused), u64::from(!reused)),
                "frame {id}"
            );
            let texture = outputs
                .get(&requested)
                .unwrap_or_else(|| panic!("frame {id}: no `{requested}` in {:?}", outputs.keys()));
            assert_eq!(
                (texture.width(), texture.height(), texture.format()),
                (size.0, size.1, format)
            );
            assert_eq!(outputs.len(), 1, "frame {id}");
            seen.push(
                report
                    .passes
                    .iter()
                    .map(|p| p.name.clone())
                    .collect::<Vec<_>>(),
            );
        }
        seen
    };
    let reusing = run(true);
    renderer.reset_history();
    let afresh = run(false);
    // The same passes ran in each frame, with or without a kept plan.
    assert_eq!(reusing, afresh);
    assert_eq!(reusing[6], ["A #1", "B #2", "C #3"]);
    renderer.set_plan_reuse(true);
    renderer.wait_idle().expect("drains");
}

/// A frame whose pass "pick" copies one of two imported images (`pick`: 0
/// or 1, each a flat grey of its own) into `picked` and whose pass "other"
/// copies the other into `other` (their roles trade as a history and its
/// twin do); returns both outputs' first pixels and the frame's report.
fn picked_frame(
    renderer: &spreadlight_render::Renderer,
    images: &[Arc<spreadlight_render::static_texture::StaticTexture>; 2],
    pick: usize,
) -> ([[f32; 4]; 2], spreadlight_render::FrameReport) {
    picked_frame_at(renderer, images, pick, (8, 8))
}

/// [`picked_frame`] at output size `size`.
fn picked_frame_at(
    renderer: &spreadlight_render::Renderer,
    images: &[Arc<spreadlight_render::static_texture::StaticTexture>; 2],
    pick: usize,
    size: (u32, u32),
) -> ([[f32; 4]; 2], spreadlight_render::FrameReport) {
    use spreadlight_render::post::CopyKey;
    use spreadlight_render::readback::render_and_read;
    use spreadlight_render::shaders::Permutation;
    struct Pick(
        [Arc<spreadlight_render::static_texture::StaticTexture>; 2],
        usize,
    );
    impl spreadlight_render::Recipe for Pick {
        fn declare<'a>(&'a self, _: &'a spreadlight_render::Renderer, fg: &mut FrameGraph<'a>) {
            fg.import("image 0", self.0[0].texture.texture.clone());
            fg.import("image 1", self.0[1].texture.texture.clone());
            for (name, image) in [("picked", self.1), ("other", 1 - self.1)] {
                let mut pass = fg.pass(name, Some(5));
                let sources = [pass.read("image 0"), pass.read("image 1")];
                let output = pass.write(name, target());
                let source = sources[image];
                pass.run(move |cx| {
                    cx.dispatch_image(
                        "copy",
                        &CopyKey.key(),
                        Bindings::new()
                            .texture("source", source)
                            .texture("output", output),
                        (8, 8),
                    )
                });
            }
        }
    }
    let recipe = Pick(images.clone(), pick);
    let (report, images) =
        render_and_read(renderer, &recipe, size, &["picked", "other"]).expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    ([images[0].pixels[0], images[1].pixels[0]], report)
}

/// A frame on a kept plan takes each dispatch's pipeline and bind groups
/// from what it resolved before (`pipelines kept`, `bind groups kept`)
/// only while it binds the same: a dispatch binding another texture than
/// last frame binds the new one, and one going back to what it bound
/// before that (a history and its twin in turns) takes those groups again;
/// another graph rendered in turns keeps its own.
#[test]
fn a_kept_plan_s_dispatch_binds_what_it_binds_now() {
    use spreadlight_render::static_texture::StaticTexture;
    let renderer = test_renderer();
    let grey = |v: f32, name: &str| {
        StaticTexture::from_rgba32f(&renderer.gpu, 8, 8, &[[v, v, v, 1.0]; 64], name)
    };
    let images = [grey(0.25, "image 0"), grey(0.75, "image 1")];
    let kept = |report: &spreadlight_render::FrameReport| {
        (
            report.counter("pipelines kept"),
            report.counter("bind groups kept"),
        )
    };
    let wanted = |pick: usize| {
        let [a, b] = [[0.25, 0.75][pick], [0.25, 0.75][1 - pick]];
        [[a, a, a, 1.0], [b, b, b, 1.0]]
    };
    // (which image "picked" copies, whether the frame's groups are kept):
    // the plan is made in the first frame and taken from the second, whose
    // calls are kept from then on.
    let frames = [
        (0, false),
        (0, false),
        (0, true),
        // The images trade roles: resolved afresh, each bound where it is now.
        (1, false),
        (1, true),
        // And back: kept from before.
        (0, true),
        (1, true),
        (0, true),
    ];
    for (frame, &(pick, groups_kept)) in frames.iter().enumerate() {
        let (pixels, report) = picked_frame(&renderer, &images, pick);
        assert_eq!(pixels, wanted(pick), "frame {frame}");
        let (pipelines, groups) = kept(&report);
        assert_eq!(
            report.counter("plans reused"),
            u64::from(frame > 0),
            "frame {frame}"
        );
        if frame > 1 {
            // The copies' pipeline, whatever they bind.
            assert_eq!(pipelines, 2, "frame {frame}: {:?}", report.counters);
        } else {
            assert_eq!((pipelines, groups), (0, 0), "frame {frame}");
        }
        let all = if groups_kept { 2 } else { 0 };
        assert_eq!(groups, all, "frame {frame}: {:?}", report.counters);
        if groups_kept {
            assert_eq!(report.counter("bind groups created"), 0, "frame {frame}");
            assert_eq!(report.counter("bind groups reused"), 2, "frame {frame}");
        }
    }
    // Another graph rendered in turns with this one (a patch with two
    // Outputs): each plan keeps its own calls.
    for turn in 0..4 {
        // The other graph: the same passes at another size, so another plan.
        let (pixels, other) = picked_frame_at(&renderer, &images, 1, (16, 8));
        assert_eq!(pixels, wanted(1), "turn {turn}");
        let (pixels, report) = picked_frame(&renderer, &images, 0);
        assert_eq!(pixels, wanted(0), "turn {turn}");
        // Pipelines only: the view cache makes the views of a texture no
        // frame used again (each graph's outputs, here), so their groups
        // are new in each turn.
        assert_eq!(kept(&report).0, 2, "turn {turn}: {:?}", report.counters);
        // Its plan is made in its first turn and keeps its calls from its second.
        let other_kept = if turn > 1 { 2 } else { 0 };
        assert_eq!(
            kept(&other).0,
            other_kept,
            "turn {turn}: {:?}",
            other.counters
        );
    }
    // Planned afresh each frame, nothing is kept and the images are the same.
    renderer.set_plan_reuse(false);
    for pick in [0, 1, 0] {
        let (pixels, report) = picked_frame(&renderer, &images, pick);
        assert_eq!(pixels, wanted(pick));
        assert_eq!(kept(&report), (0, 0), "{:?}", report.counters);
    }
    renderer.set_plan_reuse(true);
    // Kept bindings off: the plan is kept, every call looks its pipeline and
    // groups up in the shader cache, and the images are the same.
    renderer.set_kept_bindings(false);
    for (frame, pick) in [0, 0, 1, 0].into_iter().enumerate() {
        let (pixels, report) = picked_frame(&renderer, &images, pick);
        assert_eq!(pixels, wanted(pick));
        // Planned again in the first (plans made afresh were not kept).
        assert_eq!(report.counter("plans reused"), u64::from(frame > 0));
        assert_eq!(kept(&report), (0, 0), "{:?}", report.counters);
    }
    renderer.set_kept_bindings(true);
    renderer.wait_idle().expect("drains");
}
