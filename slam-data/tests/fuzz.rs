//! Mutated copies of the shipped files: no panic, and every error is one
//! line `FILE:LINE: what` with a line inside the input. Seeded, with a
//! bounded number of cases per format.

use crate::common;

use common::data;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestRunner};
use slam_data::{Error, bal, bundler, edge3, g2o, kitti_vo};

/// Cases per format.
const CASES: u32 = 2000;

/// Tokens that break parsers: non-numbers, non-finite, overflowing,
/// negative, empty, tags of other formats, non-ASCII.
const NASTY: [&str; 16] = [
    "nan",
    "inf",
    "-1",
    "1e999",
    "1e-400",
    "18446744073709551616",
    "0",
    "-0",
    "",
    "#",
    "EDGE3",
    "VERTEX_SE3:QUAT",
    "é",
    "0.5",
    "99999999",
    "\u{0}",
];

/// One change to the bytes of a file.
#[derive(Debug, Clone)]
enum Mutation {
    /// Set the byte at a position (relative, 0..1) to a value.
    SetByte(f64, u8),
    /// Delete a range: start (relative) and length.
    Delete(f64, usize),
    /// Copy a range to another position.
    Duplicate(f64, usize, f64),
    /// Replace the whitespace-separated token at a position with a nasty one.
    Token(f64, usize),
    /// Cut the file at a position.
    Truncate(f64),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (0.0..1.0, any::<u8>()).prop_map(|(at, b)| Mutation::SetByte(at, b)),
        (0.0..1.0, 1usize..200).prop_map(|(at, n)| Mutation::Delete(at, n)),
        (0.0..1.0, 1usize..200, 0.0..1.0).prop_map(|(at, n, to)| Mutation::Duplicate(at, n, to)),
        (0.0..1.0, 0..NASTY.len()).prop_map(|(at, k)| Mutation::Token(at, k)),
        (0.0..1.0).prop_map(Mutation::Truncate),
    ]
}

fn position(bytes: &[u8], at: f64) -> usize {
    ((bytes.len() as f64) * at) as usize
}

fn apply(bytes: &mut Vec<u8>, mutation: &Mutation) {
    if bytes.is_empty() {
        return;
    }
    match *mutation {
        Mutation::SetByte(at, b) => {
            let p = position(bytes, at);
            bytes[p] = b;
        }
        Mutation::Delete(at, n) => {
            let p = position(bytes, at);
            let end = (p + n).min(bytes.len());
            bytes.drain(p..end);
        }
        Mutation::Duplicate(at, n, to) => {
            let p = position(bytes, at);
            let copy: Vec<u8> = bytes[p..(p + n).min(bytes.len())].to_vec();
            let q = position(bytes, to);
            bytes.splice(q..q, copy);
        }
        Mutation::Token(at, k) => {
            let mut start = position(bytes, at);
            while start > 0 && !bytes[start - 1].is_ascii_whitespace() {
                start -= 1;
            }
            let mut end = start;
            while end < bytes.len() && !bytes[end].is_ascii_whitespace() {
                end += 1;
            }
            bytes.splice(start..end, NASTY[k].bytes());
        }
        Mutation::Truncate(at) => {
            let p = position(bytes, at);
            bytes.truncate(p);
        }
    }
}

/// The first `lines` lines of a shipped file (the large ones are cut to keep
/// the run short).
fn base(name: &str, lines: usize) -> Vec<u8> {
    let text = std::fs::read_to_string(data(name)).unwrap();
    text.split_inclusive('\n')
        .take(lines)
        .collect::<String>()
        .into_bytes()
}

/// Checks the shape of an error: `NAME:LINE: what`, one line, `NAME` one of
/// the inputs and `LINE` from 1 to one past its last line.
fn check_error(error: &Error, inputs: &[(&str, &[u8])]) -> Result<(), TestCaseError> {
    let message = error.to_string();
    prop_assert!(!message.contains('\n'), "two lines: {:?}", message);
    let Some((name, input, rest)) = inputs
        .iter()
        .find_map(|(name, input)| Some((name, input, message.strip_prefix(&format!("{name}:"))?)))
    else {
        return Err(TestCaseError::fail(format!("names no input: {message}")));
    };
    let (line, what) = rest
        .split_once(": ")
        .ok_or_else(|| TestCaseError::fail(format!("no `: `: {message}")))?;
    let line: usize = line
        .parse()
        .map_err(|_| TestCaseError::fail(format!("no line number: {message}")))?;
    let lines = input.split(|b| *b == b'\n').count();
    prop_assert!(
        (1..=lines).contains(&line),
        "{}: line {} of {}: {}",
        name,
        line,
        lines,
        message
    );
    prop_assert!(!what.is_empty(), "empty message: {}", message);
    Ok(())
}

/// Runs `read` on [`CASES`] mutated copies of `base` (named `name`);
/// `others` are the other inputs `read` takes, unchanged.
fn fuzz(
    seed: u64,
    base: &[u8],
    name: &str,
    others: &[(&str, &[u8])],
    read: impl Fn(&[u8]) -> Result<(), Error>,
) {
    fuzz_cases(CASES, seed, base, name, others, read);
}

/// [`fuzz`] with `cases` cases.
fn fuzz_cases(
    cases: u32,
    seed: u64,
    base: &[u8],
    name: &str,
    others: &[(&str, &[u8])],
    read: impl Fn(&[u8]) -> Result<(), Error>,
) {
    let config = Config {
        cases,
        rng_seed: RngSeed::Fixed(seed),
        failure_persistence: None,
        ..Config::default()
    };
    let mut runner = TestRunner::new(config);
    let strategy = proptest::collection::vec(mutation(), 1..4);
    runner
        .run(&strategy, |mutations| {
            let mut bytes = base.to_vec();
            for m in &mutations {
                apply(&mut bytes, m);
            }
            match read(&bytes) {
                Ok(()) => Ok(()),
                Err(error) => {
                    let mut inputs = vec![(name, &bytes[..])];
                    inputs.extend_from_slice(others);
                    check_error(&error, &inputs)
                }
            }
        })
        .unwrap();
}

#[test]
fn mutated_bal_files() {
    let base = base("dubrovnik-3-7-pre.txt", usize::MAX);
    fuzz(1, &base, "d.txt", &[], |b| {
        bal::read_from(b, "d.txt").map(drop)
    });
}

#[test]
fn mutated_bundler_files() {
    let base = base("Balbianello.out", usize::MAX);
    fuzz(2, &base, "b.out", &[], |b| {
        bundler::read_from(b, "b.out").map(drop)
    });
}

#[test]
fn mutated_g2o_files() {
    let base = base("pose3example.txt", usize::MAX);
    fuzz(3, &base, "p.txt", &[], |b| {
        g2o::read_from(b, "p.txt").map(drop)
    });
}

#[test]
fn mutated_edge3_files() {
    let base = base("sphere2500.txt", 300);
    fuzz(4, &base, "s.txt", &[], |b| {
        edge3::read_from(b, "s.txt").map(drop)
    });
}

#[test]
fn mutated_kitti_vo_files() {
    let c = base("VO_calibration.txt", usize::MAX);
    let p = base("VO_camera_poses_large.txt", usize::MAX);
    let f = base("VO_stereo_factors_large.txt", 300);
    let (c, p, f) = (&c[..], &p[..], &f[..]);
    fuzz(5, c, "c.txt", &[("p.txt", p), ("f.txt", f)], |b| {
        kitti_vo::read_from((b, "c.txt"), (p, "p.txt"), (f, "f.txt")).map(drop)
    });
    fuzz(6, p, "p.txt", &[("c.txt", c), ("f.txt", f)], |b| {
        kitti_vo::read_from((c, "c.txt"), (b, "p.txt"), (f, "f.txt")).map(drop)
    });
    fuzz(7, f, "f.txt", &[("c.txt", c), ("p.txt", p)], |b| {
        kitti_vo::read_from((c, "c.txt"), (p, "p.txt"), (b, "f.txt")).map(drop)
    });
}

/// Mutated files read as a stream whose format is told from its content:
/// through a reader that hands out a few bytes at a time (the sniffer's
/// replay crossing its buffer many times), the result is exactly that of
/// reading the same bytes in the format told, or the sniffer's own one-line
/// error.
#[test]
fn mutated_streams_read_once_in_the_format_their_content_tells() {
    use slam_data::{Format, Problem};
    use std::io::BufReader;
    for (seed, name) in [
        (8, "dubrovnik-3-7-pre.txt"),
        (9, "Balbianello.out"),
        (10, "pose3example.txt"),
    ] {
        let base = base(name, usize::MAX);
        fuzz_cases(300, seed, &base, "in", &[], |b| {
            let told = Format::from_content(b, "in");
            let streamed = Problem::read_from(BufReader::with_capacity(7, b), "in", None);
            match told {
                Ok(format) => assert_eq!(streamed, Problem::read_from(b, "in", Some(format))),
                Err(error) => assert_eq!(streamed, Err(error)),
            }
            streamed.map(drop)
        });
    }
}

#[test]
fn mutated_g2o_line_and_plane_graphs() {
    let lines = base("g2o-addons/line3d.g2o", 300);
    fuzz(8, &lines, "l.g2o", &[], |b| {
        g2o::read_graph_from(b, "l.g2o").map(drop)
    });
    // The head of the plane graph and its last lines (FIX).
    let text = std::fs::read_to_string(data("g2o-addons/plane3d.g2o")).unwrap();
    let all: Vec<&str> = text.split_inclusive('\n').collect();
    let planes: String = all[..300].concat() + &all[all.len() - 3..].concat();
    fuzz(9, planes.as_bytes(), "p.g2o", &[], |b| {
        g2o::read_graph_from(b, "p.g2o").map(drop)
    });
}
