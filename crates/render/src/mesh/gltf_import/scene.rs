//! The scene to show: which nodes (default scene, first scene, or root
//! nodes), their world transforms, and the instances and bounds they give.

use std::collections::HashMap;

use glam::Mat4;
use gltf::Document;

use super::animation::{self, SceneGraph};
use super::content::LightSource;
use super::{GltfError, GltfScene, Importer, MeshInstance, SceneLights, content};
use crate::mesh::Aabb;

/// glTF's node hierarchy must be a forest: no node is its own child, none
/// has two parents, and following parents never loops. The first problem,
/// named by its nodes.
fn check_forest(document: &Document) -> Result<(), String> {
    let n = document.nodes().len();
    let mut parent: Vec<Option<usize>> = vec![None; n];
    for node in document.nodes() {
        for child in node.children() {
            let (p, c) = (node.index(), child.index());
            if p == c {
                return Err(format!("node {c} is its own child"));
            }
            match parent.get_mut(c) {
                Some(Some(first)) if *first != p => {
                    return Err(format!(
                        "node {c} is a child of nodes {first} and {p}; a node has at most one parent"
                    ));
                }
                Some(slot) => *slot = Some(p),
                None => {}
            }
        }
    }
    // One parent each: walk up from every node once (O(nodes)); meeting
    // the walk's own path again is a cycle.
    let mut walked = vec![usize::MAX; n];
    for start in 0..n {
        let mut path = Vec::new();
        let mut at = Some(start);
        while let Some(node) = at {
            if walked[node] == start {
                let from = path.iter().position(|&p| p == node).unwrap_or(0);
                let mut names: Vec<String> = path[from..].iter().map(usize::to_string).collect();
                names.push(node.to_string());
                return Err(format!(
                    "nodes {} are each other's ancestors (a cycle)",
                    names.join(" -> ")
                ));
            }
            if walked[node] != usize::MAX {
                break; // walked from an earlier start: no cycle above it
            }
            walked[node] = start;
            path.push(node);
            at = parent[node];
        }
    }
    Ok(())
}

impl Importer<'_> {
    pub(super) fn scene(&mut self, document: &Document) -> Result<GltfScene, GltfError> {
        check_forest(document).map_err(|message| GltfError::Invalid {
            path: self.path.to_owned(),
            message,
        })?;
        let mut meshes = Vec::new();
        // (glTF mesh, primitive) -> index in `meshes`; skipped ones are absent.
        let mut loaded: HashMap<(usize, usize), usize> = HashMap::new();
        for mesh in document.meshes() {
            for primitive in mesh.primitives() {
                if let Some(data) = self.primitive(&mesh, &primitive)? {
                    loaded.insert((mesh.index(), primitive.index()), meshes.len());
                    meshes.push(data);
                }
            }
        }
        let materials = document
            .materials()
            .map(|m| self.material(document, &m))
            .collect::<Result<Vec<_>, _>>()?;
        let animations = self.animations(document)?;

        let mut instances = Vec::new();
        let nodes = self.scene_nodes(document);
        for (node, world, _) in &nodes {
            let (node, world) = (node, *world);
            let Some(mesh) = node.mesh() else { continue };
            if node.skin().is_some() {
                self.warnings.push(format!(
                    "node {}: skinning is ignored; the mesh is placed by the node alone",
                    node.index()
                ));
            }
            for primitive in mesh.primitives() {
                if let Some(&index) = loaded.get(&(mesh.index(), primitive.index())) {
                    instances.push(MeshInstance {
                        mesh: index,
                        transform: world,
                        material: primitive.material().index(),
                        node: node.index(),
                    });
                }
            }
        }
        let bounds = instances
            .iter()
            .filter_map(|i| Some(meshes.get(i.mesh)?.bounds.transformed(i.transform)))
            .reduce(Aabb::union)
            .unwrap_or(Aabb::ZERO);
        let reach = bounds.size().length();
        let mut lights = SceneLights::default();
        let mut light_sources = Vec::new();
        let mut cameras = Vec::new();
        for (node, world, _) in &nodes {
            if let Some(light) = node.light() {
                let source = LightSource::new(&light, node.index(), reach);
                source.place(*world, &mut lights);
                light_sources.push(source);
            }
            if let Some(camera) = node.camera() {
                cameras.push(content::camera(&camera, node.index(), *world));
            }
        }
        let graph = SceneGraph {
            order: nodes.iter().map(|(n, _, p)| (n.index(), *p)).collect(),
            rest: document.nodes().map(|n| animation::rest_of(&n)).collect(),
        };
        Ok(GltfScene {
            meshes,
            materials,
            instances,
            bounds,
            lights,
            light_sources,
            cameras,
            graph,
            animations,
            warnings: std::mem::take(&mut self.warnings),
        })
    }

    /// Every node of the scene to show, with its world transform. A node
    /// reached twice (a cycle, or a child of two parents: both invalid glTF)
    /// is kept once and reported; a non-finite transform drops its subtree.
    fn scene_nodes<'d>(
        &mut self,
        document: &'d Document,
    ) -> Vec<(gltf::Node<'d>, Mat4, Option<usize>)> {
        let roots: Vec<gltf::Node> = match document
            .default_scene()
            .or_else(|| document.scenes().next())
        {
            Some(scene) => scene.nodes().collect(),
            None => {
                let mut is_child = vec![false; document.nodes().len()];
                for child in document.nodes().flat_map(|n| n.children()) {
                    if let Some(flag) = is_child.get_mut(child.index()) {
                        *flag = true;
                    }
                }
                document
                    .nodes()
                    .filter(|n| !is_child.get(n.index()).copied().unwrap_or(false))
                    .collect()
            }
        };
        let mut visited = vec![false; document.nodes().len()];
        let mut out = Vec::new();
        let mut stack: Vec<(gltf::Node, Mat4, Option<usize>)> = roots
            .into_iter()
            .rev()
            .map(|n| (n, Mat4::IDENTITY, None))
            .collect();
        while let Some((node, parent, parent_index)) = stack.pop() {
            match visited.get_mut(node.index()) {
                Some(seen) if !*seen => *seen = true,
                _ => {
                    self.warnings.push(format!(
                        "node {} is reached twice (a cycle or a shared child); its second use is skipped",
                        node.index()
                    ));
                    continue;
                }
            }
            let local = Mat4::from_cols_array_2d(&node.transform().matrix());
            let world = parent * local;
            if !world.is_finite() {
                self.warnings.push(format!(
                    "node {}: its world transform is not finite; it and its children are skipped",
                    node.index()
                ));
                continue;
            }
            let children: Vec<_> = node.children().collect();
            stack.extend(
                children
                    .into_iter()
                    .rev()
                    .map(|c| (c, world, Some(node.index()))),
            );
            out.push((node, world, parent_index));
        }
        out
    }
}
