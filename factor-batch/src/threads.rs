//! Spreading a batch over threads: the rows cut into chunks, each chunk a
//! [`Range`] of its own column slices, run on rayon's pool.

use rayon::prelude::*;

use crate::run::Range;

/// Where a batch runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Threads {
    /// On the calling thread, in one pass.
    #[default]
    One,
    /// In chunks of [`CHUNK`] factors on rayon's pool: the global pool, or
    /// the one whose `ThreadPool::install` the call runs in (which is how
    /// to choose the number of threads).
    Rayon,
}

/// The factors per rayon task: a multiple of every lane count, small enough
/// to balance two threads on a few thousand factors and large enough that a
/// task's overhead (microseconds) is a few percent of its work.
pub const CHUNK: usize = 2048;

/// `columns` cut into pieces of `chunk` rows: piece `k` of every column,
/// for each `k`.
fn split<'a, S>(columns: Vec<&'a [S]>, pieces: usize, chunk: usize) -> Vec<Vec<&'a [S]>> {
    let mut out: Vec<Vec<&'a [S]>> = (0..pieces)
        .map(|_| Vec::with_capacity(columns.len()))
        .collect();
    for column in columns {
        for (k, piece) in column.chunks(chunk).enumerate() {
            out[k].push(piece);
        }
    }
    out
}

/// As [`split`], for optional mutable columns.
fn split_mut<'a, S>(
    columns: Vec<Option<&'a mut [S]>>,
    pieces: usize,
    chunk: usize,
) -> Vec<Vec<Option<&'a mut [S]>>> {
    let mut out: Vec<Vec<Option<&'a mut [S]>>> = (0..pieces)
        .map(|_| Vec::with_capacity(columns.len()))
        .collect();
    for column in columns {
        match column {
            Some(column) => {
                for (k, piece) in column.chunks_mut(chunk).enumerate() {
                    out[k].push(Some(piece));
                }
            }
            None => out.iter_mut().for_each(|o| o.push(None)),
        }
    }
    out
}

/// Runs `f` on `range` as `threads` says: whole, or in chunks of [`CHUNK`]
/// rows across rayon's pool.
pub(crate) fn for_each_chunk<S: Send + Sync>(
    range: Range<'_, S>,
    threads: Threads,
    f: impl Fn(&mut Range<'_, S>) + Sync,
) {
    let mut range = range;
    if threads == Threads::One || range.len <= CHUNK {
        f(&mut range);
        return;
    }
    let len = range.len;
    let pieces = len.div_ceil(CHUNK);
    let inputs = split(range.inputs, pieces, CHUNK);
    let weights: Vec<Option<&[S]>> = match range.weights {
        Some(w) => w.chunks(CHUNK).map(Some).collect(),
        None => vec![None; pieces],
    };
    let outputs = split_mut(range.outputs, pieces, CHUNK);
    inputs
        .into_iter()
        .zip(weights)
        .zip(outputs)
        .enumerate()
        .collect::<Vec<_>>()
        .into_par_iter()
        .for_each(|(k, ((inputs, weights), outputs))| {
            let mut chunk = Range {
                len: CHUNK.min(len - k * CHUNK),
                inputs,
                weights,
                outputs,
            };
            f(&mut chunk);
        });
}
