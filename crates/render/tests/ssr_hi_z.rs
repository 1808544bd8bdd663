//! SSR's hierarchical depth, built two levels a dispatch and the small
//! levels in one workgroup: every level is
//! the nearest (largest reversed-Z) depth under each texel, its 2x2 and at
//! the last row or column whatever an odd level leaves, checked level by
//! level against the same rule on the CPU, at a size whose levels are odd.

use crate::post_common;

use std::sync::Arc;

use glam::Vec3;
use post_common::image;
use spreadlight_render::camera::CameraInput;
use spreadlight_render::environment::{SSR_HIZ_DISPATCHES, Ssr, SsrSettings};
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::material::{Feature, Material, MaterialWorld};
use spreadlight_render::readback::{ImageF32, read_texture, read_texture_layer, render_and_read};
use spreadlight_render::renderer::test_renderer;
use spreadlight_render::scenes::{balls_on_floor, with_materials};
use spreadlight_render::texture::mips::level_count;
use spreadlight_render::{Renderer, SizeRule};

fn gbuffer(renderer: &Renderer, size: (u32, u32)) -> Arc<GBuffer> {
    let layer =
        balls_on_floor(renderer, &[(Vec3::new(0.0, 0.6, 0.0), 0.6)], 8.0, 32).expect("upload");
    let camera = CameraInput {
        // Rolled, so the floor's depth changes along rows as well as down
        // columns (level with the horizon it would not): a texel left out
        // of a footprint shows.
        view: glam::camera::rh::view::look_at_mat4(
            Vec3::new(0.0, 1.5, 4.0),
            Vec3::new(0.0, 0.3, 0.0),
            Vec3::new(0.4, 1.0, 0.0),
        ),
        projection: glam::camera::rh::proj::directx::perspective(
            1.0,
            size.0 as f32 / size.1 as f32,
            0.1,
            100.0,
        ),
    };
    GBuffer::new(
        renderer,
        None,
        vec![with_materials(&layer, 0, 1)],
        camera,
        None,
        SizeRule::Relative(1.0),
    )
}

/// The texels of the level below under texel `k` along one axis (the rule
/// shaders/environment/ssr.wgsl's `footprint` keeps).
fn footprint(k: u32, out: u32, src: u32) -> std::ops::RangeInclusive<u32> {
    let lo = k * 2;
    let hi = if k + 1 == out {
        src - 1
    } else {
        (lo + 1).min(src - 1)
    };
    lo..=hi
}

fn downsample(level: &ImageF32) -> ImageF32 {
    let (w, h) = ((level.width / 2).max(1), (level.height / 2).max(1));
    let mut pixels = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let mut nearest = 0.0f32;
            for sy in footprint(y, h, level.height) {
                for sx in footprint(x, w, level.width) {
                    nearest = nearest.max(level.pixel(sx, sy)[0]);
                }
            }
            pixels.push([nearest, 0.0, 0.0, 0.0]);
        }
    }
    ImageF32 {
        width: w,
        height: h,
        pixels,
    }
}

/// 99 x 61: levels of 49 x 30, 24 x 15, 12 x 7, 6 x 3, 3 x 1, 1 x 1 (seven
/// in all): the copy and mip 1 from an odd depth, then levels 2 (24 x 15) to
/// 6 in one workgroup, which halves odd levels along x and along y.
#[test]
fn every_hi_z_level_is_the_nearest_depth_under_it_at_odd_sizes() {
    hi_z_is_the_nearest_depth_under_it((99, 61), 2);
}

/// 601 x 7: levels of 300 x 3, 150 x 1, 75 x 1, 37 x 1, 18 x 1 ... 1 x 1 (ten
/// in all): the copy and mip 1 (odd along both axes), mips 2 and 3 together
/// (mip 2's one row from mip 1's three), mip 4 alone (37 from 75), then 5
/// (18 x 1) to 9 in one workgroup.
#[test]
fn every_hi_z_level_is_the_nearest_depth_under_it_through_every_kind_of_dispatch() {
    hi_z_is_the_nearest_depth_under_it((601, 7), 4);
}

/// 130 x 70: levels of 65 x 35, 32 x 17, 16 x 8 ... 1 x 1 (eight in all): the
/// copy and mip 1, then 2 (32 x 17, the widest level a tail starts from,
/// made from an odd one along both axes) to 7 in one workgroup, every one of
/// its six slots a level it writes.
#[test]
fn every_hi_z_level_is_the_nearest_depth_under_it_when_the_tail_fills_all_its_slots() {
    hi_z_is_the_nearest_depth_under_it((130, 70), 2);
}

fn hi_z_is_the_nearest_depth_under_it(size: (u32, u32), dispatches: u64) {
    let renderer = test_renderer();
    let g = gbuffer(&renderer, size);
    let lit = image(&renderer, size, |_, _| [0.5, 0.5, 0.5, 1.0]);
    let mirror = Material::new()
        .with(Feature::CookTorrance, &[[0.0, 1.0, 0.04, 0.0]])
        .and_then(|m| m.with(Feature::Reflection, &[[1.0, 0.0, 0.0, 0.0]]))
        .expect("valid");
    let materials = MaterialWorld::new(&renderer, vec![mirror.clone(), mirror]);
    let ssr = Ssr::new(
        &renderer,
        None,
        g.clone(),
        materials,
        lit.texture_ref(),
        lit.texture_ref(),
        SsrSettings::default(),
    );
    let (report, images) = render_and_read(
        &renderer,
        ssr.as_ref(),
        size,
        &[&ssr.output, &g.targets.depth],
    )
    .expect("renders");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.counter(SSR_HIZ_DISPATCHES), dispatches);
    let depth = &images[1];
    let hiz = ssr.hi_z().expect("the hi-z was built");
    assert_eq!(hiz.mip_level_count(), level_count(size.0, size.1));
    let mut below = read_texture(&renderer.gpu, &hiz).expect("reads");
    assert!(
        below
            .pixels
            .iter()
            .zip(&depth.pixels)
            .all(|(h, d)| h[0] == d[0]),
        "mip 0 is the depth"
    );
    assert!(below.pixels.iter().any(|p| p[0] > 0.0) && below.pixels.iter().any(|p| p[0] == 0.0));
    for mip in 1..hiz.mip_level_count() {
        let level = read_texture_layer(&renderer.gpu, &hiz, 0, mip).expect("reads");
        let want = downsample(&below);
        assert_eq!((level.width, level.height), (want.width, want.height));
        for (i, (got, want)) in level.pixels.iter().zip(&want.pixels).enumerate() {
            assert_eq!(got[0], want[0], "mip {mip}, texel {i}");
        }
        below = level;
    }
}
