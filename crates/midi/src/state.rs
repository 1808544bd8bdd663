//! What a stream of MIDI messages amounts to at a moment: the velocity of
//! every held note, the latest value of every controller, and the tempo of
//! the incoming clock.

use std::collections::VecDeque;

use crate::message::Message;

/// Clock ticks a quarter note.
pub const PPQN: usize = 24;

/// The tempo of a MIDI clock from the times of its ticks: the mean tick
/// interval over the last quarter note (24 ticks), which smooths the jitter
/// of a clock sent over USB or a network.
#[derive(Clone, Debug, Default)]
pub struct ClockTempo {
    /// Tick times in microseconds, the newest last; at most one quarter note and one.
    ticks: VecDeque<u64>,
    running: bool,
}

impl ClockTempo {
    /// A tick at `micros` (any monotonic microsecond count: a port's timestamps).
    pub fn tick(&mut self, micros: u64) {
        // A clock that jumps back (a restarted sender) starts over.
        if self.ticks.back().is_some_and(|&t| micros < t) {
            self.ticks.clear();
        }
        self.ticks.push_back(micros);
        while self.ticks.len() > PPQN + 1 {
            self.ticks.pop_front();
        }
    }

    pub fn start(&mut self) {
        self.running = true;
        self.ticks.clear();
    }

    pub fn stop(&mut self) {
        self.running = false;
    }

    /// Whether the sender's transport runs (between Start or Continue and Stop).
    pub fn running(&self) -> bool {
        self.running
    }

    /// Beats (quarter notes) a minute; `None` before two ticks.
    pub fn bpm(&self) -> Option<f64> {
        let (first, last) = (self.ticks.front()?, self.ticks.back()?);
        let intervals = self.ticks.len() - 1;
        if intervals == 0 || last <= first {
            return None;
        }
        let tick = (last - first) as f64 / intervals as f64;
        Some(60e6 / (tick * PPQN as f64))
    }
}

/// Notes, controllers and clock of all 16 channels.
#[derive(Clone, Debug)]
pub struct MidiState {
    /// Velocity of held notes (0 when released), by channel (0-based) and note.
    notes: Vec<[u8; 128]>,
    /// Latest controller values, by channel (0-based) and controller.
    controllers: Vec<[u8; 128]>,
    pub clock: ClockTempo,
    /// The last note-on: channel and note.
    pub last_note: Option<(u8, u8)>,
    /// The last control change: channel and controller.
    pub last_controller: Option<(u8, u8)>,
}

impl Default for MidiState {
    fn default() -> Self {
        MidiState {
            notes: vec![[0; 128]; 16],
            controllers: vec![[0; 128]; 16],
            clock: ClockTempo::default(),
            last_note: None,
            last_controller: None,
        }
    }
}

impl MidiState {
    /// Take `message`, which arrived at `micros`.
    pub fn apply(&mut self, message: Message, micros: u64) {
        let at = |channel: u8| usize::from(channel.clamp(1, 16) - 1);
        match message {
            Message::NoteOn {
                channel,
                note,
                velocity,
            } => {
                self.notes[at(channel)][usize::from(note & 0x7f)] = velocity;
                self.last_note = Some((channel, note));
            }
            Message::NoteOff { channel, note } => {
                self.notes[at(channel)][usize::from(note & 0x7f)] = 0;
            }
            Message::ControlChange {
                channel,
                controller,
                value,
            } => {
                self.controllers[at(channel)][usize::from(controller & 0x7f)] = value;
                self.last_controller = Some((channel, controller));
            }
            Message::Clock => self.clock.tick(micros),
            Message::Start | Message::Continue => self.clock.start(),
            Message::Stop => self.clock.stop(),
        }
    }

    /// The velocity of `note` (0 to 127) on `channel` 1 to 16, or the
    /// largest over all channels for channel 0.
    pub fn note(&self, channel: u8, note: u8) -> u8 {
        Self::read(&self.notes, channel, note)
    }

    /// The value of `controller` on `channel` 1 to 16; for channel 0 that
    /// of the channel that sent it last, else the largest.
    pub fn controller(&self, channel: u8, controller: u8) -> u8 {
        if channel == 0
            && let Some((c, k)) = self.last_controller
            && k == controller
        {
            return Self::read(&self.controllers, c, controller);
        }
        Self::read(&self.controllers, channel, controller)
    }

    fn read(table: &[[u8; 128]], channel: u8, k: u8) -> u8 {
        let k = usize::from(k & 0x7f);
        match channel {
            1..=16 => table[usize::from(channel - 1)][k],
            _ => table.iter().map(|c| c[k]).max().unwrap_or(0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::message::parse;

    #[test]
    fn a_clock_of_24_ticks_a_beat_gives_its_tempo() {
        // 120 BPM: a quarter note is 0.5 s, a tick 20,833 µs.
        let mut clock = ClockTempo::default();
        assert_eq!(clock.bpm(), None);
        for k in 0..60u64 {
            // A little jitter either way, as from USB.
            let jitter = if k % 2 == 0 { 300 } else { 0 };
            clock.tick(k * 500_000 / 24 + jitter);
        }
        let bpm = clock.bpm().expect("tempo");
        assert!((bpm - 120.0).abs() < 0.2, "{bpm}");
        // The sender speeds up to 150 BPM: one quarter note later it reads so.
        let t0 = 60 * 500_000 / 24;
        for k in 1..=25u64 {
            clock.tick(t0 + k * 400_000 / 24);
        }
        let bpm = clock.bpm().expect("tempo");
        assert!((bpm - 150.0).abs() < 0.2, "{bpm}");
        clock.tick(5);
        assert_eq!(clock.bpm(), None, "a clock that jumped back starts over");
    }

    #[test]
    fn notes_and_controllers_follow_the_messages() {
        let mut state = MidiState::default();
        let feed = |state: &mut MidiState, bytes: &[u8]| {
            state.apply(parse(bytes).expect("a message"), 0);
        };
        feed(&mut state, &[0x90, 60, 100]);
        feed(&mut state, &[0x91, 64, 50]);
        assert_eq!(state.note(1, 60), 100);
        assert_eq!(state.note(2, 60), 0);
        assert_eq!(state.note(0, 64), 50);
        feed(&mut state, &[0x90, 60, 0]);
        assert_eq!(state.note(1, 60), 0);
        assert_eq!(state.last_note, Some((2, 64)));
        feed(&mut state, &[0xb2, 7, 90]);
        feed(&mut state, &[0xb0, 7, 10]);
        assert_eq!(state.controller(3, 7), 90);
        // Any channel: the one that moved the controller last.
        assert_eq!(state.controller(0, 7), 10);
        feed(&mut state, &[0xfa]);
        assert!(state.clock.running());
        feed(&mut state, &[0xfc]);
        assert!(!state.clock.running());
    }
}
