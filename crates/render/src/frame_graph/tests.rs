//! What only the crate can see: the frame's live textures. A pass reaches
//! only the textures it declared (tests/frame_graph.rs checks that through
//! handles), so whether a returned temporary left the live map cannot be
//! observed from outside; these tests look at the map itself.

use std::sync::{Arc, Mutex};

use super::{FrameGraph, PassContext, TextureDesc};

/// Each pass's name, and which of the three textures were live while it recorded.
type Seen = Arc<Mutex<Vec<(&'static str, [bool; 3])>>>;

/// Which of `names` are among the frame's live textures while a pass records.
fn live(cx: &PassContext<'_>, names: [&str; 3]) -> [bool; 3] {
    names.map(|name| cx.textures.contains(name))
}

/// A temporary whose last reader has recorded is back in the pool and gone
/// from the frame: no later pass can reach its memory, whatever it asks by.
#[test]
fn a_returned_temporary_leaves_the_frame() {
    let renderer = crate::renderer::test_renderer();
    let target = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float);
    let names = ["t1", "t2", "t3"];
    let seen: Seen = Arc::default();
    let mut fg = FrameGraph::new((8, 8));
    // a writes t1, b reads t1 and writes t2, c reads t2 and writes t3.
    for (pass_name, read, write) in [
        ("a", None, "t1"),
        ("b", Some("t1"), "t2"),
        ("c", Some("t2"), "t3"),
    ] {
        let mut pass = fg.pass(pass_name, None);
        pass.read_opt(read);
        pass.write(write, target);
        let seen = seen.clone();
        pass.run(move |cx| {
            seen.lock()
                .expect("unpoisoned")
                .push((pass_name, live(cx, names)));
            Ok(())
        });
    }
    fg.request("t3");
    let (report, outputs) = fg.execute(&renderer).expect("executes");
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert!(outputs.contains_key("t3"));
    assert_eq!(
        *seen.lock().expect("unpoisoned"),
        [
            // Each pass's outputs are allocated before it records.
            ("a", [true, false, false]),
            // t1 is still live for its last reader.
            ("b", [true, true, false]),
            // b was t1's last reader: t1 left the frame; t2 is c's to read.
            ("c", [false, true, true]),
        ]
    );
    renderer.wait_idle().expect("drains");
}
