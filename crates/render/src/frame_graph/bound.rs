//! A pass written once: each texture is declared where it is bound.
//!
//! [`PassBuilder::read`] and [`PassBuilder::write`] give handles a run then
//! binds by WGSL variable name, so a pass used to name each input three
//! times (declared, kept in an `Io` struct, bound). Here the declaration
//! names the variable too, the pass keeps the [`Bindings`], and the run
//! gets them whole:
//!
//! ```ignore
//! let mut pass = fg.pass(PassName::new("SSAO").step("blur x"), owner);
//! pass.input("source", &raw);
//! pass.input("depth", &g.depth);
//! pass.output("output", &blurred, desc);
//! pass.bind(|b| b.buffer("params", &self.params));
//! pass.dispatch_image("ao blur x", BlurKey::Horizontal.key(), size);
//! ```
//!
//! What only the run knows (a buffer chosen per frame, a history's
//! freshness) it adds in [`PassBuilder::run_bound`].

use super::{Bindings, PassBuilder, PassContext, SizeRule, Tex, TextureDesc};
use crate::error::RenderError;
use crate::shaders::ShaderKey;

/// A temporal history and its twin as one pass declared and bound them:
/// the persistent texture the pass writes, and last frame's, which it reads
/// ([`PassContext::copy_history`] hands one to the other).
#[derive(Clone, Copy, Debug)]
pub struct History {
    pub history: Tex,
    pub previous: Tex,
}

impl<'a> PassBuilder<'_, 'a> {
    /// Add to what the pass binds: buffers, samplers, a library's bindings.
    pub fn bind(&mut self, add: impl FnOnce(Bindings<'a>) -> Bindings<'a>) {
        self.bindings = add(std::mem::take(&mut self.bindings));
    }

    /// What the pass binds so far: for a pass run jointly with another
    /// ([`super::FrameGraph::runs_together`]), which binds both passes' resources.
    pub fn bindings(&self) -> &Bindings<'a> {
        &self.bindings
    }

    /// Read texture `name` and bind it at WGSL variable `var`.
    pub fn input(&mut self, var: &'a str, name: &str) -> Tex {
        let tex = self.read(name);
        self.bind(|b| b.texture(var, tex));
        tex
    }

    /// An optional input: neither read nor bound when it is `None`.
    pub fn input_opt(&mut self, var: &'a str, name: Option<&str>) -> Option<Tex> {
        name.map(|name| self.input(var, name))
    }

    /// Write texture `name` (created as `desc` says) and bind it at `var`.
    pub fn output(&mut self, var: &'a str, name: &str, desc: TextureDesc) -> Tex {
        let tex = self.write(name, desc);
        self.bind(|b| b.texture(var, tex));
        tex
    }

    /// A history (`desc` made [`TextureDesc::history`]) at `history`, and
    /// its twin `previous_name` ([`TextureDesc::history_twin`]) at `previous`.
    pub fn history(
        &mut self,
        [history, previous]: [&'a str; 2],
        [name, previous_name]: [&str; 2],
        format: wgpu::TextureFormat,
        size: SizeRule,
    ) -> History {
        History {
            history: self.output(history, name, TextureDesc::history(format).size(size)),
            previous: self.output(
                previous,
                previous_name,
                TextureDesc::history_twin(format).size(size),
            ),
        }
    }

    /// Add the pass: `run` records it with what the declaration bound.
    pub fn run_bound(
        mut self,
        run: impl FnOnce(&mut PassContext<'_>, Bindings<'a>) -> Result<(), RenderError> + 'a,
    ) {
        let bindings = std::mem::take(&mut self.bindings);
        self.run(move |cx| run(cx, bindings));
    }

    /// Add the pass as the most common one: `key`'s `main`, one thread per
    /// pixel of `size` ([`PassContext::dispatch_image`]), bound as declared.
    pub fn dispatch_image(mut self, label: &'a str, key: ShaderKey, size: SizeRule) {
        self.will_dispatch(&key, "main");
        self.run_bound(move |cx, b| cx.dispatch_image(label, &key, b, size.pixels(cx.output_size)));
    }
}

impl PassContext<'_> {
    /// Hand last frame's history to its twin before the pass writes the
    /// history again ([`PassContext::copy_history`]): whether it is fresh,
    /// which is counted under `reset`.
    pub fn hand_over_history(
        &mut self,
        h: History,
        reset: &'static str,
    ) -> Result<bool, RenderError> {
        let fresh = self.copy_history(h.history, h.previous)?;
        if fresh {
            self.count(reset, 1);
        }
        Ok(fresh)
    }
}
