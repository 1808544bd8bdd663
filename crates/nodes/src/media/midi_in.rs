//! `MidiIn`: notes, controllers and the clock's tempo from a MIDI input port
//! (midir on ALSA's sequencer). Messages are read each frame without
//! waiting. MIDI learn: while the editor has armed a node through the
//! [`MidiLearn`] service, the next control change that node receives binds
//! its Controller (and Channel) pins, which the editor then sets.

use std::sync::Mutex;

use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, NodeId, Out, Pins, Registry};
use spreadlight_midi::{Binding, Learn, MidiIn as Port, MidiState, message};

use super::CATEGORY;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "MidiIn",
            CATEGORY,
            "Reads a MIDI input port: the first whose name contains Port (empty: the first \
             port). Channel 1 to 16, or 0 for any. Value gives each Controller's latest value \
             (0 to 1); Notes the velocity (0 to 1, 0 when released) of all 128 notes; Last Note \
             and Last Controller the latest numbers; BPM the tempo of an incoming MIDI clock (24 \
             ticks a beat) and Clock Running its transport. In the editor's inspector, `learn` \
             beside Controller binds the next controller that moves. Without a MIDI sequencer \
             (no /dev/snd/seq) the node says so.",
        )
        .time_dependent()
        .with_pins_node(|p| {
            let pins = MidiInPins::declare(p);
            move || MidiIn {
                pins,
                port: None,
                state: MidiState::default(),
            }
        }),
    );
}

#[derive(Clone, Copy)]
struct MidiInPins {
    port: In<String>,
    channel: In<i64>,
    controller: In<i64>,
    port_name: Out<String>,
    state: StateOutputs,
}

/// The outputs that follow the MIDI state.
#[derive(Clone, Copy)]
struct StateOutputs {
    value: Out<f32>,
    notes: Out<f32>,
    last_note: Out<i64>,
    last_controller: Out<i64>,
    bpm: Out<f32>,
    clock_running: Out<bool>,
}

impl MidiInPins {
    fn declare(p: &mut Pins<'_>) -> Self {
        let port = p.input("Port", String::new());
        let channel = p.input("Channel", 0i64);
        p.range(0.0, 16.0);
        let controller = p.input("Controller", 1i64);
        p.range(0.0, 127.0);
        let state = StateOutputs {
            value: p.output::<f32>("Value"),
            notes: p.output::<f32>("Notes"),
            last_note: p.output::<i64>("Last Note"),
            last_controller: p.output::<i64>("Last Controller"),
            bpm: p.output::<f32>("BPM"),
            clock_running: p.output::<bool>("Clock Running"),
        };
        MidiInPins {
            port,
            channel,
            controller,
            port_name: p.output::<String>("Port Name"),
            state,
        }
    }
}

/// MIDI learn between the editor and the running `MidiIn` nodes: the editor
/// arms a node by id, the node feeds what it receives, the editor takes the
/// binding and sets the pins.
#[derive(Debug, Default)]
pub struct MidiLearn(Mutex<Learn<NodeId>>);

impl MidiLearn {
    fn with<R>(&self, f: impl FnOnce(&mut Learn<NodeId>) -> R) -> R {
        f(&mut self.0.lock().unwrap_or_else(|e| e.into_inner()))
    }

    /// Bind `node`'s Controller to the next control change it receives.
    pub fn arm(&self, node: NodeId) {
        self.with(|l| l.arm(node));
    }

    pub fn cancel(&self) {
        self.with(Learn::cancel);
    }

    pub fn is_armed(&self, node: NodeId) -> bool {
        self.with(|l| l.is_armed(&node))
    }

    /// The binding made for `node`, once.
    pub fn take(&self, node: NodeId) -> Option<Binding<NodeId>> {
        self.with(|l| match l {
            Learn::Bound(b) if b.target == node => l.take(),
            _ => None,
        })
    }

    /// Feed a message `node` received (binds when `node` is armed).
    pub fn feed(&self, node: NodeId, message: &spreadlight_midi::Message) {
        self.with(|l| {
            if l.is_armed(&node) {
                l.feed(message);
            }
        });
    }
}

struct MidiIn {
    pins: MidiInPins,
    /// The open port (or why it did not open) for the Port pin's text.
    port: Option<(String, Result<Port, String>)>,
    state: MidiState,
}

/// What the node outputs from a state: pure, for tests without a port.
fn outputs(
    cx: &mut EvalContext<'_>,
    pins: StateOutputs,
    state: &MidiState,
    channel: u8,
    controllers: &[i64],
) {
    let value = controllers
        .iter()
        .map(|&c| f32::from(state.controller(channel, c.clamp(0, 127) as u8)) / 127.0)
        .collect();
    let notes = (0..128u8)
        .map(|n| f32::from(state.note(channel, n)) / 127.0)
        .collect();
    cx.put(pins.value, value);
    cx.put(pins.notes, notes);
    cx.put(
        pins.last_note,
        vec![state.last_note.map_or(-1, |(_, n)| i64::from(n))],
    );
    cx.put(
        pins.last_controller,
        vec![state.last_controller.map_or(-1, |(_, c)| i64::from(c))],
    );
    cx.put(pins.bpm, vec![state.clock.bpm().unwrap_or(0.0) as f32]);
    cx.put(pins.clock_running, vec![state.clock.running()]);
}

/// The Channel pin: 0 (any) or 1 to 16.
pub(crate) fn channel(cx: &EvalContext<'_>, pin: In<i64>) -> Result<u8, NodeError> {
    let c = cx.first(pin, 0)?;
    u8::try_from(c).ok().filter(|c| *c <= 16).ok_or_else(|| {
        cx.error(
            pin,
            format!("{c} is not a MIDI channel (0 for any, 1 to 16)"),
        )
    })
}

impl Node for MidiIn {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let wanted = cx.get(pins.port)?.first().cloned().unwrap_or_default();
        let channel = channel(cx, pins.channel)?;
        let controllers = cx.get(pins.controller)?.to_vec();
        if self.port.as_ref().is_none_or(|(w, _)| *w != wanted) {
            self.port = Some((
                wanted.clone(),
                Port::open(&wanted).map_err(|e| e.to_string()),
            ));
            self.state = MidiState::default();
        }
        let port = match &self.port {
            Some((_, Ok(port))) => port,
            Some((_, Err(e))) => return Err(cx.error(pins.port, e.clone())),
            None => return Ok(()),
        };
        let learn = cx.service::<MidiLearn>();
        for (micros, bytes) in port.drain() {
            if let Some(m) = message::parse(&bytes) {
                self.state.apply(m, micros);
                if let Some(learn) = &learn {
                    learn.feed(cx.node_id, &m);
                }
            }
        }
        let name = port.name().to_owned();
        outputs(cx, pins.state, &self.state, channel, &controllers);
        cx.put(pins.port_name, vec![name]);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use spreadlight_graph::{EvalContext, FrameClock, NodeId, ProbeLog, Services, Spread};
    use spreadlight_midi::{MidiState, message::parse};

    use super::*;

    #[test]
    fn outputs_follow_the_state_of_fed_messages() {
        let mut state = MidiState::default();
        for bytes in [
            &[0xb0, 7, 127][..],
            &[0xb0, 1, 0],
            &[0x92, 60, 127],
            &[0xfa],
        ] {
            state.apply(parse(bytes).expect("message"), 0);
        }
        for k in 0..25u64 {
            state.apply(parse(&[0xf8]).expect("clock"), k * 500_000 / 24);
        }
        let registry = crate::registry();
        let def = registry.get("MidiIn").expect("MidiIn");
        let inputs: Vec<Arc<Spread>> = def
            .inputs
            .iter()
            .map(|p| Arc::new(p.default.clone()))
            .collect();
        let mut outs: Vec<Arc<Spread>> = def
            .outputs
            .iter()
            .map(|p| Arc::new(Spread::empty(p.ty)))
            .collect();
        let (clock, mut probes, services) =
            (FrameClock::default(), ProbeLog::new(), Services::default());
        let mut cx = EvalContext::new(
            &clock,
            &inputs,
            &def.inputs,
            &mut outs,
            &mut probes,
            &services,
            NodeId(1),
        );
        // MidiIn's pins as its definition declares them.
        let mut declared = None;
        let _ = NodeDef::new("MidiIn", CATEGORY, "").with_pins(|p| {
            declared = Some(MidiInPins::declare(p));
            |_: &mut EvalContext<'_>| Ok(())
        });
        let pins = declared.expect("declared");
        outputs(&mut cx, pins.state, &state, 0, &[7, 1, 2]);
        assert_eq!(*outs[0], Spread::Float(vec![1.0, 0.0, 0.0]));
        let Spread::Float(notes) = &*outs[1] else {
            panic!("notes are floats")
        };
        assert_eq!((notes.len(), notes[60]), (128, 1.0));
        assert_eq!(*outs[2], Spread::Int(vec![60]));
        assert_eq!(*outs[3], Spread::Int(vec![1]));
        let Spread::Float(bpm) = &*outs[4] else {
            panic!("BPM is a float")
        };
        assert!((bpm[0] - 120.0).abs() < 0.01, "{bpm:?}");
        assert_eq!(*outs[5], Spread::Bool(vec![true]));
    }

    #[test]
    fn learn_binds_only_the_armed_node_and_is_taken_once() {
        let learn = MidiLearn::default();
        let cc = parse(&[0xb3, 21, 5]).expect("cc");
        learn.arm(NodeId(4));
        // Another node's controller does not bind node 4.
        learn.feed(NodeId(5), &cc);
        assert!(learn.is_armed(NodeId(4)));
        learn.feed(NodeId(4), &cc);
        assert_eq!(learn.take(NodeId(5)), None);
        let b = learn.take(NodeId(4)).expect("bound");
        assert_eq!((b.channel, b.controller), (4, 21));
        assert_eq!(learn.take(NodeId(4)), None);
        learn.arm(NodeId(4));
        learn.cancel();
        assert!(!learn.is_armed(NodeId(4)));
    }
}
