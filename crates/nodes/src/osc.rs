//! OSC (Open Sound Control) over UDP: `OSC (Network Receive)` listens on a
//! port and gives the arguments of the latest message per address pattern,
//! `OSC (Network Send)` sends values to a host and port. Packets are encoded
//! and decoded, and address patterns matched, by the `rosc` crate.
//!
//! Both use non-blocking sockets: an evaluation reads what has arrived and
//! sends what it has, and never waits on the network, so a silent sender or
//! a full buffer cannot stall a frame.

use std::collections::HashMap;
use std::net::{SocketAddr, ToSocketAddrs, UdpSocket};

use rosc::address::{Matcher, OscAddress};
use rosc::{OscMessage, OscPacket, OscType};
use spreadlight_graph::{EvalContext, In, Node, NodeDef, NodeError, Out, Registry};

const CATEGORY: &str = "Network";

/// The most packets a receiver reads in one frame; the rest wait for the next frame.
pub const MAX_PACKETS_PER_FRAME: usize = 4096;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "OSC (Network Receive)",
            CATEGORY,
            "Listens for OSC messages on UDP Port (all interfaces). Per slice of Address (an OSC \
             address pattern: `/fader/1`, `/fader/*`, `/osc/[0-9]`, `/{a,b}`; `*` matches within one \
             level, and `*` alone takes every address), Values gives the numeric arguments of the latest matching message (ints, floats, doubles, booleans \
             as 0/1; other arguments are skipped), one bin per address (Values Bin Size), and \
             Received is on in the frames a matching message arrived. Bundles are opened. Reads \
             without waiting, up to 4096 packets a frame. Port 0 lets the system pick a free \
             port; Bound Port says which (link it into a sender's Port).",
        )
        .time_dependent()
        .with_pins_node(|p| {
            let pins = ReceiverPins {
                port: p.input("Port", 9000i64),
                address: p.input("Address", "*".to_owned()),
                values: p.output::<f32>("Values"),
                values_bin_size: p.output::<i64>("Values Bin Size"),
                received: p.output::<bool>("Received"),
                last_address: p.output::<String>("Last Address"),
                bound_port: p.output::<i64>("Bound Port"),
            };
            move || Receiver {
                pins,
                socket: None,
                latest: HashMap::new(),
            }
        }),
    );
    r.add(
        NodeDef::new(
            "OSC (Network Send)",
            CATEGORY,
            "While Send is on, sends one OSC message per slice of Address to Host:Port over UDP \
             every frame, with Values as float arguments: all of them (Bin Size -1), or the \
             Values cut into bins, bin i going to address i (wrapping). Host is resolved once \
             per change (an IP address needs no lookup). Messages Sent counts this frame's. \
             Never waits: a datagram the system cannot take at once is dropped.",
        )
        .sink()
        .with_pins_node(|p| {
            let pins = SenderPins {
                host: p.input("Host", "127.0.0.1".to_owned()),
                port: p.input("Port", 9000i64),
                address: p.input("Address", "/spreadlight".to_owned()),
                values: p.input("Values", 0.0f32),
                bin_size: p.input("Bin Size", -1i64),
                send: p.input("Send", false),
                messages_sent: p.output::<i64>("Messages Sent"),
            };
            move || Sender {
                pins,
                socket: None,
                target: None,
            }
        }),
    );
}

/// A UDP port from an Int pin.
fn port(cx: &EvalContext<'_>, pin: In<i64>) -> Result<u16, NodeError> {
    let p = cx.first(pin, 0)?;
    u16::try_from(p).map_err(|_| cx.error(pin, format!("{p} is not a UDP port (0 to 65535)")))
}

#[derive(Clone, Copy)]
struct ReceiverPins {
    port: In<i64>,
    address: In<String>,
    values: Out<f32>,
    values_bin_size: Out<i64>,
    received: Out<bool>,
    last_address: Out<String>,
    bound_port: Out<i64>,
}

struct Receiver {
    pins: ReceiverPins,
    socket: Option<(u16, UdpSocket)>,
    /// The latest message per pattern, by the pattern's text.
    latest: HashMap<String, OscMessage>,
}

impl Receiver {
    /// The socket for `port`, opened (non-blocking) if the port changed.
    fn socket(&mut self, cx: &EvalContext<'_>, port: u16) -> Result<&UdpSocket, NodeError> {
        if self.socket.as_ref().is_none_or(|(p, _)| *p != port) {
            self.socket = None;
            let socket = UdpSocket::bind(("0.0.0.0", port))
                .and_then(|s| s.set_nonblocking(true).map(|()| s))
                .map_err(|e| {
                    cx.error(
                        self.pins.port,
                        format!("cannot listen on UDP port {port}: {e}"),
                    )
                })?;
            self.latest.clear();
            self.socket = Some((port, socket));
        }
        Ok(&self.socket.as_ref().expect("just opened").1)
    }
}

/// Every message in a packet, bundles opened.
fn messages(packet: OscPacket, out: &mut Vec<OscMessage>) {
    match packet {
        OscPacket::Message(m) => out.push(m),
        OscPacket::Bundle(b) => b.content.into_iter().for_each(|p| messages(p, out)),
    }
}

fn numeric(arg: &OscType) -> Option<f32> {
    match *arg {
        OscType::Int(i) => Some(i as f32),
        OscType::Long(i) => Some(i as f32),
        OscType::Float(f) => Some(f),
        OscType::Double(d) => Some(d as f32),
        OscType::Bool(b) => Some(f32::from(u8::from(b))),
        _ => None,
    }
    .filter(|v| v.is_finite())
}

impl Node for Receiver {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let port = port(cx, pins.port)?;
        // `*` alone takes every address; anything else is an OSC address pattern.
        let patterns: Vec<(String, Option<Matcher>)> = cx
            .get(pins.address)?
            .iter()
            .map(|p| {
                if p == "*" {
                    return Ok((p.clone(), None));
                }
                Matcher::new(p).map(|m| (p.clone(), Some(m))).map_err(|e| {
                    cx.error(
                        pins.address,
                        format!("`{p}` is not an OSC address pattern: {e}"),
                    )
                })
            })
            .collect::<Result<_, _>>()?;
        let socket = self.socket(cx, port)?;
        let bound = socket.local_addr().map_or(0, |a| i64::from(a.port()));
        let mut arrived = Vec::new();
        let mut buf = vec![0u8; rosc::decoder::MTU];
        for _ in 0..MAX_PACKETS_PER_FRAME {
            match socket.recv_from(&mut buf) {
                Ok((len, _)) => {
                    // A malformed packet from the network is skipped, not an error of the patch.
                    if let Ok((_, packet)) = rosc::decoder::decode_udp(&buf[..len]) {
                        messages(packet, &mut arrived);
                    }
                }
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => break,
                // Errors of earlier sends (ICMP) and the like: read on.
                Err(_) => continue,
            }
        }
        let mut received = vec![false; patterns.len()];
        for message in arrived {
            let Ok(address) = OscAddress::new(message.addr.clone()) else {
                continue;
            };
            for (k, (text, matcher)) in patterns.iter().enumerate() {
                if matcher.as_ref().is_none_or(|m| m.match_address(&address)) {
                    received[k] = true;
                    self.latest.insert(text.clone(), message.clone());
                }
            }
        }
        let (mut values, mut sizes, mut addresses) = (Vec::new(), Vec::new(), Vec::new());
        for (text, _) in &patterns {
            let latest = self.latest.get(text);
            let before = values.len();
            values.extend(
                latest
                    .iter()
                    .flat_map(|m| m.args.iter().filter_map(numeric)),
            );
            sizes.push((values.len() - before) as i64);
            addresses.push(latest.map(|m| m.addr.clone()).unwrap_or_default());
        }
        cx.put(pins.values, values);
        cx.put(pins.values_bin_size, sizes);
        cx.put(pins.received, received);
        cx.put(pins.last_address, addresses);
        cx.put(pins.bound_port, vec![bound]);
        Ok(())
    }
}

#[derive(Clone, Copy)]
struct SenderPins {
    host: In<String>,
    port: In<i64>,
    address: In<String>,
    values: In<f32>,
    bin_size: In<i64>,
    send: In<bool>,
    messages_sent: Out<i64>,
}

struct Sender {
    pins: SenderPins,
    socket: Option<UdpSocket>,
    /// The last host and port resolved, and where they led.
    target: Option<((String, u16), SocketAddr)>,
}

impl Sender {
    fn target(
        &mut self,
        cx: &EvalContext<'_>,
        host: &str,
        port: u16,
    ) -> Result<SocketAddr, NodeError> {
        let key = (host.to_owned(), port);
        if let Some((k, addr)) = &self.target
            && *k == key
        {
            return Ok(*addr);
        }
        let addr = (host, port)
            .to_socket_addrs()
            .ok()
            .and_then(|mut a| a.next())
            .ok_or_else(|| cx.error(self.pins.host, format!("cannot resolve host `{host}`")))?;
        self.target = Some((key, addr));
        Ok(addr)
    }
}

impl Node for Sender {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        if !cx.first(pins.send, false)? {
            cx.put(pins.messages_sent, vec![0i64]);
            return Ok(());
        }
        let host = cx.get(pins.host)?.first().cloned().unwrap_or_default();
        let port = port(cx, pins.port)?;
        let target = self.target(cx, &host, port)?;
        let addresses = cx.get(pins.address)?;
        if let Some(bad) = addresses
            .iter()
            .find(|a| rosc::address::verify_address(a).is_err())
        {
            return Err(cx.error(pins.address, format!("`{bad}` is not an OSC address")));
        }
        let values = cx.get(pins.values)?;
        let bins = crate::spreads::bins::bins_of(cx, values.len(), pins.bin_size)?;
        if self.socket.is_none() {
            let socket = UdpSocket::bind(("0.0.0.0", 0))
                .and_then(|s| s.set_nonblocking(true).map(|()| s))
                .map_err(|e| NodeError::Other(format!("cannot open a UDP socket: {e}")))?;
            self.socket = Some(socket);
        }
        let socket = self.socket.as_ref().expect("just opened");
        let mut sent = 0i64;
        for (k, addr) in addresses.iter().enumerate() {
            let args = match bins.get(k % bins.len().max(1)) {
                Some(bin) => values[bin.clone()]
                    .iter()
                    .map(|&v| OscType::Float(v))
                    .collect(),
                None => Vec::new(),
            };
            let packet = OscPacket::Message(OscMessage {
                addr: addr.clone(),
                args,
            });
            let bytes = rosc::encoder::encode(&packet)
                .map_err(|e| NodeError::Other(format!("cannot encode OSC for `{addr}`: {e}")))?;
            match socket.send_to(&bytes, target) {
                Ok(_) => sent += 1,
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {}
                Err(e) => return Err(NodeError::Other(format!("cannot send to {target}: {e}"))),
            }
        }
        // Streams every frame while Send is on, like vvvv's UDP sender.
        cx.reevaluate_next_frame();
        cx.put(pins.messages_sent, vec![sent]);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use std::net::UdpSocket;
    use std::time::{Duration, Instant};

    use rosc::{OscBundle, OscMessage, OscPacket, OscTime, OscType};
    use spreadlight_graph::{FrameClock, NodeDoc, NodeId, Patch, Runtime, Spread};

    use crate::testing::{Harness, floats, ints, strings_of};

    fn message(addr: &str, args: Vec<OscType>) -> OscPacket {
        OscPacket::Message(OscMessage {
            addr: addr.into(),
            args,
        })
    }

    /// Step `h` until `Received` is on somewhere, for at most two seconds.
    fn step_until_received(h: &mut Harness) -> Vec<bool> {
        let start = Instant::now();
        loop {
            let received = h.next::<bool>("Received");
            if received.contains(&true) || start.elapsed() > Duration::from_secs(2) {
                return received;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    #[test]
    fn receiver_reads_loopback_messages_without_blocking() {
        // Port 0: the system picks a free port, so parallel tests never collide.
        let mut h = Harness::new("OSC (Network Receive)");
        h.set("Port", ints(&[0]))
            .set("Address", strings_of(&["/fader/*", "/xy", "*"]));
        // Nothing sent yet: the frame returns at once with nothing received.
        assert_eq!(h.next::<bool>("Received"), [false, false, false]);
        let port = u16::try_from(h.out::<i64>("Bound Port")[0]).expect("a port");
        assert_ne!(port, 0);
        let sender = UdpSocket::bind("127.0.0.1:0").expect("sender");
        let bundle = OscPacket::Bundle(OscBundle {
            timetag: OscTime {
                seconds: 0,
                fractional: 1,
            },
            content: vec![
                message(
                    "/fader/1",
                    vec![
                        OscType::Float(0.5),
                        OscType::String("x".into()),
                        OscType::Int(3),
                    ],
                ),
                message("/other", vec![OscType::Float(9.0)]),
            ],
        });
        let bytes = rosc::encoder::encode(&bundle).expect("encode");
        sender.send_to(&bytes, ("127.0.0.1", port)).expect("send");
        sender
            .send_to(b"not osc", ("127.0.0.1", port))
            .expect("send junk");
        assert_eq!(step_until_received(&mut h), [true, false, true]);
        // `*` holds the last message of the bundle, `/other`.
        assert_eq!(h.out::<f32>("Values"), [0.5, 3.0, 9.0]);
        assert_eq!(h.out::<i64>("Values Bin Size"), [2, 0, 1]);
        assert_eq!(h.out::<String>("Last Address"), ["/fader/1", "", "/other"]);
        // The values hold; Received is a per-frame flag.
        assert_eq!(h.next::<bool>("Received"), [false, false, false]);
        assert_eq!(h.out::<f32>("Values"), [0.5, 3.0, 9.0]);
    }

    #[test]
    fn sender_streams_to_a_loopback_listener() {
        let listener = UdpSocket::bind("127.0.0.1:0").expect("listener");
        listener
            .set_read_timeout(Some(Duration::from_secs(2)))
            .expect("timeout");
        let port = listener.local_addr().expect("addr").port();
        let mut h = Harness::new("OSC (Network Send)");
        h.set("Port", ints(&[port as i64]))
            .set("Address", strings_of(&["/a", "/b"]))
            .set("Values", floats(&[1.0, 2.0, 3.0]))
            .set("Bin Size", ints(&[2]));
        // Send off: nothing goes out.
        assert_eq!(h.next::<i64>("Messages Sent"), [0]);
        h.set("Send", vec![true]);
        assert_eq!(h.next::<i64>("Messages Sent"), [2]);
        let mut buf = [0u8; 1536];
        let mut got = Vec::new();
        for _ in 0..2 {
            let (len, _) = listener.recv_from(&mut buf).expect("a datagram within 2 s");
            let (_, packet) = rosc::decoder::decode_udp(&buf[..len]).expect("osc");
            let OscPacket::Message(m) = packet else {
                panic!("a message")
            };
            got.push((m.addr, m.args));
        }
        assert_eq!(
            got,
            [
                (
                    "/a".to_owned(),
                    vec![OscType::Float(1.0), OscType::Float(2.0)]
                ),
                ("/b".to_owned(), vec![OscType::Float(3.0)]),
            ]
        );
        // With Send held, it sends again next frame although no input changed.
        assert_eq!(h.next::<i64>("Messages Sent"), [2]);
    }

    #[test]
    fn a_patch_talks_to_itself_over_loopback() {
        let mut patch = Patch::default();
        // The receiver listens on a port the system picks; its Bound Port tells the sender.
        patch.add(
            NodeDoc::new(1, "OSC (Network Send)")
                .with("Address", Spread::String(vec!["/loop".into()]))
                .with("Values", Spread::Float(vec![4.0, 2.0]))
                .with("Send", Spread::Bool(vec![true])),
        );
        patch.add(
            NodeDoc::new(2, "OSC (Network Receive)")
                .with("Port", Spread::Int(vec![0]))
                .with("Address", Spread::String(vec!["/loop".into()])),
        );
        patch.add(NodeDoc::new(3, "Probe"));
        patch.link(2, "Values", 3, "Input");
        patch.link(2, "Bound Port", 1, "Port");
        let mut runtime = Runtime::new(crate::registry());
        assert!(runtime.load(&patch).is_empty());
        let start = Instant::now();
        let mut frame = 0;
        let values = loop {
            runtime.evaluate(FrameClock::fixed(frame, 60.0));
            frame += 1;
            let v = runtime.output(NodeId(2), "Values").expect("values").clone();
            if !v.is_empty() || start.elapsed() > Duration::from_secs(2) {
                break v;
            }
            std::thread::sleep(Duration::from_millis(5));
        };
        assert_eq!(*values, Spread::Float(vec![4.0, 2.0]));
        assert!(runtime.node_errors().next().is_none());
    }

    #[test]
    fn bad_ports_and_patterns_are_errors_naming_the_pin() {
        crate::testing::eval_err("OSC (Network Receive)", &[("Port", ints(&[70000]))], "Port");
        crate::testing::eval_err(
            "OSC (Network Receive)",
            &[("Address", strings_of(&["no-slash"]))],
            "Address",
        );
        crate::testing::eval_err(
            "OSC (Network Send)",
            &[
                ("Send", vec![true].into()),
                ("Address", strings_of(&["bad"])),
            ],
            "Address",
        );
    }
}
