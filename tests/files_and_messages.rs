//! The command line never loses a user's file and never prints more than
//! one line per error (issue 17), for the commands built without the
//! feature `solve` (`solve` itself: `tests/solve.rs`):
//!
//! - outputs are written to a temporary file renamed into place: a write
//!   that fails (a file-size limit) or a run refused on its arguments
//!   leaves an existing file as it was;
//! - an output naming an input or another output is refused before any
//!   work;
//! - a stream is read once (`eval /dev/stdin` from a pipe);
//! - an empty symbols file is an error, not a passed audit;
//! - usage errors are one line, every echoed character printable;
//! - numerical differentiation accepts an exactly zero Jacobian column.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common;
use common::slamjac_with_stdin as run;
use common::{listing, stderr};

/// A fresh directory for this file's tests.
fn temp_dir(tag: &str) -> PathBuf {
    common::temp_dir("files", tag)
}

fn text(path: &Path) -> String {
    path.to_str().expect("UTF-8 path").to_owned()
}

/// Asserts exit `code` and exactly one printable line on stderr, `error: …`,
/// holding every needle.
fn assert_error(output: &Output, code: i32, needles: &[&str]) {
    let err = stderr(output);
    assert_eq!(output.status.code(), Some(code), "stderr: {err}");
    assert!(err.starts_with("error: "), "{err}");
    let line = err.strip_suffix('\n').unwrap_or(&err);
    assert!(!line.contains('\n'), "not one line: {err}");
    assert!(
        !line
            .chars()
            .any(slamjac_problem::field_path::is_unprintable),
        "unprintable character: {line:?}"
    );
    for needle in needles {
        assert!(err.contains(needle), "`{err}` lacks `{needle}`");
    }
}

fn synth(output: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "synth-bal",
        "--cameras",
        "4",
        "--points",
        "30",
        "--views",
        "3",
    ];
    args.extend_from_slice(extra);
    let output = text(output);
    args.extend_from_slice(&["--output", &output]);
    run(&args, b"")
}

#[test]
fn an_existing_output_survives_a_refused_run_and_a_failed_write() {
    let dir = temp_dir("synth");
    let old = dir.join("old.txt");
    std::fs::write(&old, "the user's data\n").unwrap();
    for bad in [
        &["--noise", "-1"][..],
        &["--outliers", "2"],
        &["--noise", "1e300"],
    ] {
        let output = synth(&old, bad);
        assert_error(&output, 2, &[]);
        assert_eq!(std::fs::read_to_string(&old).unwrap(), "the user's data\n");
    }
    // A file-size limit of one block: the write fails part way (EFBIG: the
    // program ignores SIGXFSZ, which would kill it and leave its temporary
    // file), the old file stays whole and no temporary is left.
    let limited = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -f 1; exec '{}' synth-bal --cameras 4 --points 3000 --views 3 \
             --output '{}'",
            env!("CARGO_BIN_EXE_slamjac"),
            text(&old)
        ))
        .output()
        .unwrap();
    assert_error(&limited, 2, &["old.txt", "cannot write"]);
    assert_eq!(std::fs::read_to_string(&old).unwrap(), "the user's data\n");
    assert_eq!(listing(&dir), ["old.txt"]);
    // Written in full, it replaces the file.
    let output = synth(&old, &[]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(
        std::fs::read_to_string(&old)
            .unwrap()
            .starts_with("4 30 90\n")
    );
}

#[test]
fn synth_bal_refuses_absurd_counts_and_reads_negative_numbers_as_values() {
    let dir = temp_dir("counts");
    let out = text(&dir.join("x.txt"));
    for cameras in ["1000000000", "18446744073709551615"] {
        let output = run(
            &[
                "synth-bal",
                "--cameras",
                cameras,
                "--points",
                "3",
                "--output",
                &out,
            ],
            b"",
        );
        assert_error(
            &output,
            2,
            &[&format!(
                "the number of cameras must be from 2 to 1000000, not {cameras}"
            )],
        );
    }
    let output = run(
        &[
            "synth-bal",
            "--cameras",
            "10",
            "--points",
            "200000000",
            "--output",
            &out,
        ],
        b"",
    );
    assert_error(&output, 2, &["more than 100000000 observations"]);
    let output = synth(&dir.join("y.txt"), &["--noise", "-1"]);
    assert_error(
        &output,
        2,
        &["pixel sigma must be finite and not negative, not -1"],
    );
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
}

#[test]
fn audit_reports_may_not_name_its_inputs_or_each_other() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("documents");
    let dir = temp_dir("audit");
    let document = dir.join("doc.txt");
    let symbols = dir.join("doc.symbols.toml");
    std::fs::copy(root.join("000_29653f4af9b68bb8.txt"), &document).unwrap();
    std::fs::copy(root.join("000_29653f4af9b68bb8.symbols.toml"), &symbols).unwrap();
    let before = (
        std::fs::read(&document).unwrap(),
        std::fs::read(&symbols).unwrap(),
    );
    let report = text(&dir.join("report.md"));
    let (doc, sym) = (text(&document), text(&symbols));
    let spelled = text(&dir.join(".").join("doc.txt"));
    let cases: [(&[&str], &str); 4] = [
        (&["--json", &doc], "--json names the same file as DOCUMENT"),
        (
            &["--json", &spelled],
            "--json names the same file as DOCUMENT",
        ),
        (
            &["--markdown", &sym],
            "--markdown names the same file as --symbols",
        ),
        (
            &["--markdown", &report, "--json", &report],
            "--json names the same file as --markdown",
        ),
    ];
    for (outputs, message) in cases {
        let mut args = vec!["audit", &doc, "--symbols", &sym, "--samples", "1"];
        args.extend_from_slice(outputs);
        assert_error(&run(&args, b""), 2, &[message, "refused before any work"]);
    }
    let missing = text(&dir.join("no such folder").join("r.json"));
    let output = run(&["audit", &doc, "--symbols", &sym, "--json", &missing], b"");
    assert_error(&output, 2, &["--json: cannot write here"]);
    assert_eq!(
        (
            std::fs::read(&document).unwrap(),
            std::fs::read(&symbols).unwrap()
        ),
        before
    );
    assert_eq!(listing(&dir), ["doc.symbols.toml", "doc.txt"]);
}

#[test]
fn an_empty_symbols_file_audits_nothing_and_fails() {
    let dir = temp_dir("empty");
    let empty = dir.join("empty.toml");
    std::fs::write(&empty, "").unwrap();
    let document = Path::new(env!("CARGO_MANIFEST_DIR")).join("documents/000_29653f4af9b68bb8.txt");
    let output = run(
        &["audit", &text(&document), "--symbols", &text(&empty)],
        b"",
    );
    assert_error(
        &output,
        2,
        &["empty.toml", "states no claim", "nothing to audit"],
    );
}

#[test]
fn a_piped_input_is_read_once() {
    let example = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/inputs/point_reprojection.json"),
    )
    .unwrap();
    let from_pipe = run(&["eval", "/dev/stdin"], &example);
    let from_dash = run(&["eval", "-"], &example);
    assert_eq!(from_pipe.status.code(), Some(0), "{}", stderr(&from_pipe));
    assert_eq!(from_pipe.stdout, from_dash.stdout);
}

#[test]
fn usage_errors_are_one_printable_line() {
    let cases: [(&[&str], &[&str]); 6] = [
        (
            &["solve", "x.txt", "--max-iterations", "0"],
            &["--max-iterations", "0 is not in 1..=100000"],
        ),
        (
            &["audit", "--symbols", "s.toml"],
            &["required arguments were not provided", "<DOCUMENT>"],
        ),
        (
            &["eval"],
            &["required arguments were not provided", "<FILE>"],
        ),
        (&[], &["a command is needed"]),
        (
            &["eval", "-", "--metod", "dual"],
            &["unexpected argument '--metod'"],
        ),
        // (clap drops the terminal's escape sequences from what it echoes.)
        (
            &["eval", "-", "--method", "du\u{feff}al\u{200b}\u{1b}[31m"],
            &["invalid value 'du\\ufeffal\\u200b'"],
        ),
    ];
    for (args, needles) in cases {
        assert_error(&run(args, b""), 2, needles);
    }
    let help = run(&["--help"], b"");
    assert_eq!(help.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&help.stdout).contains("Usage:"));
}

#[test]
fn echoed_input_text_is_escaped_byte_order_marks_and_zero_width_characters_too() {
    let output = run(
        &["eval", "-"],
        "\u{feff}{\"factor\": \"a\u{200b}b\u{2060}\"}".as_bytes(),
    );
    assert_error(&output, 2, &[]);
    let output = run(
        &["eval", "-"],
        "{\"factor\": \"point\u{200b}_reprojection\u{feff}\", \"variables\": {}, \"constants\": {}}"
            .as_bytes(),
    );
    assert_error(&output, 2, &["point\\u200b_reprojection\\ufeff"]);
}

/// The configuration: a line 1 m from the camera centre at the
/// identity pose, whose pose Jacobian has an exactly zero column.
#[test]
fn numerical_differentiation_accepts_an_exactly_zero_column() {
    for factor in ["plucker_line_reprojection", "line_reprojection"] {
        for focal in [400, 420, 450, 500] {
            let input = format!(
                "{{\"factor\": \"{factor}\", \"variables\": {{\"pose\": {{\"rotation\": [0, 0, 0, 1], \
                 \"translation\": [0, 0, 0]}}, \"line\": {{\"normal\": [0, -1, 0], \"direction\": \
                 [1, 0, 0]}}}}, \"constants\": {{\"intrinsics\": [{focal}, {focal}, 320, 240], \
                 \"start\": [100, 700], \"end\": [500, 720]}}}}"
            );
            let output = run(&["eval", "-", "--method", "numeric"], input.as_bytes());
            assert_eq!(
                output.status.code(),
                Some(0),
                "{factor} at f = {focal}: {}",
                stderr(&output)
            );
        }
    }
}
