//! Edits that keep a patch in order: comments and frames, bypass, layout,
//! align and nudge, and the gestures that make and link nodes in one step
//! (a wire dropped on the canvas, a node put into a link, an IOBox from a
//! pin). Each is one undo step.

use spreadlight_graph::{
    CommentDoc, FrameDoc, LinkDoc, NodeDoc, NodeId, PinRef, PinType, Registry, Spread,
};

use super::links::LinkError;
use super::{Annotations, Command, EditorDoc, Entry};
use crate::organise::{layout, measure};

/// Room around a frame made for a selection, in canvas units.
const FRAME_MARGIN: f32 = 8.0;
/// Room above a frame's nodes for its title.
const FRAME_TITLE: f32 = 10.0;

/// The IOBox type that holds values of `ty`, if there is one.
pub fn iobox_for(ty: PinType) -> Option<&'static str> {
    Some(match ty {
        PinType::Float => "IOBox (Value)",
        PinType::Int => "IOBox (Integer)",
        PinType::Bool => "IOBox (Toggle)",
        PinType::String => "IOBox (String)",
        PinType::Vec2 => "IOBox (Vector 2d)",
        PinType::Vec3 => "IOBox (Vector 3d)",
        PinType::Vec4 => "IOBox (Vector 4d)",
        PinType::Color => "IOBox (Color)",
        PinType::Mat4 => "IOBox (Transform)",
        _ => return None,
    })
}

/// The first input of `type_name` a link from an output of type `from` may go
/// into: one of the same type first, then one it converts to.
pub fn input_taking(registry: &Registry, type_name: &str, from: PinType) -> Option<String> {
    let def = registry.get(type_name)?;
    def.inputs
        .iter()
        .find(|p| p.ty == from)
        .or_else(|| def.inputs.iter().find(|p| from.links_to(p.ty)))
        .map(|p| p.name.to_string())
}

/// The first output of `type_name` that may feed an input of type `to`.
pub fn output_feeding(registry: &Registry, type_name: &str, to: PinType) -> Option<String> {
    let def = registry.get(type_name)?;
    def.outputs
        .iter()
        .find(|p| p.ty == to)
        .or_else(|| def.outputs.iter().find(|p| p.ty.links_to(to)))
        .map(|p| p.name.to_string())
}

/// A wire dragged from pins and dropped on empty canvas.
#[derive(Clone, Debug, PartialEq)]
pub enum DroppedWire {
    /// From outputs: the new node takes them on an input.
    Outputs(Vec<PinRef>),
    /// From inputs: the new node feeds them from an output.
    Inputs(Vec<PinRef>),
}

impl EditorDoc {
    /// Run `edit` as one undo step labelled `label`: the commands it executes become one batch.
    pub fn grouped<R>(&mut self, label: &str, edit: impl FnOnce(&mut Self) -> R) -> R {
        let first = self.next_serial;
        let result = edit(self);
        let mut commands = Vec::new();
        let mut last = None;
        while self.undo.back().is_some_and(|e| e.serial >= first) {
            if let Some(entry) = self.undo.pop_back() {
                last = Some((entry.serial, entry.scope));
                commands.push(entry.command);
            }
        }
        if let Some((serial, scope)) = last {
            commands.reverse();
            let command = if commands.len() == 1 {
                commands.remove(0)
            } else {
                Command::Batch(commands)
            };
            self.undo.push_back(Entry {
                label: label.to_owned(),
                command,
                scope,
                serial,
            });
        }
        result
    }

    /// The shown document's comments and frames.
    pub fn annotations(&self) -> Annotations {
        Annotations {
            comments: self.patch().comments.clone(),
            frames: self.patch().frames.clone(),
        }
    }

    /// Replace the comments and frames, as one undo step.
    pub fn set_annotations(&mut self, label: &str, new: Annotations) {
        let old = self.annotations();
        if old == new {
            return;
        }
        self.execute(
            label,
            Command::Annotate {
                old: Box::new(old),
                new: Box::new(new),
            },
        );
    }

    /// Add a comment at `pos`; returns its index.
    pub fn add_comment(&mut self, pos: (f32, f32), text: &str) -> usize {
        let mut a = self.annotations();
        a.comments.push(CommentDoc::new(pos.0, pos.1, text));
        let index = a.comments.len() - 1;
        self.set_annotations("add comment", a);
        index
    }

    pub fn set_comment(&mut self, index: usize, comment: CommentDoc) {
        let mut a = self.annotations();
        if let Some(c) = a.comments.get_mut(index) {
            *c = comment;
            self.set_annotations("edit comment", a);
        }
    }

    pub fn remove_comment(&mut self, index: usize) {
        let mut a = self.annotations();
        if index < a.comments.len() {
            a.comments.remove(index);
            self.set_annotations("delete comment", a);
        }
    }

    /// A frame around `ids` (by their measured sizes); returns its index.
    pub fn frame_around(
        &mut self,
        registry: &Registry,
        ids: &[NodeId],
        title: &str,
    ) -> Option<usize> {
        let patch = self.patch();
        let (mut lo, mut hi) = (
            (f32::INFINITY, f32::INFINITY),
            (f32::NEG_INFINITY, f32::NEG_INFINITY),
        );
        for n in ids.iter().filter_map(|&id| patch.node(id)) {
            let (w, h) = measure::node_size(n, registry, patch);
            lo = (lo.0.min(n.pos.0), lo.1.min(n.pos.1));
            hi = (hi.0.max(n.pos.0 + w), hi.1.max(n.pos.1 + h));
        }
        if !lo.0.is_finite() {
            return None;
        }
        let pos = (lo.0 - FRAME_MARGIN, lo.1 - FRAME_MARGIN - FRAME_TITLE);
        let size = (
            hi.0 - lo.0 + 2.0 * FRAME_MARGIN,
            hi.1 - lo.1 + 2.0 * FRAME_MARGIN + FRAME_TITLE,
        );
        let mut a = self.annotations();
        a.frames.push(FrameDoc::new(
            title,
            (pos.0.round(), pos.1.round()),
            (size.0.round(), size.1.round()),
        ));
        let index = a.frames.len() - 1;
        self.set_annotations("add frame", a);
        Some(index)
    }

    /// The nodes a frame holds: those whose position lies inside it.
    pub fn frame_nodes(&self, index: usize) -> Vec<NodeId> {
        let Some(frame) = self.patch().frames.get(index) else {
            return Vec::new();
        };
        self.patch()
            .nodes
            .iter()
            .filter(|n| frame.holds(n.pos))
            .map(|n| n.id)
            .collect()
    }

    /// Move frame `index` to `to`, and its nodes with it, in one undo step.
    pub fn move_frame(&mut self, index: usize, to: (f32, f32)) {
        let Some(frame) = self.patch().frames.get(index).cloned() else {
            return;
        };
        let d = (to.0 - frame.pos.0, to.1 - frame.pos.1);
        let moves: Vec<(NodeId, (f32, f32))> = self
            .frame_nodes(index)
            .into_iter()
            .filter_map(|id| {
                let p = self.node(id)?.pos;
                Some((id, (p.0 + d.0, p.1 + d.1)))
            })
            .collect();
        self.grouped("move frame", |doc| {
            doc.move_nodes(&moves);
            let mut a = doc.annotations();
            a.frames[index].pos = to;
            doc.set_annotations("move frame", a);
        });
    }

    pub fn set_frame(&mut self, index: usize, frame: FrameDoc) {
        let mut a = self.annotations();
        if let Some(f) = a.frames.get_mut(index) {
            *f = frame;
            self.set_annotations("edit frame", a);
        }
    }

    pub fn remove_frame(&mut self, index: usize) {
        let mut a = self.annotations();
        if index < a.frames.len() {
            a.frames.remove(index);
            self.set_annotations("delete frame", a);
        }
    }

    /// Bypass the nodes, or run them again when all of them are bypassed.
    pub fn toggle_bypass(&mut self, ids: &[NodeId]) {
        let all = ids.iter().filter_map(|&id| self.node(id)).all(|n| n.bypass);
        let nodes: Vec<_> = ids
            .iter()
            .filter_map(|&id| self.node(id).map(|n| (id, n.bypass, !all)))
            .filter(|(_, old, new)| old != new)
            .collect();
        if nodes.is_empty() {
            return;
        }
        let label = if all { "run again" } else { "bypass" };
        self.execute(label, Command::Bypass { nodes });
    }

    /// Lay out `ids` (every node when empty), layers following each other in
    /// `direction`: one undo step. Frames are left where they are.
    pub fn layout(&mut self, registry: &Registry, ids: &[NodeId], direction: layout::Direction) {
        let moves = layout::layout(self.patch(), registry, ids, direction);
        self.grouped("layout", |doc| doc.move_nodes(&moves));
    }

    /// Line `ids` up in a row or a column.
    pub fn align(&mut self, registry: &Registry, ids: &[NodeId]) {
        let moves = layout::align(self.patch(), registry, ids);
        self.grouped("align", |doc| doc.move_nodes(&moves));
    }

    /// Move `ids` by `by` canvas units.
    pub fn nudge(&mut self, ids: &[NodeId], by: (f32, f32)) {
        let moves: Vec<_> = ids
            .iter()
            .filter_map(|&id| {
                let p = self.node(id)?.pos;
                Some((id, (p.0 + by.0, p.1 + by.1)))
            })
            .collect();
        self.grouped("nudge", |doc| doc.move_nodes(&moves));
    }

    fn pin_type(&self, registry: &Registry, pin: &PinRef, input: bool) -> Option<PinType> {
        let def = registry.get(&self.node(pin.node())?.type_name)?;
        let pins = if input { &def.inputs } else { &def.outputs };
        pins.iter().find(|p| p.name == pin.pin()).map(|p| p.ty)
    }

    /// The pin of `type_name` a dropped wire would link to, if it fits.
    pub fn wire_fits(
        &self,
        registry: &Registry,
        type_name: &str,
        wire: &DroppedWire,
    ) -> Option<String> {
        match wire {
            DroppedWire::Outputs(pins) => {
                let ty = self.pin_type(registry, pins.first()?, false)?;
                input_taking(registry, type_name, ty)
            }
            DroppedWire::Inputs(pins) => {
                let ty = self.pin_type(registry, pins.first()?, true)?;
                output_feeding(registry, type_name, ty)
            }
        }
    }

    /// Create a `type_name` node at `pos` linked to the dropped wire's pins, in one undo step.
    pub fn add_linked_node(
        &mut self,
        registry: &Registry,
        type_name: &str,
        pos: (f32, f32),
        wire: &DroppedWire,
    ) -> NodeId {
        let pin = self.wire_fits(registry, type_name, wire);
        self.grouped(&format!("create {type_name}"), |doc| {
            let id = doc.add_node(type_name, pos);
            if let Some(pin) = pin {
                let here = PinRef(id, pin);
                match wire {
                    DroppedWire::Outputs(pins) => {
                        if let Some(from) = pins.first() {
                            let _ = doc.link(registry, from.clone(), here);
                        }
                    }
                    DroppedWire::Inputs(pins) => {
                        for to in pins {
                            let _ = doc.link(registry, here.clone(), to.clone());
                        }
                    }
                }
            }
            id
        })
    }

    /// The pins of `type_name` that would carry `link` through it (input, output).
    pub fn link_fits(
        &self,
        registry: &Registry,
        type_name: &str,
        link: &LinkDoc,
    ) -> Option<(String, String)> {
        let from = self.pin_type(registry, &link.from, false)?;
        let to = self.pin_type(registry, &link.to, true)?;
        Some((
            input_taking(registry, type_name, from)?,
            output_feeding(registry, type_name, to)?,
        ))
    }

    /// Put node `id` into `link`: the link's source feeds it and it feeds the
    /// link's target, in one undo step. Nothing changes when that would not link.
    pub fn insert_into_link(
        &mut self,
        registry: &Registry,
        link: &LinkDoc,
        id: NodeId,
    ) -> Result<(), LinkError> {
        let node = self.node(id).ok_or(LinkError::MissingNode(id))?;
        let type_name = node.type_name.clone();
        let (input, output) =
            self.link_fits(registry, &type_name, link)
                .ok_or_else(|| LinkError::Incompatible {
                    from_type: link.from.to_string(),
                    to_type: type_name.clone(),
                })?;
        let into = PinRef(id, input);
        let out = PinRef(id, output);
        self.validate_link(registry, &link.from, &into)?;
        self.validate_link(registry, &out, &link.to)?;
        self.grouped(&format!("insert {type_name}"), |doc| {
            doc.unlink(&link.from, &link.to);
            doc.link(registry, link.from.clone(), into)?;
            doc.link(registry, out, link.to.clone())
        })
    }

    /// A new `type_name` node at `pos` put into `link`, in one undo step.
    pub fn insert_new_into_link(
        &mut self,
        registry: &Registry,
        link: &LinkDoc,
        type_name: &str,
        pos: (f32, f32),
    ) -> Result<NodeId, LinkError> {
        self.link_fits(registry, type_name, link)
            .ok_or_else(|| LinkError::Incompatible {
                from_type: link.from.to_string(),
                to_type: type_name.to_owned(),
            })?;
        self.grouped(&format!("insert {type_name}"), |doc| {
            let id = doc.add_node(type_name, pos);
            doc.insert_into_link(registry, link, id).map(|()| id)
        })
    }

    /// An IOBox holding `value`, placed left of input `pin` and linked to it, in one undo step.
    pub fn iobox_for_input(
        &mut self,
        registry: &Registry,
        pin: &PinRef,
        value: Spread,
    ) -> Option<NodeId> {
        let ty = self.pin_type(registry, pin, true)?;
        let type_name = iobox_for(ty)?;
        let def = registry.get(type_name)?;
        let value_pin = def.inputs.first()?.name.to_string();
        let value = value.convert_to(def.inputs.first()?.ty)?;
        let target = self.node(pin.node())?;
        let row = registry
            .get(&target.type_name)
            .and_then(|d| d.input_index(pin.pin()))
            .unwrap_or(0) as f32;
        let probe = NodeDoc::new(0, type_name).with(&value_pin, value.clone());
        let (w, _) = measure::node_size(&probe, registry, self.patch());
        let pos = (
            (target.pos.0 - w - layout::LAYER_GAP).round(),
            (target.pos.1 + row * measure::ROW_H / crate::canvas_units::SCALE).round(),
        );
        self.grouped(&format!("IOBox for {pin}"), |doc| {
            let id = doc.add_node(type_name, pos);
            doc.set_value(id, &value_pin, Some(value), false);
            let _ = doc.link(registry, PinRef(id, "Output".to_owned()), pin.clone());
            Some(id)
        })
    }
}
