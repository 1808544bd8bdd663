//! One shader file as a node type: its annotations, its default
//! permutation (whose uniform block gives the pins), the permutations
//! compiled so far, and the [`NodeDef`] made from them.

use std::collections::{BTreeSet, HashMap};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

use spreadlight_render::frame_graph::Lifetime;
use spreadlight_render::material::library::imports_library;
use spreadlight_render::shader_nodes::{
    Annotations, Builtin, Kind, ParamKind, ParamPin, Program, ShaderNodeError,
};

/// A Bool pin a pass's `skip` may name: the i-th uniform field, or the
/// i-th `@switch`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoolPin {
    Field(usize),
    Switch(usize),
}

/// A loaded shader node file.
pub struct ShaderType {
    /// The node type name: `Blur (Shader)` for `blur.wgsl`.
    pub name: String,
    /// The file as errors name it.
    pub file: String,
    source: String,
    pub notes: Annotations,
    /// The permutation with every switch at its default: the pins come from it.
    pub base: Arc<Program>,
    permutations: Mutex<HashMap<BTreeSet<String>, Arc<Program>>>,
    /// Permutations compiled, the default one included (statistics).
    compiled: AtomicU64,
    /// The version of the file this one replaced, when its node has the same
    /// pins: it runs in this one's place where this one cannot (a permutation
    /// that does not compile, a device limit), as a file that does not
    /// compile keeps its last good version. One level only: it has none itself.
    previous: OnceLock<Arc<ShaderType>>,
}

/// `edge_detect.wgsl` -> `EdgeDetect (Shader)`.
pub fn type_name(stem: &str) -> String {
    let camel: String = stem
        .split(['_', '-', ' '])
        .filter(|w| !w.is_empty())
        .map(|w| {
            let mut c = w.chars();
            c.next()
                .map(|f| f.to_uppercase().chain(c).collect::<String>())
                .unwrap_or_default()
        })
        .collect();
    format!("{camel} (Shader)")
}

/// The file stem that makes a shader node type name: `EdgeDetect (Shader)`
/// from `edge_detect` ([`type_name`] read backwards; `edge-detect` makes it
/// too). `None` for a name that is not a shader node's.
pub fn file_stem(type_name: &str) -> Option<String> {
    let camel = type_name.strip_suffix(" (Shader)")?;
    let mut stem = String::new();
    for (i, c) in camel.chars().enumerate() {
        if c.is_uppercase() && i > 0 {
            stem.push('_');
        }
        stem.extend(c.to_lowercase());
    }
    (!stem.is_empty()).then_some(stem)
}

impl ShaderType {
    /// Read and compile a file's default permutation.
    pub fn load(name: &str, file: &str, source: &str) -> Result<Arc<Self>, ShaderNodeError> {
        let notes = Annotations::parse(file, source)?;
        let defaults: BTreeSet<String> = notes
            .switches
            .iter()
            .filter(|s| s.default)
            .map(|s| s.define.clone())
            .chain(notes.enums.iter().filter_map(|e| e.define(e.default)))
            .collect();
        let base = Arc::new(Program::compile(file, source, &notes, &defaults)?);
        let ty = ShaderType {
            name: name.to_owned(),
            file: file.to_owned(),
            source: source.to_owned(),
            notes,
            base: base.clone(),
            permutations: Mutex::new(HashMap::from([(defaults, base)])),
            compiled: AtomicU64::new(1),
            previous: OnceLock::new(),
        };
        ty.check_skips()?;
        Ok(Arc::new(ty))
    }

    /// Run `previous` where this version cannot, if its node has the same
    /// pins (so the node's inputs mean the same to both); whether it was kept.
    pub fn keep_previous(&self, previous: &ShaderType) -> bool {
        self.pin_signature() == previous.pin_signature()
            && self.previous.set(Arc::new(previous.detached())).is_ok()
    }

    /// What the node's pins are made of (def.rs), in order: two versions
    /// alike here make nodes with the same pins.
    fn pin_signature(&self) -> Vec<String> {
        let mut pins = vec![format!("{:?}", self.base.kind)];
        pins.extend(self.notes.inputs.iter().map(|(_, pin, _)| pin.clone()));
        pins.push(format!("gbuffer {}", self.reads_gbuffer()));
        pins.push(format!("materials {}", self.materials_pin()));
        pins.extend(
            self.params()
                .iter()
                .map(|p| format!("{} {:?}", p.display, p.kind)),
        );
        pins.extend(self.notes.switches.iter().map(|s| s.display.clone()));
        pins.extend(
            self.notes
                .enums
                .iter()
                .map(|e| format!("{} {}", e.display, e.options.join("|"))),
        );
        pins.extend(self.notes.outputs.iter().map(|(t, _)| format!("out {t}")));
        pins
    }

    /// The version that runs where this one cannot ([`ShaderType::keep_previous`]).
    pub fn previous(&self) -> Option<&Arc<ShaderType>> {
        self.previous.get()
    }

    /// A copy without its previous version, so versions never chain.
    fn detached(&self) -> ShaderType {
        ShaderType {
            name: self.name.clone(),
            file: self.file.clone(),
            source: self.source.clone(),
            notes: self.notes.clone(),
            base: self.base.clone(),
            permutations: Mutex::new(
                self.permutations
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .clone(),
            ),
            compiled: AtomicU64::new(self.compiled.load(Ordering::Relaxed)),
            previous: OnceLock::new(),
        }
    }

    /// A skip pin must be a Bool pin (a switch or a `bool` field).
    fn check_skips(&self) -> Result<(), ShaderNodeError> {
        for pass in &self.base.passes {
            if let Some(pin) = &pass.skip
                && self.bool_pin(pin).is_none()
            {
                return Err(ShaderNodeError::at(
                    &self.file,
                    pass.decl.at,
                    format!("skip pin `{pin}` is not a Bool pin (a `@switch` or a `bool` field)"),
                ));
            }
        }
        Ok(())
    }

    pub fn params(&self) -> &[ParamPin] {
        self.base.uniform.as_ref().map_or(&[], |u| &u.pins)
    }

    /// Which Bool pin `pin` names (a field, a define, or a display name).
    pub fn bool_pin(&self, pin: &str) -> Option<BoolPin> {
        if let Some(i) = self
            .params()
            .iter()
            .position(|p| p.kind == ParamKind::Bool && (p.field == pin || p.display == pin))
        {
            return Some(BoolPin::Field(i));
        }
        self.notes
            .switches
            .iter()
            .position(|s| s.define == pin || s.display == pin)
            .map(BoolPin::Switch)
    }

    /// The file imports `spreadlight::materials` (in any permutation): it
    /// reads the material world.
    pub fn reads_materials(&self) -> bool {
        imports_library(&self.source)
    }

    /// An image effect that reads the material world has a `Material World`
    /// pin; a material reads its DeferredBase's.
    pub fn materials_pin(&self) -> bool {
        self.reads_materials() && !self.is_material()
    }

    /// A light shader (`// @light`) rather than an image effect.
    pub fn is_light(&self) -> bool {
        self.base.kind == Kind::Light
    }

    /// The light types a light shader declares (none for other kinds).
    pub fn light_kinds(&self) -> Vec<spreadlight_render::lighting::LightKind> {
        self.notes
            .light
            .as_ref()
            .map(|(_, kinds)| kinds.clone())
            .unwrap_or_default()
    }

    /// A DeferredBase material (`// @material`) rather than an image effect.
    pub fn is_material(&self) -> bool {
        self.base.kind == Kind::Material
    }

    /// The permutation's defines for one slice: `switch(k)` gives the value
    /// of the k-th Bool switch, `choice(k)` the option of the k-th Enum.
    pub fn defines(
        &self,
        switch: &dyn Fn(usize) -> Vec<f32>,
        choice: &dyn Fn(usize) -> Option<String>,
    ) -> BTreeSet<String> {
        let switches = &self.notes.switches;
        let mut defines: BTreeSet<String> = switches
            .iter()
            .enumerate()
            .filter(|(k, _)| switch(*k) == [1.0])
            .map(|(_, s)| s.define.clone())
            .collect();
        for (k, e) in self.notes.enums.iter().enumerate() {
            let chosen = choice(k)
                .and_then(|o| e.options.iter().position(|x| *x == o))
                .unwrap_or(e.default);
            defines.extend(e.define(chosen));
        }
        defines
    }

    pub fn reads_gbuffer(&self) -> bool {
        !self.notes.gbuffer.is_empty()
    }

    /// The permutation for these switches: compiled once, then shared. The
    /// bool is true when this call compiled it.
    pub fn program(
        &self,
        defines: &BTreeSet<String>,
    ) -> Result<(Arc<Program>, bool), ShaderNodeError> {
        let mut cache = self.permutations.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(p) = cache.get(defines) {
            return Ok((p.clone(), false));
        }
        let program = Arc::new(Program::compile(
            &self.file,
            &self.source,
            &self.notes,
            defines,
        )?);
        if program.uniform != self.base.uniform {
            return Err(ShaderNodeError::at(
                &self.file,
                self.notes
                    .switches
                    .first()
                    .map_or_else(Default::default, |s| s.at),
                "the uniform block must be the same in every permutation (its fields are the pins)",
            ));
        }
        self.compiled.fetch_add(1, Ordering::Relaxed);
        cache.insert(defines.clone(), program.clone());
        Ok((program, true))
    }

    /// Permutations compiled so far (the default one included).
    pub fn permutations_compiled(&self) -> u64 {
        self.compiled.load(Ordering::Relaxed)
    }

    /// The name of the target the node outputs: the last pass's first destination.
    pub fn main_target(&self) -> &str {
        self.base
            .passes
            .last()
            .and_then(|p| p.decl.targets.first())
            .map_or("", String::as_str)
    }

    /// Re-evaluated every frame: it reads the clock or keeps history.
    pub fn time_dependent(&self) -> bool {
        let clock = self.base.uniform.as_ref().is_some_and(|u| {
            u.builtins
                .iter()
                .any(|(b, _)| matches!(b, Builtin::Time | Builtin::Delta))
        });
        clock || self.stateful()
    }

    /// Its image depends on every frame before: a persistent target carries
    /// what earlier frames wrote (a feedback, an adapted luminance).
    pub fn stateful(&self) -> bool {
        self.base
            .targets
            .iter()
            .any(|t| t.lifetime == Lifetime::Persistent)
    }
}
