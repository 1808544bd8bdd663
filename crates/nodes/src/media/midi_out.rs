//! `MidiOut`: controller values and notes to a MIDI output port (midir on
//! ALSA's sequencer). Only what changed is sent, so a patch that holds a
//! value still does not flood the port.

use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry};
use spreadlight_midi::{MidiOut as Port, message};

use super::{CATEGORY, midi_in::channel};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "MidiOut",
            CATEGORY,
            "While Send is on, sends to the first MIDI output port whose name contains Port \
             (empty: the first port) on Channel (1 to 16): a control change for each Controller \
             whose Value (0 to 1, slice by slice) changed, and a note-on or note-off for each \
             Note whose Velocity (0 to 1; 0 releases) changed. Messages Sent counts this frame's. \
             Without a MIDI sequencer (no /dev/snd/seq) the node says so.",
        )
        .sink()
        .with_pins_node(|p| {
            let port = p.input("Port", String::new());
            let channel = p.input("Channel", 1i64);
            p.range(1.0, 16.0);
            let controller = p.input("Controller", 1i64);
            p.range(0.0, 127.0);
            let value = p.input("Value", 0.0f32);
            p.range(0.0, 1.0);
            let note = p.input("Note", 60i64);
            p.range(0.0, 127.0);
            let velocity = p.input("Velocity", 0.0f32);
            p.range(0.0, 1.0);
            let pins = MidiOutPins {
                port,
                channel,
                controller,
                value,
                note,
                velocity,
                send: p.input("Send", false),
                sent: p.output::<i64>("Messages Sent"),
            };
            move || MidiOut {
                pins,
                port: None,
                sent_cc: Default::default(),
                sent_notes: Default::default(),
            }
        }),
    );
}

#[derive(Clone, Copy)]
struct MidiOutPins {
    port: In<String>,
    channel: In<i64>,
    controller: In<i64>,
    value: In<f32>,
    note: In<i64>,
    velocity: In<f32>,
    send: In<bool>,
    sent: Out<i64>,
}

struct MidiOut {
    pins: MidiOutPins,
    port: Option<(String, Result<Port, String>)>,
    /// What was last sent: (channel, controller) → value and (channel, note) → velocity.
    sent_cc: std::collections::HashMap<(u8, u8), u8>,
    sent_notes: std::collections::HashMap<(u8, u8), u8>,
}

/// A 0..1 value as a 7-bit MIDI value.
fn seven_bits(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 127.0).round() as u8
}

/// The messages that bring the receiver from `sent` to the pins' values,
/// updating `sent`: pure, for tests without a port.
fn changes(
    channel: u8,
    pairs: impl Iterator<Item = (u8, u8)>,
    sent: &mut std::collections::HashMap<(u8, u8), u8>,
    make: impl Fn(u8, u8, u8) -> [u8; 3],
) -> Vec<[u8; 3]> {
    let mut out = Vec::new();
    for (k, v) in pairs {
        if sent.insert((channel, k), v) != Some(v) {
            out.push(make(channel, k, v));
        }
    }
    out
}

fn pairs(cx: &EvalContext<'_>, keys: In<i64>, values: In<f32>) -> Result<Vec<(u8, u8)>, NodeError> {
    let k = cx.get(keys)?;
    let v = cx.get(values)?;
    if k.is_empty() || v.is_empty() {
        return Ok(Vec::new());
    }
    Ok((0..k.len().max(v.len()))
        .map(|i| {
            (
                k[i % k.len()].clamp(0, 127) as u8,
                seven_bits(v[i % v.len()]),
            )
        })
        .collect())
}

impl Node for MidiOut {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        if !cx.first(pins.send, false)? {
            cx.put(pins.sent, vec![0i64]);
            return Ok(());
        }
        let wanted = cx.get(pins.port)?.first().cloned().unwrap_or_default();
        let channel = channel(cx, pins.channel)?.max(1);
        if self.port.as_ref().is_none_or(|(w, _)| *w != wanted) {
            self.port = Some((
                wanted.clone(),
                Port::open(&wanted).map_err(|e| e.to_string()),
            ));
            self.sent_cc.clear();
            self.sent_notes.clear();
        }
        let cc = pairs(cx, pins.controller, pins.value)?;
        let notes = pairs(cx, pins.note, pins.velocity)?;
        let MidiOut {
            pins: _,
            port,
            sent_cc,
            sent_notes,
        } = self;
        // What is not sent is not remembered as sent: a port that opens later gets it all.
        let port = match port {
            Some((_, Ok(port))) => port,
            Some((_, Err(e))) => return Err(cx.error(pins.port, e.clone())),
            None => return Ok(()),
        };
        let mut messages = changes(channel, cc.into_iter(), sent_cc, message::control_change);
        messages.extend(changes(
            channel,
            notes.into_iter(),
            sent_notes,
            |c, n, v| {
                if v == 0 {
                    message::note_off(c, n)
                } else {
                    message::note_on(c, n, v)
                }
            },
        ));
        for m in &messages {
            port.send(m).map_err(|e| NodeError::Other(e.to_string()))?;
        }
        cx.put(pins.sent, vec![messages.len() as i64]);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_changed_values_are_sent() {
        let mut sent = std::collections::HashMap::new();
        let cc = |c, k, v| message::control_change(c, k, v);
        let first = changes(2, [(7, 100), (8, 0)].into_iter(), &mut sent, cc);
        assert_eq!(first, [[0xb1, 7, 100], [0xb1, 8, 0]]);
        let again = changes(2, [(7, 100), (8, 5)].into_iter(), &mut sent, cc);
        assert_eq!(again, [[0xb1, 8, 5]]);
        assert_eq!(seven_bits(0.5), 64);
        assert_eq!(seven_bits(2.0), 127);
    }
}
