//! The input nodes over the [`HostInput`] service. They read it every frame
//! (time-dependent), since the user moves without any input pin changing.

use glam::Vec2;
use spreadlight_graph::{EvalContext, NodeDef, Registry};

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
        .time_dependent()
        .with_pins(|p| {
            let position = p.output::<Vec2>("Position");
            let x = p.output::<f32>("X");
            let y = p.output::<f32>("Y");
            let buttons =
                ["Left Button", "Middle Button", "Right Button"].map(|name| p.output::<bool>(name));
            let wheel_out = p.output::<f32>("Wheel");
            let inside = p.output::<bool>("Inside");
            move |cx| {
                let s = snapshot(cx);
                let pos = s
                    .mouse_position
                    .filter(|p| p.is_finite())
                    .unwrap_or(Vec2::ZERO);
                cx.put(position, vec![pos]);
                cx.put(x, vec![pos.x]);
                cx.put(y, vec![pos.y]);
                for (pin, down) in buttons.into_iter().zip(s.mouse_buttons) {
                    cx.put(pin, vec![down]);
                }
                let wheel = if s.mouse_wheel.is_finite() {
                    s.mouse_wheel
                } else {
                    0.0
                };
                cx.put(wheel_out, vec![wheel]);
                cx.put(inside, vec![s.mouse_position.is_some()]);
                Ok(())
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Keyboard (Window)",
            CATEGORY,
            "The keys held down in the host window, by name as egui spells them (`A`, `Space`, \
             `Enter`, `ArrowLeft`, `F1`), sorted; Any Key is on while one is. Headless: none.",
        )
        .time_dependent()
        .with_pins(|p| {
            let keys_out = p.output::<String>("Keys");
            let any_key = p.output::<bool>("Any Key");
            move |cx| {
                let keys: Vec<String> = snapshot(cx).keys_down.into_iter().collect();
                let any = !keys.is_empty();
                cx.put(keys_out, keys);
                cx.put(any_key, vec![any]);
                Ok(())
            }
        }),
    );
    r.add(
        NodeDef::new(
            "KeyMatch (Keyboard)",
            CATEGORY,
            "Per slice of Key Match (a key name, as Keyboard (Window) gives them, any case), \
             whether that key is held down. Headless: never.",
        )
        .time_dependent()
        .with_pins(|p| {
            let key_match = p.input("Key Match", "Space".to_owned());
            let output = p.output::<bool>("Output");
            move |cx| {
                let down = snapshot(cx).keys_down;
                let out: Vec<bool> = cx
                    .get(key_match)?
                    .iter()
                    .map(|want| down.iter().any(|k| k.eq_ignore_ascii_case(want.trim())))
                    .collect();
                cx.put(output, out);
                Ok(())
            }
        }),
    );
    r.add(
        NodeDef::new(
            "WindowSize (Window)",
            CATEGORY,
            "The host window's client area in pixels (Size, Width, Height) and its Aspect ratio \
             (width / height). Headless, or while a window is minimised: 0 x 0 with Aspect 1.",
        )
        .time_dependent()
        .with_pins(|p| {
            let size = p.output::<Vec2>("Size");
            let width = p.output::<i64>("Width");
            let height = p.output::<i64>("Height");
            let aspect_out = p.output::<f32>("Aspect");
            move |cx| {
                let (w, h) = snapshot(cx).window_size.unwrap_or((0, 0));
                let aspect = if w > 0 && h > 0 {
                    w as f32 / h as f32
                } else {
                    1.0
                };
                cx.put(size, vec![Vec2::new(w as f32, h as f32)]);
                cx.put(width, vec![i64::from(w)]);
                cx.put(height, vec![i64::from(h)]);
                cx.put(aspect_out, vec![aspect]);
                Ok(())
            }
        }),
    );
}

/// The host's input this frame, or the defaults when there is no host window.
fn snapshot(cx: &EvalContext<'_>) -> InputSnapshot {
    cx.service::<HostInput>()
        .map(|s| s.snapshot())
        .unwrap_or_default()
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
