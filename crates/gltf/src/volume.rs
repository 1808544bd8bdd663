//! `KHR_materials_volume`: the thickness of a transmissive material's
//! volume (a factor in the mesh's units and a map, green) and how the
//! volume absorbs what passes through it (Beer-Lambert: white light is
//! `attenuationColor` after `attenuationDistance`). Read and checked here;
//! [`MaterialData::transmittance`] is the absorption along a path, finite
//! for every input (zero thickness, infinite distance, black attenuation).
//! Drawn by lit transparency: the material's Transmission feature carries
//! the thickness and the absorption coefficient σ = -ln(c) / d
//! ([`spreadlight_render::material::transmission_params`]).

use gltf::Document;
use gltf::json::Value;

use super::{GltfError, Importer, MaterialData};

impl Importer<'_> {
    /// Reads `ext` (the material's `KHR_materials_volume` object) into `data`.
    pub(super) fn volume(
        &mut self,
        document: &Document,
        who: &str,
        ext: &Value,
        data: &mut MaterialData,
    ) -> Result<(), GltfError> {
        let name = "KHR_materials_volume";
        data.thickness = self.factor(who, name, ext, "thicknessFactor", 0.0, 0.0, f32::MAX);
        data.thickness_texture =
            self.extension_texture(document, who, name, ext, "thicknessTexture", false)?;
        data.attenuation_color = self.color(who, name, ext, "attenuationColor", [1.0; 3], 1.0);
        data.attenuation_distance = match ext.get("attenuationDistance") {
            None => f32::INFINITY,
            Some(v) => match v.as_f64() {
                // JSON has no infinity: a distance too large for an f32 is one.
                Some(d) if d > 0.0 => d as f32,
                _ => {
                    self.warn(format!(
                        "{who}: {name} attenuationDistance is {v}, not a number > 0: infinity (no absorption) used"
                    ));
                    f32::INFINITY
                }
            },
        };
        Ok(())
    }
}

impl MaterialData {
    /// How much of each channel of light is left after `path` (mesh units)
    /// inside the volume: `attenuation_color ^ (path / attenuation_distance)`
    /// (the extension's Beer-Lambert law, σ = -ln(c) / d). 1 for no path,
    /// an infinite distance or a white attenuation; 0 where a channel of the
    /// attenuation colour is black and the path is not empty; always in
    /// 0..=1, never NaN.
    pub fn transmittance(&self, path: f32) -> [f32; 3] {
        let d = self.attenuation_distance;
        // No path (or NaN), no distance (or NaN), or an infinite one: nothing absorbed.
        let positive = |x: f32| x > 0.0;
        if !positive(path) || !positive(d) || d == f32::INFINITY {
            return [1.0; 3];
        }
        self.attenuation_color.map(|c| {
            if !c.is_finite() || c >= 1.0 {
                1.0
            } else if c <= 0.0 {
                0.0
            } else {
                // ln(c) < 0 and path / d > 0 (infinite path: exp(-inf) = 0).
                (c.ln() * (path / d)).exp().clamp(0.0, 1.0)
            }
        })
    }
}
