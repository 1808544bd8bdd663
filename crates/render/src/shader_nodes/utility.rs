//! The two small passes a shader node needs besides its own: filling a
//! target with its clear value, and copying a texture into a target (a
//! skipped pass passing its input on). One generated shader per format.

use std::hash::{Hash, Hasher};

use wgpu::util::DeviceExt;

use crate::error::RenderError;
use crate::frame_graph::{PassContext, Tex};

fn wgsl_format(format: wgpu::TextureFormat) -> &'static str {
    use wgpu::TextureFormat as F;
    match format {
        F::Rgba8Unorm => "rgba8unorm",
        F::Rgba32Float => "rgba32float",
        F::R32Float => "r32float",
        F::Rg32Float => "rg32float",
        _ => "rgba16float",
    }
}

fn source(format: wgpu::TextureFormat) -> String {
    format!(
        "@group(0) @binding(0) var dst: texture_storage_2d<{}, write>;
@group(0) @binding(1) var<uniform> value: vec4<f32>;
@group(0) @binding(2) var src: texture_2d<f32>;

@compute @workgroup_size(8, 8)
fn fill(@builtin(global_invocation_id) id: vec3<u32>) {{
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) {{ return; }}
    textureStore(dst, id.xy, value);
}}

@compute @workgroup_size(8, 8)
fn copy(@builtin(global_invocation_id) id: vec3<u32>) {{
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) {{ return; }}
    let s = textureDimensions(src);
    textureStore(dst, id.xy, textureLoad(src, id.xy * s / size, 0));
}}
",
        wgsl_format(format)
    )
}

/// Group 0 binding of variable `name` in the generated `module`: the
/// bind group follows the text above by name, numbered as naga parsed it.
fn binding(module: &naga::Module, name: &str) -> Result<u32, RenderError> {
    module
        .global_variables
        .iter()
        .find(|(_, v)| v.name.as_deref() == Some(name))
        .and_then(|(_, v)| v.binding.as_ref())
        .map(|b| b.binding)
        .ok_or_else(|| RenderError::Graph(format!("shader node utility: no variable `{name}`")))
}

/// `entry` writing `target` (variable `dst`), with one more resource: the
/// variable `resource.0` of the generated shader.
fn run(
    cx: &mut PassContext<'_>,
    entry: &str,
    target: Tex,
    format: wgpu::TextureFormat,
    resource: (&str, wgpu::BindingResource<'_>),
) -> Result<(), RenderError> {
    let text = source(format);
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    text.hash(&mut hasher);
    let device = cx.gpu.device.clone();
    let module = naga::front::wgsl::parse_str(&text)
        .map_err(|e| RenderError::Graph(format!("shader node utility: {}", e.message())))?;
    let (dst, other) = (binding(&module, "dst")?, binding(&module, resource.0)?);
    let pipeline = cx.shaders.external_compute_pipeline(
        &device,
        hasher.finish(),
        "shader node utility",
        move || module,
        entry,
    );
    let view = cx.view(target)?;
    let size = cx.size_of(target)?;
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(entry),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: dst,
                resource: wgpu::BindingResource::TextureView(&view),
            },
            wgpu::BindGroupEntry {
                binding: other,
                resource: resource.1,
            },
        ],
    });
    cx.dispatch(
        entry,
        &pipeline,
        &[&group],
        (size.0.div_ceil(8), size.1.div_ceil(8), 1),
    );
    Ok(())
}

/// Fill `target` with `color`.
pub fn fill(
    cx: &mut PassContext<'_>,
    target: Tex,
    format: wgpu::TextureFormat,
    color: [f32; 4],
) -> Result<(), RenderError> {
    let buffer = cx
        .gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("shader node clear"),
            contents: bytemuck::cast_slice(&color),
            usage: wgpu::BufferUsages::UNIFORM,
        });
    run(
        cx,
        "fill",
        target,
        format,
        ("value", buffer.as_entire_binding()),
    )
}

/// Copy `source` into `target` (nearest texel when the sizes differ).
pub fn copy(
    cx: &mut PassContext<'_>,
    source: Tex,
    target: Tex,
    format: wgpu::TextureFormat,
) -> Result<(), RenderError> {
    let view = cx.view(source)?;
    run(
        cx,
        "copy",
        target,
        format,
        ("src", wgpu::BindingResource::TextureView(&view)),
    )
}
