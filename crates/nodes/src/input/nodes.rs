//! The input nodes over the [`HostInput`] service. They read it every frame
//! (time-dependent), since the user moves without any input pin changing.

use glam::Vec2;
use spreadlight_graph::{EvalContext, NodeDef, NodeError, Registry};

use super::{HostInput, InputSnapshot};

const CATEGORY: &str = "Input";

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Mouse (Window)",
            CATEGORY,
            "The pointer over the host window: Position from -1 to 1 across the window, y up, \
             (0, 0) at the centre (as vvvv), X and Y the same split, the three buttons, Wheel \
             (notches summed since the window opened) and Inside (whether the pointer is over \
             the window; outside, Position holds the centre). Without a window (headless) \
             everything is at rest: centre, no buttons, wheel 0.",
        )
        .output::<Vec2>("Position")
        .output::<f32>("X")
        .output::<f32>("Y")
        .output::<bool>("Left Button")
        .output::<bool>("Middle Button")
        .output::<bool>("Right Button")
        .output::<f32>("Wheel")
        .output::<bool>("Inside")
        .time_dependent()
        .evaluate(mouse),
    );
    r.add(
        NodeDef::new(
            "Keyboard (Window)",
            CATEGORY,
            "The keys held down in the host window, by name as egui spells them (`A`, `Space`, \
             `Enter`, `ArrowLeft`, `F1`), sorted; Any Key is on while one is. Headless: none.",
        )
        .output::<String>("Keys")
        .output::<bool>("Any Key")
        .time_dependent()
        .evaluate(keyboard),
    );
    r.add(
        NodeDef::new(
            "KeyMatch (Keyboard)",
            CATEGORY,
            "Per slice of Key Match (a key name, as Keyboard (Window) gives them, any case), \
             whether that key is held down. Headless: never.",
        )
        .input("Key Match", "Space".to_owned())
        .output::<bool>("Output")
        .time_dependent()
        .evaluate(key_match),
    );
    r.add(
        NodeDef::new(
            "WindowSize (Window)",
            CATEGORY,
            "The host window's client area in pixels (Size, Width, Height) and its Aspect ratio \
             (width / height). Headless, or while a window is minimised: 0 x 0 with Aspect 1.",
        )
        .output::<Vec2>("Size")
        .output::<i64>("Width")
        .output::<i64>("Height")
        .output::<f32>("Aspect")
        .time_dependent()
        .evaluate(window_size),
    );
}

/// The host's input this frame, or the defaults when there is no host window.
fn snapshot(cx: &EvalContext<'_>) -> InputSnapshot {
    cx.service::<HostInput>()
        .map(|s| s.snapshot())
        .unwrap_or_default()
}

fn mouse(cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
    let s = snapshot(cx);
    let p = s
        .mouse_position
        .filter(|p| p.is_finite())
        .unwrap_or(Vec2::ZERO);
    cx.set(0, vec![p]);
    cx.set(1, vec![p.x]);
    cx.set(2, vec![p.y]);
    for (k, down) in s.mouse_buttons.into_iter().enumerate() {
        cx.set(3 + k, vec![down]);
    }
    let wheel = if s.mouse_wheel.is_finite() {
        s.mouse_wheel
    } else {
        0.0
    };
    cx.set(6, vec![wheel]);
    cx.set(7, vec![s.mouse_position.is_some()]);
    Ok(())
}

fn keyboard(cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
    let keys: Vec<String> = snapshot(cx).keys_down.into_iter().collect();
    let any = !keys.is_empty();
    cx.set(0, keys);
    cx.set(1, vec![any]);
    Ok(())
}

fn key_match(cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
    let down = snapshot(cx).keys_down;
    let out: Vec<bool> = cx
        .slices::<String>(0)?
        .iter()
        .map(|want| down.iter().any(|k| k.eq_ignore_ascii_case(want.trim())))
        .collect();
    cx.set(0, out);
    Ok(())
}

fn window_size(cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
    let (w, h) = snapshot(cx).window_size.unwrap_or((0, 0));
    let aspect = if w > 0 && h > 0 {
        w as f32 / h as f32
    } else {
        1.0
    };
    cx.set(0, vec![Vec2::new(w as f32, h as f32)]);
    cx.set(1, vec![i64::from(w)]);
    cx.set(2, vec![i64::from(h)]);
    cx.set(3, vec![aspect]);
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use glam::Vec2;

    use super::super::{HostInput, InputSnapshot};
    use crate::testing::{Harness, strings_of};

    #[test]
    fn headless_input_nodes_output_defaults() {
        let mut m = Harness::new("Mouse (Window)");
        assert_eq!(m.next::<Vec2>("Position"), [Vec2::ZERO]);
        assert_eq!(m.out::<bool>("Left Button"), [false]);
        assert_eq!(m.out::<bool>("Inside"), [false]);
        let mut k = Harness::new("Keyboard (Window)");
        assert!(k.next::<String>("Keys").is_empty());
        let mut w = Harness::new("WindowSize (Window)");
        assert_eq!(w.next::<Vec2>("Size"), [Vec2::ZERO]);
        assert_eq!(w.out::<f32>("Aspect"), [1.0]);
    }

    #[test]
    fn input_nodes_follow_the_host_service_every_frame() {
        let host = Arc::new(HostInput::default());
        let mut m = Harness::new("Mouse (Window)");
        let mut km = Harness::new("KeyMatch (Keyboard)");
        let mut w = Harness::new("WindowSize (Window)");
        m.provide(host.clone());
        km.provide(host.clone());
        w.provide(host.clone());
        km.set("Key Match", strings_of(&["space", "A"]));
        assert_eq!(km.next::<bool>("Output"), [false, false]);
        let size = Vec2::new(800.0, 600.0);
        host.set(InputSnapshot {
            mouse_position: Some(InputSnapshot::normalized_position(
                Vec2::new(600.0, 150.0),
                size,
            )),
            mouse_buttons: [true, false, true],
            mouse_wheel: 2.0,
            keys_down: ["Space".to_owned()].into(),
            window_size: Some((800, 600)),
        });
        // No input pin changed: the nodes still see the new state.
        assert_eq!(m.next::<Vec2>("Position"), [Vec2::new(0.5, 0.5)]);
        assert_eq!(m.out::<bool>("Right Button"), [true]);
        assert_eq!(m.out::<f32>("Wheel"), [2.0]);
        assert_eq!(m.out::<bool>("Inside"), [true]);
        assert_eq!(km.next::<bool>("Output"), [true, false]);
        assert_eq!(w.next::<i64>("Width"), [800]);
        assert!((w.out::<f32>("Aspect")[0] - 4.0 / 3.0).abs() < 1e-6);
    }
}
