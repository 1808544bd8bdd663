//! Help patches: a small patch per node family under `patches/help/` that
//! shows its nodes working. This table is the one place that says which help
//! patch covers which node type: `spreadlight nodes --help NAME` names it and
//! F1 in the editor opens it, both through [`for_type`].
//!
//! The patches are embedded in the binary (as the shipped shader nodes are),
//! so the editor can open them wherever it runs; in a source checkout it
//! opens the file itself, whose relative asset names (`../assets/...`) then
//! resolve.

/// Where the help patches live in the repository.
pub const HELP_DIR: &str = "patches/help";

/// One help patch: its file in [`HELP_DIR`], its text, and the node types it shows.
#[derive(Debug)]
pub struct HelpPatch {
    pub file: &'static str,
    pub text: &'static str,
    pub covers: &'static [&'static str],
}

impl HelpPatch {
    /// The patch's path relative to the repository root (`patches/help/post.ron`).
    pub fn path(&self) -> String {
        format!("{HELP_DIR}/{}", self.file)
    }

    /// The file in this build's source checkout, when there is one.
    pub fn source_file(&self) -> Option<std::path::PathBuf> {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../..")
            .join(HELP_DIR)
            .join(self.file);
        path.is_file().then_some(path)
    }
}

macro_rules! help {
    ($file:literal => [$($ty:literal),* $(,)?]) => {
        HelpPatch {
            file: $file,
            text: include_str!(concat!("../../../patches/help/", $file)),
            covers: &[$($ty),*],
        }
    };
}

/// Every help patch and the node types it covers (each type in one patch only).
pub const HELP_PATCHES: &[HelpPatch] = &[
    help!("deferred.ron" => [
        "DeferredBase", "MRE", "Group (Layer)", "GBufferView", "Camera", "Output", "Sphere",
        "Plane", "Triplanar (Layer)",
    ]),
    help!("lighting.ron" => [
        "AddLight (Sun)", "AddLight (Point)", "AddLight (Spot)", "SunLightBuffer",
        "PointLightBuffer", "SpotLightBuffer", "CookTorrance", "CompositeLight", "Group (Texture)",
        "Group (Lights)", "Group (Shadows)",
    ]),
    help!("shadows.ron" => ["ShadowMap (Sun)", "ShadowMap (Point)", "ShadowMap (Spot)"]),
    help!("material.ron" => [
        "AddCookTorrance", "AddEmission", "AddAmbientOcclusion", "AddMatCap", "FeatureManager",
        "MaterialManager", "MaterialBuffer", "MaterialByName", "ParameterTexture", "AddClearcoat",
        "AddIridescence", "AddUnlit",
    ]),
    help!("occlusion.ron" => ["SSAO", "HBAO", "SSGI", "SSSS", "AddFakeSSS"]),
    help!("environment.ron" => [
        "Environment (Sky)", "Environment (File)", "EnvironmentProbe", "Reflection", "SSR", "Fog",
        "Sky", "AddReflection",
    ]),
    help!("post.ron" => [
        "Transparency", "Autofocus", "DOF", "MotionBlur", "Glare", "TAA", "EyeAdaptation",
        "Tonemap", "FXAA", "BlurBuiltin",
    ]),
    help!("values.ron" => [
        "LFO", "Sin (Value)", "Cos (Value)", "Multiply (Value)", "Add (Value)",
        "Subtract (Value)", "Divide (Value)", "Map (Value)", "Clamp (Value)", "IOBox (Value)",
        "Probe",
    ]),
    help!("spreads.ron" => [
        "LinearSpread", "CircularSpread", "RandomSpread", "I (Spreads)", "Count (Spreads)",
        "Sum (Spreads)", "Mean (Spreads)", "GetSlice (Spreads)", "Reverse (Spreads)",
        "Sort (Spreads)",
    ]),
];

/// The help patch that covers node type `name`, if one does.
pub fn for_type(name: &str) -> Option<&'static HelpPatch> {
    HELP_PATCHES.iter().find(|h| h.covers.contains(&name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_covered_type_is_registered_once_and_shown_in_its_patch() {
        let registry = crate::registry();
        let mut seen = std::collections::HashSet::new();
        for help in HELP_PATCHES {
            let patch =
                spreadlight_graph::format::from_str(help.text, std::path::Path::new(help.file))
                    .unwrap_or_else(|e| panic!("{}: {e}", help.path()));
            for ty in help.covers {
                assert!(
                    registry.get(ty).is_some(),
                    "{}: no node type {ty}",
                    help.file
                );
                assert!(seen.insert(*ty), "{ty} has two help patches");
                assert!(
                    patch.nodes.iter().any(|n| n.type_name == *ty),
                    "{} covers {ty} but has no {ty} node",
                    help.path()
                );
            }
        }
        assert_eq!(
            for_type("LFO").map(|h| h.file),
            Some("values.ron"),
            "the table answers by type"
        );
        assert!(for_type("no such node").is_none());
    }
}
