//! What a composed shader binds, by name: naga's reflection of the module.
//!
//! A pass names its resources by the WGSL variable they fill (`color`,
//! `camera`, `material_meta`), and the bind groups are laid out from here,
//! so Rust never writes a group or binding number that must match the WGSL.
//! naga_oil decorates a library's globals with their module's name
//! (`material_metaX_naga_oil_mod_X…X`): the name here is the undecorated one,
//! the name written in the library.

/// Resources a dispatch binds, held inline while they are resolved and
/// matched: a frame records a hundred dispatches, and each one's half a
/// dozen small Vecs were a third of its allocations (issue 33;
/// tests/frame_allocations.rs counts them).
pub(crate) const INLINE_BINDINGS: usize = 12;

/// The bind groups of one pipeline (0 up to the last its entry points use).
pub type BindGroups = SmallVec<[wgpu::BindGroup; 4]>;
use smallvec::SmallVec;

/// One resource variable of a shader module.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ShaderVar {
    /// As written in the WGSL (library decoration removed).
    pub name: String,
    pub group: u32,
    pub binding: u32,
    /// Whether the entry point reflected reads or writes it: a derived bind
    /// group layout has exactly the used ones, so a bind group must too.
    pub used: bool,
}

/// The resource variables of one entry point's module, in declaration order.
#[derive(Clone, Debug, Default)]
pub struct Reflection {
    /// Private with `index`, which is derived from it.
    vars: Vec<ShaderVar>,
    /// Each variable's index in `vars` by name: a pass's bindings are
    /// matched to the variables once a dispatch, every frame.
    index: rustc_hash::FxHashMap<String, usize>,
}

impl Reflection {
    pub fn new(vars: Vec<ShaderVar>) -> Self {
        let index = vars
            .iter()
            .enumerate()
            .map(|(i, v)| (v.name.clone(), i))
            .collect();
        Reflection { vars, index }
    }

    /// The variables, in declaration order.
    pub fn vars(&self) -> &[ShaderVar] {
        &self.vars
    }

    /// The index in `vars` of the variable named `name`, if the permutation has it.
    pub fn position(&self, name: &str) -> Option<usize> {
        self.index.get(name).copied()
    }

    /// The (group, binding)s the entry point uses.
    pub fn used(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.vars
            .iter()
            .filter(|v| v.used)
            .map(|v| (v.group, v.binding))
    }

    /// The highest group the entry point uses (a derived layout has every group up to it).
    pub fn last_group(&self) -> Option<u32> {
        self.vars.iter().filter(|v| v.used).map(|v| v.group).max()
    }

    /// A WGSL module of its own (no `#import`s) reflected for `entry`: for a
    /// pipeline made outside the shader cache (the editor's viewport blit, a
    /// test's own module), which then binds by name with [`Reflection::entries`].
    pub fn of_wgsl(source: &str, entry: &str) -> Result<Reflection, String> {
        let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
        reflect(&module, entry)
    }

    /// A module composed elsewhere (a test composing a library) reflected for `entry`.
    pub fn of_module(module: &naga::Module, entry: &str) -> Result<Reflection, String> {
        reflect(module, entry)
    }

    /// Group `group`'s bind-group entries from `resources` by WGSL variable
    /// name, for a pipeline whose layout wgpu derived (`layout: None`): a
    /// variable the entry point does not use is left out, as the derived
    /// layout leaves it; a name the module does not declare is an error, and
    /// so is a variable the entry point uses that `resources` leaves unbound.
    pub fn entries<'r>(
        &self,
        group: u32,
        resources: &[(&str, wgpu::BindingResource<'r>)],
    ) -> Result<Vec<wgpu::BindGroupEntry<'r>>, String> {
        let groups = match_bindings(self, resources, &[], |name| {
            Err(format!("the shader declares no variable `{name}`"))
        })?;
        Ok(groups
            .into_iter()
            .nth(group as usize)
            .map(SmallVec::into_vec)
            .unwrap_or_default())
    }
}

/// The name a WGSL author wrote, without naga_oil's module decoration.
pub fn undecorated(name: &str) -> &str {
    // naga_oil's decoration prefix (private there; the test below checks it
    // against `Composer::decorated_name`).
    const PREFIX: &str = "X_naga_oil_mod_X";
    match name.find(PREFIX) {
        Some(at) if at > 0 => &name[..at],
        _ => name,
    }
}

/// Reflect `module`'s resource variables and which of them `entry` uses.
pub fn reflect(module: &naga::Module, entry: &str) -> Result<Reflection, String> {
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(module)
    .map_err(|e| e.to_string())?;
    let index = module
        .entry_points
        .iter()
        .position(|e| e.name == entry)
        .ok_or_else(|| format!("no entry point `{entry}`"))?;
    let function = info.get_entry_point(index);
    let vars = module
        .global_variables
        .iter()
        .filter_map(|(handle, var)| {
            let binding = var.binding.as_ref()?;
            Some(ShaderVar {
                name: undecorated(var.name.as_deref().unwrap_or_default()).to_owned(),
                group: binding.group,
                binding: binding.binding,
                used: !function[handle].is_empty(),
            })
        })
        .collect();
    Ok(Reflection::new(vars))
}

/// `resources` matched to `reflection`'s variables by name, one hash look-up
/// each, as the entries of groups 0..=last (those of `prebuilt` groups left
/// empty). A name the permutation lacks goes to `unknown`, which says
/// whether that is an error; a variable the entry point uses that nothing
/// binds is one.
/// One bind group's entries, inline (a dispatch matches its bindings every frame).
pub(crate) type GroupEntries<'r> = SmallVec<[wgpu::BindGroupEntry<'r>; INLINE_BINDINGS]>;

pub(super) fn match_bindings<'r>(
    reflection: &Reflection,
    resources: &[(&str, wgpu::BindingResource<'r>)],
    prebuilt: &[(u32, wgpu::BindGroup)],
    mut unknown: impl FnMut(&str) -> Result<(), String>,
) -> Result<SmallVec<[GroupEntries<'r>; 4]>, String> {
    let vars = reflection.vars();
    let made_elsewhere = |group: u32| prebuilt.iter().any(|(g, _)| *g == group);
    let mut groups: SmallVec<[GroupEntries<'r>; 4]> = match reflection.last_group() {
        Some(last) => (0..=last).map(|_| GroupEntries::new()).collect(),
        None => SmallVec::new(),
    };
    let mut bound: SmallVec<[bool; 32]> = smallvec::smallvec![false; vars.len()];
    for (name, resource) in resources {
        let Some(i) = reflection.position(name) else {
            unknown(name)?;
            continue;
        };
        let var = &vars[i];
        if var.used && !made_elsewhere(var.group) && !bound[i] {
            bound[i] = true;
            groups[var.group as usize].push(wgpu::BindGroupEntry {
                binding: var.binding,
                resource: resource.clone(),
            });
        }
    }
    if let Some(var) = vars
        .iter()
        .zip(&bound)
        .find(|(v, bound)| v.used && !made_elsewhere(v.group) && !**bound)
        .map(|(v, _)| v)
    {
        return Err(format!(
            "`{}` (group {}, binding {}) is used by the shader but no pass binds it",
            var.name, var.group, var.binding
        ));
    }
    Ok(groups)
}

/// The names of the resource variables declared anywhere in WGSL `source`,
/// whatever `#ifdef` encloses them: a pass may name a variable its
/// permutation compiled out, but not one the shader never had (a typo).
pub fn declared_names(source: &str) -> impl Iterator<Item = &str> {
    source.lines().filter_map(|line| {
        let line = line.split("//").next()?;
        if !line.contains("@binding") {
            return None;
        }
        // `@group(0) @binding(1) var<uniform> name: Type;`
        let after_var = line.split_once("var")?.1;
        let after_space = match after_var.trim_start().strip_prefix('<') {
            Some(rest) => rest.split_once('>')?.1,
            None => after_var,
        };
        let name = after_space.split(':').next()?.trim();
        (!name.is_empty()).then_some(name)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use naga_oil::compose::Composer;

    #[test]
    fn decorated_library_names_lose_their_decoration() {
        let decorated = Composer::decorated_name(Some("spreadlight::material"), "material_meta");
        assert_ne!(decorated, "material_meta");
        assert_eq!(undecorated(&decorated), "material_meta");
        assert_eq!(undecorated("color"), "color");
    }

    #[test]
    fn declared_names_are_found_behind_ifdefs_and_access_modes() {
        let source = "
@group(0) @binding(0) var<uniform> camera: Camera;
#ifdef AO
@group(0) @binding(17) var occlusion: texture_2d<f32>;
#endif
@group(1) @binding(0) var<storage, read> material_meta: array<MaterialMeta>;
// @group(0) @binding(9) var commented: texture_2d<f32>;
var<private> not_a_binding: f32;
";
        let names: Vec<&str> = declared_names(source).collect();
        assert_eq!(names, ["camera", "occlusion", "material_meta"]);
    }
}
