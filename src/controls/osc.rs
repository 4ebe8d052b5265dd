//! OSC over UDP (through `rosc`): a packet's messages as [`Event`]s. Bundles are opened
//! (their time tags are not waited for: a live glove wants its values now); arguments that
//! are numbers (int, long, float, double, bool) become numbers, others `None`. A packet
//! that does not decode is counted, never a panic.

use super::live::Event;
use rosc::{OscPacket, OscType};

/// Most messages taken from one packet (bundles nest; a hostile one could nest deep).
const MAX_MESSAGES: usize = 4096;

/// The messages of one UDP packet, or `None` when it is not OSC.
pub fn decode(bytes: &[u8]) -> Option<Vec<Event>> {
    let (_, packet) = rosc::decoder::decode_udp(bytes).ok()?;
    let mut out = Vec::new();
    let mut stack = vec![packet];
    while let Some(p) = stack.pop() {
        match p {
            OscPacket::Message(m) => {
                if out.len() >= MAX_MESSAGES {
                    break;
                }
                out.push(Event::Osc {
                    address: m.addr,
                    args: m.args.iter().map(number).collect(),
                });
            }
            OscPacket::Bundle(b) => stack.extend(b.content.into_iter().rev()),
        }
    }
    Some(out)
}

/// An argument as a number, if it is one.
fn number(a: &OscType) -> Option<f64> {
    match a {
        OscType::Int(i) => Some(f64::from(*i)),
        OscType::Long(i) => Some(*i as f64),
        OscType::Float(x) => Some(f64::from(*x)),
        OscType::Double(x) => Some(*x),
        OscType::Bool(b) => Some(f64::from(u8::from(*b))),
        _ => None,
    }
}

/// One OSC message as a UDP packet's bytes, with float arguments (what a glove sends).
pub fn encode(address: &str, args: &[f32]) -> Vec<u8> {
    let packet = OscPacket::Message(rosc::OscMessage {
        addr: address.to_string(),
        args: args.iter().map(|&x| OscType::Float(x)).collect(),
    });
    rosc::encoder::encode(&packet).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_and_bundles_decode_and_garbage_does_not() {
        let bytes = encode("/glove/flex", &[0.25, 1.0]);
        assert_eq!(
            decode(&bytes),
            Some(vec![Event::Osc {
                address: "/glove/flex".into(),
                args: vec![Some(0.25), Some(1.0)]
            }])
        );
        let bundle = OscPacket::Bundle(rosc::OscBundle {
            timetag: rosc::OscTime {
                seconds: 0,
                fractional: 1,
            },
            content: vec![
                OscPacket::Message(rosc::OscMessage {
                    addr: "/a".into(),
                    args: vec![
                        OscType::Int(3),
                        OscType::String("x".into()),
                        OscType::Bool(true),
                    ],
                }),
                OscPacket::Message(rosc::OscMessage {
                    addr: "/b".into(),
                    args: vec![OscType::Double(0.5)],
                }),
            ],
        });
        let events = decode(&rosc::encoder::encode(&bundle).unwrap()).unwrap();
        assert_eq!(
            events,
            vec![
                Event::Osc {
                    address: "/a".into(),
                    args: vec![Some(3.0), None, Some(1.0)]
                },
                Event::Osc {
                    address: "/b".into(),
                    args: vec![Some(0.5)]
                },
            ]
        );
        // Garbage, truncation and every prefix of a real packet: no panic.
        assert_eq!(decode(b"hello"), None);
        assert_eq!(decode(&[]), None);
        for n in 0..bytes.len() {
            let _ = decode(&bytes[..n]);
        }
        let mut rng = crate::random::SplitMix(5);
        for _ in 0..2000 {
            let mut b = bytes.clone();
            let k = (rng.next_u64() as usize) % b.len();
            b[k] = rng.next_u64() as u8;
            let _ = decode(&b);
        }
    }
}
