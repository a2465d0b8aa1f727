//! Records of a run held at a bounded memory however long it runs ([`SpillLog`], issue 45):
//! the most recent records stay in memory, older ones go to a spill file on disk as the run
//! goes, a chunk of [`SPILL_CHUNK`] records at a time, and every reader iterates them in order
//! from the file and memory alike. A run's samples (`run::SampleLog`), a sensor's readings
//! and a live session's controls in force at each sample are kept this way.
//!
//! The spill file is an anonymous temporary file (`tempfile::tempfile`: unlinked as it is
//! created), so a killed run leaves nothing behind and a finished one frees it with the log.
//! Records are encoded with `postcard` (every `f64` as its 8 bytes: read back bit for bit), so
//! a run's outputs are the same bytes whether its records were spilled or not. A 10-hour paced
//! session at 100 samples a second holds at most `2 * SPILL_CHUNK` samples in memory (about
//! 7 MB for PackBot), as a 10-minute one does.

use serde::Serialize;
use serde::de::DeserializeOwned;
use std::borrow::Cow;
use std::io::{Read, Seek, SeekFrom, Write};
use std::sync::{Arc, Mutex};

/// Samples moved to the spill file at a time; the memory holds between this many and twice
/// this many of the most recent samples (4096: 41 s at PackBot's 100 Hz output, so a live
/// feed reading the samples since its last visit always finds them in memory).
pub const SPILL_CHUNK: usize = 4096;

/// One spilled chunk: where its bytes are in the file.
#[derive(Clone, Copy, Debug)]
struct Chunk {
    offset: u64,
    len: u64,
}

/// The spill file, shared by clones of a log (each appends at the end and keeps its own list
/// of chunks, so a clone's samples never change).
#[derive(Debug)]
struct Spill {
    file: Mutex<std::fs::File>,
}

/// Records in order: the recent ones in memory, the older ones spilled to disk
/// ([`SPILL_CHUNK`] at a time).
#[derive(Clone, Debug)]
pub struct SpillLog<T> {
    /// The first record (kept in memory: a run's start pose).
    first: Option<T>,
    /// Records per chunk ([`SPILL_CHUNK`] unless the log was made with
    /// [`SpillLog::with_chunk`]).
    chunk: usize,
    /// The chunks written to the spill file, oldest first, each of `chunk` records.
    chunks: Vec<Chunk>,
    spill: Option<Arc<Spill>>,
    /// The samples after the spilled ones.
    recent: Vec<T>,
    /// Set when a spill failed: the log keeps every sample in memory from then on (the run
    /// goes on; only its memory grows), and says why once.
    spill_failed: bool,
}

impl<T> Default for SpillLog<T> {
    fn default() -> Self {
        SpillLog {
            chunk: SPILL_CHUNK,
            first: None,
            chunks: Vec::new(),
            spill: None,
            recent: Vec::new(),
            spill_failed: false,
        }
    }
}

/// What a record of a [`SpillLog`] must be: written and read back by serde.
pub trait Record: Clone + Serialize + DeserializeOwned {}
impl<T: Clone + Serialize + DeserializeOwned> Record for T {}

impl<T: Record + PartialEq> PartialEq for SpillLog<T> {
    fn eq(&self, other: &Self) -> bool {
        self.len() == other.len() && self.iter().zip(other.iter()).all(|(a, b)| *a == *b)
    }
}

impl<T: Record> From<Vec<T>> for SpillLog<T> {
    fn from(samples: Vec<T>) -> Self {
        let mut log = SpillLog::default();
        for s in samples {
            log.push(s);
        }
        log
    }
}

impl<T: Record> FromIterator<T> for SpillLog<T> {
    fn from_iter<I: IntoIterator<Item = T>>(iter: I) -> Self {
        let mut log = SpillLog::default();
        for s in iter {
            log.push(s);
        }
        log
    }
}

impl<'a, T: Record> IntoIterator for &'a SpillLog<T> {
    type Item = Cow<'a, T>;
    type IntoIter = SampleIter<'a, T>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

impl<T: Record> SpillLog<T> {
    /// An empty log.
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty log whose chunks hold `records` records (at least 1): a log of large records
    /// (a lidar's scans, a camera's frames) keeps fewer of them in memory.
    pub fn with_chunk(records: usize) -> Self {
        SpillLog {
            chunk: records.max(1),
            ..Self::default()
        }
    }

    /// Appends a sample; spills the oldest chunk in memory to disk when twice that
    /// many are held.
    pub fn push(&mut self, s: T) {
        if self.first.is_none() {
            self.first = Some(s.clone());
        }
        self.recent.push(s);
        if self.recent.len() >= 2 * self.chunk
            && !self.spill_failed
            && let Err(e) = self.spill_oldest()
        {
            eprintln!(
                "warning: the run's records could not be spilled to a temporary file ({e}); \
                 they are kept in memory (set TMPDIR to a writable folder with free space)"
            );
            self.spill_failed = true;
        }
    }

    /// Writes the oldest chunk of records in memory to the spill file.
    fn spill_oldest(&mut self) -> std::io::Result<()> {
        let mut bytes = Vec::new();
        for s in &self.recent[..self.chunk] {
            bytes = postcard::to_extend(s, bytes).map_err(std::io::Error::other)?;
        }
        let spill = match &self.spill {
            Some(s) => s.clone(),
            None => {
                let s = Arc::new(Spill {
                    file: Mutex::new(tempfile::tempfile()?),
                });
                self.spill = Some(s.clone());
                s
            }
        };
        let mut f = spill.file.lock().unwrap_or_else(|p| p.into_inner());
        let offset = f.seek(SeekFrom::End(0))?;
        f.write_all(&bytes)?;
        self.chunks.push(Chunk {
            offset,
            len: bytes.len() as u64,
        });
        self.recent.drain(..self.chunk);
        Ok(())
    }

    /// Reads spilled chunk `k` back.
    fn read_chunk(&self, k: usize) -> Vec<T> {
        let c = self.chunks[k];
        let spill = self.spill.as_ref().expect("a spilled chunk has its file");
        let mut bytes = vec![0; c.len as usize];
        {
            let mut f = spill.file.lock().unwrap_or_else(|p| p.into_inner());
            f.seek(SeekFrom::Start(c.offset))
                .and_then(|_| f.read_exact(&mut bytes))
                .unwrap_or_else(|e| {
                    panic!("the run's spilled samples could not be read back: {e}")
                });
        }
        let mut out = Vec::with_capacity(self.chunk);
        let mut rest = bytes.as_slice();
        while !rest.is_empty() {
            let (s, r) = postcard::take_from_bytes::<T>(rest)
                .unwrap_or_else(|e| panic!("the run's spilled samples do not decode: {e}"));
            out.push(s);
            rest = r;
        }
        out
    }

    /// How many samples.
    pub fn len(&self) -> usize {
        self.chunks.len() * self.chunk + self.recent.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The first sample.
    pub fn first(&self) -> Option<&T> {
        self.first.as_ref()
    }

    /// The last sample.
    pub fn last(&self) -> Option<&T> {
        self.recent.last()
    }

    /// The records still in memory: the most recent ones (at least a chunk of them,
    /// or all), the first of them at index [`SampleLog::recent_start`].
    pub fn recent(&self) -> &[T] {
        &self.recent
    }

    /// Index of the first sample of [`SampleLog::recent`].
    pub fn recent_start(&self) -> usize {
        self.chunks.len() * self.chunk
    }

    /// How many samples are on disk.
    pub fn spilled(&self) -> usize {
        self.recent_start()
    }

    /// Every sample in order (spilled ones read back a chunk at a time).
    pub fn iter(&self) -> SampleIter<'_, T> {
        self.iter_from(0)
    }

    /// The samples from index `i` on.
    pub fn iter_from(&self, i: usize) -> SampleIter<'_, T> {
        SampleIter {
            log: self,
            next: i,
            chunk: None,
        }
    }

    /// Consecutive pairs of samples (what `slice::windows(2)` gives of a vector).
    pub fn pairs(&self) -> impl Iterator<Item = (Cow<'_, T>, Cow<'_, T>)> + '_ {
        let mut it = self.iter();
        let mut prev = it.next();
        std::iter::from_fn(move || {
            let next = it.next()?;
            let a = prev.replace(next.clone())?;
            Some((a, next))
        })
    }

    /// Every sample as a vector (memory grows with the run: for tests and short runs).
    pub fn to_vec(&self) -> Vec<T> {
        self.iter().map(Cow::into_owned).collect()
    }

    /// Sample `i` (read from disk if spilled: for occasional access).
    pub fn get(&self, i: usize) -> Option<Cow<'_, T>> {
        self.iter_from(i).next()
    }
}

/// The records of a [`SpillLog`] in order, borrowed from memory or read from disk.
pub struct SampleIter<'a, T> {
    log: &'a SpillLog<T>,
    next: usize,
    /// The spilled chunk being read (its index, its records).
    chunk: Option<(usize, std::vec::IntoIter<T>)>,
}

impl<'a, T: Record> Iterator for SampleIter<'a, T> {
    type Item = Cow<'a, T>;

    fn next(&mut self) -> Option<Self::Item> {
        let log = self.log;
        let start = log.recent_start();
        if self.next >= start {
            let s = log.recent.get(self.next - start)?;
            self.next += 1;
            return Some(Cow::Borrowed(s));
        }
        let k = self.next / log.chunk;
        if self.chunk.as_ref().is_none_or(|(c, _)| *c != k) {
            let mut samples = log.read_chunk(k).into_iter();
            for _ in 0..self.next % log.chunk {
                samples.next();
            }
            self.chunk = Some((k, samples));
        }
        let s = self.chunk.as_mut().and_then(|(_, it)| it.next())?;
        self.next += 1;
        Some(Cow::Owned(s))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.log.len().saturating_sub(self.next);
        (n, Some(n))
    }
}

impl<T: Record> ExactSizeIterator for SampleIter<'_, T> {}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
    struct Rec {
        t: f64,
        v: Vec<f32>,
        o: Option<[f64; 2]>,
    }

    fn rec(i: usize) -> Rec {
        Rec {
            t: i as f64 * 0.01 + 1e-17,
            v: vec![i as f32 / 3.0, f32::MIN_POSITIVE],
            o: i.is_multiple_of(3).then_some([1.0 / 7.0, i as f64]),
        }
    }

    #[test]
    fn spilled_records_read_back_bit_for_bit_and_in_order() {
        let n = 5 * SPILL_CHUNK + 17;
        let log: SpillLog<Rec> = (0..n).map(rec).collect();
        assert_eq!(log.len(), n);
        assert!(
            log.spilled() >= 3 * SPILL_CHUNK,
            "{} spilled",
            log.spilled()
        );
        assert!(log.recent().len() < 2 * SPILL_CHUNK);
        for (i, s) in log.iter().enumerate() {
            assert_eq!(*s, rec(i), "record {i}");
        }
        assert_eq!(log.iter().len(), n);
        for i in [
            0,
            1,
            SPILL_CHUNK - 1,
            SPILL_CHUNK,
            2 * SPILL_CHUNK + 5,
            n - 1,
        ] {
            assert_eq!(*log.get(i).unwrap(), rec(i));
            assert_eq!(log.iter_from(i).count(), n - i);
        }
        let pairs: Vec<(f64, f64)> = log.pairs().map(|(a, b)| (a.t, b.t)).collect();
        assert_eq!(pairs.len(), n - 1);
        assert!(
            pairs
                .iter()
                .enumerate()
                .all(|(i, p)| *p == (rec(i).t, rec(i + 1).t))
        );
        assert_eq!(log.first(), Some(&rec(0)));
        assert_eq!(log.last(), Some(&rec(n - 1)));
        assert_eq!(log.get(n), None);
    }

    #[test]
    fn a_log_of_small_chunks_reads_back_in_order() {
        let mut log = SpillLog::with_chunk(3);
        for i in 0..20 {
            log.push(rec(i));
        }
        assert_eq!(log.spilled(), 15);
        assert_eq!(log.recent().len(), 5);
        assert_eq!(log.to_vec(), (0..20).map(rec).collect::<Vec<_>>());
        assert_eq!(*log.get(7).unwrap(), rec(7));
        assert_eq!(log.iter_from(4).count(), 16);
    }

    #[test]
    fn a_clone_keeps_its_records_while_the_original_grows() {
        let mut log: SpillLog<Rec> = (0..3 * SPILL_CHUNK).map(rec).collect();
        let copy = log.clone();
        for i in 3 * SPILL_CHUNK..6 * SPILL_CHUNK {
            log.push(rec(i));
        }
        assert_eq!(copy.len(), 3 * SPILL_CHUNK);
        assert_eq!(
            copy.to_vec(),
            (0..3 * SPILL_CHUNK).map(rec).collect::<Vec<_>>()
        );
        assert_eq!(
            log.to_vec(),
            (0..6 * SPILL_CHUNK).map(rec).collect::<Vec<_>>()
        );
    }
}
