//! Noise: `Perlin (1d)`, `Perlin (2d)`, `Perlin (3d)` (gradient noise,
//! summed over octaves, smooth in its input), `Noise (Animation)` (the same
//! noise running over time: values that wander smoothly) and `Random
//! (Animation)` (new random values every frame, reproducible from a seed and
//! the frame number).
//!
//! Perlin noise here is Ken Perlin's improved noise (quintic fade, 12 edge
//! gradients in 3d) with the permutation table replaced by an integer hash of
//! the lattice point and the seed, so any seed gives a different field and
//! no table is shared.

use glam::{Vec2, Vec3};
use rand_core::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::{EvalContext, In, NodeDef, NodeError, Registry};

use crate::spreads::MAX_SLICES;
use crate::typed::Value;

const CATEGORY: &str = "Animation";

/// The most octaves a Perlin node sums.
pub const MAX_OCTAVES: i64 = 16;

pub fn register(r: &mut Registry) {
    r.add(perlin::<f32>("Perlin (1d)", 0.0));
    r.add(perlin::<Vec2>("Perlin (2d)", Vec2::ZERO));
    r.add(perlin::<Vec3>("Perlin (3d)", Vec3::ZERO));
    r.add(
        NodeDef::new(
            "Noise (Animation)",
            CATEGORY,
            "Values that wander smoothly over time, about -Amplitude to Amplitude: 1d Perlin \
             noise read at time x Frequency (changes per second), one independent track per \
             slice of Random Seed. Octaves (1 to 16) and Persistence add finer jitter, as in \
             Perlin (1d). Reproducible: headless runs give the same values.",
        )
        .time_dependent()
        .with_pins(|p| {
            let freq = p.input("Frequency", 1.0f32);
            let amp = p.input("Amplitude", 1.0f32);
            let octaves_pin = p.input("Octaves", 1i64);
            let persistence = p.input("Persistence", 0.5f32);
            let seed = p.input("Random Seed", 0i64);
            let output = p.output::<f32>("Output");
            move |cx| {
                let (freq, amp) = (cx.get(freq)?, cx.get(amp)?);
                let octaves = octaves(cx, octaves_pin)?;
                let (persistence, seed) = (cx.get(persistence)?, cx.get(seed)?);
                let n = slice_count([
                    freq.len(),
                    amp.len(),
                    octaves.len(),
                    persistence.len(),
                    seed.len(),
                ]);
                let time = cx.clock.time;
                let out: Vec<f32> = (0..n)
                    .map(|i| {
                        // The phase in f64 and reduced, so hours of running keep the noise smooth.
                        let x = (time * f64::from(*wrapped(freq, i))).rem_euclid(65_536.0) as f32;
                        let v = fractal_noise(
                            Vec3::new(x, 0.0, 0.0),
                            1,
                            *wrapped(octaves, i) as u32,
                            *wrapped(persistence, i),
                            *wrapped(seed, i),
                        );
                        let out = v * *wrapped(amp, i);
                        if out.is_finite() { out } else { 0.0 }
                    })
                    .collect();
                cx.put(output, out);
                Ok(())
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Random (Animation)",
            CATEGORY,
            "Spread Count new random values in [Minimum, Maximum) every frame: noise that \
             changes with time. Reproducible: the values depend only on Random Seed and the \
             frame number, so a headless run gives the same values each time.",
        )
        .time_dependent()
        .with_pins(|p| {
            let minimum = p.input("Minimum", 0.0f32);
            let maximum = p.input("Maximum", 1.0f32);
            let seed = p.input("Random Seed", 0i64);
            let count_pin = p.input("Spread Count", 1i64);
            let output = p.output::<f32>("Output");
            move |cx| {
                let (lo, hi) = (cx.get(minimum)?, cx.get(maximum)?);
                let seed = cx.first(seed, 0)?;
                let count = cx.first(count_pin, 0)?;
                let count = usize::try_from(count)
                    .ok()
                    .filter(|&c| c <= MAX_SLICES)
                    .ok_or_else(|| {
                        cx.error(
                            count_pin,
                            format!("{count} is not a count from 0 to {MAX_SLICES}"),
                        )
                    })?;
                let n = if lo.is_empty() || hi.is_empty() {
                    0
                } else {
                    count
                };
                let mut rng = Pcg32::seed_from_u64(
                    (seed as u64) ^ cx.clock.frame.wrapping_mul(0x9e37_79b9_7f4a_7c15),
                );
                let out: Vec<f32> = (0..n)
                    .map(|i| {
                        let t = (rng.next_u32() >> 8) as f32 / (1u32 << 24) as f32;
                        let (a, b) = (*wrapped(lo, i), *wrapped(hi, i));
                        a + (b - a) * t
                    })
                    .collect();
                cx.put(output, out);
                Ok(())
            }
        }),
    );
}

/// A well-mixed 32-bit hash (Chris Wellons' lowbias32).
fn mix(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

fn lattice_hash(seed: i64, cell: [i32; 3]) -> u32 {
    // Truncating the seed to 32 bits keeps negative seeds distinct from positive ones.
    let mut h = mix(seed as u32 ^ mix((seed >> 32) as u32));
    for c in cell {
        h = mix(h ^ c as u32);
    }
    h
}

fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// The gradient of lattice point `cell` dotted with the offset `d` from it.
fn grad(seed: i64, cell: [i32; 3], d: Vec3, dims: usize) -> f32 {
    let h = lattice_hash(seed, cell);
    match dims {
        // A slope in [-1, 1].
        1 => d.x * ((h >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0),
        // One of 8 unit directions.
        2 => {
            let a = (h & 7) as f32 * std::f32::consts::FRAC_PI_4;
            d.x * a.cos() + d.y * a.sin()
        }
        // One of Perlin's 12 cube edge directions.
        _ => {
            let h = h % 12;
            let u = if h < 8 { d.x } else { d.y };
            let v = if h < 4 {
                d.y
            } else if h == 12 || h == 14 {
                d.x
            } else {
                d.z
            };
            (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
        }
    }
}

/// One octave of gradient noise in `dims` dimensions (unused coordinates 0), about [-1, 1].
fn gradient_noise(p: Vec3, seed: i64, dims: usize) -> f32 {
    // Coordinates beyond `dims` must not reach the lattice hash.
    let p = p * Vec3::new(1.0, f32::from(dims >= 2), f32::from(dims == 3));
    let cell = p.floor();
    let f = p - cell;
    let c = [cell.x as i32, cell.y as i32, cell.z as i32];
    let corner = |dx: i32, dy: i32, dz: i32| {
        grad(
            seed,
            [
                c[0].wrapping_add(dx),
                c[1].wrapping_add(dy),
                c[2].wrapping_add(dz),
            ],
            f - Vec3::new(dx as f32, dy as f32, dz as f32),
            dims,
        )
    };
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let zs = if dims == 3 { 2 } else { 1 };
    let ys = if dims >= 2 { 2 } else { 1 };
    let mut layers = [0.0f32; 2];
    for (z, layer) in layers.iter_mut().enumerate().take(zs) {
        let mut rows = [0.0f32; 2];
        for (y, row) in rows.iter_mut().enumerate().take(ys) {
            *row = lerp(
                corner(0, y as i32, z as i32),
                corner(1, y as i32, z as i32),
                u,
            );
        }
        *layer = if ys == 2 {
            lerp(rows[0], rows[1], v)
        } else {
            rows[0]
        };
    }
    let value = if zs == 2 {
        lerp(layers[0], layers[1], w)
    } else {
        layers[0]
    };
    // Scale each dimension's largest possible value to about 1.
    let scale = [2.0, std::f32::consts::SQRT_2, 1.0][dims - 1];
    (value * scale).clamp(-1.0, 1.0)
}

/// Octaves of noise summed with falling amplitude, normalised to about [-1, 1].
pub(crate) fn fractal_noise(
    p: Vec3,
    dims: usize,
    octaves: u32,
    persistence: f32,
    seed: i64,
) -> f32 {
    let (mut sum, mut norm, mut amp, mut freq) = (0.0, 0.0, 1.0, 1.0);
    for octave in 0..octaves {
        sum += amp * gradient_noise(p * freq, seed.wrapping_add(i64::from(octave)), dims);
        norm += amp;
        amp *= persistence;
        freq *= 2.0;
    }
    if norm > 0.0 && sum.is_finite() {
        sum / norm
    } else {
        0.0
    }
}

/// A point type Perlin noise can be sampled at.
trait NoisePoint: Value + Copy {
    const DIMS: usize;
    fn to_vec3(self) -> Vec3;
}

impl NoisePoint for f32 {
    const DIMS: usize = 1;
    fn to_vec3(self) -> Vec3 {
        Vec3::new(self, 0.0, 0.0)
    }
}

impl NoisePoint for Vec2 {
    const DIMS: usize = 2;
    fn to_vec3(self) -> Vec3 {
        self.extend(0.0)
    }
}

impl NoisePoint for Vec3 {
    const DIMS: usize = 3;
    fn to_vec3(self) -> Vec3 {
        self
    }
}

fn perlin<T: NoisePoint>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Perlin gradient noise at Input x Frequency: smooth, about -1 to 1, 0 at whole-number \
         points for one octave. Octaves (1 to 16) add finer layers, each twice the frequency \
         and Persistence times the amplitude of the one before. Random Seed picks another \
         field. Every pin spreads.",
    )
    .with_pins(|p| {
        let input = p.input("Input", default);
        let freq = p.input("Frequency", 1.0f32);
        let octaves_pin = p.input("Octaves", 1i64);
        let persistence = p.input("Persistence", 0.5f32);
        let seed = p.input("Random Seed", 0i64);
        let output = p.output::<f32>("Output");
        move |cx| {
            let input = cx.get(input)?;
            let freq = cx.get(freq)?;
            let octaves = octaves(cx, octaves_pin)?;
            let persistence = cx.get(persistence)?;
            let seed = cx.get(seed)?;
            let n = slice_count([
                input.len(),
                freq.len(),
                octaves.len(),
                persistence.len(),
                seed.len(),
            ]);
            let out: Vec<f32> = (0..n)
                .map(|i| {
                    let p = wrapped(input, i).to_vec3() * *wrapped(freq, i);
                    if !p.is_finite() {
                        return 0.0;
                    }
                    fractal_noise(
                        p,
                        T::DIMS,
                        *wrapped(octaves, i) as u32,
                        *wrapped(persistence, i),
                        *wrapped(seed, i),
                    )
                })
                .collect();
            cx.put(output, out);
            Ok(())
        }
    })
}

/// The Octaves pin, checked to lie in 1..=MAX_OCTAVES.
fn octaves<'a>(cx: &'a EvalContext<'_>, pin: In<i64>) -> Result<&'a [i64], NodeError> {
    let octaves = cx.get(pin)?;
    if let Some(bad) = octaves.iter().find(|o| !(1..=MAX_OCTAVES).contains(*o)) {
        return Err(cx.error(pin, format!("{bad} is not from 1 to {MAX_OCTAVES}")));
    }
    Ok(octaves)
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};
    use spreadlight_graph::Spread;

    use super::fractal_noise;
    use crate::testing::{Harness, eval_err, eval_out, floats, ints};

    #[test]
    fn perlin_is_zero_on_the_lattice_bounded_and_smooth() {
        for dims in 1..=3 {
            for seed in [0, 1, -5] {
                for i in -3..3 {
                    let p = Vec3::splat(i as f32);
                    assert_eq!(fractal_noise(p, dims, 1, 0.5, seed), 0.0);
                }
                let mut min = f32::MAX;
                let mut max = f32::MIN;
                for k in 0..2000 {
                    let p = Vec3::new(k as f32 * 0.0371, k as f32 * 0.0113, k as f32 * 0.0071);
                    let v = fractal_noise(p, dims, 3, 0.5, seed);
                    let w = fractal_noise(p + Vec3::splat(1e-3), dims, 3, 0.5, seed);
                    assert!((-1.0..=1.0).contains(&v));
                    assert!((v - w).abs() < 0.05, "not smooth at {p}: {v} vs {w}");
                    (min, max) = (min.min(v), max.max(v));
                }
                assert!(max - min > 0.5, "{dims}d noise barely varies: {min}..{max}");
            }
        }
    }

    #[test]
    fn perlin_nodes_depend_on_seed_and_spread() {
        let at = |name: &str, input: Spread, seed: i64| -> Vec<f32> {
            eval_out(
                name,
                &[("Input", input), ("Random Seed", ints(&[seed]))],
                "Output",
            )
        };
        // One octave of 1d noise, worked out outside this code from its
        // definition: the cell's slopes g = (hash >> 8) / 2^24 * 2 - 1, hash
        // from lowbias32 over (seed, cell, 0, 0); value = 2 * lerp(g0 f,
        // g1 (f - 1), fade(f)) at f = x - floor(x).
        let p = floats(&[0.3, 1.7, 2.2]);
        let expected = [
            (1, [-0.102_865_488, 0.190_580_678, -0.137_341_506]),
            (2, [-0.180_931_742, -0.628_176_853, 0.321_913_889]),
        ];
        for (seed, want) in expected {
            let got = at("Perlin (1d)", p.clone(), seed);
            assert_eq!(got.len(), 3);
            for (g, w) in got.iter().zip(want) {
                assert!((f64::from(*g) - w).abs() < 1e-5, "seed {seed}: {got:?}");
            }
        }
        let v2 = Spread::Vec2(vec![Vec2::new(0.3, 0.6)]);
        assert_ne!(at("Perlin (2d)", v2, 0), [0.0]);
        let v3 = Spread::Vec3(vec![Vec3::new(0.3, 0.6, 0.2)]);
        assert_ne!(at("Perlin (3d)", v3, 0), [0.0]);
        eval_err("Perlin (1d)", &[("Octaves", ints(&[0]))], "Octaves");
    }

    #[test]
    fn noise_wanders_smoothly_per_seed() {
        let mut h = Harness::new("Noise (Animation)");
        h.set("Random Seed", ints(&[1, 2]))
            .set("Amplitude", floats(&[2.0]));
        let frames: Vec<Vec<f32>> = (0..120).map(|_| h.next::<f32>("Output")).collect();
        for f in &frames {
            assert!(f.iter().all(|v| (-2.0..=2.0).contains(v)), "{f:?}");
        }
        // Smooth: at 1 change per second, 1/60 s moves it little; the two seeds differ.
        for w in frames.windows(2) {
            assert!((w[1][0] - w[0][0]).abs() < 0.2, "{w:?}");
        }
        assert!(frames.iter().any(|f| (f[0] - f[1]).abs() > 0.05));
        let track: Vec<f32> = frames.iter().map(|f| f[0]).collect();
        let (lo, hi) = track
            .iter()
            .fold((f32::MAX, f32::MIN), |(a, b), &v| (a.min(v), b.max(v)));
        assert!(hi - lo > 0.2, "it moves: {lo}..{hi}");
    }

    #[test]
    fn random_changes_every_frame_reproducibly() {
        let mut h = Harness::new("Random (Animation)");
        h.set("Spread Count", ints(&[4]))
            .set("Minimum", floats(&[2.0]))
            .set("Maximum", floats(&[3.0]));
        let a: Vec<Vec<f32>> = (0..3).map(|_| h.next::<f32>("Output")).collect();
        // Worked out outside this code from the definition: PCG32 seeded
        // (rand_core's seed_from_u64) with seed ^ frame * 0x9e37_79b9_7f4a_7c15,
        // each value Minimum + (Maximum - Minimum) * (next_u32 >> 8) / 2^24.
        // So the values depend only on the seed and the frame number.
        let expected = [
            [2.069_547_236, 2.986_392_915, 2.078_250_110, 2.246_012_628],
            [2.044_126_153, 2.874_498_248, 2.349_934_340, 2.952_799_499],
            [2.798_198_402, 2.202_934_206, 2.992_053_092, 2.766_674_578],
        ];
        for (frame, (got, want)) in a.iter().zip(expected).enumerate() {
            assert_eq!(got.len(), 4);
            for (g, w) in got.iter().zip(want) {
                assert!((f64::from(*g) - w).abs() < 1e-6, "frame {frame}: {got:?}");
            }
        }
    }
}
