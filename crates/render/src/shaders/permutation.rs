//! What a permutation is: a shader file's description ([`ShaderFile`]), the
//! key of one permutation ([`ShaderKey`]) and the typed keys' trait
//! ([`Permutation`]). The bottom of the shader layer: an effect's typed key
//! (`ssao/key.rs`) implements [`Permutation`] from here and declares its
//! own shader file with [`shader_file!`](crate::shader_file), so a
//! [`ShaderKey`] carries the file it compiles and no table below the
//! effects names them (only the libraries, `shaders::LIBRARIES`).

use std::collections::{BTreeSet, HashMap, HashSet};
use std::sync::{Mutex, OnceLock};

/// One WGSL file of `shaders/`: a library (in `shaders::LIBRARIES`) or an
/// entry shader (declared by its typed key, [`Permutation::FILE`]).
pub struct ShaderFile {
    /// Path below `shaders/`, e.g. `gbuffer/visibility.wgsl`.
    pub path: &'static str,
    pub source: &'static str,
    /// The feature switches the file reacts to (an entry shader's; a
    /// library's are those of the shaders that import it).
    pub features: &'static [&'static str],
    /// Libraries are imported by other shaders; they have no entry points.
    pub library: bool,
    /// An entry shader's permutations, its typed key's values (every other
    /// subset of its features is refused and never compiled); none for a library.
    pub keys: Option<fn() -> Vec<ShaderKey>>,
}

impl ShaderFile {
    /// Whether `features` is a permutation this file allows: one of its
    /// typed key's values. A library alone (a layout test composes one) takes
    /// the switches of whichever shader imports it, so any.
    pub fn check(&self, features: &BTreeSet<&'static str>) -> Result<(), String> {
        let Some(keys) = self.keys else {
            return Ok(());
        };
        match keyed_features(self.path, keys).contains(features) {
            true => Ok(()),
            false => Err(format!(
                "no value of its typed key switches on exactly {}",
                features.iter().copied().collect::<Vec<_>>().join(", ")
            )),
        }
    }
}

/// The feature sets of a keyed file's typed key, made once per file:
/// checking is a look-up (the composite has 6,720 keys).
fn keyed_features(
    path: &'static str,
    keys: fn() -> Vec<ShaderKey>,
) -> &'static HashSet<BTreeSet<&'static str>> {
    type Sets = HashMap<&'static str, &'static HashSet<BTreeSet<&'static str>>>;
    static SETS: OnceLock<Mutex<Sets>> = OnceLock::new();
    let mut sets = SETS
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    // Leaked once per entry shader of the binary: a few dozen small sets
    // that live as long as the process anyway.
    sets.entry(path)
        .or_insert_with(|| Box::leak(Box::new(keys().into_iter().map(|k| k.features).collect())))
}

/// `PATH` and `SOURCE` of an entry shader's [`Permutation`], from one path
/// below `shaders/`: the key file names its shader once, and the text is
/// embedded in the binary from there.
///
/// ```ignore
/// impl Permutation for AoKey {
///     crate::shader_file!("ssao/ao.wgsl");
///     const FEATURES: &'static [&'static str] = &["SAO", "HBAO", "HALF", "TEMPORAL"];
///     ...
/// }
/// ```
#[macro_export]
macro_rules! shader_file {
    ($path:literal) => {
        const PATH: &'static str = $path;
        const SOURCE: &'static str = $crate::shader_source!($path);
    };
}

/// The text of a file below the repository's `shaders/`, embedded in the
/// binary: the one spelling of where the shaders are, for entry shaders
/// ([`shader_file!`](crate::shader_file)), libraries
/// ([`LIBRARIES`](crate::shaders::LIBRARIES)) and the node library's
/// examples. From the including crate's manifest, so it holds for every
/// crate under `crates/` and for files at any depth.
#[macro_export]
macro_rules! shader_source {
    ($($path:tt)+) => {
        include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../../shaders/", $($path)+))
    };
}

/// A shader's permutations as a Rust type, beside the effect that runs it
/// (SSAO's `AoKey` in `ssao/key.rs`): each value is one permutation, and a
/// combination the shader does not support cannot be written, so the
/// effect's code says `AoKey { estimator, target }`, not a list of strings.
/// The key declares its shader file too ([`shader_file!`](crate::shader_file)):
/// its keys carry it to the composer.
pub trait Permutation: Copy + 'static {
    /// The shader, below `shaders/`.
    const PATH: &'static str;
    /// Its WGSL text.
    const SOURCE: &'static str;
    /// Every feature switch the shader reacts to.
    const FEATURES: &'static [&'static str];
    /// The file every key of this type carries.
    const FILE: &'static ShaderFile = &ShaderFile {
        path: Self::PATH,
        source: Self::SOURCE,
        features: Self::FEATURES,
        library: false,
        keys: Some(Self::all_keys),
    };

    /// The switches this permutation turns on.
    fn features(self) -> impl Iterator<Item = &'static str>;
    /// Every permutation the shader supports.
    fn all() -> Vec<Self>;

    fn key(self) -> ShaderKey {
        ShaderKey::new(Self::FILE, self.features())
    }

    /// The keys of [`Permutation::all`].
    fn all_keys() -> Vec<ShaderKey> {
        Self::all().into_iter().map(Self::key).collect()
    }
}

/// Which permutation of which shader: its file and the set of switched-on
/// features. Compared, ordered and hashed by the file's path and the
/// features, as when it held the path alone (pipelines are cached under it).
#[derive(Clone)]
pub struct ShaderKey {
    pub file: &'static ShaderFile,
    pub features: BTreeSet<&'static str>,
}

impl ShaderKey {
    /// A permutation of `file`; one its typed key has no value for is
    /// refused when composed. Passes make keys with [`Permutation::key`].
    pub fn new(
        file: &'static ShaderFile,
        features: impl IntoIterator<Item = &'static str>,
    ) -> Self {
        ShaderKey {
            file,
            features: features.into_iter().collect(),
        }
    }

    /// The shader's path below `shaders/`.
    pub fn path(&self) -> &'static str {
        self.file.path
    }

    pub(crate) fn describe_defs(&self) -> String {
        if self.features.is_empty() {
            String::new()
        } else {
            format!(
                " [{}]",
                self.features.iter().copied().collect::<Vec<_>>().join(", ")
            )
        }
    }

    /// What the key is compared and hashed by.
    fn id(&self) -> (&'static str, &BTreeSet<&'static str>) {
        (self.file.path, &self.features)
    }
}

impl PartialEq for ShaderKey {
    fn eq(&self, other: &Self) -> bool {
        self.id() == other.id()
    }
}

impl Eq for ShaderKey {}

impl std::hash::Hash for ShaderKey {
    // The path, then the features: what the derived hash of `{ path, features }` fed.
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.file.path.hash(state);
        self.features.hash(state);
    }
}

impl PartialOrd for ShaderKey {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for ShaderKey {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.id().cmp(&other.id())
    }
}

impl std::fmt::Debug for ShaderKey {
    // The path, not the file's whole text.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ShaderKey")
            .field("path", &self.file.path)
            .field("features", &self.features)
            .finish()
    }
}
