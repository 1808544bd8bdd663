//! Light sets in one dispatch: the `CookTorrance` recipes of one G-buffer
//! (a sun's, a spot's, the point lights'), shaded by one compute pass
//! instead of a pass each (issue 33, GPU per frame).
//!
//! Each CookTorrance pass reads the G-buffer, rebuilds the pixel's surface
//! and writes its own diffuse and specular targets; emeshe-frame.ron runs
//! three of them (0.146 + 0.107 + 0.073 ms on the H200), each with its own
//! ramp and tail of workgroups. Fused, one dispatch runs each set's light
//! loop in turn for the same 16x16 block: the block's G-buffer texels are
//! read from memory once and from the cache for the next sets, and the
//! dispatch starts and drains once. Every set still writes its own node's
//! outputs, by its own copy of the light loop (`source.rs`), so whatever
//! else reads one of them reads what the separate pass would have written.
//!
//! What fuses: CookTorrance recipes that CompositeLight combines, not yet
//! declared by another reader (a recipe declared first keeps its own pass),
//! with the same G-buffer and the same material switches (the shading part
//! of their permutation), no light shader node, each with its own cluster
//! store, within the device's per-stage binding limits and with at most one
//! walk that keeps lights in workgroup memory (WebGPU's 16 KiB of it). The
//! switch: [`LightFusion`], `SPREADLIGHT_LIGHT_FUSION`, `bench --light-fusion`.
//!
//! Where a CompositeLight adds the sets' terms, the fused pass also sums
//! them in registers and writes one pair of sums for it, and the sets' own
//! targets only where something else reads them (`sums.rs`, [`LightSums`]).
//!
//! The fused shader is generated ([`GENERATOR`], named by its sets'
//! permutations): the cold start's lists name it, so a warm start composes
//! it and creates its pipeline on threads before the frame asks, and a first
//! run's frame announces it where the pass is declared
//! (`shaders/generated.rs`).

mod source;
mod sums;

use std::hash::{Hash, Hasher};
use std::sync::Arc;

pub use source::MAX_SETS;
pub use sums::{
    LIGHT_SUMS_READ, LIGHT_SUMS_VAR, LightSums, SUMMED_LIGHT_SETS, light_sums, set_light_sums,
};
pub(crate) use sums::{SumCandidate, candidates as sum_candidates};

use super::cook_torrance::{CookTorrance, ShadeIo, Walk};
use super::cook_torrance_key::CookTorranceKey;
use crate::adapter_class::AdapterClass;
use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, Tex, TextureDesc};
use crate::recipe::{AsAny, Recipe, TextureRef};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::{GeneratedKey, Generator, Permutation, ShaderComposer, ShaderKey};
use crate::shadows::filter::ShadowFilter;

/// Whether the CookTorrance passes of one G-buffer run as one dispatch.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightFusion {
    /// A pass per CookTorrance (every session before the fused one).
    Separate,
    /// One pass for the light sets that can share it (this module).
    Fused,
    /// Fused on a GPU, separate on a CPU adapter (lavapipe runs dispatches
    /// one at a time: a pass's ramp and tail cost it nothing to save, and
    /// it crashed under load with fusion forced). The default: the H200
    /// measured fused 1% faster a frame (emeshe-frame 1.476 -> 1.459 ms);
    /// it was held back while the generated shader was in neither of the
    /// cold start's lists (a warm start composed it in the frame, past the
    /// 0.3 s target: docs/benchmarks.md, "Session 20 on the H200"), which
    /// it now is ([`GENERATOR`]).
    #[default]
    Auto,
}

/// The environment variable that picks [`LightFusion`] for a process
/// (`separate`, `fused` or `auto`), so both can be measured in one call;
/// `set_light_fusion` (`bench --light-fusion`) overrides it.
pub const LIGHT_FUSION_VAR: &str = "SPREADLIGHT_LIGHT_FUSION";

/// Counted each frame: the light sets shaded in a fused pass (two or more a pass).
pub const FUSED_LIGHT_SETS: &str = "light sets fused";

impl LightFusion {
    /// The setting a value of [`LIGHT_FUSION_VAR`] names, `None` for any other.
    pub fn parse(value: &str) -> Option<Self> {
        match value.trim().to_ascii_lowercase().as_str() {
            "separate" => Some(LightFusion::Separate),
            "fused" => Some(LightFusion::Fused),
            "auto" => Some(LightFusion::Auto),
            _ => None,
        }
    }

    /// Whether light sets fuse on an adapter of `class`.
    pub fn fuses_on(self, class: AdapterClass) -> bool {
        match self {
            LightFusion::Separate => false,
            LightFusion::Fused => true,
            LightFusion::Auto => class == AdapterClass::Gpu,
        }
    }

    /// What [`LIGHT_FUSION_VAR`] asks for; unset, the default. A value it
    /// does not know is an error naming the variable and the value.
    pub fn from_env() -> Result<Self, String> {
        crate::setting::from_env(
            LIGHT_FUSION_VAR,
            Self::parse,
            "`separate`, `fused` or `auto`",
        )
    }
}

/// The renderer's [`LightFusion`]: as set, else the environment's (an
/// unknown value there counts as the default; `bench` refuses it before it
/// measures anything).
pub fn light_fusion(renderer: &Renderer) -> LightFusion {
    renderer.setting(0, || LightFusion::from_env().unwrap_or_default())
}

/// Set the renderer's [`LightFusion`] (from the next frame graph declared on).
pub fn set_light_fusion(renderer: &Renderer, fusion: LightFusion) {
    renderer.set_setting(0, fusion);
}

/// What the bindings of one set use, against the device's per-stage limits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Use {
    uniform: u32,
    storage: u32,
    storage_textures: u32,
    sampled: u32,
    samplers: u32,
    /// Walks that keep a batch of lights in workgroup memory (about 9 KiB;
    /// 13 with Light Merge's bands).
    shared_walks: u32,
}

impl Use {
    fn add(self, o: Use) -> Use {
        Use {
            uniform: self.uniform + o.uniform,
            storage: self.storage + o.storage,
            storage_textures: self.storage_textures + o.storage_textures,
            sampled: self.sampled + o.sampled,
            samplers: self.samplers + o.samplers,
            shared_walks: self.shared_walks + o.shared_walks,
        }
    }

    fn within(self, limits: &wgpu::Limits) -> bool {
        self.uniform <= limits.max_uniform_buffers_per_shader_stage
            && self.storage <= limits.max_storage_buffers_per_shader_stage
            && self.storage_textures <= limits.max_storage_textures_per_shader_stage
            && self.sampled <= limits.max_sampled_textures_per_shader_stage
            && self.samplers <= limits.max_samplers_per_shader_stage
            && self.shared_walks <= 1
    }

    /// What the sets share, bound once: the surface target, and the
    /// material world's group (lib/material.wgsl: three buffers, its
    /// texture array, the UV target and a sampler).
    fn shared(recipe: &CookTorrance) -> Use {
        let materials = u32::from(recipe.materials().is_some());
        Use {
            uniform: 0,
            storage: 3 * materials,
            storage_textures: 0,
            sampled: 1 + 2 * materials,
            samplers: materials,
            shared_walks: 0,
        }
    }

    /// One set's own bindings (a bound: a binding its permutation compiles
    /// out is counted too).
    fn of_set(recipe: &CookTorrance) -> Use {
        let froxels = recipe.walk().uses_froxels();
        let spot = recipe.lights().kind == super::LightKind::Spot;
        let shadows = recipe.shadow_maps();
        let vsm = shadows.is_some_and(|s| matches!(s.filter(), ShadowFilter::Vsm { .. }));
        let textured = recipe.lights().textures().is_some();
        Use {
            // camera, grid, the shadows' parameters
            uniform: 2 + u32::from(shadows.is_some()),
            // lights, surfaces (the node's pins: not read with a material
            // world), the froxel lists (4), spot projections, shadow views
            storage: 1
                + u32::from(recipe.materials().is_none())
                + 4 * u32::from(froxels)
                // Light Merge's view-space bands.
                + u32::from(recipe.merges_lights())
                + u32::from(spot)
                + u32::from(shadows.is_some()),
            storage_textures: 2 + u32::from(recipe.sss.is_some()),
            // color, normals, depth, spot textures, shadow maps and moments
            sampled: 3 + u32::from(textured) + u32::from(shadows.is_some()) + u32::from(vsm),
            samplers: u32::from(textured),
            shared_walks: u32::from(matches!(recipe.walk(), Walk::Clustered | Walk::Tiled)),
        }
    }
}

/// The switches all sets of a fused pass must share: their permutation's
/// features other than a set's own.
fn shared_features(key: &CookTorranceKey) -> Vec<&'static str> {
    key.features()
        .filter(|f| !source::SET_FEATURES.contains(f))
        .collect()
}

/// A CookTorrance recipe behind a light component, if it is one.
fn cook_torrance(texture: &TextureRef) -> Option<&CookTorrance> {
    <dyn Recipe as AsAny>::as_any(&*texture.recipe).downcast_ref::<CookTorrance>()
}

/// The groups of recipes among `components` (CompositeLight's diffuse
/// inputs) that one pass can shade, each of two or more, in input order.
fn plan<'a>(
    fg: &FrameGraph<'a>,
    limits: &wgpu::Limits,
    components: impl IntoIterator<Item = &'a TextureRef>,
) -> Vec<Vec<&'a CookTorrance>> {
    let mut seen: Vec<u64> = Vec::new();
    let mut groups: Vec<(Vec<&'static str>, Use, Vec<&'a CookTorrance>)> = Vec::new();
    for texture in components {
        let Some(recipe) = cook_torrance(texture) else {
            continue;
        };
        if seen.contains(&recipe.id()) || fg.included(recipe.id()) || !recipe.fusable() {
            continue;
        }
        seen.push(recipe.id());
        let shared = shared_features(&recipe.shade_key());
        let own = Use::of_set(recipe);
        let joins = groups.iter_mut().find(|(features, used, members)| {
            let first = members[0];
            *features == shared
                && Arc::ptr_eq(first.gbuffer(), recipe.gbuffer())
                && same_world(first, recipe)
                && members.len() < MAX_SETS
                && members.iter().all(|m| !m.shares_clusters(recipe))
                && used.add(own).within(limits)
        });
        match joins {
            Some((_, used, members)) => {
                *used = used.add(own);
                members.push(recipe);
            }
            None => groups.push((shared, Use::shared(recipe).add(own), vec![recipe])),
        }
    }
    groups
        .into_iter()
        .map(|(_, _, members)| members)
        .filter(|members| members.len() >= 2)
        .collect()
}

/// The same material world (bound once for all sets), or none for either.
fn same_world(a: &CookTorrance, b: &CookTorrance) -> bool {
    match (a.materials(), b.materials()) {
        (None, None) => true,
        (Some(a), Some(b)) => Arc::ptr_eq(a, b),
        _ => false,
    }
}

/// Declare, as one pass each, the groups of CookTorrance recipes behind
/// `components` that can share a dispatch (when the renderer's
/// [`LightFusion`] fuses on its adapter). The recipes of a group are
/// included here, so declaring one later adds nothing; the others declare
/// their own passes as before.
pub(crate) fn declare<'a>(
    renderer: &'a Renderer,
    fg: &mut FrameGraph<'a>,
    components: impl IntoIterator<Item = &'a TextureRef>,
) {
    if !light_fusion(renderer).fuses_on(renderer.gpu.adapter_class()) {
        return;
    }
    let limits = renderer.gpu.device.limits();
    let summed = light_sums(renderer) == LightSums::On;
    for members in plan(fg, &limits, components) {
        for member in &members {
            fg.include(member.id());
        }
        for member in &members {
            member.declare_inputs(renderer, fg);
        }
        // Named without formatting a string each frame.
        const STEPS: [&str; MAX_SETS + 1] = [
            "",
            "",
            "shade 2 light sets",
            "shade 3 light sets",
            "shade 4 light sets",
        ];
        let name = PassName::new("CookTorrance").step(STEPS[members.len()]);
        // Made on a thread while the frame records, where it is not made
        // yet (a first run: no list names it).
        // Summed, what the frame writes depends on what later passes read,
        // unknown here: announce the usual case, both sums read and no set's
        // own output (a frame that writes otherwise makes its own, and the
        // last run's list names it the next time).
        if fg.gathers_pipelines() {
            let usual = Written {
                sums: [true; 2],
                ..Written::default()
            };
            fg.will_generate(generated_key(&members, summed.then_some(&usual)));
        }
        let mut pass = fg.pass(name, members[0].owner());
        // Summed: every output is made only where something reads it (the
        // sums by a CompositeLight of these sets, the sets' own by anything).
        let ios: Vec<ShadeIo> = members
            .iter()
            .map(|m| m.declare_shade_io(&mut pass, summed))
            .collect();
        let sums = summed.then(|| {
            let mut ids: Vec<u64> = members.iter().map(|m| m.id()).collect();
            let [diffuse, specular] = sums::sum_names(&mut ids);
            let desc = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float)
                .size(members[0].gbuffer().size)
                .only_if_read();
            [pass.write(&diffuse, desc), pass.write(&specular, desc)]
        });
        let count = members.len() as u64;
        pass.run(move |cx| {
            cx.count(FUSED_LIGHT_SETS, count);
            shade(cx, &members, &ios, sums)
        });
    }
}

/// The generated shader's switches: each set's own renamed for its
/// place, the shared ones (the first set's: a group's agree) once.
fn switches(keys: &[ShaderKey]) -> Vec<String> {
    let mut defs: Vec<String> = Vec::new();
    for (i, key) in keys.iter().enumerate() {
        let (own, shared): (Vec<&'static str>, Vec<&'static str>) = key
            .features
            .iter()
            .copied()
            .partition(|f| source::SET_FEATURES.contains(f));
        if i == 0 {
            defs.extend(shared.into_iter().map(str::to_owned));
        }
        defs.extend(own.into_iter().map(|f| source::set_feature(i, f)));
    }
    defs
}

/// The fused light loop as a generated shader: its parts are the sets'
/// CookTorrance permutations, in order (`shaders/generated.rs`).
pub static GENERATOR: Generator = Generator {
    name: "light_sets",
    file: <CookTorranceKey as Permutation>::FILE,
    entry: "main",
    compose: compose_sets,
};

/// The fused loop of `parts` (two to [`MAX_SETS`] CookTorrance
/// permutations), and its label.
fn compose_sets(
    composer: &mut ShaderComposer,
    parts: &[ShaderKey],
    options: &[String],
) -> Result<(String, naga::Module), RenderError> {
    let file = <CookTorranceKey as Permutation>::FILE;
    // The summed loop's own switches (`summed_switches`), and nothing else.
    let known = |option: &String| {
        ["LIGHT_SUM", "SUM_DIFFUSE", "SUM_SPECULAR"].contains(&option.as_str())
            || (0..parts.len()).any(|i| {
                OUTPUT_FEATURES
                    .iter()
                    .any(|f| *option == source::set_feature(i, f))
            })
    };
    let summed = options.iter().any(|o| o == "LIGHT_SUM");
    if let Some(unknown) = options
        .iter()
        .find(|o| !known(o) || (!summed && !o.is_empty()))
    {
        return Err(RenderError::Shader {
            shader: "lighting/light_sets (generated)".to_owned(),
            defs: options.join(", "),
            message: format!("no such option of the fused light loop: {unknown}"),
        });
    }
    if !(2..=MAX_SETS).contains(&parts.len()) || parts.iter().any(|p| p.path() != file.path) {
        return Err(RenderError::Shader {
            shader: "lighting/light_sets (generated)".to_owned(),
            defs: String::new(),
            message: format!(
                "fuses 2 to {MAX_SETS} permutations of {}, not {parts:?}",
                file.path
            ),
        });
    }
    let mut defs = switches(parts);
    defs.extend(options.iter().cloned());
    let label = format!("lighting/light_sets x{} [{}]", parts.len(), defs.join(", "));
    Ok((label, compose(composer, parts.len(), &defs, summed)?))
}

/// The generated shader of `members`' sets: summed (`written`: the
/// outputs it writes this frame) or not.
fn generated_key(members: &[&CookTorrance], written: Option<&Written>) -> GeneratedKey {
    GeneratedKey {
        generator: &GENERATOR,
        parts: members.iter().map(|m| m.shade_key().key()).collect(),
        options: written.map_or_else(Vec::new, |w| summed_switches(members.len(), w)),
    }
}

/// Compose the fused loop of `sets` sets with `defs` (the tests compose
/// every kind of set through it, as a frame does).
fn compose(
    composer: &mut ShaderComposer,
    sets: usize,
    defs: &[String],
    summed: bool,
) -> Result<naga::Module, RenderError> {
    let file = <CookTorranceKey as Permutation>::FILE;
    let library = |path: &'static str| {
        crate::shaders::library(path).ok_or_else(|| RenderError::Shader {
            shader: path.to_owned(),
            defs: String::new(),
            message: "no such library".to_owned(),
        })
    };
    let light_loop = composer.source_of(file).to_owned();
    let shadow_sampling = composer
        .source_of(library("lighting/shadow_sampling.wgsl")?)
        .to_owned();
    let spot = composer.source_of(library("lib/spot.wgsl")?).to_owned();
    let mut modules = Vec::new();
    for i in 0..sets {
        let set = source::set_modules(i, &light_loop, &shadow_sampling, &spot, summed).map_err(
            |message| RenderError::Shader {
                shader: file.path.to_owned(),
                defs: String::new(),
                message,
            },
        )?;
        modules.extend(set);
    }
    composer.compose_generated(
        &modules,
        "lighting/light_sets (generated)",
        &source::entry_source(sets, summed),
        defs,
    )
}

/// The outputs a summed pass writes this frame: each set's own (diffuse,
/// specular, subsurface) and the sums, where something reads them.
#[derive(Clone, Copy, Default, Hash)]
struct Written {
    sets: [[bool; 3]; MAX_SETS],
    sums: [bool; 2],
}

/// The set switches of the outputs a set writes, as `sums.rs` names them.
const OUTPUT_FEATURES: [&str; 3] = ["OUT_DIFFUSE", "OUT_SPECULAR", "OUT_SSS"];
/// The light loop's variables of those outputs.
const OUTPUT_VARS: [&str; 3] = ["out_diffuse", "out_specular", "out_sss"];

/// The summed loop's own switches for `written` (`sets` sets).
fn summed_switches(sets: usize, written: &Written) -> Vec<String> {
    let mut defs = vec!["LIGHT_SUM".to_owned()];
    for (i, outputs) in written.sets.iter().take(sets).enumerate() {
        for (feature, on) in OUTPUT_FEATURES.iter().zip(outputs) {
            if *on {
                defs.push(source::set_feature(i, feature));
            }
        }
    }
    for (feature, on) in ["SUM_DIFFUSE", "SUM_SPECULAR"].iter().zip(written.sums) {
        if on {
            defs.push((*feature).to_owned());
        }
    }
    defs
}

/// The fused pass: each set's resources under its own names, one dispatch.
/// `sums`: the pair of sums it declared (summed), else none.
fn shade(
    cx: &mut PassContext<'_>,
    members: &[&CookTorrance],
    ios: &[ShadeIo],
    sums: Option<[Tex; 2]>,
) -> Result<(), RenderError> {
    // Summed, what is read decides what is written (what nothing reads
    // was not made); else every output, as declared.
    let written = sums.map(|sums| {
        let mut written = Written {
            sums: sums.map(|t| cx.is_read(t)),
            ..Written::default()
        };
        for (set, io) in written.sets.iter_mut().zip(ios) {
            *set = io.outputs().map(|t| t.is_some_and(|t| cx.is_read(t)));
        }
        written
    });
    if written.is_some_and(|w| w.sums.iter().any(|s| *s)) {
        cx.count(SUMMED_LIGHT_SETS, members.len() as u64);
    }
    let guards: smallvec::SmallVec<[_; MAX_SETS]> = members
        .iter()
        .map(|m| m.cluster_store().get(cx.gpu, 1, m.lights().count()))
        .collect();
    let mut bindings = Bindings::new();
    // The pipeline's key: the sets' permutations in order (a hash, so a
    // frame formats no name; the switches are made only to compose).
    let mut hasher = rustc_hash::FxHasher::default();
    for (i, ((member, io), guard)) in members.iter().zip(ios).zip(&guards).enumerate() {
        let Some(clusters) = guard.as_ref() else {
            return Ok(());
        };
        member.shade_key().hash(&mut hasher);
        let mut set = member.shade_bindings(cx, io, clusters)?;
        if let Some(w) = &written {
            let outputs = w.sets[i];
            set = set.retain(|name| {
                OUTPUT_VARS
                    .iter()
                    .zip(outputs)
                    .all(|(var, on)| on || *var != name)
            });
        }
        let names = source::binding_names(i);
        let rename = |name: &str| {
            names
                .iter()
                .find(|(from, _)| *from == name)
                .map(|(_, to)| to.as_str())
        };
        bindings = bindings.extend(set.renamed(rename, i == 0));
    }
    written.hash(&mut hasher);
    if let (Some(w), Some([diffuse, specular])) = (&written, sums) {
        // The G-buffer, read once by the summed entry for every set (all
        // sets of a group shade the same one).
        let [color, normals, depth] = ios[0].gbuffer();
        bindings = bindings
            .texture("gbuffer_color", color)
            .texture("gbuffer_normals", normals)
            .texture("gbuffer_depth", depth);
        let sum_vars = [("sum_diffuse", diffuse), ("sum_specular", specular)];
        for ((var, tex), on) in sum_vars.into_iter().zip(w.sums) {
            if on {
                bindings = bindings.texture(var, tex);
            }
        }
    }
    let device = cx.gpu.device.clone();
    let (pipeline, reflection) = cx
        .shaders
        .generated_pipeline(&device, hasher.finish(), || {
            generated_key(members, written.as_ref())
        })?;
    let label = "CookTorrance: shade light sets";
    let groups = cx.bind_groups_reflected(label, &reflection, &pipeline, bindings)?;
    let groups: smallvec::SmallVec<[&wgpu::BindGroup; 4]> = groups.iter().collect();
    cx.dispatch(
        label,
        &pipeline,
        &groups,
        members[0].workgroups(cx.output_size),
    );
    Ok(())
}

#[cfg(test)]
mod tests;
