//! Rust structs uploaded to the GPU against their WGSL twins, as naga lays
//! them out: a struct whose size or member offsets drift from the shader's
//! is a test failure naming the member, not garbage on the screen.
//!
//! Every `#[repr(C)]` uniform or storage struct that mirrors a WGSL struct
//! has a test beside it:
//!
//! ```ignore
//! #[test]
//! fn gpu_layer_matches_the_shader() {
//!     crate::assert_wgsl_layout!(GpuLayer, ResolveKey, [], "Layer",
//!         [first_instance, end_instance, write_background, geometry_ids]);
//! }
//! ```
//!
//! The shader is an entry shader's typed key ([`Permutation`], with the
//! feature switches to compose it with) or, for a struct a library
//! declares, the library's path (`"lib/camera.wgsl"`): a struct below the
//! effects checks against its library, not an effect's shader above it.

#[cfg(doc)]
use super::Permutation;
use super::reflection::undecorated;
use super::{ShaderComposer, ShaderKey};

/// A Rust struct's size and its fields' offsets and sizes, in declaration order.
#[derive(Debug)]
pub struct HostLayout {
    pub name: &'static str,
    pub size: usize,
    pub fields: Vec<(&'static str, usize, usize)>,
}

/// The host layout of `$ty` (`bytemuck::Zeroable`) over the fields listed:
/// all of them, which [`check`] verifies (a `Pod` struct has no padding, so
/// its fields' sizes add up to its own).
#[macro_export]
macro_rules! host_layout {
    ($ty:ty, [$($field:ident),* $(,)?]) => {{
        let value: $ty = bytemuck::Zeroable::zeroed();
        $crate::shaders::layout::HostLayout {
            name: stringify!($ty),
            size: std::mem::size_of::<$ty>(),
            fields: vec![$((
                stringify!($field),
                std::mem::offset_of!($ty, $field),
                std::mem::size_of_val(&value.$field),
            )),*],
        }
    }};
}

/// Panics unless `$ty`'s fields sit where WGSL struct `$wgsl` of a shader
/// (with `$features`) puts its members, and the sizes agree. The shader is
/// a library's path (a literal) or an entry shader's typed key (a type).
#[macro_export]
macro_rules! assert_wgsl_layout {
    ($ty:ty, $library:literal, [$($feature:expr),* $(,)?], $wgsl:expr, [$($field:ident),* $(,)?]) => {
        let file = $crate::shaders::library($library)
            .unwrap_or_else(|| panic!("{} is no library of shaders::LIBRARIES", $library));
        $crate::assert_wgsl_layout!(@check $ty, file, [$($feature),*], $wgsl, [$($field),*]);
    };
    ($ty:ty, $key:ty, [$($feature:expr),* $(,)?], $wgsl:expr, [$($field:ident),* $(,)?]) => {
        let file = <$key as $crate::shaders::Permutation>::FILE;
        $crate::assert_wgsl_layout!(@check $ty, file, [$($feature),*], $wgsl, [$($field),*]);
    };
    (@check $ty:ty, $file:expr, [$($feature:expr),*], $wgsl:expr, [$($field:ident),*]) => {
        if let Err(e) = $crate::shaders::layout::check(
            &$crate::shaders::ShaderKey::new($file, [$($feature),*]),
            $wgsl,
            &$crate::host_layout!($ty, [$($field),*]),
        ) {
            panic!("{e}");
        }
    };
}

/// Compare `host` with struct `wgsl` of the composed permutation `key`:
/// the same size; every field starts where a member does, and a member of
/// the same name starts there too; every member lies within a field (a Rust
/// array may hold several members: `pad: [f32; 3]` for `pad0..pad2`).
pub fn check(key: &ShaderKey, wgsl: &str, host: &HostLayout) -> Result<(), String> {
    let mut composer = ShaderComposer::new().map_err(|e| e.to_string())?;
    let module = composer.compose(key).map_err(|e| e.to_string())?;
    check_module(&module, key.path(), wgsl, host)
}

/// [`check`] against a module composed already (`shader` names it in errors).
pub fn check_module(
    module: &naga::Module,
    shader: &str,
    wgsl: &str,
    host: &HostLayout,
) -> Result<(), String> {
    let label = format!("{} against `{wgsl}` of {shader}", host.name);
    let listed: usize = host.fields.iter().map(|(_, _, size)| size).sum();
    if listed != host.size {
        return Err(format!(
            "{label}: the fields listed cover {listed} of its {} bytes: list every field",
            host.size
        ));
    }
    let found = module.types.iter().find_map(|(_, ty)| {
        let name = ty.name.as_deref()?;
        match &ty.inner {
            naga::TypeInner::Struct { members, span } if undecorated(name) == wgsl => {
                Some((members, *span))
            }
            _ => None,
        }
    });
    let Some((members, span)) = found else {
        return Err(format!(
            "{shader}: no struct `{wgsl}` in the composed module"
        ));
    };
    if host.size != span as usize {
        return Err(format!(
            "{label}: {} bytes, the shader's struct {span}",
            host.size
        ));
    }
    let member_name = |m: &naga::StructMember| m.name.clone().unwrap_or_default();
    for (field, offset, _) in &host.fields {
        if let Some(m) = members.iter().find(|m| member_name(m) == *field)
            && m.offset as usize != *offset
        {
            return Err(format!(
                "{label}: `{field}` is at byte {offset}, the shader's `{field}` at {}",
                m.offset
            ));
        }
        if !members.iter().any(|m| m.offset as usize == *offset) {
            return Err(format!(
                "{label}: `{field}` at byte {offset} starts inside a member of the shader's"
            ));
        }
    }
    for m in members.iter() {
        let at = m.offset as usize;
        if !host
            .fields
            .iter()
            .any(|(_, offset, size)| (*offset..offset + size).contains(&at))
        {
            return Err(format!(
                "{label}: no field holds the shader's `{}` at byte {at}",
                member_name(m)
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use bytemuck::Zeroable;

    /// A struct as `gbuffer/resolve.wgsl` declares its `Layer`, in a module
    /// of its own (the check needs no shader file).
    const LAYER: &str = "struct Layer {
        first_instance: u32,
        end_instance: u32,
        write_background: u32,
        geometry_ids: u32,
        triplanar_sharpness: f32,
        pad0: u32,
        pad1: u32,
        pad2: u32,
    }
    @group(0) @binding(0) var<uniform> layer: Layer;";

    /// `Layer` with two fields swapped.
    #[repr(C)]
    #[derive(Clone, Copy, Zeroable)]
    struct Swapped {
        first_instance: u32,
        write_background: u32,
        end_instance: u32,
        geometry_ids: u32,
        triplanar_sharpness: f32,
        pad0: u32,
        pad1: u32,
        pad2: u32,
    }

    /// Three of its members.
    #[repr(C)]
    #[derive(Clone, Copy, Zeroable)]
    struct Short {
        first_instance: u32,
        end_instance: u32,
        write_background: u32,
    }

    fn check(host: super::HostLayout, wgsl: &str) -> Result<(), String> {
        let module = naga::front::wgsl::parse_str(LAYER).expect("parses");
        super::check_module(&module, "layer.wgsl", wgsl, &host)
    }

    #[test]
    fn a_drifted_struct_names_what_moved() {
        let e = check(
            crate::host_layout!(
                Swapped,
                [
                    first_instance,
                    write_background,
                    end_instance,
                    geometry_ids,
                    triplanar_sharpness,
                    pad0,
                    pad1,
                    pad2
                ]
            ),
            "Layer",
        )
        .expect_err("two fields swapped");
        assert!(
            e.contains("`write_background` is at byte 4, the shader's `write_background` at 8"),
            "{e}"
        );
        let e = check(
            crate::host_layout!(Short, [first_instance, end_instance, write_background]),
            "Layer",
        )
        .expect_err("a member short");
        assert!(e.contains("12 bytes, the shader's struct 32"), "{e}");
        let e = check(
            crate::host_layout!(Short, [first_instance, end_instance]),
            "Layer",
        )
        .expect_err("a field not listed");
        assert!(e.contains("cover 8 of its 12 bytes"), "{e}");
        let e = check(crate::host_layout!(Short, [first_instance]), "Nothing")
            .expect_err("no such struct");
        assert!(
            e.contains("cover 4 of its 12 bytes") || e.contains("no struct `Nothing`"),
            "{e}"
        );
    }
}
