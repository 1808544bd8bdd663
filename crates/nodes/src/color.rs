//! Colour: building and taking apart colours (`RGB`, `HSV`, `HSL` joins and
//! splits), mixing them (`Lerp`, `ColorBlend` with the usual blend modes,
//! `Add`, `Multiply`, `Complement`, `SetAlpha`), `Gradient` (colour keys
//! sampled at a position) and sRGB encoding.
//!
//! Colours on pins are linear RGBA (what shading wants). The HSV and HSL
//! nodes work on the RGB numbers as they are; to pick a colour the way a
//! colour picker shows it (sRGB), join it and follow with `sRGB (Color Decode)`.

use glam::Vec4;
use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::{Choices, Color, NodeDef, Registry};

use crate::animation::easing::{Easing, play};

const CATEGORY: &str = "Color";

/// The blend modes of `ColorBlend`, as image editors name them.
pub static BLEND_MODE: Choices<BlendMode> = Choices::new(
    "Blend Mode",
    &[
        "Normal",
        "Multiply",
        "Screen",
        "Overlay",
        "Add",
        "Subtract",
        "Difference",
        "Darken",
        "Lighten",
    ],
    &[
        BlendMode::Normal,
        BlendMode::Multiply,
        BlendMode::Screen,
        BlendMode::Overlay,
        BlendMode::Add,
        BlendMode::Subtract,
        BlendMode::Difference,
        BlendMode::Darken,
        BlendMode::Lighten,
    ],
);

/// How `ColorBlend` combines a channel of Blend with Base's (see [`BLEND_MODE`] for the names).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BlendMode {
    Normal,
    Multiply,
    Screen,
    Overlay,
    Add,
    Subtract,
    Difference,
    Darken,
    Lighten,
}

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "RGB (Color Join)",
            CATEGORY,
            "A colour from its Red, Green, Blue and Alpha components (linear), slice by slice.",
        )
        .input("Red", 1.0f32)
        .input("Green", 1.0f32)
        .input("Blue", 1.0f32)
        .input("Alpha", 1.0f32)
        .output::<Color>("Output")
        .per_slice4(|r: &f32, g: &f32, b: &f32, a: &f32| Color::rgba(*r, *g, *b, *a)),
    );
    r.add(split(
        "RGB (Color Split)",
        "Red, Green, Blue and Alpha of each colour.",
        ["Red", "Green", "Blue", "Alpha"],
        |c| [c.r, c.g, c.b, c.a],
    ));
    r.add(
        NodeDef::new(
            "HSV (Color Join)",
            CATEGORY,
            "A colour from Hue (in cycles: 0 red, 1/3 green, 2/3 blue, wrapping), Saturation, \
             Value and Alpha, slice by slice. Saturation and Value are clamped to [0, 1].",
        )
        .input("Hue", 0.0f32)
        .input("Saturation", 1.0f32)
        .input("Value", 1.0f32)
        .input("Alpha", 1.0f32)
        .output::<Color>("Output")
        .per_slice4(|h: &f32, s: &f32, v: &f32, a: &f32| hsv_to_rgb(*h, *s, *v, *a)),
    );
    r.add(split(
        "HSV (Color Split)",
        "Hue (in cycles, 0 to 1), Saturation, Value and Alpha of each colour. A grey has hue 0.",
        ["Hue", "Saturation", "Value", "Alpha"],
        rgb_to_hsv,
    ));
    r.add(
        NodeDef::new(
            "HSL (Color Join)",
            CATEGORY,
            "A colour from Hue (in cycles), Saturation, Lightness (0 black, 0.5 the pure hue, 1 \
             white) and Alpha, slice by slice. Saturation and Lightness are clamped to [0, 1].",
        )
        .input("Hue", 0.0f32)
        .input("Saturation", 1.0f32)
        .input("Lightness", 0.5f32)
        .input("Alpha", 1.0f32)
        .output::<Color>("Output")
        .per_slice4(|h: &f32, s: &f32, l: &f32, a: &f32| hsl_to_rgb(*h, *s, *l, *a)),
    );
    r.add(split(
        "HSL (Color Split)",
        "Hue (in cycles, 0 to 1), Saturation, Lightness and Alpha of each colour.",
        ["Hue", "Saturation", "Lightness", "Alpha"],
        rgb_to_hsl,
    ));
    r.add(
        NodeDef::new(
            "Lerp (Color)",
            CATEGORY,
            "Mixes Input 1 and Input 2 (all four channels): Amount 0 gives Input 1, 1 gives \
             Input 2, in between a linear mix, outside it extrapolates.",
        )
        .input("Input 1", Color::BLACK)
        .input("Input 2", Color::WHITE)
        .input("Amount", 0.5f32)
        .output::<Color>("Output")
        .per_slice3(|a: &Color, b: &Color, t: &f32| {
            Color::from_vec4(a.to_vec4().lerp(b.to_vec4(), *t))
        }),
    );
    r.add(
        NodeDef::new(
            "ColorBlend (Color)",
            CATEGORY,
            "Blends Blend over Base with a blend mode, as image editors do (per RGB channel: \
             Multiply darkens, Screen lightens, Overlay adds contrast, Difference is |a - b|, \
             ...), then mixes the result in by Opacity x Blend's alpha. The output keeps Base's \
             alpha.",
        )
        .with_pins(|p| {
            let base = p.input("Base", Color::BLACK);
            let blend = p.input("Blend", Color::WHITE);
            let mode = p.input_choice("Mode", &BLEND_MODE, BlendMode::Normal);
            let opacity = p.input("Opacity", 1.0f32);
            let output = p.output::<Color>("Output");
            move |cx| {
                let (base, blend) = (cx.get(base)?, cx.get(blend)?);
                let modes = cx.choices(mode)?;
                let opacity = cx.get(opacity)?;
                let n = slice_count([base.len(), blend.len(), modes.len(), opacity.len()]);
                let out: Vec<Color> = (0..n)
                    .map(|i| {
                        color_blend(
                            *wrapped(base, i),
                            *wrapped(blend, i),
                            *wrapped(&modes, i),
                            *wrapped(opacity, i),
                        )
                    })
                    .collect();
                cx.put(output, out);
                Ok(())
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Add (Color)",
            CATEGORY,
            "Input 1 + Input 2 per channel (alpha too), slice by slice.",
        )
        .input("Input 1", Color::BLACK)
        .input("Input 2", Color::BLACK)
        .output::<Color>("Output")
        .per_slice2(|a: &Color, b: &Color| Color::from_vec4(a.to_vec4() + b.to_vec4())),
    );
    r.add(
        NodeDef::new(
            "Multiply (Color)",
            CATEGORY,
            "Input 1 x Input 2 per channel (alpha too), slice by slice: tints a colour.",
        )
        .input("Input 1", Color::WHITE)
        .input("Input 2", Color::WHITE)
        .output::<Color>("Output")
        .per_slice2(|a: &Color, b: &Color| Color::from_vec4(a.to_vec4() * b.to_vec4())),
    );
    r.add(
        NodeDef::new(
            "Complement (Color)",
            CATEGORY,
            "The colour opposite on the hue circle (hue + 0.5), same saturation, value and alpha.",
        )
        .input("Input", Color::WHITE)
        .output::<Color>("Output")
        .per_slice1(|c: &Color| {
            let [h, s, v, a] = rgb_to_hsv(*c);
            hsv_to_rgb(h + 0.5, s, v, a)
        }),
    );
    r.add(
        NodeDef::new(
            "SetAlpha (Color)",
            CATEGORY,
            "Input with its alpha replaced by Alpha, slice by slice.",
        )
        .input("Input", Color::WHITE)
        .input("Alpha", 1.0f32)
        .output::<Color>("Output")
        .per_slice2(|c: &Color, a: &f32| Color { a: *a, ..*c }),
    );
    r.add(
        NodeDef::new(
            "Gradient (Color)",
            CATEGORY,
            "The colour at Input along a gradient: Key Position and Key Color (spread together, \
             in any order) are its stops; between two stops the colour is mixed linearly, before \
             the first and after the last it holds. One output slice per Input slice; no stops \
             give no output.",
        )
        .with_pins(|p| {
            let input = p.input("Input", 0.5f32);
            let key_position = p.input_spread("Key Position", vec![0.0f32, 1.0]);
            let key_color = p.input_spread("Key Color", vec![Color::BLACK, Color::WHITE]);
            let output = p.output::<Color>("Output");
            move |cx| {
                let input = cx.get(input)?;
                let (pos, col) = (cx.get(key_position)?, cx.get(key_color)?);
                let mut keys: Vec<(f32, Vec4, Easing)> = (0..slice_count([pos.len(), col.len()]))
                    .filter(|&k| wrapped(pos, k).is_finite())
                    .map(|k| (*wrapped(pos, k), wrapped(col, k).to_vec4(), Easing::Linear))
                    .collect();
                keys.sort_by(|a, b| a.0.total_cmp(&b.0));
                let out: Vec<Color> = if keys.is_empty() {
                    Vec::new()
                } else {
                    input
                        .iter()
                        .map(|&t| Color::from_vec4(play(&keys, t)))
                        .collect()
                };
                cx.put(output, out);
                Ok(())
            }
        }),
    );
    r.add(
        NodeDef::new(
            "sRGB (Color Decode)",
            CATEGORY,
            "Reads Input's RGB numbers as sRGB-encoded (what colour pickers, hex codes and \
             image files use) and gives the linear colour the pins carry. Alpha is unchanged.",
        )
        .input("Input", Color::WHITE)
        .output::<Color>("Output")
        .per_slice1(|c: &Color| map_rgb(*c, srgb_to_linear)),
    );
    r.add(
        NodeDef::new(
            "sRGB (Color Encode)",
            CATEGORY,
            "The sRGB-encoded numbers of a linear colour (sRGB (Color Decode)'s inverse). \
             Alpha is unchanged.",
        )
        .input("Input", Color::WHITE)
        .output::<Color>("Output")
        .per_slice1(|c: &Color| map_rgb(*c, linear_to_srgb)),
    );
}

/// A node splitting each colour into four Float outputs.
fn split(
    name: &'static str,
    help: &'static str,
    pins: [&'static str; 4],
    f: fn(Color) -> [f32; 4],
) -> NodeDef {
    NodeDef::new(name, CATEGORY, help).with_pins(|p| {
        let input = p.input("Input", Color::WHITE);
        let outputs = pins.map(|pin| p.output::<f32>(pin));
        move |cx| {
            let parts: Vec<[f32; 4]> = cx.get(input)?.iter().map(|c| f(*c)).collect();
            for (k, pin) in outputs.into_iter().enumerate() {
                cx.put(pin, parts.iter().map(|p| p[k]).collect());
            }
            Ok(())
        }
    })
}

fn map_rgb(c: Color, f: fn(f32) -> f32) -> Color {
    Color::rgba(f(c.r), f(c.g), f(c.b), c.a)
}

/// The sRGB transfer function's inverse (IEC 61966-2-1); negative values mirror.
pub fn srgb_to_linear(x: f32) -> f32 {
    let a = x.abs();
    let y = if a <= 0.04045 {
        a / 12.92
    } else {
        ((a + 0.055) / 1.055).powf(2.4)
    };
    y.copysign(x)
}

/// The sRGB transfer function (IEC 61966-2-1); negative values mirror.
pub fn linear_to_srgb(x: f32) -> f32 {
    let a = x.abs();
    let y = if a <= 0.003_130_8 {
        a * 12.92
    } else {
        1.055 * a.powf(1.0 / 2.4) - 0.055
    };
    y.copysign(x)
}

/// RGB from hue (cycles), chroma and the value offset: the shared core of HSV and HSL.
fn hue_to_rgb(h: f32, chroma: f32, m: f32, a: f32) -> Color {
    let h6 = h.rem_euclid(1.0) * 6.0;
    let x = chroma * (1.0 - (h6.rem_euclid(2.0) - 1.0).abs());
    let (r, g, b) = match h6 as u32 {
        0 => (chroma, x, 0.0),
        1 => (x, chroma, 0.0),
        2 => (0.0, chroma, x),
        3 => (0.0, x, chroma),
        4 => (x, 0.0, chroma),
        _ => (chroma, 0.0, x),
    };
    Color::rgba(r + m, g + m, b + m, a)
}

pub fn hsv_to_rgb(h: f32, s: f32, v: f32, a: f32) -> Color {
    let (s, v) = (s.clamp(0.0, 1.0), v.clamp(0.0, 1.0));
    let h = if h.is_finite() { h } else { 0.0 };
    hue_to_rgb(h, v * s, v - v * s, a)
}

pub fn hsl_to_rgb(h: f32, s: f32, l: f32, a: f32) -> Color {
    let (s, l) = (s.clamp(0.0, 1.0), l.clamp(0.0, 1.0));
    let h = if h.is_finite() { h } else { 0.0 };
    let chroma = (1.0 - (2.0 * l - 1.0).abs()) * s;
    hue_to_rgb(h, chroma, l - chroma / 2.0, a)
}

/// Hue in cycles (0 for greys), with the max and min channel.
fn hue(c: Color) -> (f32, f32, f32) {
    let max = c.r.max(c.g).max(c.b);
    let min = c.r.min(c.g).min(c.b);
    let d = max - min;
    let h = if d <= 0.0 {
        0.0
    } else if max == c.r {
        ((c.g - c.b) / d).rem_euclid(6.0)
    } else if max == c.g {
        (c.b - c.r) / d + 2.0
    } else {
        (c.r - c.g) / d + 4.0
    };
    (h / 6.0, max, min)
}

pub fn rgb_to_hsv(c: Color) -> [f32; 4] {
    let (h, max, min) = hue(c);
    let s = if max > 0.0 { (max - min) / max } else { 0.0 };
    [h, s, max, c.a]
}

pub fn rgb_to_hsl(c: Color) -> [f32; 4] {
    let (h, max, min) = hue(c);
    let l = (max + min) / 2.0;
    let d = max - min;
    let s = if d <= 0.0 {
        0.0
    } else {
        d / (1.0 - (2.0 * l - 1.0).abs()).max(1e-6)
    };
    [h, s, l, c.a]
}

fn color_blend(base: Color, blend: Color, mode: BlendMode, opacity: f32) -> Color {
    let f = |b: f32, s: f32| -> f32 {
        match mode {
            BlendMode::Normal => s,
            BlendMode::Multiply => b * s,
            BlendMode::Screen => 1.0 - (1.0 - b) * (1.0 - s),
            BlendMode::Overlay if b < 0.5 => 2.0 * b * s,
            BlendMode::Overlay => 1.0 - 2.0 * (1.0 - b) * (1.0 - s),
            BlendMode::Add => b + s,
            BlendMode::Subtract => b - s,
            BlendMode::Difference => (b - s).abs(),
            BlendMode::Darken => b.min(s),
            BlendMode::Lighten => b.max(s),
        }
    };
    let t = opacity * blend.a;
    let mix = |b: f32, s: f32| b + (f(b, s) - b) * t;
    Color::rgba(
        mix(base.r, blend.r),
        mix(base.g, blend.g),
        mix(base.b, blend.b),
        base.a,
    )
}

#[cfg(test)]
mod tests {
    use spreadlight_graph::{Color, Spread};

    use super::*;
    use crate::testing::{assert_close, eval, eval_out, floats, option};

    fn rgba(c: Color) -> [f32; 4] {
        [c.r, c.g, c.b, c.a]
    }

    #[test]
    fn hsv_and_hsl_round_trip_and_hit_the_primaries() {
        assert_close(
            &rgba(hsv_to_rgb(0.0, 1.0, 1.0, 1.0)),
            &[1.0, 0.0, 0.0, 1.0],
            1e-6,
        );
        assert_close(
            &rgba(hsv_to_rgb(1.0 / 3.0, 1.0, 1.0, 0.5)),
            &[0.0, 1.0, 0.0, 0.5],
            1e-5,
        );
        assert_close(
            &rgba(hsl_to_rgb(2.0 / 3.0, 1.0, 0.5, 1.0)),
            &[0.0, 0.0, 1.0, 1.0],
            1e-5,
        );
        assert_close(
            &rgba(hsl_to_rgb(0.3, 1.0, 1.0, 1.0)),
            &[1.0, 1.0, 1.0, 1.0],
            1e-6,
        );
        for k in 0..50 {
            let c = Color::rgba(
                (k % 5) as f32 / 4.0,
                (k % 7) as f32 / 6.0,
                (k % 3) as f32 / 2.0,
                1.0,
            );
            let [h, s, v, a] = rgb_to_hsv(c);
            assert_close(&rgba(hsv_to_rgb(h, s, v, a)), &rgba(c), 1e-5);
            let [h, s, l, a] = rgb_to_hsl(c);
            assert_close(&rgba(hsl_to_rgb(h, s, l, a)), &rgba(c), 1e-5);
        }
    }

    #[test]
    fn join_and_split_nodes() {
        let c: Vec<Color> = eval_out(
            "HSV (Color Join)",
            &[("Hue", floats(&[0.0, 0.5])), ("Value", floats(&[0.5]))],
            "Output",
        );
        assert_eq!(
            c,
            [
                Color::rgba(0.5, 0.0, 0.0, 1.0),
                Color::rgba(0.0, 0.5, 0.5, 1.0)
            ]
        );
        let out = eval(
            "HSL (Color Split)",
            &[(
                "Input",
                Spread::Color(vec![Color::rgba(1.0, 0.0, 0.0, 0.5)]),
            )],
        )
        .expect("split");
        assert_eq!(
            out,
            [
                floats(&[0.0]),
                floats(&[1.0]),
                floats(&[0.5]),
                floats(&[0.5])
            ]
        );
        let out = eval(
            "RGB (Color Split)",
            &[("Input", Spread::Color(vec![Color::BLACK]))],
        )
        .expect("rgb");
        assert_eq!(
            out,
            [
                floats(&[0.0]),
                floats(&[0.0]),
                floats(&[0.0]),
                floats(&[1.0])
            ]
        );
    }

    #[test]
    fn blend_modes() {
        let blend = |mode: &str, opacity: f32| -> Color {
            eval_out::<Color>(
                "ColorBlend (Color)",
                &[
                    (
                        "Base",
                        Spread::Color(vec![Color::rgba(0.25, 0.5, 1.0, 0.7)]),
                    ),
                    (
                        "Blend",
                        Spread::Color(vec![Color::rgba(0.5, 0.5, 0.5, 1.0)]),
                    ),
                    ("Mode", option(mode)),
                    ("Opacity", floats(&[opacity])),
                ],
                "Output",
            )[0]
        };
        assert_close(
            &rgba(blend("Multiply", 1.0)),
            &[0.125, 0.25, 0.5, 0.7],
            1e-6,
        );
        assert_close(&rgba(blend("Screen", 1.0)), &[0.625, 0.75, 1.0, 0.7], 1e-6);
        assert_close(&rgba(blend("Overlay", 1.0)), &[0.25, 0.5, 1.0, 0.7], 1e-6);
        assert_close(
            &rgba(blend("Difference", 1.0)),
            &[0.25, 0.0, 0.5, 0.7],
            1e-6,
        );
        assert_close(&rgba(blend("Normal", 0.5)), &[0.375, 0.5, 0.75, 0.7], 1e-6);
    }

    #[test]
    fn gradient_and_srgb() {
        let out: Vec<Color> = eval_out(
            "Gradient (Color)",
            &[("Input", floats(&[-1.0, 0.25, 2.0]))],
            "Output",
        );
        assert_eq!(
            out,
            [
                Color::BLACK,
                Color::rgba(0.25, 0.25, 0.25, 1.0),
                Color::WHITE
            ]
        );
        assert_close(&[srgb_to_linear(0.5)], &[0.214_041], 1e-5);
        for x in [0.0, 0.001, 0.2, 0.5, 1.0, 2.0] {
            assert_close(&[linear_to_srgb(srgb_to_linear(x))], &[x], 1e-5);
        }
        let c: Vec<Color> = eval_out(
            "Complement (Color)",
            &[(
                "Input",
                Spread::Color(vec![Color::rgba(1.0, 0.0, 0.0, 1.0)]),
            )],
            "Output",
        );
        assert_close(&rgba(c[0]), &[0.0, 1.0, 1.0, 1.0], 1e-6);
    }
}
