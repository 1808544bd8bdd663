//! How long the glTF importer takes over generated scenes of many nodes
//! (`models::bench_grid`): parsing, accessors, the node tree's world
//! transforms, materials and their images. A measurement for docs/gltf.md,
//! not a test:
//!
//! `cargo run --release -p spreadlight-gltf --example gltf_load_time [-- NODES]`

use std::time::Instant;

use spreadlight_gltf::load_gltf_slice;
use spreadlight_gltf::models;

fn main() {
    let nodes: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(5000);
    for (what, bytes) in [
        (
            "5 meshes, 1 untextured material",
            models::bench_grid(nodes, 5, 0, false),
        ),
        (
            "100 meshes and materials, 200 PNG textures",
            models::bench_grid(nodes, 100, 200, true),
        ),
    ] {
        let mut times: Vec<f64> = (0..9)
            .map(|_| {
                let start = Instant::now();
                let scene = load_gltf_slice(&bytes, None).expect("the generated scene loads");
                let ms = start.elapsed().as_secs_f64() * 1e3;
                assert_eq!(scene.instances.len(), nodes);
                ms
            })
            .collect();
        times.sort_by(f64::total_cmp);
        println!(
            "{nodes} nodes, {what} ({} KiB .gltf, data URI): load {:.1} ms (median of 9; {:.1} to {:.1})",
            bytes.len() / 1024,
            times[4],
            times[0],
            times[8]
        );
    }
}
