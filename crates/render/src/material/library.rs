//! The material world as shader nodes read it: `shaders/lib/materials.wgsl`
//! (`spreadlight::materials`), Emeshe's Materials.fxh names over the same
//! three buffers the built-in passes read, in bind group 3, which neither a
//! shader node's own bindings (group 0 for image effects, group 1 for
//! materials) nor the G-buffer resolve under a shader node material use.
//! Only a file that imports the library binds it, so a shader that does not
//! read the world costs nothing and needs no world.

use super::MaterialWorld;
use crate::frame_graph::{Bindings, Tex};

/// What a file imports to read the material world.
pub const LIBRARY: &str = "spreadlight::materials";

/// The bind group of the library's variables.
pub const GROUP: u32 = 3;

/// One variable of the library, by its WGSL name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LibraryBinding {
    /// `MatMeta`: per material, flags, address and size.
    Meta,
    /// `FeatureOffset`: per feature of each material, its parameters' place and texture.
    Offsets,
    /// `MaterialData`: every parameter vec4.
    Data,
    /// `MaterialTextures`: the MaterialBuffer's texture array (a white layer without one).
    Textures,
    /// `MaterialSampler`: linear, repeating.
    Sampler,
}

impl LibraryBinding {
    pub const ALL: [LibraryBinding; 5] = [
        LibraryBinding::Meta,
        LibraryBinding::Offsets,
        LibraryBinding::Data,
        LibraryBinding::Textures,
        LibraryBinding::Sampler,
    ];

    /// The variable's name in `shaders/lib/materials.wgsl`.
    pub fn name(self) -> &'static str {
        match self {
            LibraryBinding::Meta => "MatMeta",
            LibraryBinding::Offsets => "FeatureOffset",
            LibraryBinding::Data => "MaterialData",
            LibraryBinding::Textures => "MaterialTextures",
            LibraryBinding::Sampler => "MaterialSampler",
        }
    }

    /// The library's variable named `name` (undecorated), if it is one.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|b| b.name() == name)
    }
}

/// Whether `source` (a shader node file) imports the library, in any permutation.
pub fn imports_library(source: &str) -> bool {
    source.lines().any(|l| {
        l.trim_start()
            .strip_prefix("#import")
            .is_some_and(|rest| rest.trim_start().starts_with(LIBRARY))
    })
}

impl MaterialWorld {
    /// The library's variables by name; `array`: the world's texture array
    /// as the pass declared it (see [`MaterialWorld::textures`]), else a
    /// white stand-in.
    pub(crate) fn library_bindings(&self, array: Option<Tex>) -> Bindings<'_> {
        let b = Bindings::new()
            .buffer(LibraryBinding::Meta.name(), &self.meta)
            .buffer(LibraryBinding::Offsets.name(), &self.offsets)
            .buffer(LibraryBinding::Data.name(), &self.data)
            .sampler(
                LibraryBinding::Sampler.name(),
                crate::shaders::Sampling::LinearRepeat,
            );
        match array {
            Some(t) => b.array(LibraryBinding::Textures.name(), t),
            None => b.view(LibraryBinding::Textures.name(), self.dummies.array.clone()),
        }
    }

    /// The buffer behind a buffer variable of the library.
    pub(crate) fn library_buffer(&self, binding: LibraryBinding) -> Option<&wgpu::Buffer> {
        match binding {
            LibraryBinding::Meta => Some(&self.meta),
            LibraryBinding::Offsets => Some(&self.offsets),
            LibraryBinding::Data => Some(&self.data),
            LibraryBinding::Textures | LibraryBinding::Sampler => None,
        }
    }

    /// The white one-layer array bound where the world has no texture array.
    pub(crate) fn stand_in_array(&self) -> wgpu::TextureView {
        self.dummies.array.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_imports_the_library_only_by_an_import_line() {
        assert!(imports_library(
            "#import spreadlight::materials::{KnowFeature, GetFloat}\n"
        ));
        assert!(imports_library(
            "  #import spreadlight::materials::GetTexID"
        ));
        assert!(!imports_library(
            "#import spreadlight::material::feature_param"
        ));
        assert!(!imports_library(
            "// spreadlight::materials is not imported"
        ));
    }

    #[test]
    fn names_round_trip() {
        for b in LibraryBinding::ALL {
            assert_eq!(LibraryBinding::from_name(b.name()), Some(b));
        }
        assert_eq!(LibraryBinding::from_name("material_meta"), None);
    }

    #[test]
    fn gpu_material_meta_matches_the_librarys_materialmeta() {
        crate::assert_wgsl_layout!(
            super::super::GpuMaterialMeta,
            "lib/materials.wgsl",
            [],
            "MaterialMeta",
            [flags, address, size, pad]
        );
    }

    #[test]
    fn gpu_feature_offset_matches_the_librarys_featureentry() {
        crate::assert_wgsl_layout!(
            super::super::GpuFeatureOffset,
            "lib/materials.wgsl",
            [],
            "FeatureEntry",
            [feature, offset, count, texture, maps]
        );
    }
}
