//! Node documentation generated from the registry, so it cannot drift from
//! the code: the text `spreadlight nodes --help NAME` prints, and
//! `docs/nodes.md` (written by `spreadlight nodes --markdown`; a test checks
//! the file is current).

use std::fmt::Write;

use glam::Mat4;
use spreadlight_graph::{NodeDef, PinDef, PinType, Registry, Spread};

/// A pin's default as a patcher would type it: `0.5`, `"Space"`, `(0, 0, 0)`, `[1, 2]`.
pub fn default_text(spread: &Spread) -> String {
    fn join<T>(v: &[T], f: impl Fn(&T) -> String) -> String {
        let parts: Vec<String> = v.iter().map(f).collect();
        match parts.len() {
            0 => "(empty)".to_owned(),
            1 => parts.into_iter().next().unwrap_or_default(),
            _ => format!("[{}]", parts.join(", ")),
        }
    }
    let num = |x: &f32| format!("{x}");
    let vector = |v: &[f32]| format!("({})", v.iter().map(num).collect::<Vec<_>>().join(", "));
    match spread {
        Spread::Float(v) => join(v, num),
        Spread::Int(v) => join(v, |x| x.to_string()),
        Spread::Bool(v) => join(v, |x| x.to_string()),
        Spread::String(v) | Spread::Enum(v) => join(v, |s| format!("{s:?}")),
        Spread::Vec2(v) => join(v, |x| vector(&x.to_array())),
        Spread::Vec3(v) => join(v, |x| vector(&x.to_array())),
        Spread::Vec4(v) => join(v, |x| vector(&x.to_array())),
        Spread::Color(v) => join(v, |c| format!("rgba{}", vector(&[c.r, c.g, c.b, c.a]))),
        Spread::Mat4(v) => join(v, |m| {
            if *m == Mat4::IDENTITY {
                "identity".to_owned()
            } else {
                format!("{m:?}")
            }
        }),
        Spread::Resource(..) => "(none)".to_owned(),
    }
}

fn type_text(ty: PinType) -> String {
    match ty {
        PinType::Enum(def) => format!("{} ({})", def.name, def.options.join(" | ")),
        PinType::Any => "any type".to_owned(),
        other => other.name(),
    }
}

fn flags(def: &NodeDef) -> Vec<&'static str> {
    let mut f = Vec::new();
    if def.time_dependent {
        f.push("evaluated every frame");
    }
    if def.sink {
        f.push("a sink: evaluation starts here");
    }
    f
}

/// The help of one node type as plain text: what `spreadlight nodes --help NAME` prints.
pub fn help_text(def: &NodeDef) -> String {
    let mut s = format!("{}  [{}]\n\n{}\n", def.name, def.category, def.help);
    let pins = |s: &mut String, title: &str, pins: &[PinDef], defaults: bool| {
        if pins.is_empty() {
            return;
        }
        let _ = writeln!(s, "\n{title}:");
        for p in pins {
            let _ = write!(s, "  {}: {}", p.name, type_text(p.ty));
            if defaults {
                let _ = write!(s, " = {}", default_text(&p.default));
            }
            s.push('\n');
        }
    };
    pins(&mut s, "Inputs", &def.inputs, true);
    pins(&mut s, "Outputs", &def.outputs, false);
    let f = flags(def);
    if !f.is_empty() {
        let _ = writeln!(s, "\n({})", f.join("; "));
    }
    s
}

/// A node type by name: exactly, else ignoring case, else the only one whose name contains
/// `query`. Otherwise the candidates (all that contain it, ignoring case).
pub fn find<'a>(registry: &'a Registry, query: &str) -> Result<&'a NodeDef, Vec<&'a str>> {
    if let Some(def) = registry.get(query) {
        return Ok(def);
    }
    let q = query.trim().to_lowercase();
    if let Some(def) = registry.iter().find(|d| d.name.to_lowercase() == q) {
        return Ok(def);
    }
    let hits: Vec<&NodeDef> = registry
        .iter()
        .map(|d| d.as_ref())
        .filter(|d| d.name.to_lowercase().contains(&q))
        .collect();
    match hits.as_slice() {
        [one] => Ok(one),
        _ => Err(hits.iter().map(|d| &*d.name).collect()),
    }
}

/// Markdown anchors for headings in order, as GitHub makes them: a second
/// heading with the same slug (`!= (Value)` and `< (Value)` both give `-value`)
/// gets `-1`, the third `-2`.
fn anchors<'a>(names: impl Iterator<Item = &'a str>) -> Vec<String> {
    let mut seen = std::collections::HashMap::<String, usize>::new();
    names
        .map(|name| {
            let slug = slug(name);
            let n = seen.entry(slug.clone()).or_insert(0);
            let anchor = if *n == 0 { slug } else { format!("{slug}-{n}") };
            *n += 1;
            anchor
        })
        .collect()
}

fn slug(name: &str) -> String {
    name.to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}

/// docs/nodes.md: every node type by category, with its pins and help.
pub fn markdown(registry: &Registry) -> String {
    let mut defs: Vec<&NodeDef> = registry.iter().map(|d| d.as_ref()).collect();
    defs.sort_by(|a, b| (&a.category, &a.name).cmp(&(&b.category, &b.name)));
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Nodes\n\n{} node types. Generated from the registry by `spreadlight nodes --markdown > \
         docs/nodes.md` (a test fails when this file is out of date); `spreadlight nodes --help \
         NAME` prints one of them.\n\nEvery pin carries a spread. Unless a node says otherwise it \
         spreads slice by slice: its output has as many slices as its longest input, shorter \
         inputs wrap around, and an empty input gives an empty output.\n\n\
         ![Nodes in the editor: titles, named pins with their values edited in place, and the \
         live viewport](editor.png)\n\n\
         ![A subpatch (a module in its own file) opened in place, with the breadcrumb back to its \
         patch](editor-subpatch.png)\n",
        defs.len()
    );
    let mut categories: Vec<&str> = defs.iter().map(|d| &*d.category).collect();
    categories.dedup();
    // Every heading in document order (category headings share slugs with nodes: `Camera`),
    // then the nodes' own anchors picked out.
    let mut headings = vec!["Nodes", "Categories"];
    let mut is_node = vec![false, false];
    let mut last = "";
    for d in &defs {
        if d.category != last {
            last = &d.category;
            headings.push(&d.category);
            is_node.push(false);
        }
        headings.push(&d.name);
        is_node.push(true);
    }
    let links: Vec<String> = anchors(headings.into_iter())
        .into_iter()
        .zip(is_node)
        .filter_map(|(a, node)| node.then_some(a))
        .collect();
    let _ = writeln!(s, "## Categories\n");
    for c in &categories {
        let names: Vec<String> = defs
            .iter()
            .zip(&links)
            .filter(|(d, _)| d.category == *c)
            .map(|(d, a)| format!("[{}](#{a})", d.name))
            .collect();
        let _ = writeln!(s, "- **{c}** ({}): {}", names.len(), names.join(", "));
    }
    let mut category = "";
    for def in defs {
        if def.category != category {
            category = &def.category;
            let _ = writeln!(s, "\n## {category}");
        }
        let _ = writeln!(s, "\n### {}\n\n{}\n", def.name, def.help);
        if !def.inputs.is_empty() {
            let _ = writeln!(s, "| input | type | default |\n|---|---|---|");
            for p in &def.inputs {
                let _ = writeln!(
                    s,
                    "| {} | {} | `{}` |",
                    cell(&p.name),
                    cell(&type_text(p.ty)),
                    cell(&default_text(&p.default))
                );
            }
            s.push('\n');
        }
        if !def.outputs.is_empty() {
            let outs: Vec<String> = def
                .outputs
                .iter()
                .map(|p| format!("{} ({})", p.name, type_text(p.ty)))
                .collect();
            let _ = writeln!(s, "Outputs: {}.", outs.join(", "));
        }
        let f = flags(def);
        if !f.is_empty() {
            let _ = writeln!(s, "\n*{}.*", f.join("; "));
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::{find, help_text, markdown};

    #[test]
    fn every_node_type_has_help_and_a_category() {
        let r = crate::registry();
        assert!(r.len() >= 250, "only {} node types", r.len());
        for def in r.iter() {
            assert!(
                def.help.trim().len() > 10,
                "`{}` has no real help",
                def.name
            );
            assert!(
                !def.category.trim().is_empty(),
                "`{}` has no category",
                def.name
            );
            let text = help_text(def);
            for pin in def.inputs.iter().chain(&def.outputs) {
                assert!(
                    text.contains(&*pin.name),
                    "`{}` help misses pin `{}`",
                    def.name,
                    pin.name
                );
            }
        }
    }

    #[test]
    fn help_shows_pins_types_and_defaults() {
        let r = crate::registry();
        let text = help_text(find(&r, "GetSlice (Spreads)").expect("found"));
        assert!(text.contains("Bin Size: Int = 1"), "{text}");
        assert!(text.contains("Output Bin Size: Int"), "{text}");
        let text = help_text(find(&r, "map (value)").expect("any case"));
        assert!(
            text.contains("Mapping: Mapping (Float | Clamp | Wrap | Mirror) = \"Float\""),
            "{text}"
        );
        assert_eq!(
            find(&r, "Keyframes (3").expect("unique part").name,
            "Keyframes (3d)"
        );
        let candidates = find(&r, "GetSlice").expect_err("several");
        assert!(candidates.contains(&"GetSlice (Color)"), "{candidates:?}");
    }

    /// docs/nodes.md is generated; `SPREADLIGHT_BLESS=1` rewrites it after a change.
    #[test]
    fn docs_nodes_md_is_current() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/nodes.md");
        let want = markdown(&crate::registry());
        if std::env::var_os("SPREADLIGHT_BLESS").is_some() {
            std::fs::write(&path, &want).expect("write docs/nodes.md");
        }
        let have = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            have == want,
            "docs/nodes.md is out of date: run `cargo run -p spreadlight-cli -- nodes --markdown > docs/nodes.md` \
             (or this test with SPREADLIGHT_BLESS=1)"
        );
    }
}
