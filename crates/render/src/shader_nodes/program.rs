//! One shader node file compiled: its `#ifdef` permutation preprocessed,
//! parsed and validated by naga, and checked against its annotations. The
//! result says what every binding is (a pin's texture, a G-buffer target, a
//! render target, the uniform block...) and what each pass reads and writes,
//! so the recipe only has to look things up. Every problem is a
//! [`ShaderNodeError`] at a file, line and column.
//!
//! The steps that need no more than their own input live beside it:
//! preprocess.rs (the `#ifdef` switches), validate.rs (naga's parse and
//! validation, errors placed in the file) and uniform_layout.rs (the uniform
//! block's fields as pins).

use std::collections::{BTreeSet, HashMap};

use naga::{ScalarKind, TypeInner};

use super::annotations::{Annotations, PassDecl, Repeat, SamplerDecl, TargetDecl};
use super::error::{ShaderNodeError, Span};
use super::uniform_layout::uniform_layout;
use super::validate::{parse_and_validate, validate_composed};
use crate::frame_graph::Lifetime;
use crate::material::library::{self, LibraryBinding};

pub use super::preprocess::preprocess;
pub use super::uniform_layout::{Builtin, ParamKind, ParamPin, UniformLayout};

/// What one binding of group 0 is.
#[derive(Clone, Debug, PartialEq)]
pub enum Role {
    Uniform,
    /// The texture of input pin `i` (in `@input` order).
    Input(usize),
    /// A G-buffer texture or its camera, by name.
    GBuffer(String),
    /// A target read as a texture.
    Read(String),
    /// A target written as a storage texture.
    Write(String),
    Sampler(SamplerDecl),
    /// A variable of `spreadlight::materials` (group 3): the material world.
    Materials(LibraryBinding),
}

/// One `@pass`, resolved.
#[derive(Clone, Debug)]
pub struct PassPlan {
    pub decl: PassDecl,
    pub workgroup: [u32; 3],
    /// The bindings the entry point uses: (binding, role).
    pub bindings: Vec<(u32, Role)>,
    /// Per binding, a name unique in the pass: what the frame graph's kept
    /// bind groups compare a resource under from frame to frame.
    pub binding_names: Vec<String>,
    /// Index of the Bool pin (in [`Program::bool_pins`] order) that skips it.
    pub skip: Option<String>,
}

impl PassPlan {
    /// The targets this pass reads (textures), in binding order.
    pub fn reads(&self) -> impl Iterator<Item = &str> {
        self.bindings.iter().filter_map(|(_, r)| match r {
            Role::Read(t) => Some(t.as_str()),
            _ => None,
        })
    }
}

/// One compiled permutation of a shader node file.
#[derive(Debug)]
pub struct Program {
    pub file: String,
    pub module: naga::Module,
    /// Identifies the source text and switch set (pipelines are cached under it).
    pub key: u64,
    pub uniform: Option<UniformLayout>,
    /// Where the uniform block's `var` is (device-limit errors about its size point there).
    pub uniform_at: Span,
    pub passes: Vec<PassPlan>,
    pub targets: Vec<TargetDecl>,
    /// The texture input pins' names, in `@input` order.
    pub input_names: Vec<String>,
    pub kind: Kind,
    /// Every binding of the file and what it is.
    pub bindings: Vec<(u32, Role)>,
    /// The file's text with this permutation's switches resolved (lines
    /// kept): what a material splices into the G-buffer resolve.
    pub text: String,
}

/// What a shader node file is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// An image effect (TextureFX): compute passes writing targets.
    Effect,
    /// A DeferredBase layer's material (`// @material`): a `surface` function
    /// the G-buffer resolve calls per pixel; bindings in group 1.
    Material,
    /// A light shader (`// @light point spot sun`): a `light` function the
    /// CookTorrance loop calls per light and pixel; bindings in group 2.
    Light,
}

fn storage_format(format: naga::StorageFormat) -> Option<wgpu::TextureFormat> {
    use naga::StorageFormat as S;
    use wgpu::TextureFormat as F;
    Some(match format {
        S::Rgba8Unorm => F::Rgba8Unorm,
        S::Rgba16Float => F::Rgba16Float,
        S::Rgba32Float => F::Rgba32Float,
        S::R32Float => F::R32Float,
        S::Rg32Float => F::Rg32Float,
        _ => return None,
    })
}

impl Program {
    /// Compile the permutation of `source` with `defines` switched on.
    pub fn compile(
        file: &str,
        source: &str,
        notes: &Annotations,
        defines: &BTreeSet<String>,
    ) -> Result<Program, ShaderNodeError> {
        let text = preprocess(file, source, defines)?;
        let kind = if notes.light.is_some() {
            super::light::check_annotations(file, notes)?;
            Kind::Light
        } else if notes.material.is_some() {
            super::material::check_annotations(file, notes)?;
            Kind::Material
        } else {
            Kind::Effect
        };
        // Files that import libraries (every material imports
        // spreadlight::surface) are composed by naga_oil; others parsed as they are.
        let composed = super::compose::imports(&text);
        let (module, info) = if composed {
            let module = super::compose::compose(file, &text)?;
            let info = validate_composed(file, &module)?;
            (module, info)
        } else {
            parse_and_validate(file, &text)?
        };
        let place = |handle: naga::Handle<naga::GlobalVariable>| -> usize {
            if composed {
                let name = module.global_variables[handle]
                    .name
                    .as_deref()
                    .unwrap_or("");
                super::compose::var_offset(&text, name).unwrap_or(0)
            } else {
                module
                    .global_variables
                    .get_span(handle)
                    .to_range()
                    .map_or(0, |r| r.start)
            }
        };
        let bindings = Self::roles(file, &text, notes, &module, kind, &place)?;
        let uniform = match bindings.iter().find(|(_, _, r)| *r == Role::Uniform) {
            Some((binding, handle, _)) => {
                let var = &module.global_variables[*handle];
                Some(UniformLayout {
                    binding: *binding,
                    ..uniform_layout(
                        file,
                        &text,
                        notes,
                        &module,
                        var.ty,
                        place(*handle),
                        composed,
                    )?
                })
            }
            None => None,
        };
        let uniform_at = bindings
            .iter()
            .find(|(_, _, r)| *r == Role::Uniform)
            .map_or(Span { line: 1, column: 1 }, |(_, handle, _)| {
                super::error::span_of(&text, place(*handle))
            });
        if uniform.is_none()
            && let Some(stray) = notes.pins.values().next()
        {
            return Err(ShaderNodeError::at(
                file,
                stray.at,
                "`@pin` annotates a uniform field, and the file has no uniform block",
            ));
        }
        let key = {
            use std::hash::{Hash, Hasher};
            let mut hasher = std::collections::hash_map::DefaultHasher::new();
            (file, source, defines).hash(&mut hasher);
            hasher.finish()
        };
        if kind != Kind::Effect {
            if kind == Kind::Light {
                super::light::check(file, &text, notes, &module)?;
            } else {
                super::material::check(file, &text, notes, &module)?;
                super::compose::check_material(file, &text)?;
            }
            return Ok(Program {
                file: file.to_owned(),
                module,
                key,
                uniform,
                uniform_at,
                passes: Vec::new(),
                targets: Vec::new(),
                input_names: notes.inputs.iter().map(|(_, pin, _)| pin.clone()).collect(),
                kind,
                bindings: bindings.iter().map(|(b, _, r)| (*b, r.clone())).collect(),
                text,
            });
        }
        for (target, at) in &notes.outputs {
            if notes.target(target).is_none() {
                return Err(ShaderNodeError::at(
                    file,
                    *at,
                    format!("`@output {target}`: unknown target"),
                ));
            }
        }
        let mut passes = Vec::new();
        let mut written: HashMap<&str, usize> = HashMap::new();
        for decl in &notes.passes {
            let fail = |m: String| ShaderNodeError::at(file, decl.at, m);
            let index = module
                .entry_points
                .iter()
                .position(|e| e.name == decl.entry)
                .ok_or_else(|| fail(format!("no entry point `{}` in the shader", decl.entry)))?;
            let entry = &module.entry_points[index];
            if entry.stage != naga::ShaderStage::Compute {
                return Err(fail(format!(
                    "entry point `{}` is not a compute shader: shader node passes are compute passes",
                    decl.entry
                )));
            }
            for target in &decl.targets {
                let t = notes.target(target).ok_or_else(|| {
                    fail(format!(
                        "unknown target `{target}` (declare it with `// @target {target} ...`)"
                    ))
                })?;
                if t.lifetime == Lifetime::Persistent
                    && (written.contains_key(target.as_str()) || decl.repeat != Repeat::Once)
                {
                    return Err(fail(format!(
                        "persistent target `{target}` is written by more than one pass or iteration"
                    )));
                }
            }
            let used = info.get_entry_point(index);
            let mut pass_bindings = Vec::new();
            for (binding, handle, role) in &bindings {
                if used[*handle].is_empty() {
                    continue;
                }
                if let Role::Write(t) = role
                    && !decl.targets.contains(t)
                {
                    return Err(ShaderNodeError::at_offset(
                        file,
                        &text,
                        place(*handle),
                        format!(
                            "entry point `{}` writes `{t}`, which is not a destination of its `@pass`",
                            decl.entry
                        ),
                    ));
                }
                if let Role::Read(t) = role
                    && !written.contains_key(t.as_str())
                    && notes
                        .target(t)
                        .is_some_and(|d| d.lifetime != Lifetime::Persistent)
                    && !(decl.targets.contains(t) && decl.repeat != Repeat::Once)
                {
                    return Err(fail(format!(
                        "pass `{}` reads target `{t}` before any pass writes it",
                        decl.entry
                    )));
                }
                pass_bindings.push((*binding, role.clone()));
            }
            for target in &decl.targets {
                if !pass_bindings
                    .iter()
                    .any(|(_, r)| *r == Role::Write(target.clone()))
                {
                    return Err(fail(format!(
                        "entry point `{}` never writes destination `{target}`",
                        decl.entry
                    )));
                }
            }
            let binding_names = (pass_bindings.iter())
                .map(|(binding, role)| match role {
                    Role::Materials(_) => format!("materials {binding}"),
                    _ => format!("binding {binding}"),
                })
                .collect();
            let plan = PassPlan {
                decl: decl.clone(),
                workgroup: entry.workgroup_size,
                bindings: pass_bindings,
                binding_names,
                skip: decl.skip.clone(),
            };
            if plan.skip.is_some()
                && plan.reads().next().is_none()
                && !plan
                    .bindings
                    .iter()
                    .any(|(_, r)| matches!(r, Role::Input(_)))
            {
                return Err(fail(format!(
                    "pass `{}` can be skipped but reads no texture to pass on",
                    decl.entry
                )));
            }
            for t in &decl.targets {
                *written.entry(t.as_str()).or_default() += 1;
            }
            passes.push(plan);
        }
        if passes.is_empty() {
            return Err(ShaderNodeError::at(
                file,
                Span { line: 1, column: 1 },
                "no `// @pass ENTRY -> TARGET` annotation: a shader node needs at least one pass",
            ));
        }
        Ok(Program {
            file: file.to_owned(),
            module,
            key,
            uniform,
            uniform_at,
            passes,
            targets: notes.targets.clone(),
            input_names: notes.inputs.iter().map(|(_, pin, _)| pin.clone()).collect(),
            kind,
            bindings: bindings.iter().map(|(b, _, r)| (*b, r.clone())).collect(),
            text,
        })
    }

    /// Every resource variable with what the annotations say it is; one they
    /// do not describe is an error at its declaration.
    fn roles(
        file: &str,
        text: &str,
        notes: &Annotations,
        module: &naga::Module,
        kind: Kind,
        place: &dyn Fn(naga::Handle<naga::GlobalVariable>) -> usize,
    ) -> Result<Vec<(u32, naga::Handle<naga::GlobalVariable>, Role)>, ShaderNodeError> {
        let mut roles = Vec::new();
        let mut uniforms = 0;
        // A material's bindings are group 1: group 0 is the G-buffer resolve's.
        let group = match kind {
            Kind::Effect => 0,
            Kind::Material => 1,
            Kind::Light => super::light::LIGHT_GROUP,
        };
        for (handle, var) in module.global_variables.iter() {
            let Some(binding) = &var.binding else {
                continue;
            };
            let name = var.name.clone().unwrap_or_default();
            let at = place(handle);
            let fail = |m: String| ShaderNodeError::at_offset(file, text, at, m);
            // The material world library's variables, whatever the kind.
            if binding.group == library::GROUP
                && let Some(b) = LibraryBinding::from_name(&super::error::undecorate(&name))
            {
                roles.push((binding.binding, handle, Role::Materials(b)));
                continue;
            }
            if binding.group != group {
                let what = match kind {
                    Kind::Effect => "shader nodes bind everything in group 0",
                    Kind::Material => {
                        "a material binds everything in group 1 (group 0 is the G-buffer's)"
                    }
                    Kind::Light => {
                        "a light shader binds everything in group 2 (groups 0 and 1 are the light loop's)"
                    }
                };
                return Err(fail(format!(
                    "`{name}` is in group {}: {what}",
                    binding.group
                )));
            }
            let gbuffer = notes.gbuffer.iter().any(|(g, _)| *g == name);
            let role = match (&var.space, &module.types[var.ty].inner) {
                (naga::AddressSpace::Uniform, _) if gbuffer && name == "camera" => {
                    Role::GBuffer(name.clone())
                }
                (naga::AddressSpace::Uniform, _) => {
                    uniforms += 1;
                    if uniforms > 1 {
                        return Err(fail(
                            "a shader node has one uniform block (its pins); `{name}` is a second"
                                .into(),
                        ));
                    }
                    Role::Uniform
                }
                (_, TypeInner::Sampler { .. }) => match notes.samplers.get(&name) {
                    Some(decl) => Role::Sampler(*decl),
                    None => Role::Sampler(SamplerDecl { repeat: false }),
                },
                (
                    _,
                    TypeInner::Image {
                        class: naga::ImageClass::Storage { format, .. },
                        ..
                    },
                ) => {
                    // `lum_out` writes `lum`, so the same shader can read `lum` as a texture.
                    let target = notes
                        .target(&name)
                        .or_else(|| name.strip_suffix("_out").and_then(|t| notes.target(t)))
                        .ok_or_else(|| {
                            fail(format!(
                                "storage texture `{name}` is not a declared target (`// @target {name} ...`)"
                            ))
                        })?;
                    if storage_format(*format) != Some(target.format) {
                        return Err(fail(format!(
                            "storage texture `{name}` is {format:?} but its `@target` says {:?}",
                            target.format
                        )));
                    }
                    Role::Write(target.name.clone())
                }
                (
                    _,
                    TypeInner::Image {
                        class: naga::ImageClass::Sampled { kind, multi: false },
                        dim: naga::ImageDimension::D2,
                        arrayed: false,
                    },
                ) if *kind == ScalarKind::Float => {
                    if let Some(i) = notes.inputs.iter().position(|(v, _, _)| *v == name) {
                        Role::Input(i)
                    } else if gbuffer {
                        Role::GBuffer(name.clone())
                    } else if notes.target(&name).is_some() {
                        Role::Read(name.clone())
                    } else {
                        return Err(fail(format!(
                            "texture `{name}` is not described by the annotations: declare it with \
                             `// @input {name}`, `// @gbuffer {name}` or `// @target {name} ...`"
                        )));
                    }
                }
                _ => {
                    return Err(fail(format!(
                        "binding `{name}` is of a kind shader nodes do not bind (uniform struct, \
                         texture_2d<f32>, texture_storage_2d, sampler)"
                    )));
                }
            };
            roles.push((binding.binding, handle, role));
        }
        Ok(roles)
    }

    /// Checks against the device's limits, so a shader too big fails on its
    /// node instead of losing the device.
    pub fn check_limits(
        &self,
        limits: &wgpu::Limits,
        output: (u32, u32),
    ) -> Result<(), ShaderNodeError> {
        for pass in &self.passes {
            let fail = |m: String| ShaderNodeError::at(&self.file, pass.decl.at, m);
            let [x, y, z] = pass.workgroup;
            if x > limits.max_compute_workgroup_size_x
                || y > limits.max_compute_workgroup_size_y
                || z > limits.max_compute_workgroup_size_z
                // In u64: a workgroup of 65536^3 must fail here, not overflow.
                || u64::from(x) * u64::from(y) * u64::from(z)
                    > u64::from(limits.max_compute_invocations_per_workgroup)
            {
                return Err(fail(format!(
                    "entry point `{}`: workgroup size {x}x{y}x{z} exceeds the device's limits \
                     ({}x{}x{}, {} invocations)",
                    pass.decl.entry,
                    limits.max_compute_workgroup_size_x,
                    limits.max_compute_workgroup_size_y,
                    limits.max_compute_workgroup_size_z,
                    limits.max_compute_invocations_per_workgroup
                )));
            }
            let storage = pass
                .bindings
                .iter()
                .filter(|(_, r)| matches!(r, Role::Write(_)))
                .count() as u32;
            if storage > limits.max_storage_textures_per_shader_stage {
                return Err(fail(format!(
                    "entry point `{}` writes {storage} targets; the device allows {}",
                    pass.decl.entry, limits.max_storage_textures_per_shader_stage
                )));
            }
        }
        for t in &self.targets {
            let (w, h) = t.size.pixels(output);
            if w.max(h) > limits.max_texture_dimension_2d {
                return Err(ShaderNodeError::at(
                    &self.file,
                    t.at,
                    format!(
                        "target `{}` would be {w}x{h}; the device allows {} pixels a side",
                        t.name, limits.max_texture_dimension_2d
                    ),
                ));
            }
        }
        if let Some(u) = &self.uniform
            && u64::from(u.size) > limits.max_uniform_buffer_binding_size
        {
            return Err(ShaderNodeError::at(
                &self.file,
                self.uniform_at,
                format!(
                    "the uniform block is {} bytes; the device allows {}",
                    u.size, limits.max_uniform_buffer_binding_size
                ),
            ));
        }
        Ok(())
    }
}
