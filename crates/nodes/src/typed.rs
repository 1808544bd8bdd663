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

    /// Reads of a pin by a literal position in `line`: a number as the first
    /// argument of `slices`, `set`, `input_error` and the like, or as an index
    /// into `inputs` or `outputs`.
    fn positional_reads(line: &str) -> Vec<&str> {
        const CALLS: &[&str] = &[
            ".set(",
            ".input(",
            "input_error(",
            "set_output(",
            "set_output_arc(",
            "input_arc(",
            "enum_slices(",
            "resources_at(",
            "inputs[",
            "outputs[",
        ];
        let digit_after = |rest: &str| {
            let rest = rest.strip_prefix("cx, ").unwrap_or(rest);
            rest.starts_with(|c: char| c.is_ascii_digit())
        };
        let mut found = Vec::new();
        for call in CALLS {
            for (at, _) in line.match_indices(call) {
                if digit_after(&line[at + call.len()..]) {
                    found.push(*call);
                }
            }
        }
        for (at, _) in line.match_indices("slices::<") {
            let rest = &line[at..];
            if let Some(close) = rest.find(">(")
                && digit_after(&rest[close + 2..])
            {
                found.push("slices::<T>(");
            }
        }
        found
    }

    #[test]
    fn the_positional_read_finder_finds_them() {
        // Written in two pieces so that this file holds no positional read itself.
        assert_eq!(
            positional_reads(concat!("cx.slices::<f32>", "(0)?;")).len(),
            1
        );
        assert_eq!(
            positional_reads(concat!("cx.set", "(1, a); cx.set", "(2, b)")).len(),
            2
        );
        assert_eq!(
            positional_reads(concat!("cx.input_error", "(3, \"bad\")")).len(),
            1
        );
        assert_eq!(
            positional_reads(concat!("def.outputs", "[0].name")).len(),
            1
        );
        assert!(positional_reads("h.set(\"Input\", floats(&[1.0]))").is_empty());
        assert!(positional_reads("cx.put(out, vec![1.0])").is_empty());
    }

    /// No node reads or writes a pin by its position: each declares its
    /// pins once and uses the handles.
    #[test]
    fn converted_nodes_name_their_pins_by_handle() {
        fn visit(dir: &std::path::Path, found: &mut Vec<String>) {
            let mut entries: Vec<_> = std::fs::read_dir(dir)
                .expect("the source folder reads")
                .map(|e| e.expect("a directory entry").path())
                .collect();
            entries.sort();
            for path in entries {
                let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
                if path.is_dir() {
                    visit(&path, found);
                } else if name.ends_with(".rs") {
                    let text = std::fs::read_to_string(&path).expect("a source file reads");
                    for (n, line) in text.lines().enumerate() {
                        for call in positional_reads(line) {
                            found.push(format!("{}:{}: {call}", path.display(), n + 1));
                        }
                    }
                }
            }
        }
        let mut found = Vec::new();
        visit(
            &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
            &mut found,
        );
        assert!(
            found.is_empty(),
            "pins read by position:\n{}",
            found.join("\n")
        );
    }
}
