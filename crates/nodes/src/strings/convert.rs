//! Text from values and values from text: `AsString` for values, integers,
//! booleans, vectors and colours; `AsValue`, `AsInteger` and `AsColor` parse.

use glam::{Vec2, Vec3, Vec4};
use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::{Color, NodeDef, Registry, SliceValue};

use super::CATEGORY;
use crate::color::{linear_to_srgb, srgb_to_linear};
use crate::typed::Value;

pub fn register(r: &mut Registry) {
    r.add(as_string::<f32>("AsString (Value)", 0.0, |v, d| {
        number(*v, d)
    }));
    r.add(as_string::<Vec2>(
        "AsString (Vector 2d)",
        Vec2::ZERO,
        |v, d| components(&v.to_array(), d),
    ));
    r.add(as_string::<Vec3>(
        "AsString (Vector 3d)",
        Vec3::ZERO,
        |v, d| components(&v.to_array(), d),
    ));
    r.add(as_string::<Vec4>(
        "AsString (Vector 4d)",
        Vec4::ZERO,
        |v, d| components(&v.to_array(), d),
    ));
    r.add(
        NodeDef::new(
            "AsString (Integer)",
            CATEGORY,
            "Each whole number as decimal text.",
        )
        .input("Input", 0i64)
        .output::<String>("Output")
        .per_slice1(|i: &i64| i.to_string()),
    );
    r.add(
        NodeDef::new(
            "AsString (Boolean)",
            CATEGORY,
            "Each boolean as `true` or `false`.",
        )
        .input("Input", false)
        .output::<String>("Output")
        .per_slice1(|b: &bool| b.to_string()),
    );
    r.add(
        NodeDef::new(
            "AsString (Color)",
            CATEGORY,
            "Each colour as an sRGB hex code `#RRGGBBAA`, as colour pickers write it (the \
             linear channels are sRGB-encoded and clamped to [0, 1]).",
        )
        .input("Input", Color::WHITE)
        .output::<String>("Output")
        .per_slice1(|c: &Color| hex(*c)),
    );
    r.add(parse_node(
        "AsValue (String)",
        "Reads each slice as a number (`1.5`, `-2`, `3e-2`; white space around it is fine). \
         Text that is not a finite number gives Default and Valid off.",
        "0",
        0.0f32,
        |s| s.trim().parse::<f32>().ok().filter(|v| v.is_finite()),
    ));
    r.add(parse_node(
        "AsInteger (String)",
        "Reads each slice as a whole number (`42`, `-7`). Anything else gives Default and \
         Valid off.",
        "0",
        0i64,
        |s| s.trim().parse::<i64>().ok(),
    ));
    r.add(parse_node(
        "AsColor (String)",
        "Reads each slice as an sRGB hex colour, `#RGB`, `#RRGGBB` or `#RRGGBBAA` (the `#` \
         may be left out), and gives the linear colour. Anything else gives Default and \
         Valid off.",
        "#FFFFFF",
        Color::BLACK,
        parse_hex,
    ));
}

/// A node that reads each slice of Input with `parse`, giving Default (and
/// Valid off) where it cannot.
fn parse_node<T: Value + Copy>(
    name: &'static str,
    help: &'static str,
    input_default: &str,
    default: T,
    parse: fn(&str) -> Option<T>,
) -> NodeDef {
    NodeDef::new(name, CATEGORY, help).with_pins(|p| {
        let input = p.input("Input", input_default.to_owned());
        let default = p.input("Default", default);
        let output = p.output::<T>("Output");
        let valid = p.output::<bool>("Valid");
        move |cx| {
            let (input, default) = (cx.get(input)?, cx.get(default)?);
            let n = slice_count([input.len(), default.len()]);
            let parsed: Vec<Option<T>> =
                (0..n).map(|i| parse(wrapped(input, i).as_str())).collect();
            let out = (0..n)
                .map(|i| parsed[i].unwrap_or(*wrapped(default, i)))
                .collect();
            cx.put(output, out);
            cx.put(valid, parsed.iter().map(Option::is_some).collect());
            Ok(())
        }
    })
}

fn as_string<T: SliceValue>(
    name: &'static str,
    default: T,
    show: fn(&T, i64) -> String,
) -> NodeDef {
    NodeDef::new(
        name,
        CATEGORY,
        "Each slice as text, with Digits decimals (-1, the default: the shortest text that \
         reads back as the same number). Vectors are written `(x, y, z)`.",
    )
    .input("Input", default)
    .input("Digits", -1i64)
    .output::<String>("Output")
    .per_slice2(move |v: &T, d: &i64| show(v, *d))
}

fn number(v: f32, digits: i64) -> String {
    match usize::try_from(digits) {
        Ok(d) => format!("{v:.0$}", d.min(16)),
        Err(_) => format!("{v}"),
    }
}

fn components(v: &[f32], digits: i64) -> String {
    let parts: Vec<String> = v.iter().map(|&c| number(c, digits)).collect();
    format!("({})", parts.join(", "))
}

fn hex(c: Color) -> String {
    let byte = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    let enc = |x: f32| byte(linear_to_srgb(x));
    format!(
        "#{:02X}{:02X}{:02X}{:02X}",
        enc(c.r),
        enc(c.g),
        enc(c.b),
        byte(c.a)
    )
}

fn parse_hex(s: &str) -> Option<Color> {
    let s = s.trim();
    let s = s.strip_prefix('#').unwrap_or(s);
    if !s.chars().all(|c| c.is_ascii_hexdigit()) {
        return None;
    }
    let digits: Vec<u8> = match s.len() {
        3 => s
            .chars()
            .map(|c| {
                let d = c.to_digit(16).unwrap_or(0) as u8;
                d * 17
            })
            .collect(),
        6 | 8 => (0..s.len() / 2)
            .map(|i| u8::from_str_radix(&s[2 * i..2 * i + 2], 16).ok())
            .collect::<Option<_>>()?,
        _ => return None,
    };
    let f = |b: u8| f32::from(b) / 255.0;
    Some(Color::rgba(
        srgb_to_linear(f(digits[0])),
        srgb_to_linear(f(digits[1])),
        srgb_to_linear(f(digits[2])),
        digits.get(3).map_or(1.0, |&a| f(a)),
    ))
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use spreadlight_graph::{Color, Spread};

    use crate::testing::{eval, eval_out, floats, ints, strings_of as strings};

    #[test]
    fn values_and_vectors_as_text() {
        let s: Vec<String> = eval_out(
            "AsString (Value)",
            &[("Input", floats(&[1.5, 0.1])), ("Digits", ints(&[-1, 3]))],
            "Output",
        );
        assert_eq!(s, ["1.5", "0.100"]);
        let s: Vec<String> = eval_out(
            "AsString (Vector 3d)",
            &[
                ("Input", Spread::Vec3(vec![Vec3::new(1.0, -2.0, 0.5)])),
                ("Digits", ints(&[1])),
            ],
            "Output",
        );
        assert_eq!(s, ["(1.0, -2.0, 0.5)"]);
        let s: Vec<String> = eval_out(
            "AsString (Integer)",
            &[("Input", ints(&[i64::MAX]))],
            "Output",
        );
        assert_eq!(s, ["9223372036854775807"]);
    }

    #[test]
    fn parsing_gives_default_and_valid() {
        let out = eval(
            "AsValue (String)",
            &[
                ("Input", strings(&[" 2.5 ", "x", "inf"])),
                ("Default", floats(&[-1.0])),
            ],
        )
        .expect("as value");
        assert_eq!(out[0], floats(&[2.5, -1.0, -1.0]));
        assert_eq!(out[1], Spread::Bool(vec![true, false, false]));
        let out =
            eval("AsInteger (String)", &[("Input", strings(&["42", "4.2"]))]).expect("as integer");
        assert_eq!(out[0], ints(&[42, 0]));
    }

    #[test]
    fn hex_colours_round_trip_through_srgb() {
        let c: Vec<Color> = eval_out(
            "AsColor (String)",
            &[("Input", strings(&["#FF0000", "0f0", "#00000080", "#12"]))],
            "Output",
        );
        assert_eq!(c[0], Color::rgba(1.0, 0.0, 0.0, 1.0));
        assert_eq!(c[1], Color::rgba(0.0, 1.0, 0.0, 1.0));
        assert!((c[2].a - 128.0 / 255.0).abs() < 1e-6);
        assert_eq!(c[3], Color::BLACK);
        let text: Vec<String> =
            eval_out("AsString (Color)", &[("Input", Spread::Color(c))], "Output");
        assert_eq!(text, ["#FF0000FF", "#00FF00FF", "#00000080", "#000000FF"]);
        // Mid-grey in sRGB is about 0.214 linear, and comes back as 0x80.
        let c: Vec<Color> = eval_out(
            "AsColor (String)",
            &[("Input", strings(&["#808080"]))],
            "Output",
        );
        assert!((c[0].r - 0.2158).abs() < 1e-3, "{}", c[0].r);
    }
}
