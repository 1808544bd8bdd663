//! The document model's commands, each with its undo.
use super::links::LinkError;
use super::*;
use spreadlight_graph::PinType;

fn registry() -> Registry {
    spreadlight_nodes::registry()
}

fn lfo_probe() -> EditorDoc {
    let mut p = Patch::default();
    p.add(NodeDoc::new(1, "LFO"));
    p.add(NodeDoc::new(2, "Probe").at(0.0, 80.0));
    EditorDoc::new(p)
}

#[test]
fn create_undo_redo_restores_exactly() {
    let mut doc = EditorDoc::default();
    let before = doc.patch().clone();
    let id = doc.add_node("LFO", (10.0, 20.0));
    assert!(doc.is_dirty());
    let after = doc.patch().clone();
    assert_eq!(after.node(id).map(|n| n.type_name.as_str()), Some("LFO"));
    assert!(doc.undo());
    assert_eq!(doc.patch(), &before);
    assert!(!doc.is_dirty(), "undo back to the saved state is clean");
    assert!(doc.redo());
    assert_eq!(doc.patch(), &after);
}

#[test]
fn delete_restores_links_and_order_on_undo() {
    let reg = registry();
    let mut doc = lfo_probe();
    doc.add_node("LFO", (0.0, 0.0));
    doc.link(&reg, PinRef::new(1, "Output"), PinRef::new(2, "Input"))
        .expect("link");
    let before = doc.patch().clone();
    doc.delete_nodes(&[NodeId(1)]);
    assert!(doc.patch().links.is_empty());
    assert_eq!(doc.patch().nodes.len(), 2);
    doc.undo();
    assert_eq!(doc.patch(), &before);
}

#[test]
fn incompatible_and_cyclic_links_are_refused() {
    let reg = registry();
    let mut doc = EditorDoc::default();
    let a = doc.add_node("Add (Value)", (0.0, 0.0));
    let b = doc.add_node("Add (Value)", (0.0, 50.0));
    let cam = doc.add_node("Camera", (0.0, 100.0));
    doc.link(
        &reg,
        PinRef(a, "Output".into()),
        PinRef(b, "Input 1".into()),
    )
    .expect("a -> b");
    let cycle = doc.link(
        &reg,
        PinRef(b, "Output".into()),
        PinRef(a, "Input 1".into()),
    );
    assert!(matches!(cycle, Err(LinkError::Cycle { .. })), "{cycle:?}");
    let self_loop = doc.link(
        &reg,
        PinRef(a, "Output".into()),
        PinRef(a, "Input 2".into()),
    );
    assert!(matches!(self_loop, Err(LinkError::Cycle { .. })));
    let def = reg.get("Camera").expect("Camera");
    let out = def
        .outputs
        .iter()
        .find(|p| !p.ty.links_to(PinType::Float))
        .expect("a camera output that is not a number");
    let wrong = doc.link(
        &reg,
        PinRef(cam, out.name.to_string()),
        PinRef(b, "Input 2".into()),
    );
    assert!(
        matches!(wrong, Err(LinkError::Incompatible { .. })),
        "{wrong:?}"
    );
    assert_eq!(doc.patch().links.len(), 1, "refused links leave no trace");
}

#[test]
fn linking_an_input_again_replaces_its_link_in_one_step() {
    let reg = registry();
    let mut doc = EditorDoc::default();
    let a = doc.add_node("LFO", (0.0, 0.0));
    let b = doc.add_node("LFO", (0.0, 0.0));
    let p = doc.add_node("Probe", (0.0, 0.0));
    doc.link(&reg, PinRef(a, "Output".into()), PinRef(p, "Input".into()))
        .expect("link");
    let one = doc.patch().clone();
    doc.link(&reg, PinRef(b, "Output".into()), PinRef(p, "Input".into()))
        .expect("relink");
    assert_eq!(doc.patch().links.len(), 1);
    assert_eq!(doc.patch().links[0].from.node(), b);
    doc.undo();
    assert_eq!(doc.patch(), &one);
}

#[test]
fn value_drags_merge_into_one_undo_step() {
    let mut doc = lfo_probe();
    doc.set_value(NodeId(1), "Period", Some(Spread::Float(vec![2.0])), false);
    doc.set_value(NodeId(1), "Period", Some(Spread::Float(vec![3.0])), true);
    doc.set_value(NodeId(1), "Period", Some(Spread::Float(vec![4.0])), true);
    assert_eq!(
        doc.patch()
            .node(NodeId(1))
            .and_then(|n| n.values.get("Period")),
        Some(&Spread::Float(vec![4.0]))
    );
    doc.undo();
    assert!(doc.patch().node(NodeId(1)).expect("node").values.is_empty());
    assert!(!doc.can_undo());
    doc.redo();
    assert_eq!(
        doc.patch()
            .node(NodeId(1))
            .and_then(|n| n.values.get("Period")),
        Some(&Spread::Float(vec![4.0]))
    );
}

#[test]
fn paste_gives_fresh_ids_and_keeps_inner_links_only() {
    let reg = registry();
    let mut doc = EditorDoc::default();
    let a = doc.add_node("LFO", (0.0, 0.0));
    let b = doc.add_node("Probe", (0.0, 80.0));
    let c = doc.add_node("Probe", (100.0, 80.0));
    doc.link(&reg, PinRef(a, "Output".into()), PinRef(b, "Input".into()))
        .expect("link");
    doc.link(&reg, PinRef(a, "Output".into()), PinRef(c, "Input".into()))
        .expect("link");
    let new = doc.duplicate(&[a, b], (20.0, 20.0));
    assert_eq!(new.len(), 2);
    assert!(new.iter().all(|id| ![a, b, c].contains(id)));
    assert_eq!(
        doc.patch().links.len(),
        3,
        "one inner link copied, the one to c not"
    );
    let pasted = doc.patch().node(new[0]).expect("pasted");
    assert_eq!(pasted.pos, (20.0, 20.0));
    doc.undo();
    assert_eq!(doc.patch().nodes.len(), 3);
    assert_eq!(doc.patch().links.len(), 2);
}

#[test]
fn moves_are_recorded_once_and_undone() {
    let mut doc = lfo_probe();
    doc.move_nodes(&[(NodeId(1), (5.0, 6.0)), (NodeId(2), (0.0, 80.0))]);
    assert_eq!(
        doc.undo_label(),
        Some("move node"),
        "unmoved nodes are not recorded"
    );
    doc.undo();
    assert_eq!(doc.patch().node(NodeId(1)).expect("node").pos, (0.0, 0.0));
}

#[test]
fn unlink_undo_puts_the_link_back() {
    let reg = registry();
    let mut doc = lfo_probe();
    doc.link(&reg, PinRef::new(1, "Output"), PinRef::new(2, "Input"))
        .expect("link");
    let linked = doc.patch().clone();
    assert!(doc.unlink(&PinRef::new(1, "Output"), &PinRef::new(2, "Input")));
    assert!(doc.patch().links.is_empty());
    doc.undo();
    assert_eq!(doc.patch(), &linked);
}

fn linked_lfo_probe() -> (EditorDoc, Registry) {
    let reg = registry();
    let mut doc = lfo_probe();
    doc.link(&reg, PinRef::new(1, "Output"), PinRef::new(2, "Input"))
        .expect("link");
    (doc, reg)
}

#[test]
fn a_node_put_into_a_link_keeps_both_sides_linked_in_one_undo_step() {
    let (mut doc, reg) = linked_lfo_probe();
    let before = doc.patch().clone();
    let link = before.links[0].clone();
    let id = doc
        .insert_new_into_link(&reg, &link, "Sin (Value)", (40.0, 40.0))
        .expect("fits");
    let links = &doc.patch().links;
    assert!(
        links.contains(&LinkDoc::new(1, "Output", id.0, "Input")),
        "{links:?}"
    );
    assert!(
        links.contains(&LinkDoc::new(id.0, "Output", 2, "Input")),
        "{links:?}"
    );
    assert_eq!(links.len(), 2, "the old link is gone");
    assert!(doc.undo());
    assert_eq!(doc.patch(), &before, "one step");
    // A type with no pin for the link is refused and changes nothing.
    assert!(
        doc.insert_new_into_link(&reg, &link, "Probe", (0.0, 0.0))
            .is_err()
    );
    assert_eq!(doc.patch(), &before);
}

#[test]
fn a_dropped_wire_makes_a_linked_node_in_one_undo_step() {
    let reg = registry();
    let mut doc = lfo_probe();
    let wire = organise::DroppedWire::Outputs(vec![PinRef::new(1, "Output")]);
    assert!(doc.wire_fits(&reg, "Sin (Value)", &wire).is_some());
    assert!(
        doc.wire_fits(
            &reg,
            "LFO",
            &organise::DroppedWire::Inputs(vec![PinRef::new(2, "Input")])
        )
        .is_some()
    );
    let id = doc.add_linked_node(&reg, "Sin (Value)", (50.0, 0.0), &wire);
    assert_eq!(
        doc.patch().links,
        vec![LinkDoc::new(1, "Output", id.0, "Input")]
    );
    assert!(doc.undo());
    assert_eq!(doc.patch().nodes.len(), 2);
    assert!(doc.patch().links.is_empty());
}

#[test]
fn an_iobox_from_a_pin_holds_its_spread_and_feeds_it() {
    let reg = registry();
    let mut doc = lfo_probe();
    let pin = PinRef::new(1, "Period");
    let id = doc
        .iobox_for_input(&reg, &pin, Spread::Float(vec![2.5, 4.0]))
        .expect("an IOBox");
    let node = doc.node(id).expect("node");
    assert_eq!(node.type_name, "IOBox (Value)");
    assert_eq!(
        node.values.get("Input"),
        Some(&Spread::Float(vec![2.5, 4.0]))
    );
    assert!(node.pos.0 < 0.0, "left of the node it feeds");
    assert_eq!(
        doc.link_into(&pin).map(|l| l.from.clone()),
        Some(PinRef(id, "Output".into()))
    );
    assert!(doc.undo());
    assert_eq!(doc.patch().nodes.len(), 2, "one step");
}

#[test]
fn a_frame_moves_its_nodes_and_bypass_comments_and_layout_undo() {
    let reg = registry();
    let mut doc = lfo_probe();
    doc.add_node("LFO", (500.0, 500.0));
    let frame = doc
        .frame_around(&reg, &[NodeId(1), NodeId(2)], "Source")
        .expect("a frame");
    assert_eq!(doc.frame_nodes(frame), vec![NodeId(1), NodeId(2)]);
    let pos = doc.patch().frames[frame].pos;
    doc.move_frame(frame, (pos.0 + 30.0, pos.1 + 5.0));
    assert_eq!(doc.node(NodeId(1)).map(|n| n.pos), Some((30.0, 5.0)));
    assert_eq!(doc.node(NodeId(2)).map(|n| n.pos), Some((30.0, 85.0)));
    assert_eq!(
        doc.node(NodeId(3)).map(|n| n.pos),
        Some((500.0, 500.0)),
        "outside: stays"
    );
    assert!(doc.undo());
    assert_eq!(doc.node(NodeId(1)).map(|n| n.pos), Some((0.0, 0.0)));
    assert_eq!(
        doc.patch().frames[frame].pos,
        pos,
        "the frame and its nodes in one step"
    );

    doc.add_comment((0.0, -30.0), "# Hello");
    assert_eq!(doc.patch().comments.len(), 1);
    doc.toggle_bypass(&[NodeId(1)]);
    assert!(doc.node(NodeId(1)).is_some_and(|n| n.bypass));
    assert!(doc.undo());
    assert!(doc.node(NodeId(1)).is_some_and(|n| !n.bypass));

    let before = doc.patch().clone();
    doc.layout(&reg, &[], crate::organise::layout::Direction::LeftToRight);
    assert!(crate::organise::measure::overlapping_nodes(doc.patch(), &reg).is_empty());
    assert!(doc.undo());
    assert_eq!(doc.patch(), &before, "layout is one step");
}
