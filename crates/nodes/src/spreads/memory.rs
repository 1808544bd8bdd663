//! Nodes that remember earlier frames: `Queue`, `RingBuffer`, `FrameDelay`
//! and `S+H` (sample and hold), one node type per slice type (see `typed!`).
//!
//! They keep state between evaluations, so they must stay right under the
//! runtime's reuse rule (a node whose inputs did not change is not run): a
//! node that would give something different next frame with the same inputs
//! (a held Insert adds a frame each frame, a delay catches up) asks to run
//! again with `reevaluate_next_frame`; otherwise being reused is correct.

use std::collections::VecDeque;

use spreadlight_graph::spread::{slice_count, wrapped};
use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry};

use super::MAX_SLICES;
use crate::typed::Value;

pub fn register(r: &mut Registry) {
    typed!(r, queue, "Queue", "Spreads");
    typed!(r, ring_buffer, "RingBuffer", "Spreads");
    typed!(r, frame_delay, "FrameDelay", "Animation");
    typed!(r, sample_hold, "S+H", "Animation");
}

/// The first slice of an Int pin as a size; negative or huge values are input errors.
fn size_pin(cx: &EvalContext<'_>, pin: In<i64>, default: i64) -> Result<usize, NodeError> {
    let n = cx.first(pin, default)?;
    usize::try_from(n)
        .ok()
        .filter(|&n| n <= MAX_SLICES)
        .ok_or_else(|| cx.error(pin, format!("{n} is not a size from 0 to {MAX_SLICES}")))
}

/// Bins one after the other, with their sizes.
fn flatten<'a, T: Clone + 'a>(bins: impl Iterator<Item = &'a Vec<T>>) -> (Vec<T>, Vec<i64>) {
    let (mut out, mut sizes) = (Vec::new(), Vec::new());
    for bin in bins {
        out.extend_from_slice(bin);
        sizes.push(bin.len() as i64);
    }
    (out, sizes)
}

fn queue<T: Value>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        "Spreads",
        "Remembers the last Frame Count spreads that came in while Insert was on: each frame \
         Insert is on, the whole Input spread goes in front, and the oldest falls out beyond \
         Frame Count. Output is newest first, one bin per frame (Output Bin Size). Reset empties it.",
    )
    .stateful()
    .with_pins_node(|p| {
        let pins = BufferPins {
            input: p.input("Input", default),
            set: p.input("Insert", false),
            size: p.input("Frame Count", 10i64),
            reset: p.input("Reset", false),
            output: p.output::<T>("Output"),
            output_bin_size: p.output::<i64>("Output Bin Size"),
        };
        move || Queue::<T> {
            pins,
            frames: VecDeque::new(),
        }
    })
}

/// The pins `Queue` and `RingBuffer` share (Set is Queue's Insert, Size its Frame Count).
struct BufferPins<T: Value> {
    input: In<T>,
    set: In<bool>,
    size: In<i64>,
    reset: In<bool>,
    output: Out<T>,
    output_bin_size: Out<i64>,
}

impl<T: Value> Clone for BufferPins<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T: Value> Copy for BufferPins<T> {}

struct Queue<T: Value> {
    pins: BufferPins<T>,
    frames: VecDeque<Vec<T>>,
}

impl<T: Value> Node for Queue<T> {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let keep = size_pin(cx, pins.size, 10)?;
        if cx.first(pins.reset, false)? {
            self.frames.clear();
        }
        let insert = cx.first(pins.set, false)?;
        if insert {
            self.frames.push_front(cx.get(pins.input)?.to_vec());
            // A held Insert adds a frame every frame, even when the Input stays the same.
            cx.reevaluate_next_frame();
        }
        self.frames.truncate(keep);
        let (out, sizes) = flatten(self.frames.iter());
        cx.put(pins.output, out);
        cx.put(pins.output_bin_size, sizes);
        Ok(())
    }
}

fn ring_buffer<T: Value>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        "Spreads",
        "Buffer Size slots written in turn: each frame Set is on, the whole Input spread goes \
         into the next slot, overwriting what was there, and Current Slot says which one. \
         Output lists the slots in slot order (not by age), one bin per slot (Output Bin Size; \
         a slot not written yet is empty). Reset empties every slot and starts again at slot 0.",
    )
    .stateful()
    .with_pins_node(|p| {
        let pins = BufferPins {
            input: p.input("Input", default),
            set: p.input("Set", false),
            size: p.input("Buffer Size", 4i64),
            reset: p.input("Reset", false),
            output: p.output::<T>("Output"),
            output_bin_size: p.output::<i64>("Output Bin Size"),
        };
        let current_slot = p.output::<i64>("Current Slot");
        move || RingBuffer::<T> {
            pins,
            current_slot,
            slots: Vec::new(),
            next: 0,
            current: -1,
        }
    })
}

struct RingBuffer<T: Value> {
    pins: BufferPins<T>,
    current_slot: Out<i64>,
    slots: Vec<Vec<T>>,
    next: usize,
    current: i64,
}

impl<T: Value> Node for RingBuffer<T> {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let size = size_pin(cx, pins.size, 4)?;
        if cx.first(pins.reset, false)? {
            self.slots.clear();
            (self.next, self.current) = (0, -1);
        }
        self.slots.resize_with(size, Vec::new);
        if cx.first(pins.set, false)? && size > 0 {
            let slot = self.next % size;
            self.slots[slot] = cx.get(pins.input)?.to_vec();
            self.current = slot as i64;
            self.next = (slot + 1) % size;
            cx.reevaluate_next_frame();
        }
        let (out, sizes) = flatten(self.slots.iter());
        cx.put(pins.output, out);
        cx.put(pins.output_bin_size, sizes);
        cx.put(self.current_slot, vec![self.current]);
        Ok(())
    }
}

fn frame_delay<T: Value + PartialEq>(name: &'static str, default: T) -> NodeDef {
    NodeDef::new(
        name,
        "Animation",
        "Outputs the Input of the previous frame (Default on the first frame): breaks a \
         feedback loop, or compares a value with its last one.",
    )
    .remembers(1)
    .with_pins_node(|p| {
        let input = p.input("Input", default.clone());
        let default = p.input("Default", default);
        let output = p.output::<T>("Output");
        move || FrameDelay::<T> {
            input,
            default,
            output,
            previous: None,
        }
    })
}

struct FrameDelay<T: Value> {
    input: In<T>,
    default: In<T>,
    output: Out<T>,
    previous: Option<Vec<T>>,
}

impl<T: Value + PartialEq> Node for FrameDelay<T> {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let input = cx.get(self.input)?.to_vec();
        let out = match self.previous.take() {
            Some(previous) => previous,
            None => cx.get(self.default)?.to_vec(),
        };
        if out != input {
            // Next frame the output catches up with the input, even if nothing upstream changes.
            cx.reevaluate_next_frame();
        }
        self.previous = Some(input);
        cx.put(self.output, out);
        Ok(())
    }
}

fn sample_hold<T: Value>(name: &'static str, default: T) -> NodeDef {
    let initial = default.clone();
    NodeDef::new(
        name,
        "Animation",
        "Sample and hold, slice by slice: where Set is on, the slice takes the Input's value; \
         elsewhere it keeps the value it last took (the type's default, 0 for values, until \
         then). Input and Set spread together.",
    )
    .stateful()
    .with_pins_node(|p| {
        let input = p.input("Input", default);
        let set = p.input("Set", false);
        let output = p.output::<T>("Output");
        move || SampleHold::<T> {
            input,
            set,
            output,
            held: Vec::new(),
            initial: initial.clone(),
        }
    })
}

struct SampleHold<T: Value> {
    input: In<T>,
    set: In<bool>,
    output: Out<T>,
    held: Vec<T>,
    initial: T,
}

impl<T: Value> Node for SampleHold<T> {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let (input, set) = (cx.get(self.input)?, cx.get(self.set)?);
        let n = slice_count([input.len(), set.len()]);
        self.held.resize(n, self.initial.clone());
        for (i, held) in self.held.iter_mut().enumerate() {
            if *wrapped(set, i) {
                *held = wrapped(input, i).clone();
            }
        }
        cx.put(self.output, self.held.clone());
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use spreadlight_graph::NodeRun;

    use crate::testing::{Harness, floats, ints};

    #[test]
    fn queue_inserts_every_frame_insert_is_held() {
        let mut h = Harness::new("Queue (Spreads)");
        h.set("Frame Count", ints(&[3]))
            .set("Input", floats(&[1.0]));
        assert!(h.next::<f32>("Output").is_empty());
        h.set("Insert", vec![true]);
        assert_eq!(h.next::<f32>("Output"), [1.0]);
        // Held Insert with an unchanged Input still inserts: the node asked to run again.
        assert_eq!(h.step(), NodeRun::Evaluated);
        assert_eq!(h.out::<f32>("Output"), [1.0, 1.0]);
        h.set("Input", floats(&[2.0, 3.0]));
        assert_eq!(h.next::<f32>("Output"), [2.0, 3.0, 1.0, 1.0]);
        assert_eq!(h.out::<i64>("Output Bin Size"), [2, 1, 1]);
        h.set("Input", floats(&[4.0]));
        assert_eq!(h.next::<f32>("Output"), [4.0, 2.0, 3.0, 1.0]);
        h.set("Insert", vec![false]);
        h.step();
        // Insert off: the queue holds and the node is reused from then on.
        assert_eq!(h.step(), NodeRun::Reused);
        assert_eq!(h.out::<f32>("Output"), [4.0, 2.0, 3.0, 1.0]);
        h.set("Reset", vec![true]);
        assert!(h.next::<f32>("Output").is_empty());
    }

    #[test]
    fn ring_buffer_writes_slots_in_turn() {
        let mut h = Harness::new("RingBuffer (Spreads)");
        h.set("Buffer Size", ints(&[3])).set("Set", vec![true]);
        for (v, want) in [
            (1.0, vec![1.0]),
            (2.0, vec![1.0, 2.0]),
            (3.0, vec![1.0, 2.0, 3.0]),
            (4.0, vec![4.0, 2.0, 3.0]),
        ] {
            h.set("Input", floats(&[v]));
            assert_eq!(h.next::<f32>("Output"), want);
        }
        assert_eq!(h.out::<i64>("Current Slot"), [0]);
        h.set("Set", vec![false]);
        h.step();
        assert_eq!(h.step(), NodeRun::Reused);
        assert_eq!(h.out::<f32>("Output"), [4.0, 2.0, 3.0]);
    }

    #[test]
    fn frame_delay_catches_up_without_new_input() {
        let mut h = Harness::new("FrameDelay (Animation)");
        h.set("Input", floats(&[1.0]))
            .set("Default", floats(&[-1.0]));
        assert_eq!(h.next::<f32>("Output"), [-1.0]);
        // Nothing changed upstream, yet the delayed value arrives one frame later.
        assert_eq!(h.next::<f32>("Output"), [1.0]);
        assert_eq!(h.step(), NodeRun::Reused);
        h.set("Input", floats(&[2.0]));
        assert_eq!(h.next::<f32>("Output"), [1.0]);
        assert_eq!(h.next::<f32>("Output"), [2.0]);
    }

    #[test]
    fn sample_and_hold_per_slice() {
        let mut h = Harness::new("S+H (Animation)");
        h.set("Input", floats(&[1.0, 2.0]))
            .set("Set", vec![true, false]);
        assert_eq!(h.next::<f32>("Output"), [1.0, 0.0]);
        h.set("Input", floats(&[5.0, 6.0]))
            .set("Set", vec![false, true]);
        assert_eq!(h.next::<f32>("Output"), [1.0, 6.0]);
        h.set("Input", floats(&[7.0, 8.0]));
        assert_eq!(h.next::<f32>("Output"), [1.0, 8.0]);
    }
}
