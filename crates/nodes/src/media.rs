//! Media nodes: video files as textures (`VideoFile`, in `media/video_file.rs`).

pub mod video_file;

use spreadlight_graph::Registry;

/// How media nodes keep up with the clock, a service hosts provide. Live
/// hosts (`spreadlight play`, the editor) provide [`Playback::Live`]: media
/// nodes then decode ahead on a thread and show the last frame rather than
/// wait for a late one. Without it, or with [`Playback::Exact`] (`render`,
/// `eval`, a farm, `play --fps`), every frame is exact: the node waits for
/// the frame the clock asks for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Playback {
    #[default]
    Exact,
    Live,
}

pub fn register(r: &mut Registry) {
    video_file::register(r);
}
