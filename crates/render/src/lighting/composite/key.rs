//! `lighting/composite.wgsl`'s permutations as a type. What the string
//! rules said is now the shape of [`CompositeKey`]: light pairs are one to
//! four and a subsurface term belongs to its pair ([`LightPairs`]); what
//! reads the material library (emission, per-material AO, reflections,
//! matcaps) exists only under [`Shading::Materials`]; a textured emission
//! or matcap is a kind of emission or matcap, not a switch beside them.

use crate::shaders::permutation::Permutation;

/// One permutation of the composite.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CompositeKey {
    pub pairs: LightPairs,
    pub shading: Shading,
    /// Indirect diffuse light (GI) is added.
    pub gi: bool,
    /// The G-buffer's surface target (occlusion, metallic, emission) is read.
    pub surface_target: bool,
}

/// One to four light pairs (a light type's diffuse and specular), each
/// with or without a subsurface term.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LightPairs {
    count: u8,
    /// Bit k: pair k carries a subsurface term (only bits below `count`).
    sss: u8,
}

impl LightPairs {
    /// Pairs with these subsurface flags, one per pair; `None` outside 1..=4 pairs.
    pub fn new(sss: impl IntoIterator<Item = bool>) -> Option<Self> {
        let (mut count, mut mask) = (0u8, 0u8);
        for on in sss {
            if count == 4 {
                return None;
            }
            mask |= u8::from(on) << count;
            count += 1;
        }
        (count > 0).then_some(LightPairs { count, sss: mask })
    }
}

/// What the material library decides, if a material world is connected.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shading {
    /// No material world: AO, if any, darkens every surface alike.
    Plain {
        ao: bool,
    },
    Materials(MaterialTerms),
}

/// The per-material terms some material of the world has.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MaterialTerms {
    pub ao: MaterialAo,
    pub emission: Option<Textured>,
    pub reflection: bool,
    pub matcap: Option<Textured>,
}

/// Ambient occlusion with a material world.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MaterialAo {
    Off,
    /// Every material darkened alike.
    On,
    /// Weighted by each material's AmbientOcclusion strength.
    PerMaterial,
}

/// A term from a constant, or also from a texture of the material library.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Textured {
    Flat,
    Textured,
}

impl From<bool> for Textured {
    /// Whether the term reads a texture.
    fn from(textured: bool) -> Self {
        if textured {
            Textured::Textured
        } else {
            Textured::Flat
        }
    }
}

impl Permutation for CompositeKey {
    crate::shader_file!("lighting/composite.wgsl");
    const FEATURES: &'static [&'static str] = &[
        "LIGHTS_2",
        "LIGHTS_3",
        "LIGHTS_4",
        "EMISSION",
        "SSS_1",
        "SSS_2",
        "SSS_3",
        "SSS_4",
        "AO",
        "AO_PER_MATERIAL",
        "MATERIAL_TEXTURES",
        "MATERIALS",
        "GI",
        "REFLECTION",
        "MATCAP",
        "MATCAP_TEXTURE",
        "SURFACE_TARGET",
    ];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let pairs = ["LIGHTS_2", "LIGHTS_3", "LIGHTS_4"]
            .into_iter()
            .take(usize::from(self.pairs.count) - 1);
        let sss = ["SSS_1", "SSS_2", "SSS_3", "SSS_4"]
            .into_iter()
            .enumerate()
            .filter(move |(k, _)| self.pairs.sss & (1 << k) != 0)
            .map(|(_, f)| f);
        let mut terms: Vec<&'static str> = Vec::with_capacity(8);
        match self.shading {
            Shading::Plain { ao } => terms.extend(ao.then_some("AO")),
            Shading::Materials(m) => {
                terms.push("MATERIALS");
                match m.ao {
                    MaterialAo::Off => {}
                    MaterialAo::On => terms.push("AO"),
                    MaterialAo::PerMaterial => terms.extend(["AO", "AO_PER_MATERIAL"]),
                }
                match m.emission {
                    None => {}
                    Some(Textured::Flat) => terms.push("EMISSION"),
                    Some(Textured::Textured) => terms.extend(["EMISSION", "MATERIAL_TEXTURES"]),
                }
                terms.extend(m.reflection.then_some("REFLECTION"));
                match m.matcap {
                    None => {}
                    Some(Textured::Flat) => terms.push("MATCAP"),
                    Some(Textured::Textured) => terms.extend(["MATCAP", "MATCAP_TEXTURE"]),
                }
            }
        }
        terms.extend(self.gi.then_some("GI"));
        terms.extend(self.surface_target.then_some("SURFACE_TARGET"));
        pairs.chain(sss).chain(terms)
    }

    fn all() -> Vec<Self> {
        let pairs: Vec<LightPairs> = (1..=4u8)
            .flat_map(|count| (0..1u8 << count).map(move |sss| LightPairs { count, sss }))
            .collect();
        let optional = [None, Some(Textured::Flat), Some(Textured::Textured)];
        let mut shading = vec![Shading::Plain { ao: false }, Shading::Plain { ao: true }];
        for ao in [MaterialAo::Off, MaterialAo::On, MaterialAo::PerMaterial] {
            for emission in optional {
                for reflection in [false, true] {
                    for matcap in optional {
                        shading.push(Shading::Materials(MaterialTerms {
                            ao,
                            emission,
                            reflection,
                            matcap,
                        }));
                    }
                }
            }
        }
        let mut all = Vec::new();
        for &pairs in &pairs {
            for &shading in &shading {
                for gi in [false, true] {
                    for surface_target in [false, true] {
                        all.push(CompositeKey {
                            pairs,
                            shading,
                            gi,
                            surface_target,
                        });
                    }
                }
            }
        }
        all
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_to_four_pairs_each_with_its_own_subsurface_term() {
        assert_eq!(LightPairs::new([]), None);
        assert_eq!(LightPairs::new([false; 5]), None);
        let key = CompositeKey {
            pairs: LightPairs::new([false, true, false]).expect("three pairs"),
            shading: Shading::Plain { ao: true },
            gi: false,
            surface_target: false,
        };
        let features: Vec<_> = key.features().collect();
        assert_eq!(features, ["LIGHTS_2", "LIGHTS_3", "SSS_2", "AO"]);
    }
}
