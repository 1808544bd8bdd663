//! `MidiOut`: controller values and notes to a MIDI output port (midir on
//! ALSA's sequencer). Only what changed is sent, so a patch that holds a
//! value still does not flood the port.

use spreadlight_graph::{EvalContext, Node, NodeDef, NodeError, Registry};
use spreadlight_midi::{MidiOut as Port, message};

use super::{CATEGORY, midi_in::channel};
use crate::spreads::memory::first_bool;

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
        .input("Port", String::new())
        .input("Channel", 1i64)
        .range(1.0, 16.0)
        .input("Controller", 1i64)
        .range(0.0, 127.0)
        .input("Value", 0.0f32)
        .range(0.0, 1.0)
        .input("Note", 60i64)
        .range(0.0, 127.0)
        .input("Velocity", 0.0f32)
        .range(0.0, 1.0)
        .input("Send", false)
        .output::<i64>("Messages Sent")
        .sink()
        .construct(MidiOut::default),
    );
}

#[derive(Default)]
struct MidiOut {
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

fn pairs(cx: &EvalContext<'_>, keys: usize, values: usize) -> Result<Vec<(u8, u8)>, NodeError> {
    let k = cx.slices::<i64>(keys)?;
    let v = cx.slices::<f32>(values)?;
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
        if !first_bool(cx, 6)? {
            cx.set(0, vec![0i64]);
            return Ok(());
        }
        let wanted = cx.slices::<String>(0)?.first().cloned().unwrap_or_default();
        let channel = channel(cx, 1)?.max(1);
        if self.port.as_ref().is_none_or(|(w, _)| *w != wanted) {
            self.port = Some((
                wanted.clone(),
                Port::open(&wanted).map_err(|e| e.to_string()),
            ));
            self.sent_cc.clear();
            self.sent_notes.clear();
        }
        let cc = pairs(cx, 2, 3)?;
        let notes = pairs(cx, 4, 5)?;
        let MidiOut {
            port,
            sent_cc,
            sent_notes,
        } = self;
        // What is not sent is not remembered as sent: a port that opens later gets it all.
        let port = match port {
            Some((_, Ok(port))) => port,
            Some((_, Err(e))) => return Err(cx.input_error(0, e.clone())),
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
        cx.set(0, vec![messages.len() as i64]);
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
