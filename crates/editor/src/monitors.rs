//! The monitors a show window can open on. eframe does not list them, so the
//! show window runs eframe on its own winit event loop, wrapped in
//! [`Listing`], which reads the list from winit when the loop starts (before
//! eframe opens the window) and hands every event on to eframe. The app
//! then moves its window onto the chosen monitor on its first frame.

use std::sync::{Arc, Mutex};

use winit::application::ApplicationHandler;
use winit::event_loop::ActiveEventLoop;

/// A monitor as the window system reports it, in physical pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct Monitor {
    pub name: String,
    pub position: (i32, i32),
    pub size: (u32, u32),
    pub scale: f64,
}

/// The list, once the event loop has started.
pub type Found = Arc<Mutex<Option<Vec<Monitor>>>>;

/// Which monitor to use: `index` from `--monitor` or the Output's pin, checked against the list.
pub fn pick(monitors: &[Monitor], index: usize) -> Result<&Monitor, String> {
    monitors.get(index).ok_or_else(|| {
        let listed: Vec<String> = monitors
            .iter()
            .enumerate()
            .map(|(k, m)| {
                format!(
                    "{k}: {} {}x{} at ({}, {})",
                    m.name, m.size.0, m.size.1, m.position.0, m.position.1
                )
            })
            .collect();
        format!(
            "monitor {index} does not exist; the window system has {} ({})",
            monitors.len(),
            if listed.is_empty() {
                "none listed".to_owned()
            } else {
                listed.join("; ")
            }
        )
    })
}

/// Lists the monitors when the loop starts, then passes everything to eframe.
pub struct Listing<A> {
    app: A,
    found: Found,
}

impl<A> Listing<A> {
    pub fn new(app: A, found: Found) -> Self {
        Listing { app, found }
    }
}

impl<A: ApplicationHandler<eframe::UserEvent>> ApplicationHandler<eframe::UserEvent>
    for Listing<A>
{
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        {
            let mut found = self.found.lock().unwrap_or_else(|e| e.into_inner());
            if found.is_none() {
                *found = Some(
                    event_loop
                        .available_monitors()
                        .enumerate()
                        .map(|(k, m)| Monitor {
                            name: m.name().unwrap_or_else(|| format!("monitor {k}")),
                            position: (m.position().x, m.position().y),
                            size: (m.size().width, m.size().height),
                            scale: m.scale_factor(),
                        })
                        .collect(),
                );
            }
        }
        self.app.resumed(event_loop);
    }

    fn new_events(&mut self, event_loop: &ActiveEventLoop, cause: winit::event::StartCause) {
        self.app.new_events(event_loop, cause);
    }

    fn user_event(&mut self, event_loop: &ActiveEventLoop, event: eframe::UserEvent) {
        self.app.user_event(event_loop, event);
    }

    fn window_event(
        &mut self,
        event_loop: &ActiveEventLoop,
        window_id: winit::window::WindowId,
        event: winit::event::WindowEvent,
    ) {
        self.app.window_event(event_loop, window_id, event);
    }

    fn device_event(
        &mut self,
        event_loop: &ActiveEventLoop,
        device_id: winit::event::DeviceId,
        event: winit::event::DeviceEvent,
    ) {
        self.app.device_event(event_loop, device_id, event);
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        self.app.about_to_wait(event_loop);
    }

    fn suspended(&mut self, event_loop: &ActiveEventLoop) {
        self.app.suspended(event_loop);
    }

    fn exiting(&mut self, event_loop: &ActiveEventLoop) {
        self.app.exiting(event_loop);
    }

    fn memory_warning(&mut self, event_loop: &ActiveEventLoop) {
        self.app.memory_warning(event_loop);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_monitor_is_a_clear_error_listing_the_others() {
        let monitors = vec![
            Monitor {
                name: "DP-1".into(),
                position: (0, 0),
                size: (1920, 1080),
                scale: 1.0,
            },
            Monitor {
                name: "HDMI-1".into(),
                position: (1920, 0),
                size: (1280, 720),
                scale: 1.0,
            },
        ];
        assert_eq!(pick(&monitors, 1).map(|m| m.position), Ok((1920, 0)));
        let e = pick(&monitors, 2).unwrap_err();
        assert!(e.contains("monitor 2 does not exist"), "{e}");
        assert!(e.contains("1: HDMI-1 1280x720 at (1920, 0)"), "{e}");
        assert!(pick(&[], 0).unwrap_err().contains("none listed"));
    }
}
