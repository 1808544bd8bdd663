//! The frame's live textures by name: what a pass's handles resolve to
//! while it records (imports, persistent textures, the outputs of passes
//! that recorded, until their last reader has).
//!
//! A plan keeps its map between the frames that take it (plan.rs): those
//! frames run under the plan's names, so each name is a key already and a
//! frame only sets and clears the textures (a name copied a texture a frame
//! before, issue 33).

use rustc_hash::FxHashMap;

#[derive(Default)]
pub(crate) struct Live {
    by_name: FxHashMap<String, Option<wgpu::Texture>>,
}

impl Live {
    pub fn get(&self, name: &str) -> Option<&wgpu::Texture> {
        self.by_name.get(name)?.as_ref()
    }

    #[cfg(test)]
    pub fn contains(&self, name: &str) -> bool {
        self.get(name).is_some()
    }

    /// `name` is `texture` from now on.
    pub fn insert(&mut self, name: &str, texture: wgpu::Texture) {
        match self.by_name.get_mut(name) {
            Some(slot) => *slot = Some(texture),
            None => {
                self.by_name.insert(name.to_owned(), Some(texture));
            }
        }
    }

    /// `name` leaves the frame; its name stays a key for the next.
    pub fn remove(&mut self, name: &str) -> Option<wgpu::Texture> {
        self.by_name.get_mut(name)?.take()
    }

    /// No texture is live (the names stay, for the next frame).
    pub fn clear(&mut self) {
        for texture in self.by_name.values_mut() {
            *texture = None;
        }
    }
}
