//! What a patch holds besides its dataflow: comments and frames on the canvas
//! (format version 3). Pure data, as the rest of the document; the runtime
//! never reads them.

use serde::{Deserialize, Serialize};

/// A note on the canvas. Its text is markdown-ish: `#` headings, `**bold**`,
/// `- ` list items, and plain paragraphs (the editor draws them so).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CommentDoc {
    /// Top-left corner, in canvas units (as a node's `pos`).
    pub pos: (f32, f32),
    pub text: String,
}

impl CommentDoc {
    pub fn new(x: f32, y: f32, text: &str) -> Self {
        CommentDoc {
            pos: (x, y),
            text: text.to_owned(),
        }
    }
}

/// A titled, coloured rectangle on the canvas. The nodes whose position lies
/// inside it are its nodes: moving the frame moves them ([`FrameDoc::holds`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameDoc {
    /// Top-left corner, in canvas units.
    pub pos: (f32, f32),
    /// Width and height, in canvas units.
    pub size: (f32, f32),
    #[serde(default)]
    pub title: String,
    /// sRGB, drawn translucent behind the nodes.
    #[serde(default = "default_frame_color")]
    pub color: (u8, u8, u8),
}

/// A calm blue-grey: readable behind nodes of every pin colour.
fn default_frame_color() -> (u8, u8, u8) {
    (70, 90, 120)
}

impl FrameDoc {
    pub fn new(title: &str, pos: (f32, f32), size: (f32, f32)) -> Self {
        FrameDoc {
            pos,
            size,
            title: title.to_owned(),
            color: default_frame_color(),
        }
    }

    /// Whether a point (a node's position) lies inside the frame.
    pub fn holds(&self, p: (f32, f32)) -> bool {
        p.0 >= self.pos.0
            && p.1 >= self.pos.1
            && p.0 <= self.pos.0 + self.size.0
            && p.1 <= self.pos.1 + self.size.1
    }
}
