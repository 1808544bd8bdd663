//! Composing a patch's shader permutations ahead, on every core, while the
//! process does its other start-up work (the node registry, the GPU).
//!
//! A fresh process composes each permutation its first frame needs with
//! naga_oil (preprocessing, naga's parse and validation): 100-180 ms of one
//! core for post.ron on the H200 host, inside the first frame, one
//! permutation after another. Which permutations a patch needs is only
//! known while its passes record; so each run remembers them in a small
//! list ([`remember`]), and the next run of the same patch composes that
//! list on threads of their own from the moment it starts ([`start`]).
//! The first frame then finds them composed (the process's shared
//! permutations, `shaders/composer.rs`) and its renderer never even makes a
//! composer of its own.
//!
//! The list holds names, not composed code: each entry is composed from the
//! sources this binary embeds, exactly as the first frame would have, so a
//! changed source or a new build can never bring back a stale shader, and
//! the frames are the same bytes (tested). An entry this build does not
//! know (a shader or a feature since removed) is skipped; a damaged list is
//! a warning and a normal start. A wrong list costs CPU, never pixels.
//!
//! The list names the frame's compute pipelines too (a permutation and an
//! entry point, in the order the frame asked for them): a renderer creates
//! those on threads as soon as its device is open
//! (`crate::shaders::pipelines_ahead`), and the list's permutations are ordered so
//! that theirs are composed first.
//!
//! And the generated shaders the frame dispatched (the fused light loop,
//! `shaders/generated.rs`), by their generator's name and the permutations
//! they are made of (list format 3): composed ahead here, first (each is
//! several permutations' worth of composing), and their pipelines created
//! ahead with the others.
//!
//! Where: `permutations/` in Spreadlight's cache directory
//! ([`crate::pipeline_cache::cache_dir`]), one file per patch (by its
//! path). `SPREADLIGHT_PRECOMPOSE=off` leaves it out.
//!
//! Why not keep the composed naga modules themselves: naga's serde support
//! (its `serialize`/`deserialize` features) turns on serde in `bitflags`,
//! `hashbrown` and `half`, which nearly every crate of the tree depends
//! on, for a saving the threads already make at no risk to the pixels.

use std::collections::BTreeSet;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::permutations::{ENTRY_SHADERS, GENERATORS};
use crate::shaders::pipelines_ahead::PipelineId;
use crate::shaders::{GeneratedKey, ShaderComposer, ShaderKey};

/// The first line of a list (its format's version).
const HEADER: &str = "spreadlight permutations 3";

/// The first lines of lists earlier builds wrote: permutations only (1),
/// and compute pipelines of permutations (2).
const HEADER_1: &str = "spreadlight permutations 1";
const HEADER_2: &str = "spreadlight permutations 2";

/// The first field of a generated shader's line.
const GENERATED: &str = "generated";
/// What begins a generated shader's last field when it holds its options.
const OPTIONS: &str = "+";

/// More than any patch composes; a longer list is cut there.
const MOST: usize = 1024;

/// Whether lists are read and written (`SPREADLIGHT_PRECOMPOSE=off|0`: not).
pub fn enabled() -> bool {
    !matches!(
        std::env::var("SPREADLIGHT_PRECOMPOSE").as_deref(),
        Ok("off" | "0")
    )
}

/// The list of what `name` (a patch's path) composed last time.
pub fn list_path(name: &str) -> PathBuf {
    let mut hasher = rustc_hash::FxHasher::default();
    name.hash(&mut hasher);
    crate::pipeline_cache::cache_dir()
        .join("permutations")
        .join(format!("{:016x}.txt", hasher.finish()))
}

/// A permutation's two fields: its shader's path, and its features
/// separated by spaces, after a tab.
fn key_text(key: &ShaderKey) -> String {
    format!("{}\t{}", key.path(), features_text(key))
}

/// A permutation's features, separated by spaces.
fn features_text(key: &ShaderKey) -> String {
    let features: Vec<&str> = key.features.iter().copied().collect();
    features.join(" ")
}

/// `keys` and `pipelines` as a list's text: a header, a line per compute
/// pipeline in the order given (the frame's: `crate::shaders::pipelines_ahead`
/// creates them in that order), its permutation's fields and its entry
/// point after a second tab, or for a generated shader `generated`, its
/// generator's name and each part's features, a field each; then a line
/// per permutation. Render pipelines are not listed (their state is code).
pub fn to_text(keys: &[ShaderKey], pipelines: &[PipelineId]) -> String {
    let mut text = format!("{HEADER}\n");
    for id in pipelines.iter().take(MOST) {
        match id {
            PipelineId::Entry(key, entry) => {
                text.push_str(&format!("{}\t{entry}\n", key_text(key)));
            }
            PipelineId::Generated(generated) => {
                text.push_str(&format!("{GENERATED}\t{}", generated.generator.name));
                for part in &generated.parts {
                    text.push_str(&format!("\t{}", features_text(part)));
                }
                // The generator's own switches, a last field behind `+`.
                if !generated.options.is_empty() {
                    text.push_str(&format!("\t{OPTIONS}{}", generated.options.join(" ")));
                }
                text.push('\n');
            }
            PipelineId::Render(..) => {}
        }
    }
    for key in keys.iter().take(MOST) {
        text.push_str(&format!("{}\n", key_text(key)));
    }
    text
}

/// A list read back: its permutations this build has (those of the
/// pipelines first, in the pipelines' order), its generated shaders, its
/// compute pipelines (of permutations and of the generated shaders), and
/// how many lines named a permutation or generator this build does not
/// have (a shader, feature or generator since removed).
#[derive(Debug, Default)]
pub struct List {
    pub keys: Vec<ShaderKey>,
    pub generated: Vec<GeneratedKey>,
    pub pipelines: Vec<PipelineId>,
    pub unknown: usize,
}

/// Parse a list's text; an error says what is wrong with it, and where.
pub fn parse(text: &str) -> Result<List, String> {
    let mut lines = text.lines();
    let version = lines.next();
    if ![Some(HEADER), Some(HEADER_2), Some(HEADER_1)].contains(&version) {
        return Err(format!("its first line is not `{HEADER}`"));
    }
    let mut list = List::default();
    let mut seen = std::collections::HashSet::new();
    for (i, line) in lines.enumerate() {
        if let Some(rest) = line
            .strip_prefix(GENERATED)
            .and_then(|r| r.strip_prefix('\t'))
        {
            match generated_of(rest) {
                Some(key) if list.pipelines.len() < MOST => {
                    if !list.generated.contains(&key) {
                        list.generated.push(key.clone());
                    }
                    list.pipelines.push(PipelineId::Generated(key));
                }
                Some(_) => {}
                None => list.unknown += 1,
            }
            continue;
        }
        let mut fields = line.split('\t');
        let (Some(path), Some(features)) = (fields.next(), fields.next()) else {
            return Err(format!("line {}: not `PATH<tab>FEATURES`", i + 2));
        };
        let entry = fields.next();
        if fields.next().is_some() {
            return Err(format!("line {}: more than three fields", i + 2));
        }
        if let Some(entry) = entry
            && (entry.is_empty() || !entry.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
        {
            return Err(format!("line {}: `{entry}` is not an entry point", i + 2));
        }
        let Some(key) = key_of(path, features) else {
            list.unknown += 1;
            continue;
        };
        if list.keys.len() < MOST && seen.insert(key.clone()) {
            list.keys.push(key.clone());
        }
        if let Some(entry) = entry
            && list.pipelines.len() < MOST
        {
            list.pipelines
                .push(PipelineId::Entry(key, entry.to_owned()));
        }
    }
    Ok(list)
}

/// The generated shader a line names after `generated<tab>`: its
/// generator's name, then each part's features a field each; None where
/// this build has no such generator or lacks a part's permutation.
fn generated_of(fields: &str) -> Option<GeneratedKey> {
    let mut fields = fields.split('\t');
    let name = fields.next()?;
    let generator = GENERATORS.iter().copied().find(|g| g.name == name)?;
    let mut options = Vec::new();
    let mut parts = Vec::new();
    for field in fields {
        match field.strip_prefix(OPTIONS) {
            // Names only: a generator refuses options it does not know
            // when it composes (left to the frame, as a refused group is).
            Some(rest) => options.extend(rest.split_whitespace().map(str::to_owned)),
            None => parts.push(key_of(generator.file.path, field)?),
        }
    }
    Some(GeneratedKey {
        generator,
        parts,
        options,
    })
}

/// The permutation a line names, if this build's shaders allow it.
fn key_of(path: &str, features: &str) -> Option<ShaderKey> {
    let file = ENTRY_SHADERS.iter().find(|f| f.path == path)?;
    let features: Option<BTreeSet<&'static str>> = features
        .split_whitespace()
        .map(|name| file.features.iter().copied().find(|f| *f == name))
        .collect();
    let features = features?;
    file.check(&features).ok()?;
    Some(ShaderKey::new(file, features))
}

/// The list at `path`: None when there is none (a first run); an error
/// naming the file when it cannot be read or is not a list.
pub fn read(path: &Path) -> Result<Option<List>, String> {
    let bytes = match std::fs::read(path) {
        Ok(bytes) => bytes,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(format!("cannot read {}: {e}", path.display())),
    };
    let text = String::from_utf8(bytes)
        .map_err(|_| format!("{} is not a permutation list (not text)", path.display()))?;
    parse(&text)
        .map(Some)
        .map_err(|e| format!("{} is not a permutation list: {e}", path.display()))
}

/// Write `keys` and `pipelines` to the list at `path`, through a temporary
/// file and a rename (a run killed half-way leaves the old list). Unchanged
/// text is not written again.
pub fn remember(path: &Path, keys: &[ShaderKey], pipelines: &[PipelineId]) -> std::io::Result<()> {
    let text = to_text(keys, pipelines);
    if std::fs::read(path).is_ok_and(|old| old == text.as_bytes()) {
        return Ok(());
    }
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let temp = path.with_extension(format!("{}.tmp", std::process::id()));
    std::fs::write(&temp, text)?;
    std::fs::rename(&temp, path)
}

/// What composing ahead did (`cold_start` of the CLI's `--json`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Precomposed {
    /// Permutations and generated shaders in the list, and of them composed
    /// (the rest failed, or were composed already).
    pub listed: usize,
    pub composed: usize,
    pub threads: usize,
    /// From [`start`] until the last thread ended.
    pub wall: Duration,
    /// How long [`Precomposing::finish`] waited for them.
    pub waited: Duration,
}

/// Threads composing ahead, until [`Precomposing::finish`].
pub struct Precomposing {
    handle: Option<JoinHandle<Precomposed>>,
}

/// Compose `generated` and `keys` on up to `threads` threads (each with a
/// composer of its own) in the background; what they compose joins the
/// process's shared permutations and generated shaders, where every
/// renderer over the embedded sources finds it.
pub fn start(keys: Vec<ShaderKey>, generated: Vec<GeneratedKey>, threads: usize) -> Precomposing {
    let listed = keys.len() + generated.len();
    let threads = threads.clamp(1, listed.max(1));
    let spawned = std::thread::Builder::new()
        .name("precompose".to_owned())
        .spawn(move || {
            let started = Instant::now();
            let composed = compose_all(&keys, &generated, threads);
            Precomposed {
                listed,
                composed,
                threads,
                wall: started.elapsed(),
                waited: Duration::ZERO,
            }
        });
    // No thread (the system refused one): the first frame composes as before.
    Precomposing {
        handle: spawned.ok(),
    }
}

/// Compose `generated` then `keys` on `threads` scoped threads, each
/// taking the next not yet taken (the generated shaders first: each is the
/// longest to compose); returns how many composed. One that fails is left
/// for the renderer, which reports it where it is used.
pub fn compose_all(keys: &[ShaderKey], generated: &[GeneratedKey], threads: usize) -> usize {
    let next = AtomicUsize::new(0);
    let composed = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        for _ in 0..threads.max(1) {
            scope.spawn(|| {
                let Ok(mut composer) = ShaderComposer::new() else {
                    return;
                };
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let done = if let Some(generated) = generated.get(i) {
                        composer.generate(generated).is_ok()
                    } else if let Some(key) = keys.get(i - generated.len()) {
                        composer.compose(key).is_ok()
                    } else {
                        break;
                    };
                    if done {
                        composed.fetch_add(1, Ordering::Relaxed);
                    }
                }
            });
        }
    });
    composed.into_inner()
}

/// The threads to compose with: every core but the one the main thread
/// uses (the shader cache's pipeline threads take as many).
pub use crate::shaders::pipelines_ahead::threads;

impl Precomposing {
    /// Wait for the threads; what they did.
    pub fn finish(self) -> Precomposed {
        let started = Instant::now();
        let done = self.handle.and_then(|h| h.join().ok());
        done.map(|done| Precomposed {
            waited: started.elapsed(),
            ..done
        })
        .unwrap_or_default()
    }
}

#[cfg(test)]
mod tests;
