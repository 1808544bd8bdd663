//! Ports through midir: ALSA's sequencer on Linux. [`MidiIn`] queues what
//! arrives (midir calls back on its own thread) for the node to drain each
//! frame; [`MidiOut`] sends bytes. A machine without a sequencer device
//! (`/dev/snd/seq`: CI machines, containers) gets [`MidiError::NoSequencer`].

use std::sync::{Arc, Mutex};

use midir::{MidiInput, MidiInputConnection, MidiOutput, MidiOutputConnection};
use thiserror::Error;

#[derive(Debug, Error)]
pub enum MidiError {
    #[error("no MIDI sequencer device: {0}")]
    NoSequencer(String),
    #[error("no MIDI {direction} port matches `{wanted}` (ports: {available})")]
    NoPort {
        direction: &'static str,
        wanted: String,
        available: String,
    },
    #[error("MIDI port `{port}`: {message}")]
    Port { port: String, message: String },
}

/// The most messages kept between two drains; older ones are dropped.
const QUEUE: usize = 4096;

/// Messages received: arrival time in microseconds and bytes.
type Queue = Arc<Mutex<Vec<(u64, Vec<u8>)>>>;

/// The index and name of the first port whose name contains `wanted`
/// (case-insensitive; empty takes the first port).
fn choose(names: &[String], wanted: &str) -> Option<usize> {
    let wanted = wanted.to_lowercase();
    names
        .iter()
        .position(|n| n.to_lowercase().contains(&wanted))
}

fn no_port(direction: &'static str, wanted: &str, names: &[String]) -> MidiError {
    MidiError::NoPort {
        direction,
        wanted: wanted.to_owned(),
        available: if names.is_empty() {
            "none".to_owned()
        } else {
            names.join(", ")
        },
    }
}

/// An open input port.
pub struct MidiIn {
    name: String,
    queue: Queue,
    _connection: MidiInputConnection<()>,
}

impl std::fmt::Debug for MidiIn {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MidiIn").field("name", &self.name).finish()
    }
}

impl MidiIn {
    /// Open the first input port whose name contains `wanted`.
    pub fn open(wanted: &str) -> Result<MidiIn, MidiError> {
        let input =
            MidiInput::new("spreadlight").map_err(|e| MidiError::NoSequencer(e.to_string()))?;
        let ports = input.ports();
        let names: Vec<String> = ports
            .iter()
            .map(|p| input.port_name(p).unwrap_or_default())
            .collect();
        let k = choose(&names, wanted).ok_or_else(|| no_port("input", wanted, &names))?;
        let queue: Queue = Arc::default();
        let writer = queue.clone();
        let name = names[k].clone();
        let connection = input
            .connect(
                &ports[k],
                "spreadlight in",
                move |micros, bytes, _| {
                    let mut q = writer.lock().unwrap_or_else(|e| e.into_inner());
                    if q.len() >= QUEUE {
                        q.remove(0);
                    }
                    q.push((micros, bytes.to_vec()));
                },
                (),
            )
            .map_err(|e| MidiError::Port {
                port: name.clone(),
                message: e.to_string(),
            })?;
        Ok(MidiIn {
            name,
            queue,
            _connection: connection,
        })
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    /// Everything received since the last drain, oldest first.
    pub fn drain(&self) -> Vec<(u64, Vec<u8>)> {
        std::mem::take(&mut *self.queue.lock().unwrap_or_else(|e| e.into_inner()))
    }
}

/// An open output port.
pub struct MidiOut {
    name: String,
    connection: MidiOutputConnection,
}

impl std::fmt::Debug for MidiOut {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MidiOut").field("name", &self.name).finish()
    }
}

impl MidiOut {
    /// Open the first output port whose name contains `wanted`.
    pub fn open(wanted: &str) -> Result<MidiOut, MidiError> {
        let output =
            MidiOutput::new("spreadlight").map_err(|e| MidiError::NoSequencer(e.to_string()))?;
        let ports = output.ports();
        let names: Vec<String> = ports
            .iter()
            .map(|p| output.port_name(p).unwrap_or_default())
            .collect();
        let k = choose(&names, wanted).ok_or_else(|| no_port("output", wanted, &names))?;
        let name = names[k].clone();
        let connection =
            output
                .connect(&ports[k], "spreadlight out")
                .map_err(|e| MidiError::Port {
                    port: name.clone(),
                    message: e.to_string(),
                })?;
        Ok(MidiOut { name, connection })
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn send(&mut self, bytes: &[u8]) -> Result<(), MidiError> {
        self.connection.send(bytes).map_err(|e| MidiError::Port {
            port: self.name.clone(),
            message: e.to_string(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ports_are_chosen_by_part_of_their_name() {
        let names = vec!["Midi Through:0".to_owned(), "nanoKONTROL2:0".to_owned()];
        assert_eq!(choose(&names, ""), Some(0));
        assert_eq!(choose(&names, "kontrol"), Some(1));
        assert_eq!(choose(&names, "launchpad"), None);
        let e = no_port("input", "launchpad", &names);
        assert!(
            e.to_string().contains("Midi Through:0, nanoKONTROL2:0"),
            "{e}"
        );
    }

    /// Either the machine has a sequencer, or opening says it has none.
    #[test]
    fn opening_a_port_works_or_says_there_is_no_sequencer() {
        match MidiIn::open("") {
            Ok(port) => assert!(!port.name().is_empty(), "a port without a name"),
            Err(e) => assert!(
                matches!(e, MidiError::NoSequencer(_) | MidiError::NoPort { .. }),
                "{e}"
            ),
        }
    }
}
