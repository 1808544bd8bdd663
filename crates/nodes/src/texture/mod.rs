//! Texture nodes (category "Texture").

pub mod file_texture;
pub mod file_texture_array;

use spreadlight_graph::Registry;

pub fn register(r: &mut Registry) {
    file_texture::register(r);
    file_texture_array::register(r);
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use spreadlight_graph::{FrameClock, NodeDoc, NodeId, Patch, PatchDir, Runtime, Spread};

    /// Runs `FileTexture (Array)` on `files` in a patch that lives in `dir`;
    /// returns its Layers output and the node errors.
    fn load(dir: &std::path::Path, files: &[&str]) -> (Option<Spread>, Vec<String>) {
        let mut patch = Patch::default();
        let names: Vec<String> = files.iter().map(|f| (*f).to_owned()).collect();
        patch.add(NodeDoc::new(1, "FileTexture (Array)").with("Filenames", names));
        patch.add(NodeDoc::new(2, "Probe"));
        patch.link(1, "Layers", 2, "Input");
        let mut runtime = Runtime::new(crate::registry());
        runtime.provide(spreadlight_render::renderer::test_renderer());
        runtime.provide(Arc::new(PatchDir(dir.to_path_buf())));
        assert!(runtime.load(&patch).is_empty());
        runtime.evaluate(FrameClock::default());
        let errors = runtime.node_errors().map(|(_, e)| e.to_string()).collect();
        let layers = runtime
            .output(NodeId(1), "Layers")
            .map(|s| s.as_ref().clone());
        (layers, errors)
    }

    #[test]
    fn a_texture_array_takes_files_of_any_size_beside_the_patch_and_names_a_missing_one() {
        let dir = tempfile::tempdir().expect("tempdir");
        image::RgbaImage::from_pixel(8, 4, image::Rgba([255, 0, 0, 255]))
            .save(dir.path().join("a.png"))
            .expect("write");
        image::RgbaImage::from_pixel(3, 5, image::Rgba([0, 255, 0, 255]))
            .save(dir.path().join("b.png"))
            .expect("write");
        let (layers, errors) = load(dir.path(), &["a.png", "b.png"]);
        assert!(errors.is_empty(), "{errors:?}");
        assert_eq!(layers, Some(Spread::Int(vec![2])));
        let (_, errors) = load(dir.path(), &["a.png", "missing.png"]);
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert!(errors[0].contains("slice 1, missing.png"), "{errors:?}");
    }
}
