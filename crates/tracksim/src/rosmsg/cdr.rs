//! CDR encoding of ROS 2 messages: little-endian plain CDR (XCDR1, encapsulation `CDR_LE`)
//! with its 4-byte header `00 01 00 00`, through `cdr-encoding` (RustDDS's serde CDR). The
//! body is encoded on its own so that alignment (every primitive at a multiple of its size, 8
//! at most) counts from the first byte after the header, as the DDS implementations do.
//!
//! Mapping (serde derive): `f64`/`f32`/integers/`bool` as primitives, `String` as a `uint32`
//! length (with the NUL) then the bytes and a NUL, `Vec<T>` as a `uint32` count then the
//! elements (a ROS `T[]`), a Rust array or tuple as its elements alone (a ROS `T[N]`).

use byteorder::LittleEndian;
use serde::Serialize;
use serde::de::DeserializeOwned;

/// The encapsulation header of little-endian plain CDR (`CDR_LE`, options 0).
pub const CDR_LE_HEADER: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// Why a message could not be encoded or decoded.
#[derive(Debug, thiserror::Error)]
pub enum CdrError {
    /// The payload is shorter than the encapsulation header.
    #[error("CDR payload of {0} bytes has no encapsulation header")]
    Short(usize),
    /// The encapsulation is not little-endian plain CDR.
    #[error("unsupported CDR encapsulation {0:02x?} (expected 00 01: CDR_LE)")]
    Encapsulation([u8; 2]),
    /// The serializer or deserializer refused the value or the bytes.
    #[error("CDR: {0}")]
    Codec(String),
}

/// The CDR bytes of `msg`: the header `00 01 00 00`, then the body.
pub fn encode<T: Serialize>(msg: &T) -> Result<Vec<u8>, CdrError> {
    let mut out = CDR_LE_HEADER.to_vec();
    cdr_encoding::to_writer::<T, LittleEndian, _>(&mut out, msg)
        .map_err(|e| CdrError::Codec(e.to_string()))?;
    Ok(out)
}

/// The message in CDR bytes `data` (header first, as [`encode`] writes them).
pub fn decode<T: DeserializeOwned>(data: &[u8]) -> Result<T, CdrError> {
    if data.len() < 4 {
        return Err(CdrError::Short(data.len()));
    }
    if data[..2] != CDR_LE_HEADER[..2] {
        return Err(CdrError::Encapsulation([data[0], data[1]]));
    }
    cdr_encoding::from_bytes::<T, LittleEndian>(&data[4..])
        .map(|(m, _)| m)
        .map_err(|e| CdrError::Codec(e.to_string()))
}

/// `#[serde(with = "fixed_array")]`: a `[f64; N]` of any length as a ROS `float64[N]` (serde's
/// own impls stop at 32; a covariance has 36).
pub mod fixed_array {
    use serde::de::{Error, SeqAccess, Visitor};
    use serde::ser::SerializeTuple;
    use serde::{Deserializer, Serializer};

    /// Writes the elements alone.
    pub fn serialize<S: Serializer, const N: usize>(a: &[f64; N], s: S) -> Result<S::Ok, S::Error> {
        let mut t = s.serialize_tuple(N)?;
        for x in a {
            t.serialize_element(x)?;
        }
        t.end()
    }

    struct ArrayVisitor<const N: usize>;

    impl<'de, const N: usize> Visitor<'de> for ArrayVisitor<N> {
        type Value = [f64; N];
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            write!(f, "{N} float64 values")
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
            let mut a = [0.0; N];
            for (i, x) in a.iter_mut().enumerate() {
                *x = seq
                    .next_element()?
                    .ok_or_else(|| A::Error::invalid_length(i, &self))?;
            }
            Ok(a)
        }
    }

    /// Reads `N` elements.
    pub fn deserialize<'de, D: Deserializer<'de>, const N: usize>(
        d: D,
    ) -> Result<[f64; N], D::Error> {
        d.deserialize_tuple(N, ArrayVisitor::<N>)
    }
}

/// `#[serde(with = "byte_seq")]`: a `Vec<u8>` as a ROS `uint8[]` written in one piece (the
/// count then the bytes: what a sequence of octets is in CDR, without a call per byte).
pub mod byte_seq {
    use serde::de::{SeqAccess, Visitor};
    use serde::{Deserializer, Serializer};

    /// Writes the count and the bytes.
    pub fn serialize<S: Serializer>(v: &[u8], s: S) -> Result<S::Ok, S::Error> {
        s.serialize_bytes(v)
    }

    struct BytesVisitor;

    impl<'de> Visitor<'de> for BytesVisitor {
        type Value = Vec<u8>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a byte sequence")
        }
        fn visit_bytes<E>(self, v: &[u8]) -> Result<Self::Value, E> {
            Ok(v.to_vec())
        }
        fn visit_byte_buf<E>(self, v: Vec<u8>) -> Result<Self::Value, E> {
            Ok(v)
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
            let mut v = Vec::with_capacity(seq.size_hint().unwrap_or(0));
            while let Some(b) = seq.next_element()? {
                v.push(b);
            }
            Ok(v)
        }
    }

    /// Reads the count and the bytes.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<u8>, D::Error> {
        d.deserialize_byte_buf(BytesVisitor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Serialize, Deserialize, Debug, PartialEq)]
    struct Mixed {
        a: u8,
        b: f64,
        s: String,
        v: Vec<f32>,
        #[serde(with = "byte_seq")]
        data: Vec<u8>,
        #[serde(with = "fixed_array")]
        c: [f64; 36],
    }

    #[test]
    fn header_alignment_and_round_trip() {
        let m = Mixed {
            a: 7,
            b: 1.5,
            s: "ab".into(),
            v: vec![2.0],
            data: vec![1, 2, 3],
            c: [0.25; 36],
        };
        let bytes = encode(&m).unwrap();
        assert_eq!(bytes[..4], CDR_LE_HEADER);
        // a at 0, b aligned to 8 after the header (not counting it).
        assert_eq!(bytes[4], 7);
        assert_eq!(bytes[5..12], [0; 7]);
        assert_eq!(bytes[12..20], 1.5f64.to_le_bytes());
        // "ab": length 3 with the NUL.
        assert_eq!(bytes[20..24], 3u32.to_le_bytes());
        assert_eq!(&bytes[24..27], b"ab\0");
        let back: Mixed = decode(&bytes).unwrap();
        assert_eq!(back, m);
        assert!(matches!(decode::<Mixed>(&[0, 1]), Err(CdrError::Short(2))));
        assert!(matches!(
            decode::<Mixed>(&[0, 0, 0, 0]),
            Err(CdrError::Encapsulation(_))
        ));
    }
}
