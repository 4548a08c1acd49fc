//! Inputs read once (a pipe cannot be read twice), outputs that are either
//! complete or untouched, and synthetic problems streamed to their file.

use crate::common;

use std::io::{BufReader, Read};

use common::{SINGLE_FILES, data};
use slam_data::synthetic::{self, MAX_CAMERAS, SyntheticConfig, generate};
use slam_data::{BalProblem, Format, Problem, SNIFF_BYTES, StereoVo, VoFiles, bal, kitti_vo};

/// A source that hands out its bytes once, a few at a time, and cannot be
/// opened again or rewound: what a pipe gives.
struct Pipe {
    bytes: Vec<u8>,
    at: usize,
}

impl Read for Pipe {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = buf.len().min(self.bytes.len() - self.at).min(777);
        buf[..n].copy_from_slice(&self.bytes[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

fn pipe(bytes: Vec<u8>) -> BufReader<Pipe> {
    BufReader::new(Pipe { bytes, at: 0 })
}

#[test]
fn a_stream_is_read_once_its_format_told_from_what_was_read() {
    for (name, format) in SINGLE_FILES {
        let bytes = std::fs::read(data(name)).unwrap();
        let from_pipe = Problem::read_from(pipe(bytes), "/dev/stdin", None).unwrap();
        let from_file = Problem::read(data(name), None).unwrap();
        assert_eq!(from_pipe.format(), format.parse::<Format>().unwrap());
        assert_eq!(from_pipe, from_file, "{name}");
    }
}

#[test]
fn a_stream_whose_format_cannot_be_told_asks_for_it() {
    // g2o skips comment lines: past the sniffing limit, the first record
    // comes too late to tell the format.
    let example = std::fs::read(data("pose3example.txt")).unwrap();
    let mut commented = b"# a comment\n".repeat(SNIFF_BYTES / 12 + 1);
    commented.extend_from_slice(&example);
    let error = Problem::read_from(pipe(commented.clone()), "in", None)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("no record in the first 1 MiB") && error.contains("--format"),
        "{error}"
    );
    let given = Problem::read_from(pipe(commented), "in", Some(Format::G2o)).unwrap();
    assert_eq!(
        given,
        Problem::read(data("pose3example.txt"), None).unwrap()
    );
    let error = Problem::read_from(pipe(b"1 2\n".to_vec()), "in", None)
        .unwrap_err()
        .to_string();
    assert!(
        error.starts_with("in:1: cannot tell the format") && error.contains("--format"),
        "{error}"
    );
    let error = Problem::read_from(pipe(Vec::new()), "in", Some(Format::KittiVo))
        .unwrap_err()
        .to_string();
    assert!(error.contains("three files"), "{error}");
}

#[test]
fn a_refused_or_failed_write_leaves_the_old_files() {
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join("old.txt");
    std::fs::write(&path, "the user's data\n").unwrap();
    let mut problem = bal::read(data("dubrovnik-3-7-pre.txt")).unwrap();
    problem.points[0].x = f64::NAN;
    let error = bal::write(&problem, &path).unwrap_err().to_string();
    assert!(error.contains("point 1 of 7"), "{error}");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "the user's data\n");

    // The KITTI VO triple: the factors file cannot be created (a folder is
    // in its way), so neither of the other two is replaced.
    let vo = Problem::read(data("VO_camera_poses_large.txt"), None).unwrap();
    let files = VoFiles::named(&folder.path().join("VO_camera_poses_x.txt")).unwrap();
    for file in [&files.calibration, &files.poses] {
        std::fs::write(file, "kept\n").unwrap();
    }
    std::fs::create_dir(&files.factors).unwrap();
    let Problem::KittiVo(stereo) = &vo else {
        panic!("a KITTI VO problem")
    };
    kitti_vo::write(stereo, &files).unwrap_err();
    for file in [&files.calibration, &files.poses] {
        assert_eq!(std::fs::read_to_string(file).unwrap(), "kept\n");
    }
    std::fs::remove_dir(&files.factors).unwrap();
    vo.write(&files.poses).unwrap();
    let back: StereoVo = kitti_vo::read(&VoFiles::beside(&files.poses).unwrap()).unwrap();
    assert_eq!(Problem::KittiVo(back), vo);
}

#[test]
fn synthetic_problems_stream_the_file_generate_would_write() {
    let config = SyntheticConfig {
        cameras: 12,
        points: 700,
        ..SyntheticConfig::with_observations(0, 4)
    };
    let generated = generate(&config).unwrap();
    let mut expected = Vec::new();
    bal::write_to(&generated.problem, &mut expected, "x").unwrap();
    let mut streamed = Vec::new();
    let written = synthetic::write_to(&config, &mut streamed, "x").unwrap();
    assert_eq!(streamed, expected);
    assert_eq!(
        (written.observations, written.outliers),
        (3500, generated.outliers.len())
    );
    let back: BalProblem = bal::from_text(std::str::from_utf8(&streamed).unwrap(), "x").unwrap();
    assert_eq!(back, generated.problem);
}

#[test]
fn absurd_counts_are_refused_before_anything_is_allocated() {
    for cameras in [MAX_CAMERAS + 1, 1_000_000_000, usize::MAX] {
        let config = SyntheticConfig {
            cameras,
            points: 10,
            ..SyntheticConfig::with_observations(0, 0)
        };
        let expected = format!(
            "synthetic BAL: the number of cameras must be from 2 to 1000000, not {cameras}"
        );
        assert_eq!(generate(&config).unwrap_err().to_string(), expected);
        let mut out = Vec::new();
        let error = synthetic::write_to(&config, &mut out, "x").unwrap_err();
        assert_eq!(error.to_string(), format!("x: {expected}"));
        assert!(out.is_empty());
    }
}
