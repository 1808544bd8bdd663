//! The fused light loop's WGSL, made from the single loop's own files.
//!
//! A light set is what one `CookTorrance` shades: its light type, walk,
//! spot textures and shadow filter are `#ifdef` switches of
//! `lighting/cook_torrance.wgsl` (and of the two libraries it imports under
//! them, `lighting/shadow_sampling.wgsl` and `lib/spot.wgsl`). Several sets of
//! other types cannot share one composition of those files, whose switches
//! are global to it. So set `i` gets its own copy of the three files as
//! libraries (`spreadlight::light_set_i`, `..::shadow_sampling_i`,
//! `..::spot_i`): naga_oil then keeps their functions and globals apart,
//! each set switch is renamed `S{i}_…` (a set's light type, walk and filter
//! are its own; the material switches stay shared, as the sets must agree on
//! them), each binding moves to a range of numbers of its own and takes the
//! suffix `_s{i}` (bindings are matched by name). The loop's entry point
//! becomes `shade_set(lane, wid)`, and a generated entry calls each set's in
//! turn: one dispatch, each set's outputs written as the set's own pass would
//! write them, by the same code.
//!
//! The copies are made from the files' text, so a change to the light loop
//! reaches the fused one too; the tests below compose every kind of set.

use std::fmt::Write as _;

/// Sets one dispatch shades at most (CompositeLight takes four components).
pub const MAX_SETS: usize = 4;

/// The switches of one set, renamed per set; the others (materials, energy
/// compensation, FakeSSS, clear coat, the surface target) are shared.
pub const SET_FEATURES: &[&str] = &[
    "LIGHT_SPOT",
    "LIGHT_SUN",
    "CLUSTERED",
    "TILED",
    "PER_PIXEL",
    "MERGED",
    "SPOT_TEXTURE",
    "SHADOWS",
    "SHADOW_PCF",
    "SHADOW_PCSS",
    "SHADOW_VSM",
    // With LIGHT_SUM (sums.rs): which of the set's own targets are written.
    "OUT_DIFFUSE",
    "OUT_SPECULAR",
    "OUT_SSS",
];

/// Binding numbers of set `i` start at `SET_BINDINGS * (i + 1)`: the single
/// loop's numbers are all below it.
const SET_BINDINGS: u32 = 64;

/// The single loop's entry point, as the file declares it.
const ENTRY: &str = "@compute @workgroup_size(16, 16)\nfn main(@builtin(local_invocation_index) lane: u32, @builtin(workgroup_id) wid: vec3<u32>) {";

/// Set `i`'s entry with LIGHT_SUM: the pixel's G-buffer texels (read once
/// by the generated entry) and the sums its terms are added to.
const SUMMED_ENTRY: &str = "fn shade_set(lane: u32, wid: vec3<u32>, gbuffer_color: vec4<f32>, gbuffer_normal: vec4<f32>, gbuffer_depth: f32, light_diffuse: ptr<function, vec3<f32>>, light_specular: ptr<function, vec3<f32>>) {";

/// The per-set libraries: their import paths, as the files name them.
const SHADOW_MODULE: &str = "spreadlight::shadow_sampling";
const SPOT_MODULE: &str = "spreadlight::spot";

/// A set switch's name in set `i`.
pub fn set_feature(i: usize, feature: &str) -> String {
    format!("S{i}_{feature}")
}

/// A binding's name in set `i` (what the fused pass binds it by).
pub fn set_binding(i: usize, name: &str) -> String {
    format!("{name}_s{i}")
}

/// The import path of set `i`'s light loop.
pub fn set_module(i: usize) -> String {
    format!("spreadlight::light_set_{i}")
}

/// The names of the `@group(0)` variables `source` declares (the ones a
/// set renames).
pub fn group0_names(source: &str) -> Vec<&str> {
    source
        .lines()
        .filter_map(|line| {
            let rest = line.trim_start().strip_prefix("@group(0) @binding(")?;
            let after_var = rest.split_once(" var")?.1;
            // `var<storage, read> name: …` or `var name: …`
            let after_space = match after_var.strip_prefix('<') {
                Some(generic) => generic.split_once("> ")?.1,
                None => after_var.trim_start(),
            };
            let name = after_space.split(':').next()?.trim();
            (!name.is_empty()).then_some(name)
        })
        .collect()
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// `line` with each whole word in `words` replaced by `to(word)`; with
/// `code`, a word after `.` (a field) or before a single `:` (a field or
/// parameter declared) is left alone.
fn replace_words(line: &str, words: &[&str], code: bool, to: impl Fn(&str) -> String) -> String {
    let mut out = String::with_capacity(line.len() + 16);
    let bytes = line.as_bytes();
    let mut i = 0;
    while i < line.len() {
        let c = line[i..].chars().next().unwrap_or(' ');
        if !is_ident(c) {
            out.push(c);
            i += c.len_utf8();
            continue;
        }
        let end = line[i..]
            .find(|c: char| !is_ident(c))
            .map_or(line.len(), |n| i + n);
        let word = &line[i..end];
        let after_dot = i > 0 && bytes[i - 1] == b'.';
        let rest = line[end..].trim_start();
        let declared = rest.starts_with(':') && !rest.starts_with("::");
        if words.contains(&word) && !(code && (after_dot || declared)) {
            out.push_str(&to(word));
        } else {
            out.push_str(word);
        }
        i = end;
    }
    out
}

/// One file's text made set `i`'s: set switches renamed on the
/// preprocessor's lines, the per-set libraries' paths suffixed, group 0's
/// bindings renumbered and renamed.
fn for_set(source: &str, i: usize, names: &[&str]) -> String {
    let offset = SET_BINDINGS * (i as u32 + 1);
    let shadow = format!("{SHADOW_MODULE}_{i}");
    let spot = format!("{SPOT_MODULE}_{i}");
    let mut out = String::with_capacity(source.len() + 1024);
    for line in source.lines() {
        let trimmed = line.trim_start();
        let line = if trimmed.starts_with("#if") || trimmed.starts_with("#else") {
            replace_words(line, SET_FEATURES, false, |f| set_feature(i, f))
        } else if trimmed.starts_with("#import") || trimmed.starts_with("#define_import_path") {
            // `spreadlight::spot::spot_mask`, `spreadlight::shadow_sampling::light_shadow`
            // and the libraries' own paths; other paths are shared.
            let mut l = line.replace(&format!("{SHADOW_MODULE}::"), &format!("{shadow}::"));
            l = l.replace(&format!("{SPOT_MODULE}::"), &format!("{spot}::"));
            for (path, to) in [(SHADOW_MODULE, &shadow), (SPOT_MODULE, &spot)] {
                if l.trim_end().ends_with(path) && l.trim_start().starts_with("#define_import_path")
                {
                    l = format!("#define_import_path {to}");
                }
            }
            l
        } else if let Some(rest) = trimmed.strip_prefix("@group(0) @binding(") {
            let (number, tail) = rest.split_once(')').unwrap_or(("0", rest));
            let number: u32 = number.parse().unwrap_or(0) + offset;
            // The declared name is followed by its type's `:`: renamed all the same.
            let tail = replace_words(tail, names, false, |n| set_binding(i, n));
            format!("@group(0) @binding({number}){tail}")
        } else if trimmed.starts_with("//") {
            line.to_owned()
        } else {
            replace_words(line, names, true, |n| set_binding(i, n))
        };
        out.push_str(&line);
        out.push('\n');
    }
    out
}

/// The three libraries of set `i`: (import path, file name for messages,
/// text), in the order they must be added (each after what it imports).
/// `light_loop`, `shadow_sampling` and `spot`: the current text of
/// `lighting/cook_torrance.wgsl`, `lighting/shadow_sampling.wgsl` and
/// `lib/spot.wgsl`. `summed`: the loop adds its terms to the sets' sums
/// (LIGHT_SUM, sums.rs). An error names what no longer matches.
pub fn set_modules(
    i: usize,
    light_loop: &str,
    shadow_sampling: &str,
    spot: &str,
    summed: bool,
) -> Result<Vec<(String, String, String)>, String> {
    if !light_loop.contains(ENTRY) {
        return Err(format!(
            "lighting/cook_torrance.wgsl: the fused light loop expects its entry point as `{ENTRY}`"
        ));
    }
    let mut names: Vec<&str> = group0_names(light_loop);
    names.extend(group0_names(shadow_sampling));
    names.extend(group0_names(spot));
    let shadow = for_set(shadow_sampling, i, &names);
    let spot_text = for_set(spot, i, &names);
    let entry = if summed {
        SUMMED_ENTRY
    } else {
        "fn shade_set(lane: u32, wid: vec3<u32>) {"
    };
    let body = light_loop.replace(ENTRY, entry);
    let body = format!(
        "#define_import_path {}\n{}",
        set_module(i),
        for_set(&body, i, &names)
    );
    Ok(vec![
        (
            format!("{SHADOW_MODULE}_{i}"),
            format!("lighting/shadow_sampling.wgsl (light set {i})"),
            shadow,
        ),
        (
            format!("{SPOT_MODULE}_{i}"),
            format!("lib/spot.wgsl (light set {i})"),
            spot_text,
        ),
        (
            set_module(i),
            format!("lighting/cook_torrance.wgsl (light set {i})"),
            body,
        ),
    ])
}

/// The fused entry shader for `sets` sets: each set's loop in turn.
/// `summed`: the sets add their terms to two sums in registers, which the
/// entry writes once, each under its switch (sums.rs).
pub fn entry_source(sets: usize, summed: bool) -> String {
    let mut out = String::from(
        "// Generated (crates/render/src/lighting/light_sets/source.rs): the\n\
         // light sets of one G-buffer in one dispatch, each shaded and written\n\
         // by its own copy of lighting/cook_torrance.wgsl.\n",
    );
    for i in 0..sets {
        let _ = writeln!(out, "#import {} as set_{i}", set_module(i));
    }
    if summed {
        out.push_str(SUM_TARGETS);
    }
    out.push_str(
        "\n@compute @workgroup_size(16, 16)\n\
         fn main(@builtin(local_invocation_index) lane: u32, @builtin(workgroup_id) wid: vec3<u32>) {\n",
    );
    if summed {
        out.push_str(LOAD_TEXELS);
    }
    for i in 0..sets {
        if summed {
            let _ = writeln!(
                out,
                "    set_{i}::shade_set(lane, wid, texel_color, texel_normal, texel_depth, &diffuse, &specular);"
            );
        } else {
            let _ = writeln!(out, "    set_{i}::shade_set(lane, wid);");
        }
    }
    if summed {
        out.push_str(STORE_SUMS);
    }
    out.push_str("}\n");
    out
}

/// The sums' targets and the G-buffer the entry reads once for all sets
/// (binding numbers below every set's, above the single loop's and its
/// libraries').
const SUM_TARGETS: &str = "
@group(0) @binding(42) var gbuffer_color: texture_2d<f32>;
@group(0) @binding(43) var gbuffer_normals: texture_2d<f32>;
@group(0) @binding(44) var gbuffer_depth: texture_2d<f32>;
#ifdef SUM_DIFFUSE
@group(0) @binding(40) var sum_diffuse: texture_storage_2d<rgba16float, write>;
#endif
#ifdef SUM_SPECULAR
@group(0) @binding(41) var sum_specular: texture_storage_2d<rgba16float, write>;
#endif
";

/// The lane's pixel (as the light loop places it: 8x4 blocks per 32
/// lanes), its G-buffer texels read once (each set read them itself), and
/// the sums.
const LOAD_TEXELS: &str = "    let warp = lane / 32u;
    let pixel = wid.xy * 16u + vec2<u32>((warp & 1u) * 8u + (lane & 7u), (warp >> 1u) * 4u + ((lane >> 3u) & 3u));
    var texel_color = vec4<f32>(0.0);
    var texel_normal = vec4<f32>(0.0);
    var texel_depth = 0.0;
    if (all(pixel < textureDimensions(gbuffer_depth))) {
        texel_depth = textureLoad(gbuffer_depth, pixel, 0).r;
        texel_normal = textureLoad(gbuffer_normals, pixel, 0);
        texel_color = textureLoad(gbuffer_color, pixel, 0);
    }
    var diffuse = vec3<f32>(0.0);
    var specular = vec3<f32>(0.0);
";

/// The sums stored at the lane's pixel, clamped below half-float overflow
/// as each set's terms were; a pixel of background stores the zeros it summed.
const STORE_SUMS: &str = "#ifdef SUM_DIFFUSE
    if (all(pixel < textureDimensions(sum_diffuse))) {
        textureStore(sum_diffuse, pixel, vec4<f32>(min(diffuse, vec3<f32>(65000.0)), 1.0));
    }
#endif
#ifdef SUM_SPECULAR
    if (all(pixel < textureDimensions(sum_specular))) {
        textureStore(sum_specular, pixel, vec4<f32>(min(specular, vec3<f32>(65000.0)), 1.0));
    }
#endif
";

/// The names set `i` binds by, for each name of the single loop (group 0
/// of the three files): kept for the process, as bindings borrow them.
pub fn binding_names(i: usize) -> &'static [(&'static str, String)] {
    static NAMES: std::sync::OnceLock<Vec<Vec<(&'static str, String)>>> =
        std::sync::OnceLock::new();
    let all = NAMES.get_or_init(|| {
        let files = [
            <crate::lighting::cook_torrance_key::CookTorranceKey as crate::shaders::Permutation>::FILE
                .source,
            crate::shaders::library("lighting/shadow_sampling.wgsl").map_or("", |f| f.source),
            crate::shaders::library("lib/spot.wgsl").map_or("", |f| f.source),
        ];
        let names: Vec<&'static str> = files.into_iter().flat_map(group0_names).collect();
        (0..MAX_SETS)
            .map(|i| names.iter().map(|n| (*n, set_binding(i, n))).collect())
            .collect()
    });
    all.get(i).map_or(&[], Vec::as_slice)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_set_renames_its_switches_paths_and_bindings_only() {
        let source = "#import spreadlight::lights::{range_window}\n\
                      #import spreadlight::shadow_sampling::light_shadow\n\
                      #ifdef LIGHT_SPOT\n\
                      #import spreadlight::spot::spot_mask\n\
                      #endif\n\
                      #ifndef MATERIALS\n\
                      struct Grid { depth: vec4<f32>, }\n\
                      #endif\n\
                      @group(0) @binding(1) var<uniform> grid: Grid;\n\
                      @group(0) @binding(2) var<storage, read> lights: array<Light>;\n\
                      @group(0) @binding(10) var depth: texture_2d<f32>;\n\
                      fn f(x: u32) -> f32 { let d = textureLoad(depth, vec2<u32>(x), 0).r; return d * grid.depth.x + f32(arrayLength(&lights)); }\n\
                      // lights in a comment stay\n";
        let names = group0_names(source);
        assert_eq!(names, ["grid", "lights", "depth"]);
        let set = for_set(source, 2, &names);
        let expected = "#import spreadlight::lights::{range_window}\n\
                        #import spreadlight::shadow_sampling_2::light_shadow\n\
                        #ifdef S2_LIGHT_SPOT\n\
                        #import spreadlight::spot_2::spot_mask\n\
                        #endif\n\
                        #ifndef MATERIALS\n\
                        struct Grid { depth: vec4<f32>, }\n\
                        #endif\n\
                        @group(0) @binding(193) var<uniform> grid_s2: Grid;\n\
                        @group(0) @binding(194) var<storage, read> lights_s2: array<Light>;\n\
                        @group(0) @binding(202) var depth_s2: texture_2d<f32>;\n\
                        fn f(x: u32) -> f32 { let d = textureLoad(depth_s2, vec2<u32>(x), 0).r; return d * grid_s2.depth.x + f32(arrayLength(&lights_s2)); }\n\
                        // lights in a comment stay\n";
        assert_eq!(set, expected);
    }

    #[test]
    fn the_files_give_every_binding_a_name_and_the_loop_its_entry() {
        let light_loop = <crate::lighting::cook_torrance_key::CookTorranceKey as crate::shaders::Permutation>::FILE.source;
        let names = group0_names(light_loop);
        for name in [
            "camera",
            "grid",
            "lights",
            "indices",
            "out_diffuse",
            "out_sss",
        ] {
            assert!(names.contains(&name), "{name} in {names:?}");
        }
        // Every `@group(0)` line of the three files yields a name, and none is
        // below a set's first binding number's reach.
        for file in ["lighting/shadow_sampling.wgsl", "lib/spot.wgsl"] {
            let source = crate::shaders::library(file).expect("a library").source;
            let lines = source.matches("@group(0) @binding(").count();
            assert_eq!(group0_names(source).len(), lines, "{file}");
        }
        let highest = [light_loop]
            .into_iter()
            .chain(
                ["lighting/shadow_sampling.wgsl", "lib/spot.wgsl"]
                    .map(|f| crate::shaders::library(f).expect("a library").source),
            )
            .flat_map(|s| s.split("@binding(").skip(1))
            .filter_map(|s| s.split(')').next()?.parse::<u32>().ok())
            .max();
        assert!(highest.is_some_and(|h| h < SET_BINDINGS), "{highest:?}");
        assert!(set_modules(0, light_loop, "", "", false).is_ok());
        assert!(set_modules(0, light_loop, "", "", true).is_ok());
        let moved = light_loop.replace(ENTRY, "fn main() {");
        let err = set_modules(0, &moved, "", "", false).expect_err("no entry to turn");
        assert!(err.contains("cook_torrance.wgsl"), "{err}");
    }
}
