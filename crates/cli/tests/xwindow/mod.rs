//! A virtual X display for the editor window tests: a private Xvfb, and a
//! user's mouse and keyboard on it through XTEST.

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, Stdio};

/// A private X server on a free display, stopped when dropped.
pub struct Xvfb {
    child: Child,
    pub display: String,
}

impl Xvfb {
    /// The `spreadlight` binary set to open its windows on this display
    /// (X11, not a Wayland the test machine may have), with its settings
    /// under `config`.
    pub fn spreadlight(&self, config: &Path) -> Command {
        let mut c = Command::new(env!("CARGO_BIN_EXE_spreadlight"));
        c.env("DISPLAY", &self.display)
            .env_remove("WAYLAND_DISPLAY")
            .env("XDG_RUNTIME_DIR", std::env::temp_dir())
            .env("SPREADLIGHT_CONFIG_DIR", config);
        c
    }

    pub fn start() -> Xvfb {
        let mut child = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1920x1080x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb runs (install it: apt-get install xvfb)");
        // With -displayfd, Xvfb picks a free display and writes its number once it is ready.
        let mut line = String::new();
        BufReader::new(child.stdout.take().expect("stdout"))
            .read_line(&mut line)
            .expect("Xvfb reports its display");
        let display = format!(":{}", line.trim());
        assert!(display.len() > 1, "Xvfb gave no display number");
        Xvfb { child, display }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A user's mouse and keyboard on the virtual display, through XTEST.
pub struct Input {
    pub conn: x11rb::rust_connection::RustConnection,
    root: u32,
    keysyms: Vec<u32>,
    per_keycode: usize,
    min_keycode: u8,
}

impl Input {
    pub fn connect(x: &Xvfb) -> Input {
        use x11rb::connection::Connection;
        use x11rb::protocol::xproto::ConnectionExt;
        let (conn, screen) = x11rb::connect(Some(&x.display)).expect("connects to Xvfb");
        let root = conn.setup().roots[screen].root;
        let (min, max) = (conn.setup().min_keycode, conn.setup().max_keycode);
        let map = conn
            .get_keyboard_mapping(min, max - min + 1)
            .expect("request")
            .reply()
            .expect("keyboard mapping");
        Input {
            conn,
            root,
            keysyms: map.keysyms,
            per_keycode: usize::from(map.keysyms_per_keycode),
            min_keycode: min,
        }
    }

    /// A mapped window of at least `w` x `h` (the editor, once it is up).
    pub fn shown_window(&self, w: u16, h: u16) -> Option<u32> {
        use x11rb::protocol::xproto::{ConnectionExt, MapState};
        let tree = self.conn.query_tree(self.root).ok()?.reply().ok()?;
        tree.children.iter().copied().find(|&win| {
            let mapped = self
                .conn
                .get_window_attributes(win)
                .ok()
                .and_then(|c| c.reply().ok())
                .is_some_and(|a| a.map_state == MapState::VIEWABLE);
            let big = self
                .conn
                .get_geometry(win)
                .ok()
                .and_then(|c| c.reply().ok())
                .is_some_and(|g| g.width >= w && g.height >= h);
            mapped && big
        })
    }

    /// Wait for [`Input::shown_window`] (the editor starting); after a minute, fail.
    pub fn wait_for_window(&self, w: u16, h: u16) -> u32 {
        let waited = std::time::Instant::now();
        loop {
            if let Some(window) = self.shown_window(w, h) {
                return window;
            }
            assert!(
                waited.elapsed().as_secs() < 60,
                "no editor window after a minute"
            );
            std::thread::sleep(std::time::Duration::from_millis(200));
        }
    }

    /// Every mapped top-level window but `except`, with its size.
    pub fn other_windows(&self, except: u32) -> Vec<(u32, (u16, u16))> {
        use x11rb::protocol::xproto::{ConnectionExt, MapState};
        let Some(tree) = self
            .conn
            .query_tree(self.root)
            .ok()
            .and_then(|c| c.reply().ok())
        else {
            return Vec::new();
        };
        tree.children
            .iter()
            .copied()
            .filter(|&win| win != except)
            .filter(|&win| {
                self.conn
                    .get_window_attributes(win)
                    .ok()
                    .and_then(|c| c.reply().ok())
                    .is_some_and(|a| a.map_state == MapState::VIEWABLE)
            })
            .filter_map(|win| {
                let g = self.conn.get_geometry(win).ok()?.reply().ok()?;
                Some((win, (g.width, g.height)))
            })
            .collect()
    }

    /// Where `window` is on the screen, and its size: (x, y, width, height).
    pub fn geometry(&self, window: u32) -> (i16, i16, i16, i16) {
        use x11rb::protocol::xproto::ConnectionExt;
        let size = self
            .conn
            .get_geometry(window)
            .expect("request")
            .reply()
            .expect("geometry");
        let at = self
            .conn
            .translate_coordinates(window, self.root, 0, 0)
            .expect("request")
            .reply()
            .expect("position");
        let side = |v: u16| i16::try_from(v).expect("on screen");
        (at.dst_x, at.dst_y, side(size.width), side(size.height))
    }

    /// Resize `window` to `w` x `h` pixels, as a user dragging its corner would.
    pub fn resize(&self, window: u32, w: u16, h: u16) {
        use x11rb::connection::Connection;
        use x11rb::protocol::xproto::{ConfigureWindowAux, ConnectionExt};
        let size = ConfigureWindowAux::new()
            .width(u32::from(w))
            .height(u32::from(h));
        self.conn.configure_window(window, &size).expect("resize");
        self.conn.flush().expect("flush");
    }

    /// Give `window` the keyboard, as a window manager would on a click.
    pub fn focus(&self, window: u32) {
        use x11rb::connection::Connection;
        use x11rb::protocol::xproto::{ConnectionExt, InputFocus};
        self.conn
            .set_input_focus(InputFocus::POINTER_ROOT, window, x11rb::CURRENT_TIME)
            .expect("focus");
        self.conn.flush().expect("flush");
    }

    /// The whole screen as a PNG (Xvfb's 24-bit screen comes as BGRX).
    pub fn shot(&self, path: &Path) {
        use x11rb::protocol::xproto::{ConnectionExt, ImageFormat};
        let img = self
            .conn
            .get_image(ImageFormat::Z_PIXMAP, self.root, 0, 0, 1920, 1080, !0)
            .expect("request")
            .reply()
            .expect("image");
        let rgba: Vec<u8> = img
            .data
            .chunks(4)
            .flat_map(|p| [p[2], p[1], p[0], 255])
            .collect();
        if let Some(image) = image::RgbaImage::from_raw(1920, 1080, rgba) {
            let _ = image.save(path);
        }
    }

    /// The pixels of a screen rectangle, to see when it changes.
    pub fn region(&self, x: i16, y: i16, w: u16, h: u16) -> Vec<u8> {
        use x11rb::protocol::xproto::{ConnectionExt, ImageFormat};
        self.conn
            .get_image(ImageFormat::Z_PIXMAP, self.root, x, y, w, h, !0)
            .expect("request")
            .reply()
            .expect("image")
            .data
    }

    /// Wait until the screen rectangle differs from `before` (the window drew
    /// what an input asked for): a fixed sleep is too short on a loaded
    /// machine. After a minute it fails with a screenshot.
    pub fn wait_for_change(&self, (x, y, w, h): (i16, i16, u16, u16), before: &[u8], what: &str) {
        let waited = std::time::Instant::now();
        while self.region(x, y, w, h) == before {
            if waited.elapsed().as_secs() >= 60 {
                let shot = std::env::temp_dir().join("spreadlight-window-test.png");
                self.shot(&shot);
                panic!(
                    "{what}: nothing changed in a minute; the screen: {}",
                    shot.display()
                );
            }
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        // The frame that drew it also gave the keyboard to what it opened; one more to be sure.
        std::thread::sleep(std::time::Duration::from_millis(200));
    }

    fn fake(&self, kind: u8, detail: u8, x: i16, y: i16) {
        use x11rb::connection::Connection;
        use x11rb::protocol::xtest::ConnectionExt;
        self.conn
            .xtest_fake_input(kind, detail, 0, self.root, x, y, 0)
            .expect("XTEST");
        self.conn.flush().expect("flush");
        std::thread::sleep(std::time::Duration::from_millis(40));
    }

    /// Move the pointer to `x`, `y` and let the window draw what hovering shows.
    pub fn hover(&self, x: i16, y: i16) {
        const MOTION: u8 = 6;
        self.fake(MOTION, 0, x, y);
        std::thread::sleep(std::time::Duration::from_millis(500));
    }

    pub fn double_click(&self, x: i16, y: i16) {
        // egui counts a click within 0.3 s of the last one as part of it (a
        // triple click is no double-click): start well apart from any before.
        std::thread::sleep(std::time::Duration::from_millis(500));
        const MOTION: u8 = 6;
        const PRESS: u8 = 4;
        const RELEASE: u8 = 5;
        self.fake(MOTION, 0, x, y);
        for _ in 0..2 {
            self.fake(PRESS, 1, x, y);
            self.fake(RELEASE, 1, x, y);
        }
    }

    /// Type a key by its X keysym (lowercase letters are their ASCII code).
    pub fn key(&self, keysym: u32) {
        const PRESS: u8 = 2;
        const RELEASE: u8 = 3;
        let index = self
            .keysyms
            .chunks(self.per_keycode)
            .position(|syms| syms.first() == Some(&keysym))
            .unwrap_or_else(|| panic!("no key for keysym {keysym:#x}"));
        let code = self.min_keycode + u8::try_from(index).expect("a keycode");
        self.fake(PRESS, code, 0, 0);
        self.fake(RELEASE, code, 0, 0);
    }
}
