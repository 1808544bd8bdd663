//! Temporal histories without copies. A temporal pass reads last frame's
//! result and writes this frame's; copying one into the other
//! (`copy_texture_to_texture`) cost 0.3 ms of GPU per 1080p RGBA16F texture
//! on the H100, most of the frame's idle time between passes. So where the
//! two textures are interchangeable (same format, size and usage, and the
//! temporary is neither handed to the caller nor kept for the frame) they
//! trade places instead: the names point at the other texture, the
//! persistent store keeps the one written this frame, and the pool gets the
//! other back. Where they are not, the copy stays.

use super::{PassContext, Tex};
use crate::error::RenderError;

/// A persistent history that took a temporary's texture this frame: the
/// store keeps the history's new texture, and `temporary`'s output slot
/// gives `release` back to the pool (the texture the history had).
pub(crate) struct Handover {
    pub persistent: String,
    pub temporary: String,
    pub release: wgpu::Texture,
}

/// Counted each time a history trades textures instead of copying.
pub const HANDED_OVER: &str = "histories handed over, not copied";
/// Counted each time a history is copied (the textures could not trade).
pub const COPIED: &str = "histories copied";

impl PassContext<'_> {
    /// Make `previous` last frame's `history` before the history is written
    /// again (see [`super::TextureDesc::history`]), and say whether the
    /// history is fresh (created this frame: it holds nothing). The pass
    /// must write every texel of the history it reads back later: after a
    /// trade, the texture it writes holds another frame's leftovers. Both
    /// are textures this pass declared.
    pub fn copy_history(&mut self, history: Tex, previous: Tex) -> Result<bool, RenderError> {
        let (history, previous) = (
            self.declared(history)?.to_owned(),
            self.declared(previous)?.to_owned(),
        );
        self.copy_history_by_name(&history, &previous)
    }

    /// This frame's `output` (all of it written) is next frame's `history`:
    /// from here on `history` names the output's texture, and the texture
    /// it had goes back to the pool when the output's last reader is done.
    /// Both are textures this pass declared.
    pub fn keep_as_history(&mut self, output: Tex, history: Tex) -> Result<(), RenderError> {
        let (output, history) = (
            self.declared(output)?.to_owned(),
            self.declared(history)?.to_owned(),
        );
        self.keep_as_history_by_name(&output, &history)
    }

    /// [`PassContext::copy_history`] by the declared names: a trade renames
    /// textures, so it works on the names, not the handles.
    fn copy_history_by_name(&mut self, history: &str, previous: &str) -> Result<bool, RenderError> {
        let (last, spare) = (self.live(history)?.clone(), self.live(previous)?.clone());
        if self.can_trade(previous, &last, &spare) {
            self.textures.insert(previous, last.clone());
            self.hand_over(history, spare, previous, last);
        } else {
            self.encoder().copy_texture_to_texture(
                last.as_image_copy(),
                spare.as_image_copy(),
                last.size(),
            );
            self.count(COPIED, 1);
        }
        Ok(self.fresh.contains(history))
    }

    /// [`PassContext::keep_as_history`] by the declared names.
    fn keep_as_history_by_name(&mut self, output: &str, history: &str) -> Result<(), RenderError> {
        let (written, last) = (self.live(output)?.clone(), self.live(history)?.clone());
        if self.can_trade(output, &written, &last) {
            self.hand_over(history, written, output, last);
        } else {
            let size = wgpu::Extent3d {
                width: written.width().min(last.width()),
                height: written.height().min(last.height()),
                depth_or_array_layers: 1,
            };
            self.encoder().copy_texture_to_texture(
                written.as_image_copy(),
                last.as_image_copy(),
                size,
            );
            self.count(COPIED, 1);
        }
        Ok(())
    }

    /// `history` names `takes` from now on, and `temporary`'s output slot
    /// gives `release` (the texture the history had) back to the pool.
    fn hand_over(
        &mut self,
        history: &str,
        takes: wgpu::Texture,
        temporary: &str,
        release: wgpu::Texture,
    ) {
        self.textures.insert(history, takes);
        self.handovers.push(Handover {
            persistent: history.to_owned(),
            temporary: temporary.to_owned(),
            release,
        });
        self.count(HANDED_OVER, 1);
    }

    /// Whether `temporary` (texture `a`) and a persistent texture `b` may
    /// trade: alike in every property a pass or the pool sees.
    fn can_trade(&self, temporary: &str, a: &wgpu::Texture, b: &wgpu::Texture) -> bool {
        self.tradable.contains(temporary)
            && a != b
            && a.format() == b.format()
            && a.size() == b.size()
            && a.usage() == b.usage()
            && a.mip_level_count() == b.mip_level_count()
            && a.sample_count() == b.sample_count()
            && a.dimension() == b.dimension()
    }
}
