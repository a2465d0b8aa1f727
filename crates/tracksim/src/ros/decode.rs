//! A DDS sample read as its message type only when it is one, within bounds (issue 45).
//!
//! DDS matches a subscription to any writer of the same type *name*; the bytes are the
//! writer's word. A sample is therefore read whole ([`Whole`]): the message, then nothing but
//! (for a message of variable length) up to 3 zero bytes of alignment padding. A sample with
//! bytes left over (a `std_msgs/String` of 47 characters published as a "Twist" has 4) or
//! too few does not decode: the subscription drops and counts it ([`super::dds::Sub`]).
//!
//! The command messages of variable length are read within bounds before anything is kept
//! ([`BoundedJointState`]): at most [`MAX_JOINT_NAMES`] entries per array, names and the
//! frame at most [`MAX_NAME_BYTES`] bytes; a longer one is refused while it is read, so a
//! peer's 50,000 names never become 50,000 strings.

use crate::rosmsg::{Float64, Header, JointState, Time, Twist, TwistStamped};
use serde::Deserializer;
use serde::de::{DeserializeSeed, Error, SeqAccess, Visitor};
use std::marker::PhantomData;

/// Most entries of a joint command's arrays (`name`, `position`, ...).
pub const MAX_JOINT_NAMES: usize = 64;
/// Longest name (a joint's, a frame's) in a command, bytes.
pub const MAX_NAME_BYTES: usize = 256;

/// A message type the node subscribes to, and how its samples are read.
pub trait Bounded: Sized + 'static {
    /// Whether the message's length varies (then a sample may end with up to 3 zero bytes of
    /// padding); a fixed-length message must be exactly its length.
    const VARIABLE: bool;
    /// Reads one message within its bounds.
    type Seed: for<'de> DeserializeSeed<'de, Value = Self> + Default + Clone;
}

impl Bounded for Twist {
    const VARIABLE: bool = false;
    type Seed = PhantomData<Twist>;
}

impl Bounded for TwistStamped {
    const VARIABLE: bool = true;
    type Seed = BoundedTwistStamped;
}

impl Bounded for Float64 {
    const VARIABLE: bool = false;
    type Seed = PhantomData<Float64>;
}

impl Bounded for JointState {
    const VARIABLE: bool = true;
    type Seed = BoundedJointState;
}

/// Reads a whole sample of `M`: the message, then no more bytes than padding.
pub struct Whole<M>(PhantomData<M>);

impl<M> Default for Whole<M> {
    fn default() -> Self {
        Whole(PhantomData)
    }
}

impl<M> Clone for Whole<M> {
    fn clone(&self) -> Self {
        Whole(PhantomData)
    }
}

impl<'de, M: Bounded> DeserializeSeed<'de> for Whole<M> {
    type Value = M;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<M, D::Error> {
        // The message, then up to 4 single bytes: what is left of the sample.
        d.deserialize_tuple(5, self)
    }
}

impl<'de, M: Bounded> Visitor<'de> for Whole<M> {
    type Value = M;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a whole message")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<M, A::Error> {
        let m = seq
            .next_element_seed(M::Seed::default())?
            .ok_or_else(|| A::Error::custom("empty sample"))?;
        let mut left = Vec::new();
        // The end of the bytes is an error here: that is the whole message read.
        while let Ok(Some(b)) = seq.next_element::<u8>() {
            left.push(b);
            if left.len() == 4 {
                break;
            }
        }
        let padding = M::VARIABLE && left.len() < 4 && left.iter().all(|&b| b == 0);
        if left.is_empty() || padding {
            Ok(m)
        } else {
            Err(A::Error::custom(format!(
                "{}{} bytes after the message: not this message type",
                if left.len() == 4 { "at least " } else { "" },
                left.len()
            )))
        }
    }
}

/// A string of at most [`MAX_NAME_BYTES`] bytes (checked before it is copied).
#[derive(Clone, Copy, Default)]
struct BoundedString;

impl<'de> DeserializeSeed<'de> for BoundedString {
    type Value = String;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<String, D::Error> {
        d.deserialize_str(self)
    }
}

impl Visitor<'_> for BoundedString {
    type Value = String;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "a string of at most {MAX_NAME_BYTES} bytes")
    }

    fn visit_str<E: Error>(self, v: &str) -> Result<String, E> {
        if v.len() > MAX_NAME_BYTES {
            return Err(E::custom(format!(
                "a name of {} bytes (at most {MAX_NAME_BYTES})",
                v.len()
            )));
        }
        Ok(v.to_string())
    }
}

/// A sequence of at most [`MAX_JOINT_NAMES`] elements, each read by `S`.
#[derive(Clone, Copy, Default)]
struct BoundedSeq<S>(S);

impl<'de, S: DeserializeSeed<'de> + Copy> DeserializeSeed<'de> for BoundedSeq<S> {
    type Value = Vec<S::Value>;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de, S: DeserializeSeed<'de> + Copy> Visitor<'de> for BoundedSeq<S> {
    type Value = Vec<S::Value>;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "at most {MAX_JOINT_NAMES} entries")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        if seq.size_hint().is_some_and(|n| n > MAX_JOINT_NAMES) {
            return Err(A::Error::custom(format!(
                "{} entries (at most {MAX_JOINT_NAMES})",
                seq.size_hint().unwrap_or(0)
            )));
        }
        let mut out = Vec::new();
        while let Some(x) = seq.next_element_seed(self.0)? {
            if out.len() == MAX_JOINT_NAMES {
                return Err(A::Error::custom(format!(
                    "more than {MAX_JOINT_NAMES} entries"
                )));
            }
            out.push(x);
        }
        Ok(out)
    }
}

/// A `sensor_msgs/JointState` command within bounds: arrays of at most [`MAX_JOINT_NAMES`]
/// entries, names and the frame of at most [`MAX_NAME_BYTES`] bytes.
#[derive(Clone, Copy, Default)]
pub struct BoundedJointState;

impl<'de> DeserializeSeed<'de> for BoundedJointState {
    type Value = JointState;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<JointState, D::Error> {
        // The fields in order: header (stamp, frame_id), name, position, velocity, effort.
        d.deserialize_tuple(6, self)
    }
}

impl<'de> Visitor<'de> for BoundedJointState {
    type Value = JointState;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a sensor_msgs/JointState")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<JointState, A::Error> {
        let missing = || A::Error::custom("a JointState cut short");
        let stamp: Time = seq.next_element()?.ok_or_else(missing)?;
        let frame_id = seq.next_element_seed(BoundedString)?.ok_or_else(missing)?;
        let names = BoundedSeq(BoundedString);
        let numbers = BoundedSeq(PhantomData::<f64>);
        Ok(JointState {
            header: Header { stamp, frame_id },
            name: seq.next_element_seed(names)?.ok_or_else(missing)?,
            position: seq.next_element_seed(numbers)?.ok_or_else(missing)?,
            velocity: seq.next_element_seed(numbers)?.ok_or_else(missing)?,
            effort: seq.next_element_seed(numbers)?.ok_or_else(missing)?,
        })
    }
}

/// A `geometry_msgs/TwistStamped` command within bounds: its frame of at most
/// [`MAX_NAME_BYTES`] bytes.
#[derive(Clone, Copy, Default)]
pub struct BoundedTwistStamped;

impl<'de> DeserializeSeed<'de> for BoundedTwistStamped {
    type Value = TwistStamped;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<TwistStamped, D::Error> {
        // The fields in order: header (stamp, frame_id), twist.
        d.deserialize_tuple(3, self)
    }
}

impl<'de> Visitor<'de> for BoundedTwistStamped {
    type Value = TwistStamped;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a geometry_msgs/TwistStamped")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<TwistStamped, A::Error> {
        let missing = || A::Error::custom("a TwistStamped cut short");
        let stamp: Time = seq.next_element()?.ok_or_else(missing)?;
        let frame_id = seq.next_element_seed(BoundedString)?.ok_or_else(missing)?;
        Ok(TwistStamped {
            header: Header { stamp, frame_id },
            twist: seq.next_element()?.ok_or_else(missing)?,
        })
    }
}

/// Reads CDR bytes `data` (header first) as a whole `M` within bounds ([`Whole`]): what the
/// node's subscriptions do with each sample, for tests and tools.
pub fn decode<M: Bounded>(data: &[u8]) -> Result<M, String> {
    // The encapsulation header: `00 01` is little-endian plain CDR (CDR_LE).
    if data.len() < 4 || data[..2] != [0x00, 0x01] {
        return Err("not a little-endian CDR sample".into());
    }
    let mut d = cdr_encoding::CdrDeserializer::<byteorder::LittleEndian>::new(&data[4..]);
    Whole::<M>::default()
        .deserialize(&mut d)
        .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rosmsg::{RosString, Vector3, encode};

    fn twist() -> Twist {
        Twist {
            linear: Vector3 {
                x: 0.5,
                ..Vector3::default()
            },
            angular: Vector3::default(),
        }
    }

    /// Issue 61: the stamped and the plain `cmd_vel` never read as each other, so that the
    /// node can subscribe to both on one topic and count what is neither.
    #[test]
    fn a_stamped_twist_is_not_a_twist_nor_a_twist_stamped() {
        for frame in ["", "base_link", &"f".repeat(MAX_NAME_BYTES)] {
            let st = TwistStamped {
                header: Header {
                    stamp: Time::from_secs(12.5),
                    frame_id: frame.into(),
                },
                twist: twist(),
            };
            let bytes = encode(&st).unwrap();
            assert_eq!(decode::<TwistStamped>(&bytes).unwrap(), st, "{frame}");
            assert!(decode::<Twist>(&bytes).is_err(), "{frame}");
        }
        assert!(decode::<TwistStamped>(&encode(&twist()).unwrap()).is_err());
        let long = TwistStamped {
            header: Header {
                stamp: Time::default(),
                frame_id: "f".repeat(MAX_NAME_BYTES + 1),
            },
            twist: twist(),
        };
        assert!(decode::<TwistStamped>(&encode(&long).unwrap()).is_err());
    }

    #[test]
    fn a_twist_is_exactly_a_twist() {
        let bytes = encode(&twist()).unwrap();
        assert_eq!(bytes.len(), 4 + 48);
        assert_eq!(decode::<Twist>(&bytes).unwrap(), twist());
        // A string of 47 characters under the Twist's name: 52 bytes, 4 left over.
        let s = encode(&RosString {
            data: "x".repeat(47),
        })
        .unwrap();
        assert!(
            decode::<Twist>(&s)
                .unwrap_err()
                .contains("after the message")
        );
        let mut padded = bytes.clone();
        padded.push(0);
        assert!(
            decode::<Twist>(&padded).is_err(),
            "a fixed length: no padding"
        );
        assert!(decode::<Twist>(&bytes[..40]).is_err(), "cut short");
        assert!(
            decode::<Float64>(&bytes).is_err(),
            "a twist is not a Float64"
        );
    }

    #[test]
    fn joint_commands_are_bounded_while_read() {
        let js = |n: usize, len: usize| JointState {
            name: (0..n).map(|i| format!("{i:0len$}")).collect(),
            position: vec![0.1; n],
            ..JointState::default()
        };
        let ok = js(MAX_JOINT_NAMES, 8);
        let mut bytes = encode(&ok).unwrap();
        assert_eq!(decode::<JointState>(&bytes).unwrap(), ok);
        bytes.extend([0, 0, 0]);
        assert_eq!(decode::<JointState>(&bytes).unwrap(), ok, "padding");
        let mut other = bytes.clone();
        other[bytes.len() - 1] = 7;
        assert!(decode::<JointState>(&other).is_err(), "not padding");
        bytes.push(0);
        assert!(decode::<JointState>(&bytes).is_err(), "4 bytes left over");
        let many = encode(&js(50_000, 4)).unwrap();
        let e = decode::<JointState>(&many).unwrap_err();
        assert!(e.contains("more than 64 entries"), "{e}");
        let long = encode(&js(1, MAX_NAME_BYTES + 1)).unwrap();
        assert!(decode::<JointState>(&long).unwrap_err().contains("bytes"));
    }
}
