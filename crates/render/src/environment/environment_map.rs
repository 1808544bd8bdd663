//! An environment for image-based light: a cube map made from an
//! equirectangular HDR image or from the procedural sky, prefiltered per
//! roughness level (split-sum), its diffuse irradiance, and the split-sum
//! BRDF table (built by compute in [`super::prefilter`]).
//!
//! The maps outlive frames: they are kept in `Renderer::state` under the
//! owning node and rebuilt only when the source or quality changes (the
//! frame report counts "environment prefiltered" and "environment reused").
//! Readers order themselves after the build by reading [`Environment::token`].
//!
//! A probe's maps (`EnvironmentSource::Probe`) are rendered from its layer
//! and rebuilt as its [`ProbeUpdate`] says: counted as "environment probe
//! rendered" and "environment probe reused".

use std::hash::{Hash, Hasher};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

use super::probe::ProbeUpdate;
use super::probe::faces::{PackedProbe, ProbeTextures};
use super::source::{EnvironmentMaps, EnvironmentQuality, EnvironmentSource};
use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, TextureDesc};
use crate::gbuffer::Layer;
use crate::recipe::{Recipe, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::Permutation;

/// Where a node's maps are kept across frames, and (for a probe updated
/// every n frames) the frames since they were built.
#[derive(Default)]
pub struct EnvironmentStore(pub(crate) Mutex<Option<Arc<EnvironmentMaps>>>, AtomicU32);

/// Statistics: a probe's faces rendered (and prefiltered) this frame, or its cube kept.
pub const PROBE_RENDERED: &str = "environment probe rendered";
pub const PROBE_REUSED: &str = "environment probe reused";

/// The environment recipe: one pass that builds the maps when its source or
/// quality changed and otherwise only counts the reuse.
pub struct Environment {
    id: u64,
    owner: Option<u32>,
    pub source: EnvironmentSource,
    pub quality: EnvironmentQuality,
    key: u64,
    store: Arc<EnvironmentStore>,
    token: String,
    /// A probe's layers as instances and draws (hashed into `key`).
    probe: Option<PackedProbe>,
}

impl std::fmt::Debug for Environment {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Environment({:?})", self.quality)
    }
}

/// Identifies a source and quality: a change means a rebuild.
fn source_key(
    source: &EnvironmentSource,
    quality: EnvironmentQuality,
    probe: Option<&PackedProbe>,
) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    quality.hash(&mut h);
    match source {
        EnvironmentSource::Probe(scene) => {
            2u8.hash(&mut h);
            if let Some(packed) = probe {
                scene.hash_content(packed, &mut h);
            }
        }
        EnvironmentSource::Equirect(image) => {
            0u8.hash(&mut h);
            (image.width, image.height).hash(&mut h);
            for p in &image.pixels {
                for c in p {
                    c.to_bits().hash(&mut h);
                }
            }
        }
        EnvironmentSource::Sky(s) => {
            1u8.hash(&mut h);
            for v in [s.zenith, s.horizon, s.ground, s.sun_direction, s.sun_color] {
                for c in v.to_array() {
                    c.to_bits().hash(&mut h);
                }
            }
            s.sun_radius.to_bits().hash(&mut h);
            s.glow.to_bits().hash(&mut h);
        }
    }
    h.finish()
}

impl Environment {
    /// An environment for node `owner` (its maps are kept under it and
    /// reused while the source and quality stay the same; without an owner
    /// every recipe builds its own).
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        source: EnvironmentSource,
        quality: EnvironmentQuality,
    ) -> Arc<Self> {
        let quality = quality.sanitized();
        let id = next_recipe_id();
        let store = match owner {
            Some(node) => renderer.state::<EnvironmentStore>(u64::from(node)),
            None => Arc::new(EnvironmentStore::default()),
        };
        let probe = match &source {
            EnvironmentSource::Probe(scene) => Some(PackedProbe::new(scene.layers())),
            _ => None,
        };
        Arc::new(Environment {
            id,
            owner,
            key: source_key(&source, quality, probe.as_ref()),
            source,
            quality,
            store,
            token: format!("environment{id}/maps"),
            probe,
        })
    }

    /// Read this in a pass that uses [`Environment::maps`]: it orders the build first.
    pub fn token(&self) -> &str {
        &self.token
    }

    /// The maps, once the build pass has run (this frame or an earlier one).
    pub fn maps(&self) -> Option<Arc<EnvironmentMaps>> {
        self.store
            .0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// The maps a reader's pass needs now, or an error naming that pass.
    pub(crate) fn maps_for(&self, pass: &str) -> Result<Arc<EnvironmentMaps>, RenderError> {
        self.maps().ok_or_else(|| RenderError::Pass {
            pass: pass.to_owned(),
            message: "the environment was not built this frame".to_owned(),
        })
    }

    /// The parallax volume Reflection corrects with: a probe's with a box or sphere, else none.
    pub(crate) fn parallax(&self) -> Option<super::probe::GpuProbeVolume> {
        match &self.source {
            EnvironmentSource::Probe(scene) => Some(scene.gpu_volume()).filter(|v| v.corrects()),
            _ => None,
        }
    }

    /// Whether the kept maps serve this frame: the same source (a probe:
    /// as its update rate says).
    fn current(&self, maps: Option<&EnvironmentMaps>) -> bool {
        let Some(maps) = maps else {
            return false;
        };
        let EnvironmentSource::Probe(scene) = &self.source else {
            return maps.key == self.key;
        };
        let frames = self.store.1.fetch_add(1, Ordering::Relaxed) + 1;
        maps.quality == self.quality
            && match scene.settings().update {
                ProbeUpdate::OnChange => maps.key == self.key,
                ProbeUpdate::EveryNFrames(n) => frames < n,
                ProbeUpdate::Once => true,
            }
    }

    fn run(
        &self,
        cx: &mut PassContext<'_>,
        renderer: &Renderer,
        textures: &ProbeTextures,
    ) -> Result<(), RenderError> {
        let mut guard = self.store.0.lock().unwrap_or_else(|e| e.into_inner());
        let probe = matches!(self.source, EnvironmentSource::Probe(_));
        if self.current(guard.as_deref()) {
            cx.count(
                if probe {
                    PROBE_REUSED
                } else {
                    "environment reused"
                },
                1,
            );
            return Ok(());
        }
        let faces = match (&self.source, &self.probe) {
            (EnvironmentSource::Probe(scene), Some(packed)) => {
                Some((renderer, &**scene, packed, textures))
            }
            _ => None,
        };
        let maps = super::prefilter::build(cx, &self.source, self.quality, self.key, faces)?;
        *guard = Some(Arc::new(maps));
        self.store.1.store(0, Ordering::Relaxed);
        cx.count(
            if probe {
                PROBE_RENDERED
            } else {
                "environment prefiltered"
            },
            1,
        );
        Ok(())
    }
}

impl Recipe for Environment {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        let name = match self.source {
            EnvironmentSource::Probe(_) => {
                PassName::new("EnvironmentProbe").step("faces and prefilter")
            }
            _ => PassName::new("Environment").step("prefilter"),
        };
        // A probe's layers' Color Textures and Normal Maps, and its sun's
        // shadow maps, made before its faces sample them.
        let (layers, sun_shadow): (&[Arc<Layer>], _) = match &self.source {
            EnvironmentSource::Probe(scene) => (scene.layers(), scene.sun_shadow()),
            _ => (&[], None),
        };
        // (A glTF layer's surface maps replace them: uploaded arrays, no recipe.)
        let normal_map = |l: &'a Arc<Layer>| {
            (l.normal_map.as_ref()).filter(|_| l.features.normal_map && l.map_world().is_none())
        };
        let color_map =
            |l: &'a Arc<Layer>| l.color_map.as_ref().filter(|_| l.map_world().is_none());
        for map in layers
            .iter()
            .flat_map(|l| color_map(l).into_iter().chain(normal_map(l)))
        {
            map.recipe.declare(renderer, fg);
        }
        if let Some(sun) = sun_shadow {
            sun.maps.declare(renderer, fg);
        }
        // Its light buffers' spot textures and shadow maps.
        let lights = match &self.source {
            EnvironmentSource::Probe(scene) => scene.lights(),
            _ => &[],
        };
        for set in lights {
            if let Some(textures) = set.lights.textures() {
                textures.recipe.declare(renderer, fg);
            }
            if let Some(shadows) = &set.shadows {
                shadows.declare(renderer, fg);
            }
        }
        let mut pass = fg.pass(name, self.owner);
        // The pipelines prefiltering dispatches (frame_graph/gather.rs).
        let first = match self.source {
            EnvironmentSource::Equirect(_) => Some("from_equirect"),
            EnvironmentSource::Sky(_) => Some("from_sky"),
            EnvironmentSource::Probe(_) => None,
        };
        let key = super::prefilter_key::PrefilterKey.key();
        for entry in first
            .into_iter()
            .chain(["downsample", "prefilter", "irradiance", "brdf_lut"])
        {
            pass.will_dispatch(&key, entry);
        }
        let textures = ProbeTextures {
            color: (layers.iter())
                .map(|l| color_map(l).map(|m| pass.read(&m.name)))
                .collect(),
            normal: (layers.iter())
                .map(|l| normal_map(l).map(|m| pass.read(&m.name)))
                .collect(),
            spots: (lights.iter())
                .map(|set| set.lights.textures().map(|t| pass.read(&t.name)))
                .collect(),
        };
        // A probe's faces' render pipelines (frame_graph/gather.rs).
        if let (EnvironmentSource::Probe(scene), Some(packed)) = (&self.source, &self.probe)
            && pass.graph().gathers_pipelines()
        {
            super::probe::faces::announce(&mut pass, scene, packed, &textures);
        }
        if let Some(sun) = sun_shadow {
            pass.read(sun.maps.token());
        }
        for shadows in lights.iter().filter_map(|set| set.shadows.as_ref()) {
            pass.read(shadows.token());
        }
        // The maps live in the store; the token orders the passes that read them.
        pass.write(&self.token, TextureDesc::token());
        pass.run(move |cx| self.run(cx, renderer, &textures));
    }
}
