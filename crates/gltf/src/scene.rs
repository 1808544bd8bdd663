//! The scene to show: which nodes (default scene, first scene, or root
//! nodes), their world transforms, and the instances and bounds they give.

use std::collections::HashMap;

use glam::Mat4;
use gltf::Document;

use super::animation::{self, SceneGraph};
use super::content::LightSource;
use super::{GltfError, GltfScene, Importer, MeshInstance, SceneLights, content};
use spreadlight_render::mesh::Aabb;

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
        let mut deforms = Vec::new();
        // (glTF mesh, primitive) -> index in `meshes`; skipped ones are absent.
        let mut loaded: HashMap<(usize, usize), usize> = HashMap::new();
        for mesh in document.meshes() {
            for primitive in mesh.primitives() {
                if let Some((data, deform)) = self.primitive(&mesh, &primitive)? {
                    loaded.insert((mesh.index(), primitive.index()), meshes.len());
                    meshes.push(data);
                    deforms.push(deform);
                }
            }
        }
        let skins = self.skins(document)?;
        let materials = document
            .materials()
            .map(|m| self.material(document, &m))
            .collect::<Result<Vec<_>, _>>()?;
        let animations = self.animations(document)?;
        let variants = self.variant_names(document);

        let mut instances = Vec::new();
        let nodes = self.scene_nodes(document);
        for (node, world, _) in &nodes {
            let (node, world) = (node, *world);
            let Some(mesh) = node.mesh() else { continue };
            for primitive in mesh.primitives() {
                if let Some(&index) = loaded.get(&(mesh.index(), primitive.index())) {
                    let skin = self.instance_skin(
                        node,
                        &mesh,
                        primitive.index(),
                        &deforms[index],
                        &skins,
                    )?;
                    let targets = deforms[index].targets.len();
                    let variant_materials =
                        self.variant_materials(&mesh, &primitive, variants.len(), materials.len());
                    instances.push(MeshInstance {
                        mesh: index,
                        transform: world,
                        material: primitive.material().index(),
                        node: node.index(),
                        skin,
                        weights: self.rest_weights(node, &mesh, targets),
                        variant_materials,
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
        let mut scene = GltfScene {
            meshes,
            deforms,
            skins,
            materials,
            instances,
            bounds,
            lights,
            light_sources,
            cameras,
            graph,
            animations,
            variants,
            warnings: std::mem::take(&mut self.warnings),
        };
        // Skinned meshes lie where their joints put them, not where their
        // node is: the bounds (what `view` frames) follow the rest pose.
        if scene.instances.iter().any(|i| scene.is_deformed(i)) {
            let world = scene.node_worlds(None, 0.0);
            scene.bounds = scene.bounds_at(&world, &[]);
        }
        Ok(scene)
    }

    /// The skin that deforms a primitive of `node`'s mesh: its node's, when
    /// the primitive has joint influences. A joint index beyond the skin's
    /// joints refuses the file; a skin without influences (or influences
    /// without a skin) is drawn rigid, with a warning.
    fn instance_skin(
        &mut self,
        node: &gltf::Node,
        mesh: &gltf::Mesh,
        primitive: usize,
        deform: &super::deform::Deform,
        skins: &[super::skin::Skin],
    ) -> Result<Option<usize>, GltfError> {
        let name = super::primitive::primitive_name(mesh, primitive);
        let node_name = match node.name() {
            Some(n) => format!("node {} `{n}`", node.index()),
            None => format!("node {}", node.index()),
        };
        match (node.skin(), &deform.influences) {
            (None, None) => Ok(None),
            (None, Some(_)) => {
                self.warn(format!(
                    "{node_name}: {name} has joint weights but the node has no skin; drawn unskinned"
                ));
                Ok(None)
            }
            (Some(_), None) => {
                self.warn(format!(
                    "{node_name}: {name} has no JOINTS_0/WEIGHTS_0; the skin is ignored for it"
                ));
                Ok(None)
            }
            (Some(skin), Some(influences)) => {
                let Some(s) = skins.get(skin.index()) else {
                    return Ok(None);
                };
                if let Some((joint, vertex)) = influences.max_joint
                    && joint as usize >= s.joints.len()
                {
                    return Err(GltfError::Skin {
                        path: self.path.to_owned(),
                        skin: format!("{node_name}, {}", s.name),
                        reason: format!(
                            "{name}: vertex {vertex} uses joint {joint}, but the skin has {} joints",
                            s.joints.len()
                        ),
                    });
                }
                Ok(Some(skin.index()))
            }
        }
    }

    /// Morph weights at rest: the node's, else the mesh's, else zeros; one
    /// per target (a list of another length is fitted, with a warning).
    fn rest_weights(&mut self, node: &gltf::Node, mesh: &gltf::Mesh, targets: usize) -> Vec<f32> {
        let mut weights: Vec<f32> = node
            .weights()
            .or_else(|| mesh.weights())
            .map(<[f32]>::to_vec)
            .unwrap_or_default();
        if !weights.is_empty() && weights.len() != targets {
            self.warn(format!(
                "node {}: {} morph weights for {targets} morph targets; the list is fitted",
                node.index(),
                weights.len()
            ));
        }
        weights.resize(targets, 0.0);
        weights
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
