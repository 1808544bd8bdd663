//! One node type per spread type: the macro that registers a generic node
//! function once for each slice type vvvv patchers move around (values,
//! strings, colours, 2d/3d/4d vectors, transforms), named as vvvv names the
//! variants: `GetSlice (Spreads)`, `GetSlice (String)`, ..., `GetSlice (Transform)`.
//!
//! Integers and booleans get variants too (`GetSlice (Integer)`, `GetSlice
//! (Toggle)`, named like their IOBoxes): an Int output links to a Float input,
//! but a Float never links back into an Int pin, so indices and counts taken
//! through the value variant could not be used as indices again.

/// What a node written once for every slice type asks of the type: a plain
/// value read and written through typed pin handles.
pub(crate) trait Value:
    spreadlight_graph::SliceValue + spreadlight_graph::typed_pins::PinData<Meta = ()>
{
}

impl<T: spreadlight_graph::SliceValue + spreadlight_graph::typed_pins::PinData<Meta = ()>> Value
    for T
{
}

/// `typed!(r, make, "Base", "Spreads")` registers `make::<T>(name, default)`
/// for each slice type, named `Base (Spreads)` for values and `Base (Integer)`,
/// `Base (Toggle)`, `Base (String)`,
/// `Base (Color)`, `Base (Vector 2d)`, `Base (Vector 3d)`, `Base (Vector 4d)`,
/// `Base (Transform)` for the others. With a fourth literal, `typed!(r, make,
/// "Stallone", "Spreads", "Split")`, the version follows the type:
/// `Stallone (Spreads Split)`, `Stallone (String Split)`, ...
macro_rules! typed {
    ($r:expr, $make:ident, $base:literal, $value:literal $(, $version:literal)?) => {{
        $r.add($make::<f32>(concat!($base, " (", $value, $(" ", $version,)? ")"), 0.0));
        $r.add($make::<i64>(concat!($base, " (Integer", $(" ", $version,)? ")"), 0));
        $r.add($make::<bool>(concat!($base, " (Toggle", $(" ", $version,)? ")"), false));
        $r.add($make::<String>(
            concat!($base, " (String", $(" ", $version,)? ")"),
            String::new(),
        ));
        $r.add($make::<spreadlight_graph::Color>(
            concat!($base, " (Color", $(" ", $version,)? ")"),
            spreadlight_graph::Color::WHITE,
        ));
        $r.add($make::<glam::Vec2>(
            concat!($base, " (Vector 2d", $(" ", $version,)? ")"),
            glam::Vec2::ZERO,
        ));
        $r.add($make::<glam::Vec3>(
            concat!($base, " (Vector 3d", $(" ", $version,)? ")"),
            glam::Vec3::ZERO,
        ));
        $r.add($make::<glam::Vec4>(
            concat!($base, " (Vector 4d", $(" ", $version,)? ")"),
            glam::Vec4::ZERO,
        ));
        $r.add($make::<glam::Mat4>(
            concat!($base, " (Transform", $(" ", $version,)? ")"),
            glam::Mat4::IDENTITY,
        ));
    }};
}

#[cfg(test)]
mod tests {
    /// Every per-type node exists for every slice type, under vvvv's naming.
    #[test]
    fn every_typed_node_has_every_variant() {
        let r = crate::registry();
        let ops = [
            ("GetSlice", "Spreads", ""),
            ("SetSlice", "Spreads", ""),
            ("GetSpread", "Spreads", ""),
            ("Select", "Spreads", ""),
            ("Reverse", "Spreads", ""),
            ("Shift", "Spreads", ""),
            ("Zip", "Spreads", ""),
            ("Unzip", "Spreads", ""),
            ("Stallone", "Spreads", " Join"),
            ("Stallone", "Spreads", " Split"),
            ("Cons", "Spreads", ""),
            ("Queue", "Spreads", ""),
            ("RingBuffer", "Spreads", ""),
            ("FrameDelay", "Animation", ""),
            ("S+H", "Animation", ""),
        ];
        let types = [
            "Integer",
            "Toggle",
            "String",
            "Color",
            "Vector 2d",
            "Vector 3d",
            "Vector 4d",
            "Transform",
        ];
        for (base, value, version) in ops {
            let names = std::iter::once(format!("{base} ({value}{version})"))
                .chain(types.iter().map(|t| format!("{base} ({t}{version})")));
            for name in names {
                assert!(r.get(&name).is_some(), "missing `{name}`");
            }
        }
    }
}
