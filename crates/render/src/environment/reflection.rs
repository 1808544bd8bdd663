//! `Reflection`: image-based light from an [`Environment`] over the
//! G-buffer (shaders/environment/reflection.wgsl): the prefiltered
//! environment along each pixel's reflected (or refracted) direction at its
//! roughness, times the split-sum factor, and the diffuse irradiance.
//!
//! Two passes, so each runs only when read: `specular` (only pixels whose
//! material has the Reflection feature) and `diffuse` (every surface: the
//! environment's diffuse light does not depend on reflecting). When no
//! material of the world has the Reflection feature, the specular pass
//! only clears its output ("reflection skipped" in the frame report), and
//! the environment is built only if the diffuse light is read.
//!
//! A world with a Clearcoat material (CLEARCOAT) gives coated pixels the
//! coat's own reflection of the environment (its normal, its roughness, f0
//! 0.04) over the base's, dimmed by 1 - factor x F(N.V) as CookTorrance
//! dims the base under each light; the diffuse light under a coat is
//! dimmed by the same factor. A world with an anisotropic material
//! (ANISOTROPY, the G-buffer's anisotropy target) reflects its pixels about
//! the extension's bent normal.

use std::sync::Arc;

use super::environment_map::Environment;
use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, Tex, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::material::{
    FEATURE_CLEARCOAT, FEATURE_COOK_TORRANCE, FEATURE_IRIDESCENCE, FEATURE_REFLECTION,
    FEATURE_SHEEN, MaterialTextures, MaterialWorld,
};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::Permutation;
use crate::texture_pool::ViewSpec;

pub use super::reflection_key::ReflectionKey;
/// Statistic: Reflection passes that wrote the diffuse light and the
/// specular in one dispatch (the frame read both).
pub const BOTH_IN_ONE_PASS: &str = "reflection diffuse and specular in one pass";

/// What the specular output shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReflectionMode {
    /// The environment mirrored about the normal, times F0 A + B.
    Reflect,
    /// The environment seen through the surface along the refracted
    /// direction (index of refraction `ior` inside, air outside), times
    /// 1 - (F0 A + B); total internal reflection reflects instead.
    Refract { ior: f32 },
}

impl ReflectionMode {
    /// (mode, ior) for the shader: a bad IOR (NaN, below 1) is glass's 1.5 or 1.
    fn params(self) -> (u32, f32) {
        match self {
            ReflectionMode::Reflect => (0, 1.0),
            ReflectionMode::Refract { ior } => {
                let ior = if ior.is_finite() {
                    ior.clamp(1.0, 4.0)
                } else {
                    1.5
                };
                (1, ior)
            }
        }
    }
}

pub struct Reflection {
    id: u64,
    owner: Option<u32>,
    gbuffer: Arc<GBuffer>,
    materials: Arc<MaterialWorld>,
    environment: Arc<Environment>,
    pub mode: ReflectionMode,
    params: wgpu::Buffer,
    /// A probe's influence volume, when it has one: each reflected ray is
    /// corrected for parallax against it (the PARALLAX permutation).
    volume: Option<wgpu::Buffer>,
    /// Reflected (or refracted) radiance, additive.
    pub specular: String,
    /// Irradiance / pi from the environment: multiply by albedo to light a surface.
    pub diffuse: String,
}

impl Reflection {
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        materials: Arc<MaterialWorld>,
        environment: Arc<Environment>,
        mode: ReflectionMode,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let (mode_id, ior) = mode.params();
        let levels = environment.quality.levels();
        let params = renderer.kept_init(
            owner,
            "reflection params",
            bytemuck::cast_slice(&[mode_id, levels, ior.to_bits(), 0]),
            wgpu::BufferUsages::UNIFORM,
        );
        let volume = environment.parallax().map(|v| {
            renderer.kept_init(
                owner,
                "reflection probe volume",
                bytemuck::bytes_of(&v),
                wgpu::BufferUsages::UNIFORM,
            )
        });
        Arc::new(Reflection {
            id,
            owner,
            gbuffer,
            materials,
            environment,
            mode,
            params,
            volume,
            specular: format!("reflection{id}/specular"),
            diffuse: format!("reflection{id}/diffuse"),
        })
    }

    pub fn specular_texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.specular.clone(),
        }
    }

    pub fn diffuse_texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.diffuse.clone(),
        }
    }

    pub fn gbuffer(&self) -> &Arc<GBuffer> {
        &self.gbuffer
    }

    pub fn materials(&self) -> &Arc<MaterialWorld> {
        &self.materials
    }

    pub fn environment(&self) -> &Arc<Environment> {
        &self.environment
    }

    /// Whether some material reflects: otherwise there is nothing to compute.
    pub fn active(&self) -> bool {
        self.materials.any_has(FEATURE_REFLECTION)
    }

    fn textured(&self) -> bool {
        self.materials.textured(1 << FEATURE_COOK_TORRANCE)
    }

    fn key(&self) -> ReflectionKey {
        ReflectionKey {
            material_textures: self.textured(),
            surface_target: self.gbuffer.targets.surface.is_some(),
            parallax: self.volume.is_some(),
            // Only a world with a coat compiles the coat's lobe.
            clearcoat: self.materials.any_has(FEATURE_CLEARCOAT),
            // Only a reflective world's specular reads the anisotropy target.
            anisotropy: self.active() && self.gbuffer.targets.anisotropy.is_some(),
            iridescence: self.materials.any_has(FEATURE_IRIDESCENCE),
            // Only a reflective world's passes read colours and materials.
            sheen: self.active() && self.materials.any_has(FEATURE_SHEEN),
        }
    }

    fn clear(&self, cx: &mut PassContext<'_>, specular: Tex) -> Result<(), RenderError> {
        cx.count("reflection skipped", 1);
        let b = Bindings::new()
            .buffer("camera", self.gbuffer.camera_buffer())
            .texture("out_specular", specular);
        self.dispatch(cx, "clear", "reflection clear", b)
    }

    /// `entry` over the G-buffer.
    fn dispatch(
        &self,
        cx: &mut PassContext<'_>,
        entry: &'static str,
        label: &str,
        bindings: Bindings<'_>,
    ) -> Result<(), RenderError> {
        let (w, h) = self.gbuffer.pixel_size(cx.output_size);
        cx.dispatch_shader(
            label,
            &self.key().key(),
            entry,
            bindings,
            (w.div_ceil(8), h.div_ceil(8), 1),
        )
    }

    /// The diffuse light, the specular, or both in one dispatch.
    fn run(
        &self,
        cx: &mut PassContext<'_>,
        outputs: Outputs,
        io: &ReflectionIo,
    ) -> Result<(), RenderError> {
        let specular = outputs != Outputs::Diffuse;
        if specular {
            cx.count("reflection shaded", 1);
        }
        if outputs == Outputs::Both {
            cx.count(BOTH_IN_ONE_PASS, 1);
        }
        let maps = self.environment.maps_for("reflection")?;
        // Cached views: new ones each frame would make new bind groups.
        let mut b = Bindings::new()
            .buffer("camera", self.gbuffer.camera_buffer())
            .buffer("params", &self.params)
            .texture_opt("color", io.color)
            .texture("normals", io.normals)
            .texture("depth", io.depth)
            .view(
                "prefiltered",
                cx.view_of(&maps.prefiltered, ViewSpec::cube()),
            )
            .view("irradiance", cx.view_of(&maps.irradiance, ViewSpec::cube()))
            .view("lut", cx.view_of(&maps.lut, ViewSpec::default()))
            .sampler_object("cube_sampler", maps.sampler.clone());
        // Only the outputs this pass writes (a diffuse-only pass has no
        // specular); roughness and metallic where the G-buffer resolved them
        // (only the specular reads them), and the materials.
        if outputs != Outputs::Specular {
            b = b.texture("out_diffuse", io.diffuse);
        }
        if specular {
            b = b
                .texture_opt("out_specular", io.specular)
                .texture_opt("anisotropy_target", io.anisotropy)
                .buffer_opt("volume", self.volume.as_ref());
        }
        // The diffuse entry reads the materials too where a sheen or a coat
        // dims it (a coat's factor where the surface target resolved its map).
        let key = self.key();
        if specular || key.sheen || key.clearcoat {
            b = b
                .texture_opt("surface_target", io.surface)
                .extend(self.materials.bindings(io.material_textures));
            // SHEEN and IRIDESCENCE read the sheen and film target, or a
            // stand-in of factors only where the G-buffer has none.
            if key.sheen || key.iridescence {
                b = match io.sheen_film {
                    Some(t) => b.texture("sheen_film_target", t),
                    None => b.view("sheen_film_target", self.materials.sheen_film_stand_in()),
                };
            }
        }
        match outputs {
            Outputs::Both => self.dispatch(cx, "both", "reflection", b),
            Outputs::Specular => self.dispatch(cx, "main", "reflection", b),
            Outputs::Diffuse => self.dispatch(cx, "diffuse", "reflection diffuse", b),
        }
    }
}

/// What a Reflection pass declared: the diffuse pass of a world that does
/// not reflect reads no colour and no surface (unless a coat dims it).
struct ReflectionIo {
    color: Option<Tex>,
    normals: Tex,
    depth: Tex,
    surface: Option<Tex>,
    /// The G-buffer's sheen and film target, where it has one.
    sheen_film: Option<Tex>,
    diffuse: Tex,
    /// Not in the diffuse pass of a world that does not reflect.
    specular: Option<Tex>,
    material_textures: Option<MaterialTextures>,
    /// The G-buffer's anisotropy target, read where ANISOTROPY is compiled.
    anisotropy: Option<Tex>,
}

/// Which of a Reflection's outputs a pass writes.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Outputs {
    Diffuse,
    Specular,
    Both,
}

impl Recipe for Reflection {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.gbuffer.declare(renderer, fg);
        let hdr = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        let g = &self.gbuffer.targets;
        self.environment.declare(renderer, fg);
        if !self.active() {
            // A coated world dims the diffuse light under each coat: the
            // pass reads the pixels' materials (and their resolved coat).
            let coated = self.key().clearcoat;
            let mut pass = fg.pass(PassName::new("Reflection").step("diffuse"), self.owner);
            pass.read(self.environment.token());
            let (normals, depth) = (pass.read(&g.normals), pass.read(&g.depth));
            let color = coated.then(|| pass.read(&g.color));
            let surface = if coated {
                pass.read_opt(g.surface.as_deref())
            } else {
                None
            };
            let io = ReflectionIo {
                color,
                normals,
                depth,
                surface,
                sheen_film: None,
                diffuse: pass.write(&self.diffuse, hdr),
                specular: None,
                material_textures: None,
                anisotropy: None,
            };
            pass.run(move |cx| self.run(cx, Outputs::Diffuse, &io));
            let mut pass = fg.pass(
                PassName::new("Reflection").step("none reflective"),
                self.owner,
            );
            let specular = pass.write(&self.specular, hdr);
            pass.run(move |cx| self.clear(cx, specular));
            return;
        }
        self.materials
            .declare_upstream(renderer, fg, self.textured());
        // One pass for both outputs: it runs when either is read, and
        // writes only what the frame reads.
        let mut pass = fg.pass(
            PassName::new("Reflection").step("diffuse and specular"),
            self.owner,
        );
        pass.read(self.environment.token());
        let io = ReflectionIo {
            color: Some(pass.read(&g.color)),
            normals: pass.read(&g.normals),
            depth: pass.read(&g.depth),
            surface: pass.read_opt(g.surface.as_deref()),
            sheen_film: {
                let key = self.key();
                if key.sheen || key.iridescence {
                    pass.read_opt(g.sheen_film.as_deref())
                } else {
                    None
                }
            },
            material_textures: self.materials.read_textures(
                &mut pass,
                self.textured(),
                g.surface_targets(),
            ),
            diffuse: pass.write(&self.diffuse, hdr),
            specular: Some(pass.write(&self.specular, hdr)),
            anisotropy: if self.key().anisotropy {
                pass.read_opt(g.anisotropy.as_deref())
            } else {
                None
            },
        };
        pass.run(move |cx| {
            let specular = io.specular.is_some_and(|s| cx.is_read(s));
            let outputs = match (cx.is_read(io.diffuse), specular) {
                (true, true) => Outputs::Both,
                (true, false) => Outputs::Diffuse,
                _ => Outputs::Specular,
            };
            self.run(cx, outputs, &io)
        });
        // Its pipeline, by the outputs the frame reads, as `run` picks it
        // (frame_graph/gather.rs).
        fg.will_dispatch_by_reads(
            PassName::new("Reflection").step("diffuse and specular"),
            self.owner,
            &self.key().key(),
            &[self.diffuse.as_str(), self.specular.as_str()],
            |read| match read {
                [true, true] => "both",
                [true, false] => "diffuse",
                _ => "main",
            },
        );
    }
}
