//! Building an environment's maps (shaders/environment/prefilter.wgsl), in
//! the open compute pass: the base cube from the source, its mip chain,
//! the prefiltered roughness levels, the irradiance cube and the split-sum
//! table. Cost: cube_size^2 * 6 * (4/3) texels for the base, and
//! samples per texel for the rough levels (each a quarter of the last).

use wgpu::util::DeviceExt;

use super::probe::ProbeScene;
use super::probe::faces::PackedProbe;
use super::source::{
    EnvironmentMaps, EnvironmentQuality, EnvironmentSource, EquirectImage, IRRADIANCE_SIZE,
    LUT_SAMPLES, LUT_SIZE,
};
use crate::error::RenderError;
use crate::frame_graph::{Bindings, PassContext};
use crate::renderer::Renderer;
use crate::shaders::{Permutation, Sampling};

pub use super::prefilter_key::PrefilterKey;

/// Matches `Params` in shaders/environment/prefilter.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    size: u32,
    samples: u32,
    base_size: u32,
    base_mips: u32,
    roughness: f32,
    pad: [f32; 3],
}

fn cube(device: &wgpu::Device, label: &str, size: u32, mips: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: 6,
        },
        mip_level_count: mips,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba16Float,
        // Render attachment: a probe draws its faces into the base cube's level 0.
        usage: wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// One mip of a cube as a 2D array (to write it, or to load from it).
fn faces(texture: &wgpu::Texture, mip: u32) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        base_mip_level: mip,
        mip_level_count: Some(1),
        ..Default::default()
    })
}

/// The equirect image as half floats (clamped to 0..=65000, NaN as 0): a
/// filterable format, so the base cube samples it bilinearly.
fn upload_equirect(cx: &PassContext<'_>, image: &EquirectImage) -> wgpu::Texture {
    let data: Vec<u8> = image
        .pixels
        .iter()
        .flat_map(|p| p.map(|c| half::f16::from_f32(EquirectImage::sanitized(c)).to_bits()))
        .flat_map(u16::to_le_bytes)
        .collect();
    cx.gpu.device.create_texture_with_data(
        &cx.gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("environment equirect"),
            size: wgpu::Extent3d {
                width: image.width,
                height: image.height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &data,
    )
}

/// Record every step and return the maps (valid once the frame is submitted).
/// One dispatch of the prefilter: its pipeline, bind groups and workgroups.
type Step = (
    wgpu::ComputePipeline,
    crate::frame_graph::BindGroups,
    (u32, u32, u32),
);

/// What a probe's faces are drawn from: its scene, packed, and each layer's
/// Color Texture and Normal Map as the frame graph handed them to the pass.
pub(crate) type ProbeFaces<'p> = (
    &'p Renderer,
    &'p ProbeScene,
    &'p PackedProbe,
    &'p super::probe::faces::ProbeTextures,
);

pub(crate) fn build(
    cx: &mut PassContext<'_>,
    source: &EnvironmentSource,
    quality: EnvironmentQuality,
    key: u64,
    probe: Option<ProbeFaces<'_>>,
) -> Result<EnvironmentMaps, RenderError> {
    let device = cx.gpu.device.clone();
    let n = quality.cube_size;
    let base_mips = quality.base_mips();
    let levels = quality.levels();
    let base = cube(&device, "environment base", n, base_mips);
    let prefiltered = cube(&device, "environment prefiltered", n, levels);
    let irradiance = cube(&device, "environment irradiance", IRRADIANCE_SIZE, 1);
    let lut = split_sum_texture(&device, wgpu::TextureUsages::COPY_SRC);
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("environment trilinear"),
        address_mode_u: wgpu::AddressMode::ClampToEdge,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        address_mode_w: wgpu::AddressMode::ClampToEdge,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    });
    let params = |size: u32, samples: u32, roughness: f32| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("environment params"),
            contents: bytemuck::bytes_of(&Params {
                size,
                samples,
                base_size: n,
                base_mips,
                roughness,
                pad: [0.0; 3],
            }),
            usage: wgpu::BufferUsages::UNIFORM,
        })
    };
    let key_shader = PrefilterKey.key();
    // Recorded in order into one pass.
    let mut steps: Vec<Step> = Vec::new();
    let mut step = |cx: &mut PassContext<'_>,
                    entry: &'static str,
                    bindings: Bindings<'_>,
                    size: u32,
                    layers: u32|
     -> Result<(), RenderError> {
        let pipeline = cx.compute_pipeline(&key_shader, entry)?;
        let groups = cx.bind_groups(&key_shader, entry, &pipeline, bindings)?;
        let workgroups = size.div_ceil(8);
        steps.push((pipeline, groups, (workgroups, workgroups, layers)));
        Ok(())
    };

    // The base cube's level 0.
    let out0 = faces(&base, 0);
    match source {
        EnvironmentSource::Equirect(image) => {
            let equirect = upload_equirect(cx, image);
            let view = equirect.create_view(&Default::default());
            // Enough samples per side that every image texel under a cube texel is seen (at most 8).
            let per_side = (image.width as f32 / (4.0 * n as f32))
                .ceil()
                .clamp(1.0, 8.0) as u32;
            let p = params(n, per_side, 0.0);
            step(
                cx,
                "from_equirect",
                Bindings::new()
                    .buffer("params", &p)
                    .view("equirect", view)
                    .sampler("linear_sampler", Sampling::LinearRepeat)
                    .view("out_faces", out0.clone()),
                n,
                6,
            )?;
        }
        EnvironmentSource::Probe(_) => {
            let Some((renderer, scene, packed, textures)) = probe else {
                return Err(RenderError::Pass {
                    pass: "EnvironmentProbe".to_owned(),
                    message: "a probe's layers were not packed".to_owned(),
                });
            };
            // Render passes now, before the compute pass the steps go into.
            super::probe::faces::render(cx, renderer, scene, packed, textures, &base)?;
        }
        EnvironmentSource::Sky(_) => {
            let sky = source.gpu_sky().unwrap_or_default();
            let sky = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("environment sky"),
                contents: bytemuck::bytes_of(&sky),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let p = params(n, 1, 0.0);
            step(
                cx,
                "from_sky",
                Bindings::new()
                    .buffer("params", &p)
                    .view("out_faces", out0.clone())
                    .buffer("sky", &sky),
                n,
                6,
            )?;
        }
    }
    // Its mip chain.
    for mip in 1..base_mips {
        let size = (n >> mip).max(1);
        let p = params(size, 1, 0.0);
        let (src, dst) = (faces(&base, mip - 1), faces(&base, mip));
        step(
            cx,
            "downsample",
            Bindings::new()
                .buffer("params", &p)
                .view("out_faces", dst)
                .view("source_faces", src),
            size,
            6,
        )?;
    }
    // The roughness levels.
    let base_cube = EnvironmentMaps::cube_view(&base);
    for level in 0..levels {
        let size = (n >> level).max(1);
        let roughness = if levels > 1 {
            level as f32 / (levels - 1) as f32
        } else {
            0.0
        };
        let p = params(size, quality.samples, roughness);
        let dst = faces(&prefiltered, level);
        step(
            cx,
            "prefilter",
            Bindings::new()
                .buffer("params", &p)
                .sampler_object("linear_sampler", sampler.clone())
                .view("out_faces", dst)
                .view("base", base_cube.clone()),
            size,
            6,
        )?;
    }
    // Irradiance from the base mip of (at most) the irradiance cube's size.
    let source_mip = n.ilog2().saturating_sub(IRRADIANCE_SIZE.ilog2());
    let p = params(IRRADIANCE_SIZE, 1, 0.0);
    let (src, dst) = (faces(&base, source_mip), faces(&irradiance, 0));
    step(
        cx,
        "irradiance",
        Bindings::new()
            .buffer("params", &p)
            .view("out_faces", dst)
            .view("source_faces", src),
        IRRADIANCE_SIZE,
        6,
    )?;
    let p = params(LUT_SIZE, LUT_SAMPLES, 0.0);
    let lut_view = lut.create_view(&Default::default());
    step(
        cx,
        "brdf_lut",
        Bindings::new()
            .buffer("params", &p)
            .view("out_lut", lut_view),
        LUT_SIZE,
        1,
    )?;

    let pass = cx.compute_pass("environment prefilter");
    for (pipeline, groups, (x, y, z)) in &steps {
        pass.set_pipeline(pipeline);
        for (i, group) in groups.iter().enumerate() {
            pass.set_bind_group(i as u32, group, &[]);
        }
        pass.dispatch_workgroups(*x, *y, *z);
    }
    Ok(EnvironmentMaps {
        key,
        quality,
        base,
        prefiltered,
        irradiance,
        lut,
        sampler,
    })
}

/// The split-sum table alone, for passes without an environment (SSR):
/// made once per renderer and kept.
#[derive(Default)]
pub struct SplitSumStore(std::sync::Mutex<Option<wgpu::Texture>>);

/// The table from `store`, recorded into this pass the first time.
pub(crate) fn split_sum_table(
    cx: &mut PassContext<'_>,
    store: &SplitSumStore,
) -> Result<wgpu::Texture, RenderError> {
    let mut guard = store.0.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(t) = guard.as_ref() {
        return Ok(t.clone());
    }
    let device = cx.gpu.device.clone();
    let lut = split_sum_texture(&device, wgpu::TextureUsages::empty());
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("split-sum params"),
        contents: bytemuck::bytes_of(&Params {
            size: LUT_SIZE,
            samples: LUT_SAMPLES,
            base_size: 1,
            base_mips: 1,
            roughness: 0.0,
            pad: [0.0; 3],
        }),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let groups = LUT_SIZE.div_ceil(8);
    cx.dispatch_shader(
        "split-sum table",
        &PrefilterKey.key(),
        "brdf_lut",
        Bindings::new()
            .buffer("params", &params)
            .view("out_lut", lut.create_view(&Default::default())),
        (groups, groups, 1),
    )?;
    *guard = Some(lut.clone());
    Ok(lut)
}

/// The split-sum table's texture (RG of F0 scale and bias, RGBA16F), written by compute and sampled, plus `extra` usages.
fn split_sum_texture(device: &wgpu::Device, extra: wgpu::TextureUsages) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("split-sum table"),
        size: wgpu::Extent3d {
            width: LUT_SIZE,
            height: LUT_SIZE,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba16Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING | extra,
        view_formats: &[],
    })
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn params_matches_params_in_the_shader() {
        crate::assert_wgsl_layout!(
            Params,
            crate::environment::prefilter_key::PrefilterKey,
            [],
            "Params",
            [size, samples, base_size, base_mips, roughness, pad]
        );
    }
}
