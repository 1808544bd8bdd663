//! `BenchLights` (category "Bench"): the light placement of the benchmark
//! scene (docs/bench/scene.md), exactly: xorshift64 from a seed,
//! per light x, y, z, r, g, b in that order, so Spreadlight's picture and
//! timings compare with Bevy's on the same lights.

mod pass_chain;

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
    pass_chain::register(r);
    r.add(
        NodeDef::new(
            "BenchLights",
            "Bench",
            "The benchmark scene's point-light placement (docs/bench/scene.md): Count lights from xorshift64 \
             with Seed, x in -50..50, y in 0.5..3, z in -50..50, colour uniform in 0..1.",
        )
        .with_pins(|p| {
            let count_in = p.input("Count", 1000i64);
            let seed_in = p.input("Seed", 1i64);
            let position = p.output::<Vec3>("Position");
            let color = p.output::<Color>("Color");
            move |cx| {
                let count = cx.first(count_in, 0)?;
                if !(0..=MAX_LIGHTS).contains(&count) {
                    return Err(cx.error(count_in, format!("must be 0 to {MAX_LIGHTS}")));
                }
                let seed = cx.first(seed_in, 1)? as u64;
                let (positions, colors) = bench_lights(count as usize, seed);
                cx.put(position, positions);
                cx.put(color, colors);
                Ok(())
            }
        }),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The generator's first states from seed 1, worked from the scene's
    /// definition (docs/bench/scene.md) outside this code: the first by hand,
    /// s = 1; s ^= s << 13 (0x2001); s ^= s >> 7 (0x2041); s ^= s << 17
    /// (0x4082_2041); the rest with the same three steps in another language.
    const SEED_1_STATES: [u64; 12] = [
        0x4082_2041,
        0x1000_4106_0c01_1441,
        0x9b1e_842f_6e86_2629,
        0xf554_f503_555d_8025,
        0x860c_1fb0_9059_9265,
        0xf6b0_5302_e553_1801,
        0xa246_0108_ebbd_9e71,
        0xc62c_9fc1_14d9_590d,
        0x7d3e_032e_9a79_08ff,
        0x73a3_97e1_324c_252e,
        0x1cca_c1c3_8a4c_36e4,
        0xefad_64f8_379b_9789,
    ];

    #[test]
    fn the_generator_follows_the_scene_definition() {
        let mut rng = Xorshift64::new(1);
        let states: Vec<u64> = (0..12).map(|_| rng.next_u64()).collect();
        assert_eq!(states, SEED_1_STATES);
        // u = (s >> 11) / 2^53: the first state gives 0x4082_2041 >> 11 = 0x81044 = 528452.
        let mut rng = Xorshift64::new(1);
        assert_eq!(rng.next_unit(), 528_452.0 / 9_007_199_254_740_992.0);
    }

    #[test]
    fn the_first_lights_are_the_scene_definitions() {
        // Each light takes six u in the order x, y, z, r, g, b: x = -50 + 100u,
        // y = 0.5 + 2.5u, z = -50 + 100u, r = g = b = u. From SEED_1_STATES,
        // worked out outside this code in f64 and rounded to 8 or more digits:
        let expected = [
            (
                [-49.999_999_994, 0.656_259_69, 10.593_439_25],
                [0.958_327_59, 0.523_622_49, 0.963_628_0],
            ),
            (
                [13.388_067_69, 2.435_296_02, -1.077_251_54],
                [0.451_714_99, 0.112_468_82, 0.936_239_54],
            ),
        ];
        let (positions, colors) = bench_lights(2, 1);
        for (i, (position, color)) in expected.iter().enumerate() {
            let got = [positions[i].x, positions[i].y, positions[i].z];
            for (g, want) in got.iter().zip(position) {
                // f32 near 50 is exact to about 4e-6.
                assert!((f64::from(*g) - want).abs() < 1e-5, "light {i}: {got:?}");
            }
            let got = [colors[i].r, colors[i].g, colors[i].b, colors[i].a];
            for (g, want) in got.iter().zip(color) {
                assert!((f64::from(*g) - want).abs() < 1e-6, "light {i}: {got:?}");
            }
            assert_eq!(got[3], 1.0);
        }
        // 1,000 lights stay in the scene's ranges; another seed places them elsewhere.
        let (p, c) = bench_lights(1000, 1);
        assert_eq!(p.len(), 1000);
        assert!(p.iter().all(|p| (-50.0..50.0).contains(&p.x)
            && (0.5..3.0).contains(&p.y)
            && (-50.0..50.0).contains(&p.z)));
        assert!(c.iter().all(|c| (0.0..1.0).contains(&c.r)));
        assert_ne!(bench_lights(10, 1).0, bench_lights(10, 2).0);
    }
}
