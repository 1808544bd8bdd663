//! Running the patch: reloading the runtime on edits, advancing time, rendering the viewports' textures.

use super::*;

impl EditorApp {
    /// Pick up saved shader files: their node types are replaced and the
    /// patch recompiled, keeping links and values; errors go to the status bar.
    pub(super) fn poll_shaders(&mut self, now: f64) {
        if let Some(changes) = self.shaders.poll(now, &mut self.registry) {
            self.runtime.set_registry(self.registry.clone());
            self.loaded_generation = None;
            self.synced_generation = None;
            self.status = self.shaders.describe(&changes);
        }
    }

    /// Reload on change; with `dt`, also advance time when playing or stepping.
    pub(super) fn evaluate_if_needed(&mut self, dt: Option<f64>) {
        let mut run = false;
        if self.loaded_generation != Some(self.doc.generation()) {
            self.runtime.load(self.doc.top());
            self.loaded_generation = Some(self.doc.generation());
            run = true;
        }
        if let Some(dt) = dt {
            if self.playing {
                self.clock.advance(dt);
                run = true;
            } else if self.step {
                self.clock.advance(1.0 / 60.0);
                run = true;
            }
            self.step = false;
        }
        if run {
            self.runtime.evaluate(self.clock);
            self.evaluations += 1;
            for v in &mut self.viewports {
                v.rendered_size = (0, 0);
            }
        }
    }

    /// The texture a viewport's source points at, if the runtime has one.
    pub(super) fn texture_of(&self, source: &Source) -> Result<TextureRef, ViewportError> {
        let (node, pin) = match source {
            Source::None => return Err(ViewportError::NoTexture),
            Source::Pin(node, pin) => (*node, pin.clone()),
            Source::Output => {
                // Viewports show the top patch, whichever document is open.
                let patch = self.doc.top();
                let is_output =
                    |id: &NodeId| patch.node(*id).is_some_and(|n| n.type_name == "Output");
                let chosen = self
                    .selected()
                    .into_iter()
                    .rev()
                    .find(is_output)
                    .or_else(|| patch.nodes.iter().map(|n| n.id).find(is_output))
                    .ok_or(ViewportError::NoTexture)?;
                let into = PinRef(chosen, "Texture".to_owned());
                let link = patch
                    .links
                    .iter()
                    .find(|l| l.to == into)
                    .ok_or(ViewportError::NoTexture)?;
                (link.from.node(), link.from.pin().to_owned())
            }
        };
        let network = self.runtime.network();
        let needed = network
            .index_at(&[node])
            .or_else(|| network.instance_output(&[node], &pin))
            .is_some_and(|i| network.is_needed(i));
        if !needed {
            return Err(ViewportError::NotEvaluated(format!("{node}.{pin}")));
        }
        match self.runtime.output(node, &pin).map(|s| &**s) {
            Some(Spread::Resource(ResourceKind::Texture, handles)) => handles
                .first()
                .and_then(|h| h.downcast_arc::<TextureRef>())
                .map(|t| (*t).clone())
                .ok_or(ViewportError::NoTexture),
            _ => Err(ViewportError::NoTexture),
        }
    }

    pub(super) fn render_viewports(&mut self) {
        let Some(gpu) = &self.gpu else {
            return;
        };
        for k in 0..self.viewports.len() {
            let size = self.viewports[k].size;
            if self.viewports[k].rendered_size == size {
                continue;
            }
            let texture = self.texture_of(&self.viewports[k].source);
            let v = &mut self.viewports[k];
            v.rendered_size = size;
            let result = texture.and_then(|t| {
                viewport::render_into(
                    &gpu.state,
                    &gpu.renderer,
                    &gpu.blitter,
                    &t,
                    size,
                    &mut v.target,
                )
            });
            match result {
                Ok(report) => {
                    v.error = None;
                    if k == 0 {
                        self.gpu_ms.clear();
                        for pass in report.passes {
                            if let (Some(owner), Some(ms)) = (pass.owner, pass.gpu_ms) {
                                *self.gpu_ms.entry(owner).or_default() += ms;
                            }
                        }
                        self.gpu_errors.clear();
                        for (owner, message) in report.errors {
                            if let Some(owner) = owner {
                                self.gpu_errors.insert(owner, message);
                            }
                        }
                    }
                }
                Err(e) => v.error = Some(e),
            }
        }
    }
}
