//! Composing a permutation: naga_oil over the embedded (or on-disk) sources,
//! with a library swapped for a shader node material where asked. The
//! libraries are added up front; an entry shader's text comes with its key
//! ([`ShaderKey::file`]), so the composer knows no list of them.

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use naga_oil::compose::{
    ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderDefValue, ShaderLanguage,
    ShaderType,
};

use super::generated::GeneratedKey;
use super::preprocess::{self, without_comments};
use super::{LIBRARIES, ShaderFile, ShaderKey};
use crate::error::RenderError;

/// Composes shader permutations into validated naga modules. No GPU needed,
/// so tests can validate every permutation anywhere.
pub struct ShaderComposer {
    composer: Composer,
    /// By path: every library's text, and each entry shader's once composed.
    sources: HashMap<&'static str, Cow<'static, str>>,
    /// Where edited sources are read from (`from_dir`); an entry shader is
    /// read from there when first composed.
    dir: Option<PathBuf>,
    /// Over the embedded sources, with no library replaced: what it composes
    /// is the same in every composer of the process (see [`embedded_modules`]).
    embedded: bool,
    /// A library is replaced ([`ShaderComposer::replace_library`]).
    replaced: bool,
}

/// Permutations of the embedded sources composed so far in this process.
/// Composing (naga_oil's preprocessing, naga's parse and validation) is
/// most of what opening a renderer costs the CPU, and every renderer of a
/// process (each test, each CLI run's renderers) composes the same
/// permutations from the same compiled-in text: they are made once.
/// Also which permutations a composer is composing now: another that
/// wants one of those waits for it rather than composing it again (the
/// threads composing ahead, those creating pipelines ahead and the first
/// frame often reach the same permutation at once).
/// The same for generated shaders (`shaders/generated.rs`), with their labels.
/// The modules are shared (`Arc`): a taker clones its own copy after the
/// lock is let go (a module's clone took 0.05-0.25 ms on the H200 host, and
/// every thread making pipelines ahead takes one; session 25).
#[derive(Default)]
struct Embedded {
    modules: HashMap<ShaderKey, Arc<naga::Module>>,
    composing: std::collections::HashSet<ShaderKey>,
    generated: HashMap<GeneratedKey, Arc<Generated>>,
    generating: std::collections::HashSet<GeneratedKey>,
}

/// A generated shader composed: its label and module.
pub(crate) type Generated = (String, naga::Module);

fn embedded_modules() -> &'static (std::sync::Mutex<Embedded>, std::sync::Condvar) {
    static MODULES: std::sync::OnceLock<(std::sync::Mutex<Embedded>, std::sync::Condvar)> =
        std::sync::OnceLock::new();
    MODULES.get_or_init(Default::default)
}

fn embedded() -> std::sync::MutexGuard<'static, Embedded> {
    embedded_modules()
        .0
        .lock()
        .unwrap_or_else(|e| e.into_inner())
}

/// Permutation `key` of the embedded sources, if a composer of this process
/// (a renderer's, or the precompose threads') composed it already.
pub(crate) fn embedded_module(key: &ShaderKey) -> Option<naga::Module> {
    let shared = embedded().modules.get(key).cloned();
    shared.map(Arc::unwrap_or_clone)
}

/// [`embedded_module`], waiting first where a composer is composing it
/// (a renderer without a composer of its own need not make one for it).
pub(crate) fn embedded_module_or_wait(key: &ShaderKey) -> Option<naga::Module> {
    let mut shared = embedded();
    while shared.composing.contains(key) {
        shared = embedded_modules()
            .1
            .wait(shared)
            .unwrap_or_else(|e| e.into_inner());
    }
    let module = shared.modules.get(key).cloned();
    drop(shared);
    module.map(Arc::unwrap_or_clone)
}

/// Generated shader `key` over the embedded sources, if a composer of this
/// process generated it already, waiting first where one is generating it.
pub(crate) fn embedded_generated_or_wait(key: &GeneratedKey) -> Option<Generated> {
    let mut shared = embedded();
    while shared.generating.contains(key) {
        shared = embedded_modules()
            .1
            .wait(shared)
            .unwrap_or_else(|e| e.into_inner());
    }
    let generated = shared.generated.get(key).cloned();
    drop(shared);
    generated.map(Arc::unwrap_or_clone)
}

/// A generated shader this composer is generating ([`Composing`]'s twin).
struct Generating<'k>(&'k GeneratedKey);

impl Drop for Generating<'_> {
    fn drop(&mut self) {
        embedded().generating.remove(self.0);
        embedded_modules().1.notify_all();
    }
}

/// Generated shader `key` made already, or waited for; else None, with it
/// marked as this caller's to generate until the guard is dropped.
fn generated_or_claim(key: &GeneratedKey) -> Result<Generated, Generating<'_>> {
    let mut shared = embedded();
    loop {
        if let Some(made) = shared.generated.get(key).cloned() {
            drop(shared);
            return Ok(Arc::unwrap_or_clone(made));
        }
        if shared.generating.insert(key.clone()) {
            return Err(Generating(key));
        }
        shared = embedded_modules()
            .1
            .wait(shared)
            .unwrap_or_else(|e| e.into_inner());
    }
}

/// Whether permutation `key` of the embedded sources is composed in this process.
#[cfg(test)]
pub(crate) fn is_composed(key: &ShaderKey) -> bool {
    embedded().modules.contains_key(key)
}

/// A permutation this composer is composing (see [`Embedded`]): taken off
/// the list when it ends (composed, failed or panicked), waking those waiting.
struct Composing<'k>(&'k ShaderKey);

impl Drop for Composing<'_> {
    fn drop(&mut self) {
        embedded().composing.remove(self.0);
        embedded_modules().1.notify_all();
    }
}

/// Permutation `key` composed already, or waited for where another
/// composer is composing it; else None, with `key` marked as this caller's
/// to compose until the guard is dropped.
fn composed_or_claim(key: &ShaderKey) -> Result<naga::Module, Composing<'_>> {
    let mut shared = embedded();
    loop {
        if let Some(module) = shared.modules.get(key).cloned() {
            drop(shared);
            return Ok(Arc::unwrap_or_clone(module));
        }
        if shared.composing.insert(key.clone()) {
            return Err(Composing(key));
        }
        shared = embedded_modules()
            .1
            .wait(shared)
            .unwrap_or_else(|e| e.into_inner());
    }
}

/// [`ShaderComposer::declared_names`] over the embedded sources, without a
/// composer (a renderer whose permutations were all composed ahead never makes one).
pub(super) fn embedded_declared_names(file: &'static ShaderFile) -> rustc_hash::FxHashSet<String> {
    LIBRARIES
        .iter()
        .chain([file])
        .flat_map(|f| super::reflection::declared_names(f.source))
        .map(str::to_owned)
        .collect()
}

impl ShaderComposer {
    /// Whether what it composes is what every composer over the embedded
    /// sources composes (no folder on disk, no library replaced): then
    /// [`embedded_module`] may stand in for it.
    pub(super) fn shares_embedded(&self) -> bool {
        self.embedded && !self.replaced
    }

    /// The resource variables `file` and the libraries declare under any
    /// feature (a pass may bind one its permutation compiled out).
    pub(super) fn declared_names(
        &mut self,
        file: &'static ShaderFile,
    ) -> rustc_hash::FxHashSet<String> {
        self.load(file);
        LIBRARIES
            .iter()
            .chain([file])
            .filter_map(|f| self.sources.get(f.path))
            .flat_map(|source| super::reflection::declared_names(source))
            .map(str::to_owned)
            .collect()
    }

    /// A composer over the embedded sources.
    pub fn new() -> Result<Self, RenderError> {
        let sources = LIBRARIES
            .iter()
            .map(|s| (s.path, without_comments(Cow::Borrowed(s.source))))
            .collect();
        let mut composer = Self::with_sources(sources, None)?;
        composer.embedded = true;
        Ok(composer)
    }

    /// A composer over the sources in a `shaders/` folder on disk (for live
    /// editing); files missing there fall back to the embedded ones.
    pub fn from_dir(dir: &Path) -> Result<Self, RenderError> {
        let sources = LIBRARIES
            .iter()
            .map(|file| (file.path, without_comments(read_or_embedded(dir, file))))
            .collect();
        Self::with_sources(sources, Some(dir.to_owned()))
    }

    /// Put `file`'s text in [`Self::sources`], read (from the folder, or
    /// the binary) the first time it is asked for.
    fn load(&mut self, file: &'static ShaderFile) {
        let dir = &self.dir;
        self.sources.entry(file.path).or_insert_with(|| {
            without_comments(match dir {
                Some(dir) => read_or_embedded(dir, file),
                None => Cow::Borrowed(file.source),
            })
        });
    }

    fn with_sources(
        sources: HashMap<&'static str, Cow<'static, str>>,
        dir: Option<PathBuf>,
    ) -> Result<Self, RenderError> {
        // Validate with what the compute rasterizer needs; devices without it never compile that shader.
        let mut composer = Composer::default().with_capabilities(
            naga::valid::Capabilities::SHADER_INT64
                | naga::valid::Capabilities::SHADER_INT64_ATOMIC_MIN_MAX,
        );
        for file in LIBRARIES {
            let source = &sources[file.path];
            let result = composer
                .add_composable_module(ComposableModuleDescriptor {
                    source,
                    file_path: file.path,
                    language: ShaderLanguage::Wgsl,
                    ..Default::default()
                })
                .map(|_| ())
                .map_err(|e| e.emit_to_string(&composer));
            result.map_err(|message| RenderError::Shader {
                shader: file.path.to_owned(),
                defs: String::new(),
                message,
            })?;
        }
        Ok(ShaderComposer {
            composer,
            sources,
            dir,
            embedded: false,
            replaced: false,
        })
    }

    /// A composer over the embedded sources that keeps what it composes to
    /// itself: the exhaustive test composes tens of thousands of
    /// permutations no renderer of its process asks for, and holding them
    /// all in the process's map ([`Embedded`]), a copy of each, took 6 GB.
    #[cfg(test)]
    pub(crate) fn unshared() -> Result<Self, RenderError> {
        let mut composer = Self::new()?;
        composer.embedded = false;
        Ok(composer)
    }

    /// Compose and validate one permutation.
    pub fn compose(&mut self, key: &ShaderKey) -> Result<naga::Module, RenderError> {
        let file = key.file;
        // A switch the file does not have first: naming it says more than
        // "no value of its typed key". (A library composed alone takes any.)
        if let Some(unknown) = key
            .features
            .iter()
            .find(|f| !file.library && !file.features.contains(f))
        {
            return Err(RenderError::Shader {
                shader: key.path().to_owned(),
                defs: key.describe_defs(),
                message: format!(
                    "`{unknown}` is not a feature of this shader (features: {})",
                    file.features.join(", ")
                ),
            });
        }
        if let Err(message) = file.check(&key.features) {
            return Err(RenderError::Shader {
                shader: key.path().to_owned(),
                defs: key.describe_defs(),
                message,
            });
        }
        let shared = self.embedded && !self.replaced;
        let _composing = match shared.then(|| composed_or_claim(key)) {
            Some(Ok(module)) => return Ok(module),
            Some(Err(claimed)) => Some(claimed),
            None => None,
        };
        let module = self.make_module(key, true)?;
        if shared {
            // Before the claim is dropped (which wakes those waiting).
            let stored = Arc::new(module.clone());
            embedded().modules.insert(key.clone(), stored);
        }
        Ok(module)
    }

    /// naga_oil's module for permutation `key`. Where `decide`, from the
    /// entry shader's text with its conditionals decided here
    /// ([`preprocess::decide`]: a third to half the lines to compose); if
    /// that text does not compose, or cannot be decided here, from the text
    /// as written, whose error names the file's own lines.
    fn make_module(&mut self, key: &ShaderKey, decide: bool) -> Result<naga::Module, RenderError> {
        let file = key.file;
        self.load(file);
        let defs = || -> HashMap<String, ShaderDefValue> {
            key.features
                .iter()
                .map(|f| ((*f).to_owned(), ShaderDefValue::Bool(true)))
                .collect()
        };
        let decided = decide
            .then(|| preprocess::decide(&self.sources[file.path], &key.features))
            .flatten();
        if let Some(text) = decided {
            let module = self.composer.make_naga_module(NagaModuleDescriptor {
                source: &text,
                file_path: file.path,
                shader_type: ShaderType::Wgsl,
                shader_defs: defs(),
                additional_imports: &[],
            });
            if let Ok(module) = module {
                return Ok(module);
            }
        }
        let result = self.composer.make_naga_module(NagaModuleDescriptor {
            source: &self.sources[file.path],
            file_path: file.path,
            shader_type: ShaderType::Wgsl,
            shader_defs: defs(),
            additional_imports: &[],
        });
        result.map_err(|e| RenderError::Shader {
            shader: key.path().to_owned(),
            defs: key.describe_defs(),
            message: e.emit_to_string(&self.composer),
        })
    }

    /// Permutation `key` composed with its conditionals left to naga_oil
    /// (what [`Self::compose`] did before deciding them itself), to compare.
    #[cfg(test)]
    pub(super) fn compose_as_written(
        &mut self,
        key: &ShaderKey,
    ) -> Result<naga::Module, RenderError> {
        self.make_module(key, false)
    }
}

impl ShaderComposer {
    /// Compose a WGSL file that no typed key declares (a shader node's)
    /// as a top-level module: it may `#import` every library. Its own
    /// `#ifdef`s must already be resolved. The error is naga_oil's, for the
    /// caller to place in the file ([`ShaderComposer::composer`] undecorates it).
    pub fn compose_external(
        &mut self,
        file_path: &str,
        source: &str,
    ) -> Result<naga::Module, Box<naga_oil::compose::ComposerError>> {
        self.composer
            .make_naga_module(NagaModuleDescriptor {
                source,
                file_path,
                shader_type: ShaderType::Wgsl,
                ..Default::default()
            })
            .map_err(Box::new)
    }

    /// The naga_oil composer (to format and undecorate its errors).
    pub fn composer(&self) -> &Composer {
        &self.composer
    }

    /// Put `source` (a shader node material's file, named `file_path`) in
    /// the place of library `module` (an import path such as
    /// `spreadlight::custom_surface`) until [`ShaderComposer::restore_library`].
    pub fn replace_library(
        &mut self,
        module: &str,
        file_path: &str,
        source: &str,
    ) -> Result<(), Box<naga_oil::compose::ComposerError>> {
        // Even a failed replacement may leave the library half-replaced.
        self.replaced = true;
        self.composer
            .add_composable_module(ComposableModuleDescriptor {
                source,
                file_path,
                language: ShaderLanguage::Wgsl,
                as_name: Some(module.to_owned()),
                ..Default::default()
            })
            .map(|_| ())
            .map_err(Box::new)
    }

    /// Put library `module` back as [`LIBRARIES`] has it.
    pub fn restore_library(&mut self, module: &str) -> Result<(), RenderError> {
        let library = LIBRARIES
            .iter()
            .find(|f| f.source.contains(&format!("#define_import_path {module}")))
            .ok_or_else(|| RenderError::Shader {
                shader: module.to_owned(),
                defs: String::new(),
                message: "no such library".to_owned(),
            })?;
        let restored = self
            .composer
            .add_composable_module(ComposableModuleDescriptor {
                source: &self.sources[library.path],
                file_path: library.path,
                language: ShaderLanguage::Wgsl,
                ..Default::default()
            })
            .map(|_| ())
            .map_err(|e| e.emit_to_string(&self.composer));
        restored.map_err(|message| RenderError::Shader {
            shader: library.path.to_owned(),
            defs: String::new(),
            message,
        })?;
        self.replaced = false;
        Ok(())
    }

    /// Compose permutation `key` with library `module` replaced, for this
    /// composition only, by a shader node material's `source`.
    pub fn compose_with_module(
        &mut self,
        key: &ShaderKey,
        module: &str,
        file_path: &str,
        source: &str,
    ) -> Result<naga::Module, RenderError> {
        let replaced = self
            .replace_library(module, file_path, source)
            .map_err(|e| e.emit_to_string(&self.composer));
        let composed = match replaced {
            Ok(()) => self.compose(key),
            Err(message) => Err(RenderError::Shader {
                shader: file_path.to_owned(),
                defs: String::new(),
                message,
            }),
        };
        // Put the library back, so built-in permutations compose as before.
        self.restore_library(module)?;
        composed
    }
}

impl ShaderComposer {
    /// The current text of `file` (from the folder when live editing).
    pub fn source_of(&mut self, file: &'static ShaderFile) -> &str {
        self.load(file);
        &self.sources[file.path]
    }

    /// Generated shader `key` composed: over the embedded sources once in
    /// the process, as [`Self::compose`] does a permutation (the threads
    /// composing ahead, those creating pipelines ahead and the frame reach
    /// the same one), else by this composer.
    pub fn generate(&mut self, key: &GeneratedKey) -> Result<Generated, RenderError> {
        let shared = self.shares_embedded();
        let _generating = match shared.then(|| generated_or_claim(key)) {
            Some(Ok(made)) => return Ok(made),
            Some(Err(claimed)) => Some(claimed),
            None => None,
        };
        let made = key.compose_with(self)?;
        if shared {
            // Before the claim is dropped (which wakes those waiting).
            let stored = Arc::new(made.clone());
            embedded().generated.insert(key.clone(), stored);
        }
        Ok(made)
    }

    /// Compose a generated entry shader (`source`, named `file_path`) over
    /// the libraries plus `modules` (import path, file name for messages,
    /// text; each after what it imports), with `defs` set: the fused light
    /// loop (`lighting::light_sets`). The added libraries stay: a later
    /// composition adds them again over themselves.
    pub fn compose_generated(
        &mut self,
        modules: &[(String, String, String)],
        file_path: &str,
        source: &str,
        defs: &[String],
    ) -> Result<naga::Module, RenderError> {
        let describe = || format!(" [{}]", defs.join(", "));
        for (name, path, text) in modules {
            let added = self
                .composer
                .add_composable_module(ComposableModuleDescriptor {
                    source: text,
                    file_path: path,
                    language: ShaderLanguage::Wgsl,
                    as_name: Some(name.clone()),
                    ..Default::default()
                })
                .map(|_| ())
                .map_err(|e| e.emit_to_string(&self.composer));
            added.map_err(|message| RenderError::Shader {
                shader: path.clone(),
                defs: describe(),
                message,
            })?;
        }
        let shader_defs = defs
            .iter()
            .map(|f| (f.clone(), ShaderDefValue::Bool(true)))
            .collect();
        self.composer
            .make_naga_module(NagaModuleDescriptor {
                source,
                file_path,
                shader_type: ShaderType::Wgsl,
                shader_defs,
                additional_imports: &[],
            })
            .map_err(|e| RenderError::Shader {
                shader: file_path.to_owned(),
                defs: describe(),
                message: e.emit_to_string(&self.composer),
            })
    }
}

/// `file`'s text in `dir`, or the embedded one where `dir` lacks it.
fn read_or_embedded(dir: &Path, file: &ShaderFile) -> Cow<'static, str> {
    std::fs::read_to_string(dir.join(file.path))
        .map(Cow::Owned)
        .unwrap_or(Cow::Borrowed(file.source))
}

/// A shader node material's file, composed into a permutation in place of a library.
#[derive(Clone, Copy, Debug)]
pub struct Splice<'a> {
    /// Changes with the source (pipelines are cached under it).
    pub key: u64,
    /// The library it replaces, e.g. `spreadlight::custom_surface`.
    pub module: &'a str,
    pub file_path: &'a str,
    /// Its text, `#ifdef`s resolved.
    pub source: &'a str,
}
