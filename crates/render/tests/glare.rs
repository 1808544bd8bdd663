//! Glare: a bright spot glows, fading with distance; below the threshold
//! nothing glows; chromatic aberration parts red from blue radially; with
//! nothing to add it costs a counted copy.

use crate::post_common;

use post_common::*;
use spreadlight_render::post::glare::SKIPPED;
use spreadlight_render::post::{Glare, GlareSettings};
use spreadlight_render::readback::ImageF32;
use spreadlight_render::renderer::test_renderer;

const SIZE: (u32, u32) = (64, 64);

fn spot(x: u32, y: u32) -> [f32; 4] {
    if x.abs_diff(16) <= 1 && y.abs_diff(32) <= 1 {
        [50.0, 50.0, 50.0, 1.0]
    } else {
        [0.0, 0.0, 0.0, 1.0]
    }
}

fn glare(settings: GlareSettings) -> (ImageF32, u64) {
    let renderer = test_renderer();
    let input = image(&renderer, SIZE, spot);
    let pass = Glare::new(&renderer, None, input.texture_ref(), settings);
    let (report, out) = render(&renderer, pass.as_ref(), &pass.output, SIZE);
    (out, report.counter(SKIPPED))
}

#[test]
fn a_bright_spot_glows_less_with_distance() {
    let (out, skipped) = glare(GlareSettings {
        threshold: 1.0,
        intensity: 1.0,
        spread: 0.8,
        aberration: 0.0,
        levels: 5,
    });
    assert_eq!(skipped, 0);
    let at = |x: u32| out.pixels[(32 * SIZE.0 + x) as usize][1];
    assert!(
        at(20) > at(26) && at(26) > at(34) && at(34) > 0.0,
        "{} {} {}",
        at(20),
        at(26),
        at(34)
    );
    // Energy is spread, not made: the glow beside the spot is far below it.
    assert!(at(20) < 10.0, "{}", at(20));
    // The spot itself stays (source plus glow).
    assert!(at(16) >= 50.0);
}

#[test]
fn below_the_threshold_nothing_glows() {
    let (out, _) = glare(GlareSettings {
        threshold: 100.0,
        intensity: 1.0,
        aberration: 0.0,
        ..Default::default()
    });
    for (i, p) in out.pixels.iter().enumerate() {
        let want = spot(i as u32 % SIZE.0, i as u32 / SIZE.0);
        assert_eq!(p[..3], want[..3], "pixel {i}");
    }
}

#[test]
fn aberration_parts_red_from_blue_radially() {
    let (out, _) = glare(GlareSettings {
        threshold: 1000.0,
        intensity: 0.0,
        aberration: 0.1,
        ..Default::default()
    });
    let centroid = |c: usize| {
        let (mut sum, mut weight) = (0.0, 0.0);
        for (i, p) in out.pixels.iter().enumerate() {
            sum += (i as u32 % SIZE.0) as f32 * p[c];
            weight += p[c];
        }
        sum / weight
    };
    let (r, g, b) = (centroid(0), centroid(1), centroid(2));
    assert!((g - 16.0).abs() < 0.5, "green stays: {g}");
    // Red is read from further out, so it lands nearer the centre (x = 32); blue the other way.
    assert!(r > g + 1.0 && b < g - 1.0, "r {r} g {g} b {b}");
}

/// A source in a filterable format (another node's Rgba16Float output) is
/// read through the sampler, one fetch a tap; one that is not (Rgba32Float)
/// by four loads: the same aberrated image.
#[test]
fn an_aberrated_source_reads_the_same_through_the_sampler_as_by_four_loads() {
    let settings = GlareSettings {
        threshold: 1.0,
        intensity: 0.5,
        aberration: 0.1,
        ..Default::default()
    };
    let ramp = |x: u32, y: u32| {
        let v = (x as f32 * 0.3).sin().abs() * 4.0 + y as f32 * 0.05;
        [v, v * 0.5 + 0.25, 2.0 - v * 0.25, 1.0]
    };
    let renderer = test_renderer();
    let input = image(&renderer, SIZE, ramp);
    let loads = Glare::new(&renderer, None, input.texture_ref(), settings);
    let (_, by_loads) = render(&renderer, loads.as_ref(), &loads.output, SIZE);
    // The same image as Rgba16Float: a Glare that adds nothing copies it.
    let copy = Glare::new(
        &renderer,
        None,
        input.texture_ref(),
        GlareSettings {
            intensity: 0.0,
            aberration: 0.0,
            ..settings
        },
    );
    let filtered = Glare::new(&renderer, None, copy.texture(), settings);
    let (_, by_sampler) = render(&renderer, filtered.as_ref(), &filtered.output, SIZE);
    let mut moved = 0;
    for (i, (a, b)) in by_loads.pixels.iter().zip(&by_sampler.pixels).enumerate() {
        for k in 0..3 {
            assert!(
                (a[k] - b[k]).abs() <= 4e-3 * a[k].abs().max(1.0),
                "pixel {i}, channel {k}: {} by loads, {} by the sampler",
                a[k],
                b[k]
            );
        }
        let (x, y) = (i as u32 % SIZE.0, i as u32 / SIZE.0);
        moved += usize::from((a[0] - ramp(x, y)[0]).abs() > 0.05);
    }
    assert!(moved > 500, "the aberration moved {moved} pixels' red");
}

#[test]
fn nothing_to_add_costs_a_copy() {
    let (out, skipped) = glare(GlareSettings {
        intensity: 0.0,
        aberration: 0.0,
        ..Default::default()
    });
    assert_eq!(skipped, 1);
    assert_eq!(out.pixels[(32 * SIZE.0 + 16) as usize][0], 50.0);
}

/// The glare chain on the CPU, as shaders/post/glare.wgsl defines it (no
/// aberration): bright pass, downs, ups, composite; f32 throughout.
mod reference {
    const HALF_MAX: f32 = 65000.0;

    #[derive(Clone)]
    pub struct Level {
        pub w: u32,
        pub h: u32,
        pub px: Vec<[f32; 3]>,
    }

    impl Level {
        fn at(&self, x: i32, y: i32) -> [f32; 3] {
            let x = x.clamp(0, self.w as i32 - 1) as u32;
            let y = y.clamp(0, self.h as i32 - 1) as u32;
            self.px[(y * self.w + x) as usize]
        }

        fn bilinear(&self, u: f32, v: f32) -> [f32; 3] {
            let (px, py) = (u * self.w as f32 - 0.5, v * self.h as f32 - 0.5);
            let (bx, by) = (px.floor(), py.floor());
            let (fx, fy) = (px - bx, py - by);
            let (ix, iy) = (bx as i32, by as i32);
            let (a, b) = (self.at(ix, iy), self.at(ix + 1, iy));
            let (c, d) = (self.at(ix, iy + 1), self.at(ix + 1, iy + 1));
            std::array::from_fn(|k| {
                let top = a[k] + (b[k] - a[k]) * fx;
                let bottom = c[k] + (d[k] - c[k]) * fx;
                top + (bottom - top) * fy
            })
        }

        fn make(w: u32, h: u32, f: impl Fn(u32, u32) -> [f32; 3]) -> Level {
            let px = (0..w * h).map(|i| f(i % w, i / w)).collect();
            Level { w, h, px }
        }
    }

    fn clamp_half(c: [f32; 3]) -> [f32; 3] {
        c.map(|v| v.clamp(0.0, HALF_MAX))
    }

    /// The glare of `source` (w x h) with `threshold`, `intensity`, `spread`, `levels`.
    pub fn glare(
        source: &Level,
        threshold: f32,
        intensity: f32,
        spread: f32,
        levels: u32,
    ) -> Level {
        let (w, h) = (source.w, source.h);
        let mut n = 1usize;
        while n < levels as usize && (w.min(h) >> (n + 1)) >= 2 {
            n += 1;
        }
        let size = |l: usize| {
            let s = 0.5f32.powi(l as i32 + 1);
            (
                ((w as f32 * s).round() as u32).max(1),
                ((h as f32 * s).round() as u32).max(1),
            )
        };
        let (bw, bh) = size(0);
        let mut downs = vec![Level::make(bw, bh, |x, y| {
            let mut c = [0.0f32; 3];
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let s = source.at(2 * x as i32 + dx, 2 * y as i32 + dy);
                for k in 0..3 {
                    c[k] += s[k].max(0.0);
                }
            }
            let c = c.map(|v| v * 0.25);
            let l = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
            let keep = ((l - threshold).max(0.0) / l.max(1e-6)).min(1.0);
            clamp_half(c.map(|v| v * keep))
        })];
        for l in 1..n {
            let (lw, lh) = size(l);
            let prev = downs[l - 1].clone();
            downs.push(Level::make(lw, lh, |x, y| {
                let (u, v) = ((x as f32 + 0.5) / lw as f32, (y as f32 + 0.5) / lh as f32);
                let (tx, ty) = (1.0 / prev.w as f32, 1.0 / prev.h as f32);
                let mut c = [0.0f32; 3];
                for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
                    let s = prev.bilinear(u + sx * tx, v + sy * ty);
                    for k in 0..3 {
                        c[k] += s[k];
                    }
                }
                clamp_half(c.map(|v| v * 0.25))
            }));
        }
        let mut lower = downs[n - 1].clone();
        for l in (0..n - 1).rev() {
            let here = &downs[l];
            let below = lower.clone();
            lower = Level::make(here.w, here.h, |x, y| {
                let (u, v) = (
                    (x as f32 + 0.5) / here.w as f32,
                    (y as f32 + 0.5) / here.h as f32,
                );
                let (tx, ty) = (1.0 / below.w as f32, 1.0 / below.h as f32);
                let mut c = [0.0f32; 3];
                for (sx, sy, weight) in [
                    (0.0, 0.0, 4.0),
                    (-1.0, 0.0, 2.0),
                    (1.0, 0.0, 2.0),
                    (0.0, -1.0, 2.0),
                    (0.0, 1.0, 2.0),
                    (-1.0, -1.0, 1.0),
                    (1.0, 1.0, 1.0),
                    (1.0, -1.0, 1.0),
                    (-1.0, 1.0, 1.0),
                ] {
                    let s = below.bilinear(u + sx * tx, v + sy * ty);
                    for k in 0..3 {
                        c[k] += s[k] * weight;
                    }
                }
                let here = here.at(x as i32, y as i32);
                clamp_half(std::array::from_fn(|k| here[k] + spread * c[k] / 16.0))
            });
        }
        let norm: f32 = (0..levels).map(|i| spread.powi(i as i32)).sum();
        Level::make(w, h, |x, y| {
            let (u, v) = ((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            let glow = lower.bilinear(u, v);
            let base = source.at(x as i32, y as i32);
            std::array::from_fn(|k| {
                (base[k] + intensity * glow[k] / norm.max(1e-6)).clamp(0.0, HALF_MAX)
            })
        })
    }
}

/// The chain gives the glare the CPU gives, to half-float precision, at odd
/// sizes where a level is not half the one before.
#[test]
fn the_chain_gives_the_glare_the_cpu_gives_at_odd_sizes() {
    const ODD: (u32, u32) = (70, 46);
    let texel = |x: u32, y: u32| -> [f32; 4] {
        let spot = if x.abs_diff(20) <= 2 && y.abs_diff(25) <= 1 {
            40.0
        } else {
            0.0
        };
        let ramp = (x as f32 * 0.37 + y as f32 * 0.11).sin().abs() * 3.0;
        [spot + ramp, spot * 0.5 + ramp * 0.3, ramp * 0.7, 1.0]
    };
    let settings = GlareSettings {
        threshold: 1.0,
        intensity: 0.8,
        spread: 0.7,
        aberration: 0.0,
        levels: 6,
    };
    let renderer = test_renderer();
    let input = image(&renderer, ODD, texel);
    let pass = Glare::new(&renderer, None, input.texture_ref(), settings);
    let (report, out) = render(&renderer, pass.as_ref(), &pass.output, ODD);
    // 35x23, 18x12, 9x6, 4x3: four levels (none whose short side would be
    // under 2 pixels); the bright pass, three downs and three ups.
    let passes = |what: &str| passes_named(&report, what);
    assert_eq!((passes("down"), passes("up")), (3, 3));
    let source = reference::Level {
        w: ODD.0,
        h: ODD.1,
        px: (0..ODD.0 * ODD.1)
            .map(|i| {
                let t = texel(i % ODD.0, i / ODD.0);
                [t[0], t[1], t[2]]
            })
            .collect(),
    };
    let want = reference::glare(&source, 1.0, 0.8, 0.7, 6);
    let mut worst = 0.0f32;
    for (got, want) in out.pixels.iter().zip(&want.px) {
        for k in 0..3 {
            worst = worst.max((got[k] - want[k]).abs() / (1.0 + want[k].abs()));
        }
    }
    assert!(worst < 2e-3, "worst relative difference {worst}");
}
