//! Spreadlight's MIDI: messages parsed from bytes ([`message`]), the state a
//! stream of them builds (held notes, controller values, the tempo of a
//! 24-per-quarter clock: [`state`]), MIDI learn ([`learn`]), and ports in and
//! out through midir, ALSA's sequencer on Linux ([`port`]).
//!
//! Everything but [`port`] is pure: it is tested by feeding bytes, with no
//! device. A machine without a sequencer (a CI machine, a container) gets
//! [`MidiError::NoSequencer`] from the ports.

pub mod learn;
pub mod message;
pub mod port;
pub mod state;

pub use learn::{Binding, Learn};
pub use message::Message;
pub use port::{MidiError, MidiIn, MidiOut};
pub use state::{ClockTempo, MidiState};
