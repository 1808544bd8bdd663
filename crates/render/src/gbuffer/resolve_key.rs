//! `gbuffer/resolve.wgsl`'s permutations as a type, [`ResolveKey`]: what the
//! string rules said is its shape. The motion resolve writes velocity and
//! UVs alone, so the surface's colour map, surface target and vertex
//! extras exist only in [`Written::Surface`]; a mesh's UVs and a planar
//! projection are one choice ([`Uv`]); surface maps and a shader node
//! material write the surface target and are one choice ([`SurfaceOut`]).
//! The G-buffer's resolve (`gbuffer/resolve.rs`) and the shader node
//! compiler's material check (`shader_nodes/compose.rs`) both build it;
//! it declares its shader file (`shader_file!`) and imports no pass.

use crate::shaders::permutation::Permutation;

/// One permutation of the G-buffer resolve.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ResolveKey {
    /// The visibility comes from the compute raster's 64-bit buffer (else the
    /// hardware raster's IDs).
    pub compute_raster: bool,
    pub uv: Uv,
    /// Normals perturbed by the layer's normal map.
    pub normal_map: bool,
    /// Velocity from the mesh's previous-frame positions as well.
    pub velocity_from_geometry: bool,
    pub written: Written,
}

/// Where texture coordinates come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Uv {
    #[default]
    None,
    /// The mesh's own (TEXCOORDS).
    Mesh,
    /// Projected from world position (TRIPLANAR).
    Triplanar,
}

/// Which targets a dispatch writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Written {
    /// Velocity and texture coordinates alone (MOTION).
    Motion,
    /// Colour, normals and depth, and with `velocity` the motion targets too.
    Surface(SurfaceResolve),
}

/// What a surface resolve reads and writes beside colour, normals and depth.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SurfaceResolve {
    /// The layer's Color Texture (COLOR_MAP).
    pub color_map: bool,
    /// Vertex colours and the second UV set (VERTEX_EXTRAS).
    pub vertex_extras: bool,
    /// Velocity and UVs written in the same dispatch (VELOCITY_OUT).
    pub velocity: bool,
    /// The surface target, and what fills it.
    pub surface: Option<SurfaceOut>,
    /// The anisotropy target (ANISOTROPY): the direction and strength of
    /// the layer's Anisotropy materials per pixel. Only with surface maps
    /// (`SurfaceOut::MaterialMaps` or `ExtendedMaps`), whose world has one.
    pub anisotropy: bool,
    /// The sheen and film target (SHEEN_FILM): the sheen colour and
    /// roughness and the film's factor and thickness per pixel of the
    /// layer's glTF materials. Only with extension maps
    /// (`SurfaceOut::ExtendedMaps`: sheen and iridescence maps are
    /// extension maps), whose world has such a map.
    pub sheen_film: bool,
}

/// The surface target is written (SURFACE_OUT), from the material world's
/// constants, its surface maps or a shader node material.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SurfaceOut {
    Target,
    /// A glTF material world's surface maps (MATERIAL_MAPS).
    MaterialMaps,
    /// Its surface maps and its material extensions' maps, the coat's and
    /// the specular's (MATERIAL_MAPS, EXTENSION_MAPS): some material has one.
    ExtendedMaps,
    /// A shader node material's `surface` function (CUSTOM_SURFACE), which
    /// binds group 1, where surface maps would put the material world.
    Custom,
}

impl Uv {
    fn feature(self) -> Option<&'static str> {
        match self {
            Uv::None => None,
            Uv::Mesh => Some("TEXCOORDS"),
            Uv::Triplanar => Some("TRIPLANAR"),
        }
    }

    /// This choice, or `other` where this is none.
    pub fn or(self, other: Uv) -> Uv {
        match self {
            Uv::None => other,
            uv => uv,
        }
    }
}

impl ResolveKey {
    /// A surface resolve writing `surface`, reading nothing else.
    pub fn surface(surface: SurfaceResolve) -> Self {
        ResolveKey {
            compute_raster: false,
            uv: Uv::None,
            normal_map: false,
            velocity_from_geometry: false,
            written: Written::Surface(surface),
        }
    }

    /// A motion resolve with no UVs, velocity from transforms.
    pub fn motion() -> Self {
        ResolveKey {
            written: Written::Motion,
            ..ResolveKey::surface(SurfaceResolve::default())
        }
    }

    /// The resolve a shader node material is spliced into
    /// (`shader_nodes/compose.rs` checks its file against it).
    pub fn custom_surface() -> Self {
        ResolveKey::surface(SurfaceResolve {
            surface: Some(SurfaceOut::Custom),
            ..SurfaceResolve::default()
        })
    }

    /// Where the G-buffer has a surface target, a surface resolve writes
    /// it, from the material's constants where the layer fills it no other way.
    pub fn with_surface_target(mut self) -> Self {
        if let Written::Surface(s) = &mut self.written {
            s.surface.get_or_insert(SurfaceOut::Target);
        }
        self
    }
}

impl Permutation for ResolveKey {
    crate::shader_file!("gbuffer/resolve.wgsl");
    const FEATURES: &'static [&'static str] = &[
        "COMPUTE_RASTER",
        "MOTION",
        "TEXCOORDS",
        "NORMAL_MAP",
        "TRIPLANAR",
        "VELOCITY_FROM_GEOMETRY",
        "COLOR_MAP",
        "SURFACE_OUT",
        "MATERIAL_MAPS",
        "EXTENSION_MAPS",
        "CUSTOM_SURFACE",
        "VERTEX_EXTRAS",
        "VELOCITY_OUT",
        "ANISOTROPY",
        "SHEEN_FILM",
    ];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let mut f: Vec<&'static str> = Vec::with_capacity(8);
        f.extend(self.compute_raster.then_some("COMPUTE_RASTER"));
        f.extend(self.uv.feature());
        f.extend(self.normal_map.then_some("NORMAL_MAP"));
        f.extend(
            self.velocity_from_geometry
                .then_some("VELOCITY_FROM_GEOMETRY"),
        );
        match self.written {
            Written::Motion => f.push("MOTION"),
            Written::Surface(s) => {
                f.extend(s.color_map.then_some("COLOR_MAP"));
                f.extend(s.vertex_extras.then_some("VERTEX_EXTRAS"));
                f.extend(s.velocity.then_some("VELOCITY_OUT"));
                match s.surface {
                    None => {}
                    Some(SurfaceOut::Target) => f.push("SURFACE_OUT"),
                    Some(SurfaceOut::MaterialMaps) => f.extend(["SURFACE_OUT", "MATERIAL_MAPS"]),
                    Some(SurfaceOut::ExtendedMaps) => {
                        f.extend(["SURFACE_OUT", "MATERIAL_MAPS", "EXTENSION_MAPS"])
                    }
                    Some(SurfaceOut::Custom) => f.extend(["SURFACE_OUT", "CUSTOM_SURFACE"]),
                }
                f.extend(s.anisotropy.then_some("ANISOTROPY"));
                f.extend(s.sheen_film.then_some("SHEEN_FILM"));
            }
        }
        f.into_iter()
    }

    /// 2 rasters x 3 UV sources x 2 x 2 x (the motion resolve and 72
    /// surface resolves): the 1,752 feature sets the string rules allow
    /// (792 before EXTENSION_MAPS, which only surface maps take; 984 before
    /// ANISOTROPY, which only surface maps take too; 1,368 before
    /// SHEEN_FILM, which only extension maps take).
    fn all() -> Vec<Self> {
        let surfaces = [
            None,
            Some(SurfaceOut::Target),
            Some(SurfaceOut::MaterialMaps),
            Some(SurfaceOut::ExtendedMaps),
            Some(SurfaceOut::Custom),
        ];
        let mut written = vec![Written::Motion];
        for color_map in [false, true] {
            for vertex_extras in [false, true] {
                for velocity in [false, true] {
                    for surface in surfaces {
                        let maps = matches!(
                            surface,
                            Some(SurfaceOut::MaterialMaps | SurfaceOut::ExtendedMaps)
                        );
                        let extended = surface == Some(SurfaceOut::ExtendedMaps);
                        for anisotropy in [false, true] {
                            for sheen_film in [false, true] {
                                if anisotropy && !maps || sheen_film && !extended {
                                    continue;
                                }
                                written.push(Written::Surface(SurfaceResolve {
                                    color_map,
                                    vertex_extras,
                                    velocity,
                                    surface,
                                    anisotropy,
                                    sheen_film,
                                }));
                            }
                        }
                    }
                }
            }
        }
        let mut all = Vec::new();
        for compute_raster in [false, true] {
            for uv in [Uv::None, Uv::Mesh, Uv::Triplanar] {
                for normal_map in [false, true] {
                    for velocity_from_geometry in [false, true] {
                        for &written in &written {
                            all.push(ResolveKey {
                                compute_raster,
                                uv,
                                normal_map,
                                velocity_from_geometry,
                                written,
                            });
                        }
                    }
                }
            }
        }
        all
    }
}
