//! Shadow maps, after Emeshe's ShadowMap modules and Castor3D's shadow
//! passes: one `ShadowMaps` recipe serves a whole spread of lights of one
//! type. Spots get one layer each of a 2D depth array, point lights six
//! (a cube map array's layout), suns one per cascade. `CookTorrance` samples
//! the layer a light's `shadow` slice names, with the filter compiled in as
//! a permutation (Raw, PCF, PCSS or VSM).
//!
//! Only the shadows a scene calls for: a light with no slice renders
//! nothing; a light whose volume misses the camera's frustum renders
//! nothing; a slice whose light and casters are unchanged since it was
//! rendered is reused (the maps live in the renderer between frames, under
//! the node's id). A sun's cascade that only moved across the light by whole
//! texels (a moving camera) is scrolled: its kept texels are copied into
//! place and only the uncovered strips are drawn (scroll.rs). The frame
//! report counts each decision ("shadow maps rendered", "shadow maps
//! reused", "shadow maps culled", "shadow layers scrolled"...).

// Named by the permutation keys without the passes.
pub(crate) mod filter;
mod filter_key;
pub mod layers;
mod raster;
pub(crate) mod raster_key;
mod raster_layered;
mod scroll;
pub(crate) mod scroll_key;
mod slices;
mod store;
pub mod views;

use std::sync::Arc;

use glam::{Mat4, Vec3};

use crate::camera::CameraInput;
use crate::frame_graph::{FrameGraph, TextureDesc};
use crate::gbuffer::{Layer, LayerMemo, RasterChoice};
use crate::recipe::{Recipe, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;

use raster::{CasterSet, SetKind, StillSets};
use store::ShadowStore;

pub use filter::ShadowFilter;
pub use filter_key::ShadowKey;
pub use layers::{ShadowLayers, set_shadow_layers, shadow_layers};
pub use views::{Cascades, LayerView};

/// What every shadow map of a node shares.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowSettings {
    /// Texels along each side of a layer.
    pub resolution: u32,
    pub filter: ShadowFilter,
    /// Subtracted from the receiver's depth, in world units.
    pub depth_bias: f32,
    /// The receiver moves this many texels along its normal before it is compared.
    pub normal_bias: f32,
    /// Which rasterizer draws the maps (see [`compute_rasterizes`]).
    pub raster: RasterChoice,
}

impl Default for ShadowSettings {
    fn default() -> Self {
        ShadowSettings {
            resolution: 1024,
            filter: ShadowFilter::Pcf { kernel: 3 },
            depth_bias: 0.02,
            normal_bias: 1.5,
            raster: RasterChoice::Auto,
        }
    }
}

/// The lights of one type that cast, with their slices.
#[derive(Clone, Debug)]
pub enum ShadowLights {
    /// (slice, view, projection) of each casting spot.
    Spot(Vec<(u32, Mat4, Mat4)>),
    /// (slice, position, range) of each casting point light.
    Point(Vec<(u32, Vec3, f32)>),
    /// (slice, direction) of each casting sun, with the cascade setup.
    Sun {
        lights: Vec<(u32, Vec3)>,
        cascades: Cascades,
    },
}

impl ShadowLights {
    /// Layers per slice: 1 for a spot, 6 for a point light, the cascades for a sun.
    pub fn layers_per_slice(&self) -> u32 {
        match self {
            ShadowLights::Spot(_) => 1,
            ShadowLights::Point(_) => 6,
            ShadowLights::Sun { cascades, .. } => cascades.count.clamp(1, 4),
        }
    }

    /// A hash of the lights as they were given, not of the views made from
    /// them (a sun's cascades follow the camera): what a reader that shades
    /// outside the camera's view (an environment probe) keys its re-render on.
    fn content_key(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        let mut floats = |values: &[f32]| {
            for v in values {
                v.to_bits().hash(&mut h);
            }
        };
        match self {
            ShadowLights::Spot(l) => {
                for (slice, view, projection) in l {
                    floats(&[*slice as f32]);
                    floats(&view.to_cols_array());
                    floats(&projection.to_cols_array());
                }
            }
            ShadowLights::Point(l) => {
                for (slice, position, range) in l {
                    floats(&[*slice as f32, position.x, position.y, position.z, *range]);
                }
            }
            ShadowLights::Sun { lights, cascades } => {
                for (slice, d) in lights {
                    floats(&[*slice as f32, d.x, d.y, d.z]);
                }
                floats(&[
                    cascades.count as f32,
                    cascades.split_lambda,
                    cascades.distance,
                ]);
            }
        }
        h.finish()
    }

    fn slices(&self) -> Vec<u32> {
        match self {
            ShadowLights::Spot(l) => l.iter().map(|x| x.0).collect(),
            ShadowLights::Point(l) => l.iter().map(|x| x.0).collect(),
            ShadowLights::Sun { lights, .. } => lights.iter().map(|x| x.0).collect(),
        }
    }
}

/// Why a set of shadow lights cannot be rendered.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ShadowError {
    #[error("shadow slice {slice} is given to two lights")]
    SliceTwice { slice: u32 },
    #[error(
        "shadow slice {slice} is too high: a texture array holds {max} layers, {per} per slice here"
    )]
    TooManySlices { slice: u32, max: u32, per: u32 },
    #[error("resolution {0} is outside 16..={1}")]
    Resolution(u32, u32),
}

/// What is rendered where: one entry per slice that renders this frame.
#[derive(Clone, Debug)]
struct SlicePlan {
    slice: u32,
    views: Vec<LayerView>,
    /// The light's volume misses the camera: nothing to render.
    culled: bool,
}

/// Matches `ShadowParams` in shaders/lighting/shadow_sampling.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuShadowParams {
    /// depth bias, normal bias (texels), filter reach (PCF radius or VSM blur, texels), PCSS light size (world)
    bias: [f32; 4],
    /// PCSS samples, VSM bleeding, resolution, layers per slice
    filter: [f32; 4],
}

/// Room for one view matrix per uniform slot, at the usual offset alignment.
const VIEW_STRIDE: u64 = 256;

/// A node's shadow maps for one frame: a recipe whose pass renders the
/// slices that need it into the renderer's stored maps.
pub struct ShadowMaps {
    id: u64,
    /// The light type these maps are laid out for.
    pub kind: crate::light_kind::LightKind,
    owner: Option<u32>,
    pub settings: ShadowSettings,
    per_slice: u32,
    /// The lights' [`ShadowLights::content_key`].
    light_key: u64,
    plans: Vec<SlicePlan>,
    /// Every layer's view, slice-major (what the shader reads), even for slices with no light.
    views: wgpu::Buffer,
    params: wgpu::Buffer,
    /// One view matrix per uniform slot, for the depth pass.
    view_uniforms: wgpu::Buffer,
    casters: Vec<Arc<Layer>>,
    /// What the layers are drawn from (both rasterizers read the sets).
    sets: Sets,
    /// The compute rasterizer's camera uniform per layer, where it draws
    /// the maps ([`compute_rasterizes`]) one layer at a time.
    cameras: Option<Vec<wgpu::Buffer>>,
    /// The compute rasterizer's camera per layer, where it draws the maps
    /// (empty where the raster hardware draws them).
    layer_cameras: Vec<crate::camera::GpuCamera>,
    /// The compute rasterizer draws the layers together (layers.rs).
    together: bool,
    store: Arc<ShadowStore>,
    layers: u32,
    /// Per layer, what its resolve and moments dispatches read: (layer, VSM
    /// blur radius) and the region they fill (the whole layer); kept under
    /// the node so their bind groups are reused.
    layer_info: Vec<wgpu::Buffer>,
    /// What readers wait for: the maps (and for VSM their moments) are ready.
    token: String,
    /// VSM: the depth layers are drawn (the moments pass waits for it).
    depth_token: String,
    /// Suns: casters' bounds computed anew and kept from the last recipe.
    bounds_made: (u64, u64),
}

impl std::fmt::Debug for ShadowMaps {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "ShadowMaps({} slices x {} layers)",
            self.layers / self.per_slice,
            self.per_slice
        )
    }
}

/// The casters of a recipe, as the rasterizers draw them.
enum Sets {
    /// All together: every caster is new, or none changed since the node's last recipe.
    One(CasterSet),
    /// Some casters are the node's last recipe's (still) and some are not
    /// (moving): a slice whose views hold caches the still ones and draws
    /// only the moving ones over them each frame.
    /// The still set is the store's, kept while its casters stay.
    Split {
        still: Arc<CasterSet>,
        moving: CasterSet,
    },
}

/// The largest map side the nodes allow.
pub const MAX_RESOLUTION: u32 = 8192;

impl ShadowMaps {
    /// Shadow maps of `lights` cast by `casters`, for a frame seen by
    /// `camera` (culling and sun cascades follow it). `owner` keys the
    /// stored maps: the same node reuses its maps from frame to frame.
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        lights: &ShadowLights,
        casters: Vec<Arc<Layer>>,
        camera: &CameraInput,
        settings: ShadowSettings,
    ) -> Result<Arc<Self>, ShadowError> {
        let id = next_recipe_id();
        let max_layers = renderer.gpu.device.limits().max_texture_array_layers;
        let max_side = renderer
            .gpu
            .device
            .limits()
            .max_texture_dimension_2d
            .min(MAX_RESOLUTION);
        if !(16..=max_side).contains(&settings.resolution) {
            return Err(ShadowError::Resolution(settings.resolution, max_side));
        }
        let per = lights.layers_per_slice();
        let mut seen = std::collections::HashSet::new();
        for slice in lights.slices() {
            if !seen.insert(slice) {
                return Err(ShadowError::SliceTwice { slice });
            }
            if slice
                .checked_add(1)
                .and_then(|s| s.checked_mul(per))
                .is_none_or(|layers| layers > max_layers)
            {
                return Err(ShadowError::TooManySlices {
                    slice,
                    max: max_layers,
                    per,
                });
            }
        }
        let slices = lights.slices().into_iter().max().map_or(0, |m| m + 1);
        let layers = (slices * per).max(1);
        let res = settings.resolution;
        let camera_vp = camera.projection * camera.view;
        // Only a sun's cascades fit the casters' bounds; a node's casters
        // that did not change keep theirs (see `LayerMemo`).
        let mut bounds_made = (0, 0);
        let (bounds_center, bounds_radius) = match (lights, owner) {
            (ShadowLights::Sun { .. }, Some(node)) => {
                let (boxes, made) = renderer
                    .state::<LayerMemo<Option<(Vec3, Vec3)>>>(u64::from(node))
                    .get(&casters, layer_box);
                bounds_made = (made, casters.len() as u64 - made);
                sphere_around(boxes.iter().map(|b| **b))
            }
            (ShadowLights::Sun { .. }, None) => caster_bounds(&casters),
            _ => (Vec3::ZERO, 1.0),
        };
        let plans: Vec<SlicePlan> = match lights {
            ShadowLights::Spot(list) => list
                .iter()
                .map(|&(slice, view, projection)| {
                    let v = views::spot(view, projection, res);
                    let position = crate::camera::safe_inverse(view).w_axis.truncate();
                    let culled = match v {
                        Some(v) => !views::sphere_in_frustum(camera_vp, position, v.far),
                        None => true,
                    };
                    SlicePlan {
                        slice,
                        views: v.into_iter().collect(),
                        culled,
                    }
                })
                .collect(),
            ShadowLights::Point(list) => list
                .iter()
                .map(|&(slice, position, range)| SlicePlan {
                    slice,
                    views: views::point(position, range, res).to_vec(),
                    culled: !views::sphere_in_frustum(camera_vp, position, range.max(0.0)),
                })
                .collect(),
            ShadowLights::Sun { lights, cascades } => {
                // A still camera's cascades hold their boxes while they hold
                // their slices (views::sun_held), whatever its sub-pixel
                // jitter; a camera that moved places them afresh.
                let memory = owner.map(|node| renderer.state::<HeldCascades>(u64::from(node)));
                let mut held = memory
                    .as_ref()
                    .map(|m| m.0.lock().unwrap_or_else(|e| e.into_inner()));
                let still_camera = jitter_free(camera);
                if let Some(h) = held.as_mut()
                    && h.camera != Some(still_camera)
                {
                    h.camera = Some(still_camera);
                    h.boxes.clear();
                }
                lights
                    .iter()
                    .map(|&(slice, direction)| {
                        let before = held
                            .as_ref()
                            .and_then(|h| h.boxes.get(&slice).cloned())
                            .unwrap_or_default();
                        let (views, boxes) = views::sun_held(
                            direction,
                            camera,
                            *cascades,
                            (bounds_center, bounds_radius),
                            res,
                            &before,
                        );
                        if let Some(h) = held.as_mut() {
                            h.boxes.insert(slice, boxes);
                        }
                        SlicePlan {
                            slice,
                            views,
                            culled: false,
                        }
                    })
                    .collect()
            }
        };
        let device = &renderer.gpu.device;
        let mut all = vec![
            LayerView {
                view_projection: Mat4::ZERO,
                near: 0.0,
                far: 1.0,
                texel: 0.0,
                orthographic: false,
                split: 0.0,
            }
            .to_gpu();
            layers as usize
        ];
        let mut uniforms = vec![0u8; (layers as usize) * VIEW_STRIDE as usize];
        for plan in &plans {
            for (k, v) in plan.views.iter().enumerate() {
                let layer = (plan.slice * per) as usize + k;
                all[layer] = v.to_gpu();
                let at = layer * VIEW_STRIDE as usize;
                uniforms[at..at + 64]
                    .copy_from_slice(bytemuck::cast_slice(&v.view_projection.to_cols_array()));
            }
        }
        let views_buffer = renderer.kept_init(
            owner,
            "shadow views",
            bytemuck::cast_slice(&all),
            wgpu::BufferUsages::STORAGE,
        );
        let view_uniforms = renderer.kept_init(
            owner,
            "shadow view uniforms",
            &uniforms,
            wgpu::BufferUsages::UNIFORM,
        );
        let (radius, light_size, samples, bleeding) = match settings.filter {
            ShadowFilter::Raw => (0.0, 0.0, 0.0, 0.0),
            ShadowFilter::Pcf { kernel } => ((kernel.clamp(1, 9) / 2) as f32, 0.0, 0.0, 0.0),
            ShadowFilter::Pcss {
                light_size,
                samples,
            } => (
                0.0,
                finite_non_negative(light_size),
                samples.clamp(1, 64) as f32,
                0.0,
            ),
            // The blur is how far VSM's filter reaches, for the slope bias.
            ShadowFilter::Vsm { bleeding, blur } => (
                blur.min(8) as f32,
                0.0,
                0.0,
                finite_non_negative(bleeding).min(0.99),
            ),
        };
        let params = GpuShadowParams {
            bias: [
                finite_non_negative(settings.depth_bias),
                finite_non_negative(settings.normal_bias),
                radius,
                light_size,
            ],
            filter: [samples, bleeding, res as f32, per as f32],
        };
        let params = renderer.kept_init(
            owner,
            "shadow params",
            bytemuck::bytes_of(&params),
            wgpu::BufferUsages::UNIFORM,
        );
        let compute = compute_rasterizes(
            settings.raster,
            renderer.gpu.adapter_class(),
            res,
            device.limits().max_storage_buffer_binding_size,
        );
        let layer_cameras: Vec<crate::camera::GpuCamera> = if compute {
            (0..layers)
                .map(|layer| {
                    CameraInput {
                        view: Mat4::IDENTITY,
                        projection: all_views(&plans, per, layer),
                    }
                    .to_gpu(None, (res, res))
                })
                .collect()
        } else {
            Vec::new()
        };
        let together = compute && layers::shadow_layers(renderer) == ShadowLayers::Together;
        // Together, the layers' cameras go in one array as the pass draws
        // (raster_layered.rs): no uniform a layer.
        let cameras = (compute && !together).then(|| {
            layer_cameras
                .iter()
                .enumerate()
                .map(|(layer, camera)| {
                    renderer.kept_init_at(
                        owner,
                        "shadow layer camera",
                        layer as u32,
                        bytemuck::bytes_of(camera),
                        wgpu::BufferUsages::UNIFORM,
                    )
                })
                .collect()
        });
        // A node's maps outlive its recipes; a recipe without a node keeps its own.
        let store = match owner {
            Some(node) => renderer.state::<ShadowStore>(u64::from(node)),
            None => Arc::new(ShadowStore::default()),
        };
        let sets = match store.split(&casters) {
            Some((still, moving)) => Sets::Split {
                still: match owner {
                    Some(node) => renderer.state::<StillSets>(u64::from(node)),
                    None => Arc::default(),
                }
                .get(still, compute, |still| {
                    CasterSet::new(renderer, owner, SetKind::Still, still, compute)
                }),
                moving: CasterSet::new(renderer, owner, SetKind::Moving, moving, compute),
            },
            None => Sets::One(CasterSet::new(
                renderer,
                owner,
                SetKind::All,
                casters.clone(),
                compute,
            )),
        };
        let kind = match lights {
            ShadowLights::Spot(_) => crate::light_kind::LightKind::Spot,
            ShadowLights::Point(_) => crate::light_kind::LightKind::Point,
            ShadowLights::Sun { .. } => crate::light_kind::LightKind::Sun,
        };
        let blur = match settings.filter {
            ShadowFilter::Vsm { blur, .. } => blur.min(8),
            _ => 0,
        };
        let layer_info = (0..layers)
            .map(|layer| {
                renderer.kept_init_at(
                    owner,
                    "shadow layer",
                    layer,
                    bytemuck::cast_slice(&[layer, blur, 0, 0, 0, 0, res, res]),
                    wgpu::BufferUsages::UNIFORM,
                )
            })
            .collect();
        Ok(Arc::new(ShadowMaps {
            id,
            kind,
            owner,
            settings,
            per_slice: per,
            light_key: lights.content_key(),
            plans,
            views: views_buffer,
            params,
            view_uniforms,
            casters,
            sets,
            cameras,
            layer_cameras,
            together,
            store,
            layers,
            layer_info,
            token: format!("shadows{id}/maps"),
            depth_token: format!("shadows{id}/depth"),
            bounds_made,
        }))
    }

    /// The frame-graph name a reader lists to run after the maps are rendered.
    pub fn token(&self) -> &str {
        &self.token
    }

    pub fn filter(&self) -> ShadowFilter {
        self.settings.filter
    }

    /// How many slices the maps hold (a slice per casting light's index).
    pub fn slice_count(&self) -> u32 {
        self.layers / self.per_slice.max(1)
    }

    /// What the maps show, as far as the camera does not decide it: the
    /// lights as given, the settings and every caster's instances and
    /// draws (an environment probe's re-render key: a change of light or a
    /// moved caster changes its shadows, a moved camera only the cascades).
    pub fn hash_content(&self, h: &mut impl std::hash::Hasher) {
        use std::hash::Hash;
        self.light_key.hash(h);
        let s = &self.settings;
        (
            s.resolution,
            s.depth_bias.to_bits(),
            s.normal_bias.to_bits(),
        )
            .hash(h);
        let (instances, draws, ranges) = crate::gbuffer::pack_instances(&self.casters);
        for i in &instances {
            for c in i.model.iter().flatten() {
                c.to_bits().hash(h);
            }
            i.info.hash(h);
        }
        for d in &draws {
            (d.index_count, d.first_instance, d.instance_count).hash(h);
        }
        ranges.hash(h);
    }

    /// The layer views a reader binds (slice-major).
    pub(crate) fn views(&self) -> &wgpu::Buffer {
        &self.views
    }

    pub(crate) fn params(&self) -> &wgpu::Buffer {
        &self.params
    }

    /// The stored depth array (and VSM moments), once the pass has run.
    pub(crate) fn textures(&self) -> Option<(wgpu::Texture, Option<wgpu::Texture>)> {
        let guard = self.store.maps.lock().unwrap_or_else(|e| e.into_inner());
        guard.as_ref().map(|m| (m.depth.clone(), m.moments.clone()))
    }

    /// Every layer of the depth maps as the last frame left them
    /// (conventional depth in R, 1 where nothing was drawn), slice-major; None
    /// before a frame rendered them. For tests and tools comparing rasterizers.
    pub fn read_depth(
        &self,
        gpu: &crate::context::GpuContext,
    ) -> Result<Option<Vec<crate::readback::ImageF32>>, crate::error::RenderError> {
        let Some((depth, _)) = self.textures() else {
            return Ok(None);
        };
        (0..depth.depth_or_array_layers())
            .map(|layer| crate::readback::read_texture_layer(gpu, &depth, layer, 0))
            .collect::<Result<Vec<_>, _>>()
            .map(Some)
    }

    /// Whether the compute rasterizer draws these maps (else the raster hardware).
    pub fn compute_raster(&self) -> bool {
        !self.layer_cameras.is_empty()
    }

    fn label(&self, what: impl Into<std::borrow::Cow<'static, str>>) -> PassName {
        PassName::new("ShadowMap").step(what)
    }
}

/// Whether the compute rasterizer draws maps of `resolution` texels a side
/// (the raster hardware otherwise). It writes 32-bit depth words, so any
/// adapter can, as long as a layer's words fit one storage binding.
///
/// `Auto` follows the adapter (adapter_class.rs). On a GPU, compute at every
/// resolution: measured on the H200 (docs/benchmarks.md, "Session 16"),
/// compute ties the hardware at 1024 texels a side and wins at 2048 (0.60
/// against 1.45 ms for shadows.ron's three cascades, 0.28 against 0.73 for
/// emeshe-heavy.ron's spots), and the hardware falls off a cliff where many
/// casters meet several cascades (emeshe-heavy.ron's VSM sun: 6.2 ms at any
/// resolution against 0.5-0.9 in compute); it wins only small maps of few
/// casters, by at most 0.17 ms (shadows.ron's sun at 256 and 512). On a CPU
/// adapter the hardware:
/// lavapipe drew patches/shadows.ron's three 512 cascades in 13-141 ms
/// with its raster pipeline and 1,338-1,417 ms with the compute one
/// (docs/shadows.md, "Two rasterizers"): a CPU runs the compute raster's
/// workgroups one after another, and a map's few big triangles (a floor)
/// are its worst case.
pub fn compute_rasterizes(
    choice: RasterChoice,
    class: crate::adapter_class::AdapterClass,
    resolution: u32,
    max_binding: u64,
) -> bool {
    let fits = u64::from(resolution) * u64::from(resolution) * 4 <= max_binding;
    fits && match choice {
        RasterChoice::Compute => true,
        RasterChoice::Hardware => false,
        RasterChoice::Auto => class == crate::adapter_class::AdapterClass::Gpu,
    }
}

/// The view-projection of `layer` (identity-free zero for a layer no light uses).
fn all_views(plans: &[SlicePlan], per: u32, layer: u32) -> Mat4 {
    plans
        .iter()
        .find(|p| p.slice == layer / per)
        .and_then(|p| p.views.get((layer % per) as usize))
        .map_or(Mat4::ZERO, |v| v.view_projection)
}

/// One layer of an array texture, as a 2D view.
/// One layer of the maps as a 2D view, made once and kept while frames use
/// it: a new view each frame would make the passes' bind groups anew.
fn layer_view(
    cx: &crate::frame_graph::PassContext<'_>,
    texture: &wgpu::Texture,
    layer: u32,
) -> wgpu::TextureView {
    cx.view_of(texture, crate::texture_pool::ViewSpec::layer(layer))
}

fn finite_non_negative(v: f32) -> f32 {
    if v.is_finite() { v.max(0.0) } else { 0.0 }
}

/// A sun node's cascade boxes as last placed, per slice (views::sun_held),
/// and the camera they were placed for, its jitter left out.
#[derive(Default)]
struct HeldCascades(std::sync::Mutex<Held>);

#[derive(Default)]
struct Held {
    camera: Option<[f32; 32]>,
    boxes: std::collections::HashMap<u32, Vec<Option<views::CascadeBox>>>,
}

/// `camera`'s view and projection with the terms a sub-pixel jitter moves
/// (`camera::jittered`: the projection's NDC offset, which a symmetric
/// frustum has at 0) left out: two frames of a still camera give the same.
fn jitter_free(camera: &CameraInput) -> [f32; 32] {
    let mut key = [0.0; 32];
    key[..16].copy_from_slice(&camera.view.to_cols_array());
    let mut projection = camera.projection.to_cols_array();
    // Column 2's x and y, and column 3's: where T(ndc) * P adds ndc times
    // the projection's last row (-1 at [2][3] for a perspective, 1 at [3][3]
    // for an orthographic projection).
    for i in [8, 9, 12, 13] {
        projection[i] = 0.0;
    }
    key[16..].copy_from_slice(&projection);
    key
}

/// A sphere around every caster (their meshes' boxes, transformed).
fn caster_bounds(layers: &[Arc<Layer>]) -> (Vec3, f32) {
    sphere_around(layers.iter().map(|l| layer_box(l)))
}

/// The sphere around boxes (min, max); a unit sphere at the origin around none.
fn sphere_around(boxes: impl Iterator<Item = Option<(Vec3, Vec3)>>) -> (Vec3, f32) {
    let (min, max) = boxes.flatten().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(min, max), (lo, hi)| (min.min(lo), max.max(hi)),
    );
    if min.x > max.x {
        return (Vec3::ZERO, 1.0);
    }
    ((min + max) * 0.5, (max - min).length() * 0.5)
}

/// The box around a layer's instances (their meshes' boxes, transformed;
/// corners that are not finite left out), None if it has none.
fn layer_box(layer: &Layer) -> Option<(Vec3, Vec3)> {
    let mut min = Vec3::splat(f32::INFINITY);
    let mut max = Vec3::splat(f32::NEG_INFINITY);
    for batch in &layer.batches {
        let b = batch.mesh.bounds;
        for instance in &batch.instances {
            for i in 0..8 {
                let corner = Vec3::new(
                    if i & 1 == 0 { b.min.x } else { b.max.x },
                    if i & 2 == 0 { b.min.y } else { b.max.y },
                    if i & 4 == 0 { b.min.z } else { b.max.z },
                );
                let p = instance.transform.transform_point3(corner);
                if p.is_finite() {
                    min = min.min(p);
                    max = max.max(p);
                }
            }
        }
    }
    (min.x <= max.x).then_some((min, max))
}

impl Recipe for ShadowMaps {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        for (name, n) in [
            ("caster bounds computed", self.bounds_made.0),
            ("caster bounds kept", self.bounds_made.1),
        ] {
            if n > 0 {
                fg.count(name, n);
            }
        }
        // Their pipelines made on threads on a first frame (frame_graph/gather.rs).
        self.announce(renderer, fg);
        // The maps live in the store; this token orders their pass before readers.
        let token = TextureDesc::token();
        // VSM: the depth pass, then the moments pass, each timed on its own.
        let vsm = matches!(self.settings.filter, ShadowFilter::Vsm { .. });
        let mut pass = fg.pass(self.label("render"), self.owner);
        pass.write(if vsm { &self.depth_token } else { &self.token }, token);
        pass.run(move |cx| self.render(cx, renderer));
        if vsm {
            let mut pass = fg.pass(self.label("moments"), self.owner);
            pass.read(&self.depth_token);
            pass.write(&self.token, token);
            pass.run(move |cx| self.moments_pass(cx));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::adapter_class::AdapterClass::{Cpu, Gpu};

    #[test]
    fn auto_rasterizes_in_compute_on_a_gpu_and_never_on_a_cpu_adapter() {
        let binding = 128 << 20;
        for (choice, class, res, expected) in [
            (RasterChoice::Auto, Gpu, 512, true),
            (RasterChoice::Auto, Gpu, 1024, true),
            (RasterChoice::Auto, Gpu, 2048, true),
            (RasterChoice::Auto, Cpu, 256, false),
            (RasterChoice::Auto, Cpu, 4096, false),
            (RasterChoice::Compute, Cpu, 4096, true),
            (RasterChoice::Compute, Gpu, 4096, true),
            (RasterChoice::Hardware, Gpu, 512, false),
        ] {
            assert_eq!(
                compute_rasterizes(choice, class, res, binding),
                expected,
                "{choice:?} {class:?} {res}"
            );
        }
        // 4 bytes a texel must fit one storage binding, whatever was asked.
        assert!(!compute_rasterizes(
            RasterChoice::Compute,
            Gpu,
            8192,
            1 << 20
        ));
    }
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_shadow_params_matches_shadowparams_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuShadowParams,
            "lighting/shadow_sampling.wgsl",
            ["SHADOWS"],
            "ShadowParams",
            [bias, filter]
        );
    }
}
