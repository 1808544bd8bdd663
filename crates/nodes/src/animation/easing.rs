//! Easing curves and Timeliner-style keyframes: `Ease (Animation)` shapes a
//! 0..1 ramp, `Keyframes (Animation)` and its 2d/3d/4d variants play a track
//! of keys (time, value, easing into the next key) at a given time, as vvvv's
//! Timeliner does with its value tracks.

use glam::{Vec2, Vec3, Vec4};
use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::{Choices, EnumDef, NodeDef, Registry};

use crate::filters::Linear;
use crate::typed::Value;

const CATEGORY: &str = "Animation";

/// The easing curves' names, as Robert Penner named them (and vvvv's Tweener nodes).
const EASING_NAMES: &[&str] = &[
    "Linear",
    "Step",
    "Quad In",
    "Quad Out",
    "Quad InOut",
    "Cubic In",
    "Cubic Out",
    "Cubic InOut",
    "Sine In",
    "Sine Out",
    "Sine InOut",
    "Expo In",
    "Expo Out",
    "Back In",
    "Back Out",
    "Elastic Out",
    "Bounce Out",
];

/// The easing curves, as Robert Penner named them (and vvvv's Tweener nodes).
pub static EASING: EnumDef = EnumDef {
    name: "Easing",
    options: EASING_NAMES,
};

/// [`EASING`]'s names beside the curves they stand for, for the pins.
pub static EASINGS: Choices<Easing> = Choices::new(
    "Easing",
    EASING_NAMES,
    &[
        Easing::Linear,
        Easing::Step,
        Easing::QuadIn,
        Easing::QuadOut,
        Easing::QuadInOut,
        Easing::CubicIn,
        Easing::CubicOut,
        Easing::CubicInOut,
        Easing::SineIn,
        Easing::SineOut,
        Easing::SineInOut,
        Easing::ExpoIn,
        Easing::ExpoOut,
        Easing::BackIn,
        Easing::BackOut,
        Easing::ElasticOut,
        Easing::BounceOut,
    ],
);

/// An easing curve (see [`EASING`] for the names).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Easing {
    Linear,
    Step,
    QuadIn,
    QuadOut,
    QuadInOut,
    CubicIn,
    CubicOut,
    CubicInOut,
    SineIn,
    SineOut,
    SineInOut,
    ExpoIn,
    ExpoOut,
    BackIn,
    BackOut,
    ElasticOut,
    BounceOut,
}

/// The curve `name` at `t` in [0, 1] (clamped): 0 at 0, 1 at 1. `None` for an unknown name.
pub fn ease(name: &str, t: f32) -> Option<f32> {
    Some(EASINGS.value(name)?.at(t))
}

impl Easing {
    /// The curve at `t` in [0, 1] (clamped): 0 at 0, 1 at 1.
    pub fn at(self, t: f32) -> f32 {
        use std::f32::consts::PI;
        let t = t.clamp(0.0, 1.0);
        let in_out = |f: fn(f32) -> f32| {
            if t < 0.5 {
                f(2.0 * t) / 2.0
            } else {
                1.0 - f(2.0 - 2.0 * t) / 2.0
            }
        };
        const BACK: f32 = 1.70158;
        match self {
            Easing::Linear => t,
            Easing::Step => {
                if t < 1.0 {
                    0.0
                } else {
                    1.0
                }
            }
            Easing::QuadIn => t * t,
            Easing::QuadOut => 1.0 - (1.0 - t) * (1.0 - t),
            Easing::QuadInOut => in_out(|x| x * x),
            Easing::CubicIn => t * t * t,
            Easing::CubicOut => 1.0 - (1.0 - t).powi(3),
            Easing::CubicInOut => in_out(|x| x * x * x),
            Easing::SineIn => 1.0 - (t * PI / 2.0).cos(),
            Easing::SineOut => (t * PI / 2.0).sin(),
            Easing::SineInOut => (1.0 - (t * PI).cos()) / 2.0,
            Easing::ExpoIn if t == 0.0 => 0.0,
            Easing::ExpoIn => 2f32.powf(10.0 * t - 10.0),
            Easing::ExpoOut if t == 1.0 => 1.0,
            Easing::ExpoOut => 1.0 - 2f32.powf(-10.0 * t),
            Easing::BackIn => t * t * ((BACK + 1.0) * t - BACK),
            Easing::BackOut => {
                let u = t - 1.0;
                1.0 + u * u * ((BACK + 1.0) * u + BACK)
            }
            Easing::ElasticOut if t == 0.0 || t == 1.0 => t,
            Easing::ElasticOut => {
                2f32.powf(-10.0 * t) * ((t * 10.0 - 0.75) * (2.0 * PI / 3.0)).sin() + 1.0
            }
            Easing::BounceOut => bounce_out(t),
        }
    }
}

fn bounce_out(t: f32) -> f32 {
    const N: f32 = 7.5625;
    const D: f32 = 2.75;
    if t < 1.0 / D {
        N * t * t
    } else if t < 2.0 / D {
        let t = t - 1.5 / D;
        N * t * t + 0.75
    } else if t < 2.5 / D {
        let t = t - 2.25 / D;
        N * t * t + 0.9375
    } else {
        let t = t - 2.625 / D;
        N * t * t + 0.984375
    }
}

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Ease (Animation)",
            CATEGORY,
            "Shapes a ramp: Input from 0 to 1 (clamped) through the Easing curve, 0 at 0 and 1 at \
             1 (Back and Elastic overshoot in between). Drive it with an LFO or a LinearFilter.",
        )
        .with_pins(|p| {
            let input = p.input("Input", 0.0f32);
            let easing = p.input_choice("Easing", &EASINGS, Easing::Linear);
            let output = p.output::<f32>("Output");
            move |cx| {
                let input = cx.get(input)?;
                let easings = cx.choices(easing)?;
                let n = slice_count([input.len(), easings.len()]);
                let out: Vec<f32> = (0..n)
                    .map(|i| wrapped(&easings, i).at(*wrapped(input, i)))
                    .collect();
                cx.put(output, out);
                Ok(())
            }
        }),
    );
    r.add(keyframes::<f32>("Keyframes (Animation)"));
    r.add(keyframes::<Vec2>("Keyframes (2d)"));
    r.add(keyframes::<Vec3>("Keyframes (3d)"));
    r.add(keyframes::<Vec4>("Keyframes (4d)"));
}

fn keyframes<T: Linear + Value>(name: &'static str) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "A keyframe track played at Time, as a Timeliner value track: Key Time and Key Value \
         (spread together) are the keys, in any order; between two keys the value moves with \
         the earlier key's Easing (Easing spreads over the keys, wrapping). Before the first key \
         it holds the first value, after the last the last. One output slice per Time slice; no \
         keys give no output. Colour tracks: Keyframes (4d), as Color pins link to and from 4d \
         vectors.",
    )
    .with_pins(|p| {
        let time = p.input("Time", 0.0f32);
        let key_time = p.input("Key Time", 0.0f32);
        let key_value = p.input("Key Value", T::ZERO);
        let easing = p.input_choice("Easing", &EASINGS, Easing::Linear);
        let output = p.output::<T>("Output");
        move |cx| {
            let time = cx.get(time)?;
            let (key_time, key_value) = (cx.get(key_time)?, cx.get(key_value)?);
            let easings = cx.choices(easing)?;
            let mut keys: Vec<(f32, T, Easing)> =
                (0..slice_count([key_time.len(), key_value.len()]))
                    .filter(|&k| wrapped(key_time, k).is_finite())
                    .map(|k| {
                        let easing = if easings.is_empty() {
                            Easing::Linear
                        } else {
                            *wrapped(&easings, k)
                        };
                        (*wrapped(key_time, k), *wrapped(key_value, k), easing)
                    })
                    .collect();
            keys.sort_by(|a, b| a.0.total_cmp(&b.0));
            let out: Vec<T> = if keys.is_empty() {
                Vec::new()
            } else {
                time.iter().map(|&t| play(&keys, t)).collect()
            };
            cx.put(output, out);
            Ok(())
        }
    })
}

/// The track's value at `t`: `keys` sorted by time, not empty.
pub(crate) fn play<T: Linear>(keys: &[(f32, T, Easing)], t: f32) -> T {
    // The first key after t; the segment is the key before it to it.
    let next = keys.partition_point(|k| k.0 <= t);
    if next == 0 {
        return keys[0].1;
    }
    if next == keys.len() {
        return keys[next - 1].1;
    }
    let (a, b) = (&keys[next - 1], &keys[next]);
    let u = (t - a.0) / (b.0 - a.0);
    let e = a.2.at(u);
    a.1 + (b.1 - a.1) * e
}

#[cfg(test)]
mod tests {
    use glam::Vec2;
    use spreadlight_graph::Spread;

    use super::{EASING, ease};
    use crate::testing::{assert_close, eval_err, eval_out, floats, option};

    #[test]
    fn every_easing_starts_at_0_and_ends_at_1() {
        for name in EASING.options {
            assert_eq!(ease(name, 0.0), Some(0.0), "{name}");
            let end = ease(name, 1.0).expect("known");
            assert!((end - 1.0).abs() < 1e-6, "{name}: {end}");
            // Finite everywhere, also outside [0, 1] (clamped).
            for t in [-1.0, 0.25, 0.5, 0.75, 2.0] {
                assert!(ease(name, t).expect("known").is_finite(), "{name} at {t}");
            }
        }
        assert_close(&[ease("Quad In", 0.5).expect("quad")], &[0.25], 1e-6);
        assert_close(&[ease("Cubic InOut", 0.5).expect("cubic")], &[0.5], 1e-6);
        assert!(
            ease("Back In", 0.2).expect("back") < 0.0,
            "Back undershoots"
        );
        assert_eq!(ease("Wobble", 0.5), None);
    }

    #[test]
    fn ease_node_spreads_its_curve() {
        let out: Vec<f32> = eval_out(
            "Ease (Animation)",
            &[
                ("Input", floats(&[0.5])),
                (
                    "Easing",
                    Spread::Enum(vec!["Linear".into(), "Quad Out".into()]),
                ),
            ],
            "Output",
        );
        assert_close(&out, &[0.5, 0.75], 1e-6);
        eval_err(
            "Ease (Animation)",
            &[("Easing", option("Wobble"))],
            "Easing",
        );
    }

    #[test]
    fn keyframes_play_a_track_with_easing() {
        let keys = [
            ("Key Time", floats(&[2.0, 0.0, 1.0])),
            ("Key Value", floats(&[0.0, 0.0, 10.0])),
            // Per key in the given order: key at 2 s Linear, at 0 s Quad In, at 1 s Linear.
            (
                "Easing",
                Spread::Enum(vec!["Linear".into(), "Quad In".into(), "Linear".into()]),
            ),
        ];
        let mut v = keys.to_vec();
        v.push(("Time", floats(&[-1.0, 0.0, 0.5, 1.0, 1.5, 2.0, 9.0])));
        let out: Vec<f32> = eval_out("Keyframes (Animation)", &v, "Output");
        assert_close(&out, &[0.0, 0.0, 2.5, 10.0, 5.0, 0.0, 0.0], 1e-5);
        let out: Vec<Vec2> = eval_out(
            "Keyframes (2d)",
            &[
                ("Key Time", floats(&[0.0, 1.0])),
                (
                    "Key Value",
                    Spread::Vec2(vec![Vec2::ZERO, Vec2::new(2.0, 4.0)]),
                ),
                ("Time", floats(&[0.5])),
            ],
            "Output",
        );
        assert_eq!(out, [Vec2::new(1.0, 2.0)]);
    }
}
