//! How long posing a skinned herd takes on the CPU, apart from the GPU
//! dispatch that deforms it: node world transforms (animation channels
//! sampled), then each skinned instance's joint palette and posed bounds,
//! as the glTF node does each frame. A measurement, not a test:
//!
//! `cargo run --release -p spreadlight-gltf --example pose_time [-- FILE.gltf FRAMES]`
//! (default patches/assets/bench-skinning.gltf, 2000 frames). The instances
//! are posed on the posing threads, as the node poses a herd; with
//! `SL_SERIAL` set, on this thread alone (session 30 measured both on the
//! H200's host: docs/benchmarks.md).

use std::path::PathBuf;
use std::time::Instant;

use rayon::prelude::*;
use spreadlight_gltf::load_gltf;

fn main() {
    let mut args = std::env::args().skip(1);
    let file = args.next().map_or_else(
        || PathBuf::from("patches/assets/bench-skinning.gltf"),
        PathBuf::from,
    );
    let frames: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(2000);
    let parallel = std::env::var_os("SL_SERIAL").is_none();
    let scene = load_gltf(&file).expect("the file loads");
    let animation = (!scene.animations.is_empty()).then_some(0);
    let mut worlds_ms = Vec::with_capacity(frames);
    let mut poses_ms = Vec::with_capacity(frames);
    let mut joints = 0;
    for frame in 0..frames {
        let time = frame as f32 / 60.0;
        let start = Instant::now();
        let world = scene.node_worlds(animation, time);
        let weights = scene.morph_weights(animation, time);
        let posed = Instant::now();
        let pose = |i: &spreadlight_gltf::MeshInstance| {
            scene
                .is_deformed(i)
                .then(|| scene.deform_pose(i, &world, &weights))
        };
        let poses: Vec<_> = if parallel {
            spreadlight_gltf::pool::posing(|| {
                scene
                    .instances
                    .par_iter()
                    .with_min_len(8)
                    .map(pose)
                    .collect()
            })
        } else {
            scene.instances.iter().map(pose).collect()
        };
        worlds_ms.push((posed - start).as_secs_f64() * 1e3);
        poses_ms.push(posed.elapsed().as_secs_f64() * 1e3);
        joints = poses.iter().flatten().map(|p| p.palette.len()).sum();
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    println!(
        "{}: {} instances, {joints} joints; node worlds {:.3} ms, poses ({}) {:.3} ms (medians of {frames})",
        file.display(),
        scene.instances.len(),
        median(&mut worlds_ms),
        if parallel {
            "posing threads"
        } else {
            "one thread"
        },
        median(&mut poses_ms),
    );
}
