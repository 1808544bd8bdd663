//! Input from the user: `Mouse (Window)`, `Keyboard (Window)`, `KeyMatch
//! (Keyboard)` and `WindowSize (Window)` read a [`HostInput`] service that the
//! host window provides (`Runtime::provide`), as file nodes read
//! `graph::PatchDir`. Headless hosts provide none: the nodes then output
//! their defaults (pointer at the centre, nothing pressed, a 0 x 0 window).
//! OSC over UDP is in `osc.rs`.
//!
//! The service is shared, not copied per frame: the host keeps an
//! `Arc<HostInput>`, provides it once and writes each frame's state into it
//! with [`HostInput::set`], from any thread (evaluation may run off the UI thread).

mod nodes;

use std::collections::BTreeSet;
use std::sync::RwLock;

use glam::Vec2;

pub use nodes::register;

/// The node types that read the [`HostInput`]: a host evaluates a patch
/// holding one again when the input changes, even while time stands still.
pub const HOST_INPUT_NODES: &[&str] = &[
    "Mouse (Window)",
    "Keyboard (Window)",
    "KeyMatch (Keyboard)",
    "WindowSize (Window)",
];

/// The state of the pointer, keys and window in one frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InputSnapshot {
    /// The pointer in the window, as vvvv measures it: x and y from -1 to 1 across the
    /// window, y up, (0, 0) at the centre. `None` while the pointer is outside.
    pub mouse_position: Option<Vec2>,
    /// Left, middle and right button.
    pub mouse_buttons: [bool; 3],
    /// Wheel steps summed since the window opened (one notch is 1, up positive).
    pub mouse_wheel: f32,
    /// The keys held down, named as egui's `Key::name` spells them (`A`, `Space`, `ArrowLeft`, `F1`).
    pub keys_down: BTreeSet<String>,
    /// The window's client area in physical pixels; `None` when the host has no window.
    pub window_size: Option<(u32, u32)>,
}

impl InputSnapshot {
    /// A pointer position in pixels (origin top left, y down) in a window of `size`,
    /// as the nodes give it: -1 to 1 across, y up.
    pub fn normalized_position(pixel: Vec2, size: Vec2) -> Vec2 {
        if size.x <= 0.0 || size.y <= 0.0 {
            return Vec2::ZERO;
        }
        Vec2::new(pixel.x / size.x * 2.0 - 1.0, 1.0 - pixel.y / size.y * 2.0)
    }
}

/// The host service: the latest [`InputSnapshot`] of one window.
#[derive(Debug, Default)]
pub struct HostInput {
    state: RwLock<InputSnapshot>,
}

impl HostInput {
    pub fn new(snapshot: InputSnapshot) -> Self {
        HostInput {
            state: RwLock::new(snapshot),
        }
    }

    /// Replace the state (the host calls this once a frame).
    pub fn set(&self, snapshot: InputSnapshot) {
        // A writer that panicked left a whole snapshot behind: still good to overwrite.
        *self.state.write().unwrap_or_else(|e| e.into_inner()) = snapshot;
    }

    /// The current state.
    pub fn snapshot(&self) -> InputSnapshot {
        self.state.read().unwrap_or_else(|e| e.into_inner()).clone()
    }
}
