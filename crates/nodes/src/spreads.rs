//! Spread generators, in the "Spreads" category: `LinearSpread`,
//! `CircularSpread`, `RandomSpread` and `I (Spreads)`, nodes that make many
//! slices out of a few parameters.
//!
//! As in vvvv, every parameter pin is itself a spread: the node spreads its
//! parameters with the runtime's rule (the longest pin decides the number of
//! "bins", shorter pins wrap, an empty pin gives an empty output), makes one
//! sub-spread per bin and outputs the bins one after the other. With
//! one-slice parameters, as usual, that is simply one spread.
//!
//! Operations on whole spreads live beside this file, in `spreads/`: reading
//! and writing slices (`slices`), joining and splitting (`combine`), memory
//! over frames (`memory`), whole-spread maths (`reduce`), bin sizes (`bins`).
//!
//! A negative Spread Count is an input error, and so is a request for more
//! than [`MAX_SLICES`] slices in all, so a typo cannot exhaust memory.

use std::f64::consts::TAU;

use rand_core::{Rng, SeedableRng};
use rand_pcg::Pcg32;
use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::{Choices, EvalContext, In, NodeDef, NodeError, Registry};

pub(crate) mod bins;
pub mod combine;
pub mod memory;
pub mod reduce;
pub mod slices;

const CATEGORY: &str = "Spreads";

/// The most slices one spread generator outputs in one evaluation, over all its bins.
pub const MAX_SLICES: usize = 10_000_000;

/// How `LinearSpread` places its slices in its range, as vvvv names the options.
pub static ALIGNMENT: Choices<Alignment> = Choices::new(
    "Spread Alignment",
    &["Centered", "LeftJustified", "RightJustified", "Block"],
    &[
        Alignment::Centered,
        Alignment::LeftJustified,
        Alignment::RightJustified,
        Alignment::Block,
    ],
);

pub fn register(r: &mut Registry) {
    slices::register(r);
    combine::register(r);
    memory::register(r);
    reduce::register(r);
    register_generators(r);
}

/// The generators alone (this file's nodes).
pub fn register_generators(r: &mut Registry) {
    r.add(cross_2d());
    r.add(
        NodeDef::new(
            "LinearSpread",
            CATEGORY,
            "Spread Count values evenly spaced over the range of Width around Input \
             ([Input - Width/2, Input + Width/2]). Alignment, as in vvvv: Centered puts each value \
             in the middle of its step (count 5, width 1: -0.4, -0.2, 0, 0.2, 0.4), \
             LeftJustified starts at the left end, RightJustified ends at the right end, Block \
             includes both ends (a single slice sits at Input). Phase shifts the values by \
             Phase x Width, wrapping around within the range (Block ignores Phase). Every pin \
             spreads: each slice of the longest pin makes its own sub-spread and the \
             sub-spreads are output one after the other.",
        )
        .with_pins(|p| {
            let input = p.input("Input", 0.0f32);
            let width = p.input("Width", 1.0f32);
            let alignment = p.input_choice("Alignment", &ALIGNMENT, Alignment::Centered);
            let phase = p.input("Phase", 0.0f32);
            let count = p.input("Spread Count", 1i64);
            let output = p.output::<f32>("Output");
            move |cx| {
                let input = cx.get(input)?;
                let width = cx.get(width)?;
                let alignments = cx.choices(alignment)?;
                let phase = cx.get(phase)?;
                let n = slice_count([
                    input.len(),
                    width.len(),
                    alignments.len(),
                    phase.len(),
                    cx.spread(count).len(),
                ]);
                let counts = bin_counts(cx, count, n)?;
                let mut out = Vec::with_capacity(counts.iter().sum());
                for (b, &count) in counts.iter().enumerate() {
                    let center = f64::from(*wrapped(input, b));
                    let width = f64::from(*wrapped(width, b));
                    let alignment = *wrapped(&alignments, b);
                    let phase = f64::from(*wrapped(phase, b));
                    out.extend((0..count).map(|i| {
                        let t = linear_position(i, count, alignment, phase);
                        (center + width * (t - 0.5)) as f32
                    }));
                }
                cx.put(output, out);
                Ok(())
            }
        }),
    );
    r.add(
        NodeDef::new(
            "CircularSpread",
            CATEGORY,
            "Spread Count points on an ellipse around (Input X, Input Y), Width and Height \
             across (radii Width/2 and Height/2), output as Output X and Output Y. The first \
             point is at angle Phase (in cycles; 0 is +X, counter-clockwise); the points cover \
             Factor full turns (1: evenly around once, 0.5: a half circle). Every pin spreads: \
             each slice of the longest pin makes its own ring and the rings are output one \
             after the other.",
        )
        .with_pins(|p| {
            let params = [
                p.input("Input X", 0.0f32),
                p.input("Input Y", 0.0f32),
                p.input("Width", 1.0f32),
                p.input("Height", 1.0f32),
                p.input("Factor", 1.0f32),
                p.input("Phase", 0.0f32),
            ];
            let count = p.input("Spread Count", 1i64);
            let out_x = p.output::<f32>("Output X");
            let out_y = p.output::<f32>("Output Y");
            move |cx| {
                let mut slices: [&[f32]; 6] = [&[]; 6];
                for (slot, pin) in slices.iter_mut().zip(params) {
                    *slot = cx.get(pin)?;
                }
                let n = slice_count(
                    slices
                        .iter()
                        .map(|p| p.len())
                        .chain([cx.spread(count).len()]),
                );
                let counts = bin_counts(cx, count, n)?;
                let total = counts.iter().sum();
                let (mut xs, mut ys) = (Vec::with_capacity(total), Vec::with_capacity(total));
                for (b, &count) in counts.iter().enumerate() {
                    let [x, y, width, height, factor, phase] =
                        slices.map(|p| f64::from(*wrapped(p, b)));
                    for i in 0..count {
                        let (cos, sin) = cos_sin_cycles(phase + factor * i as f64 / count as f64);
                        xs.push((x + cos * width / 2.0) as f32);
                        ys.push((y + sin * height / 2.0) as f32);
                    }
                }
                cx.put(out_x, xs);
                cx.put(out_y, ys);
                Ok(())
            }
        }),
    );
    r.add(
        NodeDef::new(
            "RandomSpread",
            CATEGORY,
            "Spread Count random values in [Input - Width/2, Input + Width/2). Deterministic: \
             the same Random Seed always gives the same values (a PCG32 generator seeded with \
             it), another seed gives others. Every pin spreads: each slice of the longest pin \
             makes its own sub-spread, drawn from a generator seeded with that slice's Random \
             Seed, and the sub-spreads are output one after the other.",
        )
        .with_pins(|p| {
            let input = p.input("Input", 0.0f32);
            let width = p.input("Width", 1.0f32);
            let seed = p.input("Random Seed", 0i64);
            let count = p.input("Spread Count", 1i64);
            let output = p.output::<f32>("Output");
            move |cx| {
                let input = cx.get(input)?;
                let width = cx.get(width)?;
                let seed = cx.get(seed)?;
                let n = slice_count([input.len(), width.len(), seed.len(), cx.spread(count).len()]);
                let counts = bin_counts(cx, count, n)?;
                let mut out = Vec::with_capacity(counts.iter().sum());
                for (b, &count) in counts.iter().enumerate() {
                    let center = *wrapped(input, b);
                    let width = *wrapped(width, b);
                    // The seed's bits as they are: negative seeds are as good as positive ones.
                    let mut rng = Pcg32::seed_from_u64(*wrapped(seed, b) as u64);
                    out.extend((0..count).map(|_| center + width * (unit_random(&mut rng) - 0.5)));
                }
                cx.put(output, out);
                Ok(())
            }
        }),
    );
    r.add(
        NodeDef::new(
            "I (Spreads)",
            CATEGORY,
            "The integers from Start up to but not including End (vvvv's I node): Start 2, \
             End 5 gives 2, 3, 4. End at or below Start gives an empty spread. Both pins \
             spread: each slice pair makes its own range and the ranges are output one after \
             the other.",
        )
        .with_pins(|p| {
            let start = p.input("Start", 0i64);
            let end = p.input("End", 1i64);
            let output = p.output::<i64>("Output");
            move |cx| {
                let (starts, ends) = (cx.get(start)?, cx.get(end)?);
                let n = slice_count([starts.len(), ends.len()]);
                let mut total = 0usize;
                let mut ranges = Vec::with_capacity(n);
                for b in 0..n {
                    let (s, e) = (*wrapped(starts, b), *wrapped(ends, b));
                    // In i128 so that the widest ranges cannot overflow.
                    let len = (i128::from(e) - i128::from(s)).max(0);
                    total = total.saturating_add(usize::try_from(len).unwrap_or(usize::MAX));
                    if total > MAX_SLICES {
                        return Err(cx.error(
                            end,
                            format!("the ranges hold more than {MAX_SLICES} slices in all"),
                        ));
                    }
                    ranges.push(s..e);
                }
                let out: Vec<i64> = ranges.into_iter().flatten().collect();
                cx.put(output, out);
                Ok(())
            }
        }),
    );
}

/// The slice count of each of `n` bins, from the Int pin `pin`: checks that
/// none is negative and that all of them together stay within [`MAX_SLICES`].
fn bin_counts(cx: &EvalContext<'_>, pin: In<i64>, n: usize) -> Result<Vec<usize>, NodeError> {
    let counts = cx.get(pin)?;
    let mut total = 0usize;
    (0..n)
        .map(|i| {
            let count = *wrapped(counts, i);
            if count < 0 {
                return Err(cx.error(pin, format!("slice {i}: {count} is negative")));
            }
            let count = usize::try_from(count).unwrap_or(usize::MAX);
            total = total.saturating_add(count);
            if total > MAX_SLICES {
                return Err(cx.error(
                    pin,
                    format!("asks for more than {MAX_SLICES} slices in all"),
                ));
            }
            Ok(count)
        })
        .collect()
}

/// Where `LinearSpread` puts its slices (see [`ALIGNMENT`] for the names).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Alignment {
    Centered,
    LeftJustified,
    RightJustified,
    Block,
}

/// Where slice `i` of `count` sits in the range, 0 the left end and 1 the right end.
fn linear_position(i: usize, count: usize, alignment: Alignment, phase: f64) -> f64 {
    let (i, n) = (i as f64, count as f64);
    let t = match alignment {
        Alignment::Block if count < 2 => return 0.5,
        Alignment::Block => return i / (n - 1.0),
        Alignment::Centered => (i + 0.5) / n + phase,
        Alignment::LeftJustified => i / n + phase,
        Alignment::RightJustified => (i + 1.0) / n + phase,
    };
    // Wrap into [0, 1), or (0, 1] for RightJustified, whose last slice sits on the right end.
    let wrapped = if alignment == Alignment::RightJustified {
        t - t.ceil() + 1.0
    } else {
        t - t.floor()
    };
    if wrapped.is_finite() { wrapped } else { 0.5 }
}

/// (cos, sin) of an angle in cycles, reduced to one turn first for precision.
fn cos_sin_cycles(cycles: f64) -> (f64, f64) {
    let (sin, cos) = (cycles.rem_euclid(1.0) * TAU).sin_cos();
    (cos, sin)
}

/// A uniform random float in [0, 1) from the generator's next 24 bits.
fn unit_random(rng: &mut Pcg32) -> f32 {
    (rng.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// `Cross (2d)`: every pairing of two spreads, X varying slowest, as vvvv's.
fn cross_2d() -> NodeDef {
    NodeDef::new(
        "Cross (2d)",
        "Spreads",
        "Every combination of the slices of X and Y: X[0] with each Y, then X[1] with each Y, and so on \
         (a grid from two rows of values).",
    )
    .with_pins(|p| {
        let x = p.input("X", 0.0f32);
        let y = p.input("Y", 0.0f32);
        let out_x = p.output::<f32>("X");
        let out_y = p.output::<f32>("Y");
        move |cx| {
            let (xs, ys) = (cx.get(x)?.to_vec(), cx.get(y)?.to_vec());
            if xs.len().saturating_mul(ys.len()) > MAX_SLICES {
                return Err(cx.error(y, format!("the cross would have over {MAX_SLICES} slices")));
            }
            let xs_out = xs.iter().flat_map(|x| std::iter::repeat_n(*x, ys.len())).collect();
            let ys_out = xs.iter().flat_map(|_| ys.iter().copied()).collect();
            cx.put(out_x, xs_out);
            cx.put(out_y, ys_out);
            Ok(())
        }
    })
}

#[cfg(test)]
mod tests {
    use spreadlight_graph::Spread;

    use super::MAX_SLICES;
    use crate::testing::{assert_close, eval, eval_err, eval_out, floats, ints, option};

    #[test]
    fn cross_pairs_every_x_with_every_y() {
        let values = [
            ("X", floats(&[1.0, 2.0])),
            ("Y", floats(&[10.0, 20.0, 30.0])),
        ];
        let x: Vec<f32> = eval_out("Cross (2d)", &values, "X");
        let y: Vec<f32> = eval_out("Cross (2d)", &values, "Y");
        assert_eq!(x, [1.0, 1.0, 1.0, 2.0, 2.0, 2.0]);
        assert_eq!(y, [10.0, 20.0, 30.0, 10.0, 20.0, 30.0]);
    }

    fn linear(values: &[(&str, Spread)]) -> Vec<f32> {
        eval_out("LinearSpread", values, "Output")
    }

    #[test]
    fn linear_spread_defaults_to_one_centered_slice() {
        assert_eq!(linear(&[]), vec![0.0]);
    }

    #[test]
    fn linear_spread_alignments_match_vvvv() {
        let count = ("Spread Count", ints(&[5]));
        assert_close(
            &linear(std::slice::from_ref(&count)),
            &[-0.4, -0.2, 0.0, 0.2, 0.4],
            1e-6,
        );
        assert_close(
            &linear(&[count.clone(), ("Alignment", option("LeftJustified"))]),
            &[-0.5, -0.3, -0.1, 0.1, 0.3],
            1e-6,
        );
        assert_close(
            &linear(&[count.clone(), ("Alignment", option("RightJustified"))]),
            &[-0.3, -0.1, 0.1, 0.3, 0.5],
            1e-6,
        );
        assert_close(
            &linear(&[count.clone(), ("Alignment", option("Block"))]),
            &[-0.5, -0.25, 0.0, 0.25, 0.5],
            1e-6,
        );
        assert_close(
            &linear(&[
                count,
                ("Input", floats(&[10.0])),
                ("Width", floats(&[-2.0])),
            ]),
            &[10.8, 10.4, 10.0, 9.6, 9.2],
            1e-5,
        );
        assert_eq!(
            linear(&[("Alignment", option("Block")), ("Input", floats(&[3.0]))]),
            vec![3.0]
        );
    }

    #[test]
    fn linear_spread_phase_wraps_within_the_range() {
        assert_close(
            &linear(&[("Spread Count", ints(&[4])), ("Phase", floats(&[0.25]))]),
            &[-0.125, 0.125, 0.375, -0.375],
            1e-6,
        );
        // A whole cycle of phase changes nothing, in either direction.
        for phase in [1.0, -1.0, -3.0] {
            assert_close(
                &linear(&[("Spread Count", ints(&[5])), ("Phase", floats(&[phase]))]),
                &[-0.4, -0.2, 0.0, 0.2, 0.4],
                1e-5,
            );
        }
        // Block ignores the phase.
        assert_close(
            &linear(&[
                ("Spread Count", ints(&[3])),
                ("Alignment", option("Block")),
                ("Phase", floats(&[0.3])),
            ]),
            &[-0.5, 0.0, 0.5],
            1e-6,
        );
    }

    #[test]
    fn linear_spread_concatenates_one_sub_spread_per_bin() {
        assert_close(
            &linear(&[
                ("Input", floats(&[0.0, 10.0])),
                ("Spread Count", ints(&[2, 3])),
            ]),
            &[-0.25, 0.25, 10.0 - 1.0 / 3.0, 10.0, 10.0 + 1.0 / 3.0],
            1e-5,
        );
        assert!(linear(&[("Spread Count", ints(&[0]))]).is_empty());
        assert!(linear(&[("Spread Count", ints(&[]))]).is_empty());
        assert!(linear(&[("Width", floats(&[]))]).is_empty());
    }

    #[test]
    fn spread_counts_are_checked() {
        for name in ["LinearSpread", "CircularSpread", "RandomSpread"] {
            eval_err(name, &[("Spread Count", ints(&[-1]))], "Spread Count");
            let too_many = i64::try_from(MAX_SLICES).expect("fits") + 1;
            eval_err(name, &[("Spread Count", ints(&[too_many]))], "Spread Count");
            eval_err(name, &[("Spread Count", ints(&[i64::MAX]))], "Spread Count");
            // Each bin is fine, together they are too many.
            let half = i64::try_from(MAX_SLICES / 2).expect("fits") + 1;
            eval_err(
                name,
                &[("Spread Count", ints(&[half, half]))],
                "Spread Count",
            );
        }
    }

    #[test]
    fn circular_spread_goes_around_counter_clockwise() {
        let values = [
            ("Input X", floats(&[1.0])),
            ("Input Y", floats(&[2.0])),
            ("Width", floats(&[2.0])),
            ("Height", floats(&[4.0])),
            ("Spread Count", ints(&[4])),
        ];
        let out = eval("CircularSpread", &values).expect("circular");
        let x = out[0].clone();
        let y = out[1].clone();
        let (Spread::Float(x), Spread::Float(y)) = (x, y) else {
            panic!("float outputs")
        };
        assert_close(&x, &[2.0, 1.0, 0.0, 1.0], 1e-6);
        assert_close(&y, &[2.0, 4.0, 2.0, 0.0], 1e-6);
    }

    #[test]
    fn circular_spread_factor_and_phase() {
        let x: Vec<f32> = eval_out(
            "CircularSpread",
            &[
                ("Factor", floats(&[0.5])),
                ("Phase", floats(&[0.5])),
                ("Spread Count", ints(&[2])),
            ],
            "Output X",
        );
        // Half a turn in two steps starting at 180 degrees: -X, then -Y (x = 0).
        assert_close(&x, &[-0.5, 0.0], 1e-6);
        let y: Vec<f32> = eval_out(
            "CircularSpread",
            &[
                ("Factor", floats(&[0.5])),
                ("Phase", floats(&[0.5])),
                ("Spread Count", ints(&[2])),
            ],
            "Output Y",
        );
        assert_close(&y, &[0.0, -0.5], 1e-6);
        let y: Vec<f32> = eval_out(
            "CircularSpread",
            &[("Spread Count", ints(&[1, 2]))],
            "Output Y",
        );
        assert_eq!(y.len(), 3);
    }

    fn random(values: &[(&str, Spread)]) -> Vec<f32> {
        eval_out("RandomSpread", values, "Output")
    }

    #[test]
    fn random_spread_is_deterministic_per_seed_and_in_bounds() {
        let with_seed = |seed: i64| {
            random(&[
                ("Input", floats(&[5.0])),
                ("Width", floats(&[2.0])),
                ("Random Seed", ints(&[seed])),
                ("Spread Count", ints(&[1000])),
            ])
        };
        let a = with_seed(7);
        assert_eq!(a.len(), 1000);
        assert_eq!(a, with_seed(7));
        let b = with_seed(8);
        assert_ne!(a, b);
        assert_ne!(a, with_seed(-7));
        for v in a.iter().chain(&b) {
            assert!((4.0..6.0).contains(v), "{v} out of [4, 6)");
        }
        // Not all the same, and spread over the range.
        let (min, max) = a
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        assert!(min < 4.1 && max > 5.9, "{min}..{max}");
    }

    #[test]
    fn random_spread_bins_use_their_own_seed() {
        let out = random(&[
            ("Random Seed", ints(&[1, 2, 1])),
            ("Spread Count", ints(&[3])),
        ]);
        assert_eq!(out.len(), 9);
        assert_eq!(out[0..3], out[6..9]);
        assert_ne!(out[0..3], out[3..6]);
        // Width 0 gives Input exactly.
        assert_eq!(
            random(&[("Width", floats(&[0.0])), ("Input", floats(&[3.0]))]),
            vec![3.0]
        );
    }

    fn range(start: &[i64], end: &[i64]) -> Vec<i64> {
        eval_out(
            "I (Spreads)",
            &[("Start", ints(start)), ("End", ints(end))],
            "Output",
        )
    }

    #[test]
    fn i_gives_half_open_integer_ranges() {
        assert_eq!(range(&[0], &[1]), vec![0]);
        assert_eq!(range(&[2], &[5]), vec![2, 3, 4]);
        assert_eq!(range(&[-2], &[1]), vec![-2, -1, 0]);
        assert!(range(&[3], &[3]).is_empty());
        assert!(range(&[5], &[2]).is_empty());
        assert_eq!(range(&[0, 10], &[2, 12]), vec![0, 1, 10, 11]);
        assert_eq!(range(&[0, 5], &[2]), vec![0, 1]);
    }

    #[test]
    fn i_refuses_absurd_ranges() {
        eval_err(
            "I (Spreads)",
            &[("Start", ints(&[i64::MIN])), ("End", ints(&[i64::MAX]))],
            "End",
        );
        let too_many = i64::try_from(MAX_SLICES).expect("fits") + 1;
        eval_err("I (Spreads)", &[("End", ints(&[too_many]))], "End");
        // At the limit itself it still works.
        assert_eq!(
            range(&[0], &[i64::try_from(MAX_SLICES).expect("fits")]).len(),
            MAX_SLICES
        );
    }
}
