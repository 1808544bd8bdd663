//! MIDI messages from their bytes, and the bytes of those the nodes send.
//! Channels are 1 to 16 here, as devices label them; on the wire they are 0 to 15.

/// A channel or system real-time message the nodes act on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Message {
    NoteOn {
        channel: u8,
        note: u8,
        velocity: u8,
    },
    /// Also a note-on of velocity 0, as running-status senders write it.
    NoteOff {
        channel: u8,
        note: u8,
    },
    ControlChange {
        channel: u8,
        controller: u8,
        value: u8,
    },
    /// A tick of the MIDI clock: 24 a quarter note.
    Clock,
    Start,
    Continue,
    Stop,
}

/// The message in `bytes` (one whole message, as ports deliver them), or
/// `None` for what the nodes ignore (aftertouch, pitch bend, SysEx, ...) or
/// malformed bytes.
pub fn parse(bytes: &[u8]) -> Option<Message> {
    let (&status, data) = bytes.split_first()?;
    let channel = (status & 0x0f) + 1;
    let byte = |k: usize| data.get(k).copied().filter(|b| *b < 0x80);
    match status {
        0xf8 => Some(Message::Clock),
        0xfa => Some(Message::Start),
        0xfb => Some(Message::Continue),
        0xfc => Some(Message::Stop),
        0x80..=0x8f => Some(Message::NoteOff {
            channel,
            note: byte(0)?,
        }),
        0x90..=0x9f => {
            let (note, velocity) = (byte(0)?, byte(1)?);
            Some(if velocity == 0 {
                Message::NoteOff { channel, note }
            } else {
                Message::NoteOn {
                    channel,
                    note,
                    velocity,
                }
            })
        }
        0xb0..=0xbf => Some(Message::ControlChange {
            channel,
            controller: byte(0)?,
            value: byte(1)?,
        }),
        _ => None,
    }
}

/// The wire status byte of a channel message: `kind` (0x80, 0x90, 0xb0) on
/// `channel` 1 to 16 (clamped).
fn status(kind: u8, channel: u8) -> u8 {
    kind | (channel.clamp(1, 16) - 1)
}

/// The bytes of a control change; numbers over 127 are clamped.
pub fn control_change(channel: u8, controller: u8, value: u8) -> [u8; 3] {
    [status(0xb0, channel), controller.min(127), value.min(127)]
}

/// The bytes of a note-on (velocity 0 is a note-off by convention).
pub fn note_on(channel: u8, note: u8, velocity: u8) -> [u8; 3] {
    [status(0x90, channel), note.min(127), velocity.min(127)]
}

pub fn note_off(channel: u8, note: u8) -> [u8; 3] {
    [status(0x80, channel), note.min(127), 0]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn notes_controllers_and_clock_parse_with_channels_from_one() {
        assert_eq!(
            parse(&[0x93, 60, 100]),
            Some(Message::NoteOn {
                channel: 4,
                note: 60,
                velocity: 100
            })
        );
        assert_eq!(
            parse(&[0x90, 60, 0]),
            Some(Message::NoteOff {
                channel: 1,
                note: 60
            })
        );
        assert_eq!(
            parse(&[0x8f, 61, 64]),
            Some(Message::NoteOff {
                channel: 16,
                note: 61
            })
        );
        assert_eq!(
            parse(&[0xb0, 7, 127]),
            Some(Message::ControlChange {
                channel: 1,
                controller: 7,
                value: 127
            })
        );
        assert_eq!(parse(&[0xf8]), Some(Message::Clock));
        assert_eq!(parse(&[0xfa]), Some(Message::Start));
        assert_eq!(parse(&[0xfc]), Some(Message::Stop));
        // Pitch bend, a cut-off message, a data byte where a status belongs: ignored.
        assert_eq!(parse(&[0xe0, 0, 64]), None);
        assert_eq!(parse(&[0xb0, 7]), None);
        assert_eq!(parse(&[0x40, 1, 2]), None);
        assert_eq!(parse(&[0x90, 200, 1]), None);
        assert_eq!(parse(&[]), None);
    }

    #[test]
    fn sent_messages_round_trip_through_the_parser() {
        assert_eq!(
            parse(&control_change(10, 74, 64)),
            Some(Message::ControlChange {
                channel: 10,
                controller: 74,
                value: 64
            })
        );
        assert_eq!(
            parse(&note_on(16, 36, 127)),
            Some(Message::NoteOn {
                channel: 16,
                note: 36,
                velocity: 127
            })
        );
        assert_eq!(
            parse(&note_off(1, 36)),
            Some(Message::NoteOff {
                channel: 1,
                note: 36
            })
        );
        assert_eq!(control_change(0, 200, 255), [0xb0, 127, 127]);
    }
}
