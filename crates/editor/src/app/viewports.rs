//! The viewports' state: what each of the two side-panel viewports and the
//! show window's asks for, where each was drawn, and the patch's window
//! (the first viewport's area, where the patch reads the pointer and wheel).

use spreadlight_graph::NodeId;

/// Which texture a viewport shows.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Source {
    /// Nothing until a pin is picked (rendering the Output twice would cost for nothing).
    None,
    /// The selected Output node, or the first one.
    Output,
    Pin(NodeId, String),
}

/// A viewport's wish (what and how big); what it shows comes from the worker's frame.
pub(super) struct Viewport {
    pub(super) source: Source,
    pub(super) size: (u32, u32),
}

impl Viewport {
    pub(super) fn new(source: Source) -> Self {
        Viewport {
            source,
            size: (1, 1),
        }
    }
}

pub(super) struct Viewports {
    /// The two side-panel viewports, then the show window's (`show_window.rs`).
    pub(super) views: [Viewport; 3],
    /// Where each was drawn last frame, in points.
    pub(super) rects: [Option<egui::Rect>; 3],
    /// The first viewport's whole area, in points: the patch's window (`host_input.rs`).
    pub(super) area: Option<egui::Rect>,
    /// Wheel notches summed over the patch's window.
    pub(super) wheel: f32,
}

impl Viewports {
    /// The first viewport shows the patch's Output; the others nothing until a pin is picked.
    pub(super) fn new() -> Self {
        Viewports {
            views: [
                Viewport::new(Source::Output),
                Viewport::new(Source::None),
                Viewport::new(Source::None),
            ],
            rects: [None; 3],
            area: None,
            wheel: 0.0,
        }
    }
}
