//! Shader node costs on the CPU. Run with
//! `cargo bench -p spreadlight-nodes --bench shader_nodes`.
//!
//! - `node_evaluation`: Noise -> N x `Blur (Shader)` -> Probe, every node
//!   re-run each frame (`invalidate_all`). The Probe is a sink that renders
//!   nothing, so this is the nodes' own work (pins into the uniform block,
//!   the permutation lookup, the limits check, the recipe): time / (N + 1)
//!   per shader node per frame (target: under 20 µs).
//! - `reload_200_lines`: a 200-line shader file read from disk, parsed,
//!   validated, checked against its annotations and swapped into the
//!   registry, as a save in the editor does (target: under 100 ms).
//!   Pipelines are created on the next frame that uses them, like any pass's.

use spreadlight_graph::{FrameClock, NodeDoc, Patch, Runtime};
use spreadlight_nodes::shader_nodes::ShaderLibrary;

fn main() {
    divan::main();
}

const CHAIN: u32 = 100;

#[divan::bench(counter = divan::counter::ItemsCount::new(CHAIN as usize + 1))]
fn node_evaluation(bencher: divan::Bencher) {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "Noise (Shader)"));
    let mut prev = 1;
    for i in 0..CHAIN {
        let id = 2 + i;
        p.add(NodeDoc::new(id, "Blur (Shader)"));
        p.link(prev, "Texture", id, "Texture");
        prev = id;
    }
    p.add(NodeDoc::new(2 + CHAIN, "Probe").with("Name", vec!["end".to_owned()]));
    p.link(prev, "Texture", 2 + CHAIN, "Input");
    let mut rt = Runtime::new(spreadlight_nodes::registry());
    rt.provide(spreadlight_render::renderer::test_renderer());
    assert!(rt.load(&p).is_empty(), "benchmark patch has problems");
    let mut frame = 0;
    bencher.bench_local(|| {
        rt.invalidate_all();
        let stats = rt.evaluate(FrameClock::fixed(frame, 60.0));
        assert_eq!(stats.failed, 0);
        frame += 1;
    });
}

/// The blur example grown to 200 lines with helper functions (all parsed and validated).
fn two_hundred_lines(variant: u32) -> String {
    let mut text = spreadlight_render::shader_source!("nodes/blur.wgsl").to_owned();
    let mut k = 0;
    while text.lines().count() < 196 {
        text.push_str(&format!(
            "\nfn helper_{k}(x: vec4<f32>) -> vec4<f32> {{\n    return x * {variant}.0 + vec4<f32>(f32({k}));\n}}\n"
        ));
        k += 1;
    }
    text
}

#[divan::bench]
fn reload_200_lines(bencher: divan::Bencher) {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("big.wgsl");
    let mut library = ShaderLibrary::new(vec![dir.path().to_owned()]);
    let mut registry = spreadlight_nodes::registry();
    assert_eq!(
        two_hundred_lines(1).lines().count() / 10,
        19,
        "about 200 lines"
    );
    let mut variant = 0u32;
    bencher
        .with_inputs(|| {
            // A different length each time, so the library sees a change.
            variant += 1;
            std::fs::write(
                &path,
                two_hundred_lines(variant) + &" ".repeat(variant as usize % 7 + 1),
            )
            .expect("write");
        })
        .bench_local_values(|()| {
            let changes = library.poll(&mut registry);
            assert_eq!(changes.updated.len(), 1);
            assert!(library.errors().is_empty(), "{:?}", library.errors());
        });
}
