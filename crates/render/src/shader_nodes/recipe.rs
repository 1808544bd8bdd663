//! A shader node's recipe: its passes declared into the frame graph like any
//! built-in pass (culled when nothing reads their targets, timed, pooled).
//!
//! Targets are versioned: each write of a target (a pass, or one iteration of
//! a repeated pass) is a frame-graph texture of its own, and a read sees the
//! latest version written before it, so repetition and ping-ponging need no
//! swapping. A target's last write is named `shader{id}/{target}`, which is
//! what the node outputs; a persistent target keeps one name across frames,
//! and the pass that writes it reads last frame's value through a copy. A
//! skipped pass (its Bool pin on) passes its first texture on.

use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use super::program::{Builtin, PassPlan, Program, Role};
use super::utility;
use crate::error::RenderError;
use crate::frame_graph::{
    BindGroups, Bindings, FrameGraph, Lifetime, PassContext, SizeRule, Tex, TextureDesc,
};
use crate::gbuffer::GBuffer;
use crate::material::MaterialWorld;
use crate::material::library::LibraryBinding;
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::Sampling;

/// What the node gives one slice's recipe.
pub struct ShaderNodeInputs {
    /// Per `@input`, in order.
    pub textures: Vec<Option<TextureRef>>,
    pub gbuffer: Option<Arc<GBuffer>>,
    /// The material world the file reads through `spreadlight::materials`
    /// (its `Material World` pin); None where it does not import it.
    pub materials: Option<Arc<MaterialWorld>>,
    /// The uniform block with the pins written (empty without one).
    pub params: Vec<u8>,
    /// Per pass: whether its skip pin is on.
    pub skips: Vec<bool>,
    pub time: f32,
    pub delta: f32,
    pub slice: u32,
    /// Permutations compiled to make this recipe (counted once in the frame report).
    pub compiled: u64,
}

/// One version of a target, or something outside the node passed on by a skip.
#[derive(Clone, Debug, PartialEq)]
enum Source {
    Version { target: usize, write: u32 },
    Outside(String),
}

/// One dispatch (a pass, or one iteration of it) with everything resolved.
struct Step {
    /// Its place among the recipe's steps (which kept uniform it writes).
    ordinal: u32,
    pass: usize,
    iteration: u32,
    /// Per destination: target index, its write number, size.
    dests: Vec<(usize, u32, (u32, u32))>,
    /// Per `Role::Read` binding: what it reads.
    reads: HashMap<u32, Source>,
}

pub struct ShaderNodeRecipe {
    id: u64,
    owner: Option<u32>,
    type_name: String,
    program: Arc<Program>,
    inputs: ShaderNodeInputs,
    /// Names persistent targets keep across frames (node and slice).
    history: String,
    counted: AtomicBool,
}

impl ShaderNodeRecipe {
    pub fn new(
        owner: Option<u32>,
        type_name: &str,
        program: Arc<Program>,
        inputs: ShaderNodeInputs,
    ) -> Arc<Self> {
        let history = format!(
            "shader {type_name} #{}/{}",
            owner.map_or(0, |o| o),
            inputs.slice
        );
        Arc::new(ShaderNodeRecipe {
            id: next_recipe_id(),
            owner,
            type_name: type_name.to_owned(),
            program,
            inputs,
            history,
            counted: AtomicBool::new(false),
        })
    }

    /// The frame-graph name `target` ends the frame under.
    pub fn target_name(&self, target: &str) -> String {
        match self.program.targets.iter().find(|t| t.name == target) {
            Some(t) if t.lifetime == Lifetime::Persistent => format!("{} {target}", self.history),
            _ => format!("shader{}/{target}", self.id),
        }
    }

    /// The texture `target` holds when the node's passes are done.
    pub fn texture(self: &Arc<Self>, target: &str) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.target_name(target),
        }
    }

    fn version_name(&self, target: usize, write: u32, last: &[u32]) -> String {
        let decl = &self.program.targets[target];
        if decl.lifetime == Lifetime::Persistent || last[target] == write {
            self.target_name(&decl.name)
        } else {
            format!("shader{}/{}#{write}", self.id, decl.name)
        }
    }

    fn source_name(&self, source: &Source, last: &[u32]) -> String {
        match source {
            Source::Version { target, write } => self.version_name(*target, *write, last),
            Source::Outside(name) => name.clone(),
        }
    }

    fn target_index(&self, name: &str) -> usize {
        self.program
            .targets
            .iter()
            .position(|t| t.name == name)
            .unwrap_or(0)
    }

    /// Where binding `role` of a pass reads from, outside the node's targets.
    fn outside(&self, role: &Role) -> Option<String> {
        match role {
            Role::Input(i) => self
                .inputs
                .textures
                .get(*i)?
                .as_ref()
                .map(|t| t.name.clone()),
            Role::GBuffer(name) => {
                let g = &self.inputs.gbuffer.as_ref()?.targets;
                Some(match name.as_str() {
                    "color" => g.color.clone(),
                    "normals" => g.normals.clone(),
                    "depth" => g.depth.clone(),
                    "velocity" => g.velocity_uv.clone(),
                    _ => return None,
                })
            }
            _ => None,
        }
    }

    /// The material world's texture array, when some material reads it and
    /// some pass samples it (`SampleFeature`); else a stand-in is bound.
    fn materials_array(&self) -> Option<&TextureRef> {
        let samples = (self.program.passes.iter().flat_map(|p| &p.bindings))
            .any(|(_, r)| *r == Role::Materials(LibraryBinding::Textures));
        self.inputs
            .materials
            .as_ref()
            .filter(|_| samples)?
            .textures()
    }

    /// What a target's `scale=` is a scale of: the node's first connected
    /// texture input's size, as any image effect takes its source's
    /// ([`FrameGraph::effect_size`]), so a filter keeps a texture of
    /// another size whole instead of reading it texel for texel into a
    /// frame-size target; with no texture input (a source such as Noise),
    /// the frame's size. Declared after the inputs, which declare first.
    fn size_basis(&self, fg: &FrameGraph<'_>) -> (u32, u32) {
        let output = fg.output_size();
        match self.inputs.textures.iter().flatten().next() {
            Some(input) => fg.effect_size(&input.name).pixels(output),
            None => output,
        }
    }

    /// Unroll the passes into dispatches for targets whose `scale=` is of
    /// `output` pixels ([`ShaderNodeRecipe::size_basis`]).
    fn plan(&self, output: (u32, u32)) -> (Vec<Step>, Vec<Option<Source>>, u64) {
        let targets = &self.program.targets;
        let mut current: Vec<Option<(Source, (u32, u32))>> = vec![None; targets.len()];
        let mut writes = vec![0u32; targets.len()];
        let mut steps = Vec::new();
        let mut skipped = 0;
        for (index, pass) in self.program.passes.iter().enumerate() {
            let dest_ids: Vec<usize> = pass
                .decl
                .targets
                .iter()
                .map(|t| self.target_index(t))
                .collect();
            if self.inputs.skips.get(index).copied().unwrap_or(false) {
                skipped += 1;
                let through = self.first_read(pass, &current);
                for &d in &dest_ids {
                    let size = targets[d].size.pixels(output);
                    current[d] = through.clone().map(|s| (s, size));
                }
                continue;
            }
            let mut iteration = 0u32;
            loop {
                let done = match pass.decl.repeat {
                    super::annotations::Repeat::Once => iteration >= 1,
                    super::annotations::Repeat::Times(n) => iteration >= n,
                    super::annotations::Repeat::Until { width, height } => {
                        iteration >= 64
                            || current[dest_ids[0]]
                                .as_ref()
                                .is_some_and(|(_, (w, h))| *w <= width && *h <= height)
                    }
                };
                if done {
                    break;
                }
                let mut reads = HashMap::new();
                for (binding, role) in &pass.bindings {
                    let source = match role {
                        Role::Read(t) => {
                            let t = self.target_index(t);
                            match &current[t] {
                                // The writer of a persistent target reads last frame's value (a copy).
                                _ if targets[t].lifetime == Lifetime::Persistent => None,
                                Some((s, _)) => Some(s.clone()),
                                None => None,
                            }
                        }
                        _ => None,
                    };
                    if let Some(s) = source {
                        reads.insert(*binding, s);
                    }
                }
                let mut dests = Vec::new();
                for &d in &dest_ids {
                    let size = match &current[d] {
                        Some((_, (w, h))) if pass.decl.step < 1.0 => (
                            ((*w as f32 * pass.decl.step).ceil() as u32).max(1),
                            ((*h as f32 * pass.decl.step).ceil() as u32).max(1),
                        ),
                        _ => targets[d].size.pixels(output),
                    };
                    writes[d] += 1;
                    dests.push((d, writes[d], size));
                }
                for &(d, write, size) in &dests {
                    current[d] = Some((Source::Version { target: d, write }, size));
                }
                steps.push(Step {
                    ordinal: steps.len() as u32,
                    pass: index,
                    iteration,
                    dests,
                    reads,
                });
                iteration += 1;
            }
        }
        (
            steps,
            current.into_iter().map(|c| c.map(|(s, _)| s)).collect(),
            skipped,
        )
    }

    fn first_read(
        &self,
        pass: &PassPlan,
        current: &[Option<(Source, (u32, u32))>],
    ) -> Option<Source> {
        pass.bindings.iter().find_map(|(_, role)| match role {
            Role::Read(t) => current[self.target_index(t)]
                .as_ref()
                .map(|(s, _)| s.clone()),
            other => self.outside(other).map(Source::Outside),
        })
    }

    fn run(
        &self,
        renderer: &Renderer,
        cx: &mut PassContext<'_>,
        step: &Step,
        io: &StepIo,
    ) -> Result<(), RenderError> {
        let pass = &self.program.passes[step.pass];
        let device = cx.gpu.device.clone();
        let mut fresh = false;
        for (&(d, _, _), &target) in step.dests.iter().zip(&io.dests) {
            let decl = &self.program.targets[d];
            let persistent = decl.lifetime == Lifetime::Persistent;
            if persistent && cx.is_fresh(target) {
                fresh = true;
            }
            if let Some(color) = decl.clear
                && (!persistent || cx.is_fresh(target))
            {
                utility::fill(cx, target, decl.format, color)?;
            }
        }
        for &(history, copy) in &io.histories {
            cx.copy_history(history, copy)?;
        }
        if step.iteration > 0 {
            cx.count("shader node repeats", 1);
        }
        let size = step.dests[0].2;
        let uniform = self.program.uniform.as_ref().map(|u| {
            let mut bytes = self.inputs.params.clone();
            bytes.resize(u.size as usize, 0);
            for &(builtin, offset) in &u.builtins {
                let words: Vec<u32> = match builtin {
                    Builtin::Size => vec![(size.0 as f32).to_bits(), (size.1 as f32).to_bits()],
                    Builtin::Texel => vec![
                        (1.0 / size.0 as f32).to_bits(),
                        (1.0 / size.1 as f32).to_bits(),
                    ],
                    Builtin::Time => vec![self.inputs.time.to_bits()],
                    Builtin::Delta => vec![self.inputs.delta.to_bits()],
                    Builtin::Iteration => vec![step.iteration],
                    Builtin::Fresh => vec![u32::from(fresh)],
                    Builtin::Slice => vec![self.inputs.slice],
                };
                for (k, w) in words.iter().enumerate() {
                    let at = offset as usize + 4 * k;
                    bytes[at..at + 4].copy_from_slice(&w.to_le_bytes());
                }
            }
            // Kept under the node, one buffer per slice and step, written
            // only when its bytes change, so the bind groups over it are
            // kept too (`bind_groups_made`). Past 65,536 slices or steps, a
            // new buffer each frame rather than one shared by two steps.
            let kept = (self.inputs.slice < 1 << 16 && step.ordinal < 1 << 16)
                .then_some(self.owner)
                .flatten();
            renderer.kept_init_at(
                kept,
                "shader node uniform",
                self.inputs.slice << 16 | step.ordinal,
                &bytes,
                wgpu::BufferUsages::UNIFORM,
            )
        });
        enum Bound {
            View(wgpu::TextureView),
            Buffer(wgpu::Buffer),
            Sampler(wgpu::Sampler),
        }
        // (binding, its name in the pass, resource).
        let mut bound: Vec<(u32, &str, Bound)> = Vec::new();
        // Group 3: the material world (spreadlight::materials).
        let mut world: Vec<(u32, &str, Bound)> = Vec::new();
        for ((binding, role), name) in pass.bindings.iter().zip(&pass.binding_names) {
            if let Role::Materials(what) = role {
                let materials = self
                    .inputs
                    .materials
                    .as_ref()
                    .ok_or_else(|| missing(&self.type_name, "Material World"))?;
                let resource = match what {
                    LibraryBinding::Textures => Bound::View(match io.array {
                        Some(tex) => {
                            let texture = cx.texture(tex)?.clone();
                            cx.view_of(&texture, crate::texture_pool::ViewSpec::array())
                        }
                        None => materials.stand_in_array(),
                    }),
                    LibraryBinding::Sampler => Bound::Sampler(cx.sampler(Sampling::LinearRepeat)),
                    buffer => Bound::Buffer(
                        materials
                            .library_buffer(*buffer)
                            .ok_or_else(|| missing(&self.type_name, "Material World"))?
                            .clone(),
                    ),
                };
                world.push((*binding, name, resource));
                continue;
            }
            let resource = match role {
                Role::Uniform => Bound::Buffer(uniform.clone().ok_or_else(|| {
                    RenderError::Graph("uniform block without a layout".to_owned())
                })?),
                Role::GBuffer(name) if name == "camera" => match &self.inputs.gbuffer {
                    Some(g) => Bound::Buffer(g.camera_buffer().clone()),
                    None => return Err(missing(&self.type_name, "GBuffer")),
                },
                Role::Sampler(decl) => Bound::Sampler(cx.sampler(if decl.repeat {
                    Sampling::LinearRepeat
                } else {
                    Sampling::LinearClamp
                })),
                Role::Write(t) => {
                    let i = pass.decl.targets.iter().position(|d| d == t).unwrap_or(0);
                    let target = io.dests.get(i).ok_or_else(|| {
                        RenderError::Graph(format!("{}: no target `{t}`", self.type_name))
                    })?;
                    Bound::View(cx.view(*target)?)
                }
                Role::Read(_) => {
                    let tex = io.reads.get(binding).ok_or_else(|| {
                        missing(&self.type_name, "a target read before it is written")
                    })?;
                    Bound::View(cx.view(*tex)?)
                }
                other => {
                    let tex = io.outside.get(binding).ok_or_else(|| {
                        missing(
                            &self.type_name,
                            &match other {
                                Role::Input(i) => self
                                    .program
                                    .input_names
                                    .get(*i)
                                    .cloned()
                                    .unwrap_or_default(),
                                _ => "GBuffer".to_owned(),
                            },
                        )
                    })?;
                    Bound::View(cx.view(*tex)?)
                }
            };
            bound.push((*binding, name, resource));
        }
        let program = self.program.clone();
        let pipeline = cx.shaders.external_compute_pipeline(
            &device,
            self.program.key,
            &self.program.file,
            move || program.module.clone(),
            &pass.decl.entry,
        );
        let group_of = |index: u32, bound: &[(u32, &str, Bound)]| {
            let entries: Vec<wgpu::BindGroupEntry<'_>> = bound
                .iter()
                .map(|(binding, _, b)| wgpu::BindGroupEntry {
                    binding: *binding,
                    resource: match b {
                        Bound::View(v) => wgpu::BindingResource::TextureView(v),
                        Bound::Buffer(b) => b.as_entire_binding(),
                        Bound::Sampler(s) => wgpu::BindingResource::Sampler(s),
                    },
                })
                .collect();
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(&self.type_name),
                layout: &pipeline.get_bind_group_layout(index),
                entries: &entries,
            })
        };
        // What the groups hold, by name: last frame's groups are bound again
        // when it is all the same (a still uniform, the same textures).
        let held =
            (bound.iter().chain(&world)).fold(Bindings::new(), |held, (_, name, b)| match b {
                Bound::View(v) => held.view(name, v.clone()),
                Bound::Buffer(b) => held.buffer(name, b),
                Bound::Sampler(s) => held.sampler_object(name, s.clone()),
            });
        let groups = cx.bind_groups_made(&pass.decl.entry, &pipeline, held, || {
            let mut groups = BindGroups::new();
            groups.push(group_of(0, &bound));
            // A pass reading the world has a derived layout of four groups,
            // the two between empty.
            if !world.is_empty() {
                groups.extend((1..crate::material::library::GROUP).map(|g| group_of(g, &[])));
                groups.push(group_of(crate::material::library::GROUP, &world));
            }
            groups
        })?;
        let groups: Vec<&wgpu::BindGroup> = groups.iter().collect();
        let [wx, wy, _] = pass.workgroup;
        cx.dispatch(
            &pass.decl.entry,
            &pipeline,
            &groups,
            (size.0.div_ceil(wx.max(1)), size.1.div_ceil(wy.max(1)), 1),
        );
        Ok(())
    }
}

fn missing(node: &str, what: &str) -> RenderError {
    RenderError::Graph(format!("{node}: nothing connected to `{what}`"))
}

/// A step's frame-graph names, resolved once at declaration.
struct StepNames {
    dests: Vec<String>,
    /// Per `Role::Read` binding.
    reads: HashMap<u32, String>,
    /// Per binding of a texture from outside the node (an input, a G-buffer target).
    outside: HashMap<u32, String>,
    /// (persistent target, its copy) for persistent targets the pass also reads.
    histories: Vec<(String, String)>,
    /// The material world's texture array, where the pass samples it.
    array: Option<String>,
}

impl StepNames {
    /// The handles of these names among what the step's pass `declared`
    /// (each name is one of its writes or reads: a read of what the pass
    /// writes is declared as the write).
    fn io(&self, declared: &HashMap<&str, Tex>) -> Result<StepIo, String> {
        let tex = |name: &String| {
            declared
                .get(name.as_str())
                .copied()
                .ok_or_else(|| format!("`{name}` was not declared"))
        };
        let by_binding = |names: &HashMap<u32, String>| {
            names
                .iter()
                .map(|(binding, name)| Ok((*binding, tex(name)?)))
                .collect::<Result<HashMap<u32, Tex>, String>>()
        };
        Ok(StepIo {
            dests: self.dests.iter().map(tex).collect::<Result<_, _>>()?,
            reads: by_binding(&self.reads)?,
            outside: by_binding(&self.outside)?,
            histories: (self.histories.iter())
                .map(|(history, copy)| Ok((tex(history)?, tex(copy)?)))
                .collect::<Result<_, String>>()?,
            array: self.array.as_ref().map(tex).transpose()?,
        })
    }
}

/// What a step's pass declared, as [`StepNames`] names it.
struct StepIo {
    dests: Vec<Tex>,
    reads: HashMap<u32, Tex>,
    outside: HashMap<u32, Tex>,
    histories: Vec<(Tex, Tex)>,
    array: Option<Tex>,
}

impl Recipe for ShaderNodeRecipe {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        for t in self.inputs.textures.iter().flatten() {
            t.recipe.declare(renderer, fg);
        }
        if let Some(g) = &self.inputs.gbuffer {
            g.declare(renderer, fg);
        }
        if let Some(t) = self.materials_array() {
            t.recipe.declare(renderer, fg);
        }
        if !self.counted.swap(true, Ordering::Relaxed) && self.inputs.compiled > 0 {
            fg.count("shader node permutations compiled", self.inputs.compiled);
        }
        let basis = self.size_basis(fg);
        let (steps, finals, skipped) = self.plan(basis);
        if skipped > 0 {
            fg.count("shader node passes skipped", skipped);
        }
        let mut last = vec![0u32; self.program.targets.len()];
        for step in &steps {
            for &(d, write, _) in &step.dests {
                last[d] = write;
            }
        }
        // A final version that is not the last write (a skip passed something
        // else on) is not named as the target: the target's name gets a copy.
        let copied: Vec<bool> = finals
            .iter()
            .enumerate()
            .map(|(t, source)| match source {
                Some(Source::Version { target, write }) => *target != t || *write != last[t],
                Some(Source::Outside(_)) => true,
                None => false,
            })
            .collect();
        for (t, copy) in copied.iter().enumerate() {
            if *copy {
                last[t] = u32::MAX;
            }
        }
        for step in steps {
            let plan = &self.program.passes[step.pass];
            let mut names = StepNames {
                dests: Vec::new(),
                reads: HashMap::new(),
                outside: (plan.bindings.iter())
                    .filter_map(|(binding, role)| Some((*binding, self.outside(role)?)))
                    .collect(),
                histories: Vec::new(),
                array: self
                    .materials_array()
                    .filter(|_| {
                        (plan.bindings.iter())
                            .any(|(_, r)| *r == Role::Materials(LibraryBinding::Textures))
                    })
                    .map(|t| t.name.clone()),
            };
            let mut writes: Vec<(String, TextureDesc)> = Vec::new();
            for &(d, write, (width, height)) in &step.dests {
                let decl = &self.program.targets[d];
                let name = self.version_name(d, write, &last);
                let size = SizeRule::Absolute { width, height };
                let desc = match decl.lifetime {
                    Lifetime::Persistent => TextureDesc::history(decl.format).size(size),
                    lifetime => TextureDesc::storage(decl.format)
                        .size(size)
                        .lifetime(lifetime),
                };
                writes.push((name.clone(), desc));
                names.dests.push(name);
            }
            for (binding, role) in &plan.bindings {
                let Role::Read(t) = role else { continue };
                let d = self.target_index(t);
                let decl = &self.program.targets[d];
                let name = if decl.lifetime == Lifetime::Persistent {
                    let persistent = self.target_name(t);
                    if plan.decl.targets.contains(t) {
                        let copy = format!("shader{}/{t} previous", self.id);
                        let (_, _, (width, height)) =
                            step.dests[plan.decl.targets.iter().position(|x| x == t).unwrap_or(0)];
                        writes.push((
                            copy.clone(),
                            // Copied, not traded: a user's shader may leave
                            // texels unwritten and expect last frame's there.
                            TextureDesc::history_copy(decl.format)
                                .size(SizeRule::Absolute { width, height }),
                        ));
                        names.histories.push((persistent, copy.clone()));
                        copy
                    } else {
                        persistent
                    }
                } else {
                    match step.reads.get(binding) {
                        Some(source) => self.source_name(source, &last),
                        None => continue,
                    }
                };
                names.reads.insert(*binding, name);
            }
            let mut reads: Vec<String> = names.reads.values().cloned().collect();
            reads.extend(names.outside.values().cloned());
            reads.extend(names.array.iter().cloned());
            // A pass does not read what it writes (its persistent target's copy holds last frame).
            reads.retain(|r| {
                !writes.iter().any(|(w, _)| w == r) && !names.histories.iter().any(|(h, _)| h == r)
            });
            if let Some(g) = &self.inputs.gbuffer
                && plan
                    .bindings
                    .iter()
                    .any(|(_, r)| *r == Role::GBuffer("camera".into()))
            {
                reads.push(g.targets.depth.clone());
            }
            let label = match step.iteration {
                0 => plan.decl.entry.clone(),
                i => format!("{} {i}", plan.decl.entry),
            };
            let pass_name = PassName::new(self.type_name.clone()).step(label);
            let mut pass = fg.pass(pass_name, self.owner);
            let mut declared: HashMap<&str, Tex> = HashMap::new();
            for (name, desc) in &writes {
                declared.insert(name, pass.write(name, *desc));
            }
            for name in &reads {
                declared.insert(name, pass.read(name));
            }
            let io = names
                .io(&declared)
                .map_err(|e| RenderError::Graph(format!("{}: {e}", self.type_name)));
            pass.run(move |cx| self.run(renderer, cx, &step, &io?));
        }
        // Targets whose final content is not their last write: copy it under the target's name.
        for (t, source) in finals.iter().enumerate() {
            if !copied[t] {
                continue;
            }
            let Some(source) = source else { continue };
            let decl = &self.program.targets[t];
            if decl.lifetime == Lifetime::Persistent {
                continue;
            }
            let from = self.source_name(source, &last);
            let to = self.target_name(&decl.name);
            let size = decl.size.pixels(basis);
            let desc = TextureDesc::storage(decl.format).size(SizeRule::Absolute {
                width: size.0,
                height: size.1,
            });
            let format = decl.format;
            let name = PassName::new(self.type_name.clone()).step(format!("pass {} on", decl.name));
            let mut pass = fg.pass(name, self.owner);
            let (from, to) = (pass.read(&from), pass.write(&to, desc));
            pass.run(move |cx| utility::copy(cx, from, to, format));
        }
    }
}
