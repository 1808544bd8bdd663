//! `BenchLights` (category "Bench"): the light placement of the shared
//! benchmark scene (shared/bench/README.md), exactly: xorshift64 from a seed,
//! per light x, y, z, r, g, b in that order, so Spreadlight's picture and
//! timings compare with Bevy's on the same lights.

use glam::Vec3;
use spreadlight_graph::{Color, NodeDef, Registry};

/// The benchmark's generator: `s ^= s << 13; s ^= s >> 7; s ^= s << 17`.
pub struct Xorshift64(u64);

impl Xorshift64 {
    pub fn new(seed: u64) -> Self {
        // Zero is xorshift's fixed point; the benchmark never uses it, but a user might.
        Xorshift64(if seed == 0 {
            0x9E37_79B9_7F4A_7C15
        } else {
            seed
        })
    }

    pub fn next_u64(&mut self) -> u64 {
        let mut s = self.0;
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        self.0 = s;
        s
    }

    /// Uniform in [0, 1): `(next() >> 11) / 2^53`.
    pub fn next_unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The benchmark's lights: positions and colours, in order.
pub fn bench_lights(count: usize, seed: u64) -> (Vec<Vec3>, Vec<Color>) {
    let mut rng = Xorshift64::new(seed);
    let mut positions = Vec::with_capacity(count);
    let mut colors = Vec::with_capacity(count);
    for _ in 0..count {
        let mut u = || rng.next_unit() as f32;
        let x = -50.0 + 100.0 * u();
        let y = 0.5 + 2.5 * u();
        let z = -50.0 + 100.0 * u();
        positions.push(Vec3::new(x, y, z));
        let (r, g, b) = (u(), u(), u());
        colors.push(Color::rgba(r, g, b, 1.0));
    }
    (positions, colors)
}

/// More lights than any scene should need; beyond it a typo, not a scene.
const MAX_LIGHTS: i64 = 10_000_000;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "BenchLights",
            "Bench",
            "The shared benchmark's point-light placement (shared/bench/README.md): Count lights from xorshift64 \
             with Seed, x in -50..50, y in 0.5..3, z in -50..50, colour uniform in 0..1.",
        )
        .input("Count", 1000i64)
        .input("Seed", 1i64)
        .output::<Vec3>("Position")
        .output::<Color>("Color")
        .evaluate(|cx| {
            let count = cx.slices::<i64>(0)?.first().copied().unwrap_or(0);
            if !(0..=MAX_LIGHTS).contains(&count) {
                return Err(cx.input_error(0, format!("must be 0 to {MAX_LIGHTS}")));
            }
            let seed = cx.slices::<i64>(1)?.first().copied().unwrap_or(1) as u64;
            let (positions, colors) = bench_lights(count as usize, seed);
            cx.set(0, positions);
            cx.set(1, colors);
            Ok(())
        }),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sequence_is_the_benchmarks() {
        // Seed 1: the first state after one step is 1 ^ 1<<13 ..., computed by hand once:
        let mut rng = Xorshift64::new(1);
        let first = rng.next_u64();
        let mut s: u64 = 1;
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        assert_eq!(first, s);
        let (p, c) = bench_lights(1000, 1);
        assert_eq!(p.len(), 1000);
        assert!(p.iter().all(|p| (-50.0..50.0).contains(&p.x)
            && (0.5..3.0).contains(&p.y)
            && (-50.0..50.0).contains(&p.z)));
        assert!(c.iter().all(|c| (0.0..1.0).contains(&c.r)));
        // Deterministic: the same seed gives the same lights.
        assert_eq!(bench_lights(10, 1), bench_lights(10, 1));
        assert_ne!(bench_lights(10, 1).0, bench_lights(10, 2).0);
    }
}
