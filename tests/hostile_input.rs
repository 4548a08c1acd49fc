//! `slamjac eval` against hostile input: unbounded and non-UTF-8 sources,
//! number literals beyond the `f64` range by the ten thousand, and a seeded,
//! bounded fuzz over mutated example inputs and hand-made hostile files.
//!
//! Every run is limited by [`CASE_TIMEOUT`], which only catches hangs and
//! super-linear blow-ups: each case here finishes in milliseconds to a
//! fraction of a second in a debug build, while the quadratic parser this
//! replaces needed 14 to 21 s for 20,000 literals in a release build, and
//! `/dev/urandom` never finished. No speed target is asserted. The contract checked on every case:
//! exit 0, 1 or 2 (never a panic's 101 or a signal); on success the output is
//! JSON whose residual and Jacobians are numbers (never a silent NaN, which
//! JSON would print as `null`) and stderr is empty; on failure stdout is
//! empty and stderr is exactly one line, `error: …`, free of control and
//! line-separator characters and of `NaN` and `inf` (no number computed from
//! finite input may be printed non-finite).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

use crate::common;
use common::Rng;

/// A run slower than this is a hang or a blow-up (see the module docs).
/// The largest case, 10 MiB of literals, takes about 2 s in a debug
/// build on a quiet machine and ran out of a 10 s limit beside other
/// builds on two cores: a minute still separates that from a hang or from
/// the quadratic parser, which would have needed hours for 1.2 million
/// literals (14–21 s for 20,000 in a release build).
const CASE_TIMEOUT: Duration = Duration::from_secs(60);
/// The input cap of `slamjac eval` (`slamjac_problem::source::MAX_INPUT_BYTES`).
const MAX_INPUT_BYTES: usize = 16 * 1024 * 1024;
/// Exit code of rejected input.
const BAD_INPUT: i32 = 2;

/// What a finished run left behind.
#[derive(Debug)]
struct Run {
    /// The exit code (`None` when a signal ended the process).
    code: Option<i32>,
    stdout: Vec<u8>,
    stderr: String,
}

/// A fresh path in the temporary directory.
fn temp_path(tag: &str) -> PathBuf {
    common::temp_path("hostile", tag)
}

/// Runs `slamjac args…` with `stdin`, panicking when it outlives [`CASE_TIMEOUT`]
/// (the process is killed first). `label` names the case in failures.
fn run(args: &[&str], stdin: &[u8], label: &str) -> Run {
    let (out_path, err_path) = (temp_path("stdout"), temp_path("stderr"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_slamjac"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(std::fs::File::create(&out_path).expect("stdout file"))
        .stderr(std::fs::File::create(&err_path).expect("stderr file"))
        .spawn()
        .expect("slamjac starts");
    let mut pipe = child.stdin.take().expect("piped stdin");
    let input = stdin.to_vec();
    // A process that exits before reading all its input closes the pipe; that is fine.
    let writer = std::thread::spawn(move || drop(pipe.write_all(&input)));
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if start.elapsed() > CASE_TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{label}: no answer within {CASE_TIMEOUT:?}");
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    writer.join().expect("writer thread");
    let read = |path: &Path| {
        let bytes = std::fs::read(path).expect("output file");
        let _ = std::fs::remove_file(path);
        bytes
    };
    Run {
        code: status.code(),
        stdout: read(&out_path),
        stderr: String::from_utf8_lossy(&read(&err_path)).into_owned(),
    }
}

/// `eval -` on `input`.
fn eval(input: &[u8], label: &str) -> Run {
    run(&["eval", "-"], input, label)
}

/// Whether `c` would break a one-line message, drive a terminal or print
/// nothing (a byte-order mark, a zero-width character, a soft hyphen).
fn unprintable(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{2028}'
                | '\u{2029}'
                | '\u{202a}'..='\u{202e}'
                | '\u{feff}'
                | '\u{200b}'..='\u{200f}'
                | '\u{2060}'..='\u{2064}'
                | '\u{ad}'
        )
}

/// Whether a message shows `NaN` or an infinity as a number: no input
/// literal can be either (they are rejected as such), so one there was
/// computed from finite input.
fn prints_non_finite(line: &str) -> bool {
    line.split(|c: char| !(c.is_alphanumeric() || c == '-'))
        .any(|word| matches!(word, "NaN" | "inf" | "-inf"))
}

/// The contract of the module docs; returns the exit code.
fn assert_contract(run: &Run, label: &str) -> i32 {
    let code = run
        .code
        .unwrap_or_else(|| panic!("{label}: ended by a signal; stderr: {}", run.stderr));
    match code {
        0 => {
            assert!(
                run.stderr.is_empty(),
                "{label}: stderr on success: {}",
                run.stderr
            );
            let output: Value = serde_json::from_slice(&run.stdout)
                .unwrap_or_else(|e| panic!("{label}: output is not JSON: {e}"));
            let mut numbers = output["residual"].as_array().expect("residual").clone();
            for block in output["jacobians"].as_object().expect("jacobians").values() {
                for row in block.as_array().expect("rows") {
                    numbers.extend(row.as_array().expect("row").iter().cloned());
                }
            }
            assert!(
                numbers.iter().all(Value::is_number),
                "{label}: a non-number in the output: {output}"
            );
        }
        1 | 2 => {
            assert!(
                run.stdout.is_empty(),
                "{label}: stdout on error: {}",
                String::from_utf8_lossy(&run.stdout)
            );
            let line = run
                .stderr
                .strip_suffix('\n')
                .unwrap_or_else(|| panic!("{label}: stderr is not one line: {:?}", run.stderr));
            assert!(line.starts_with("error: "), "{label}: {line:?}");
            assert!(
                !line.chars().any(unprintable),
                "{label}: raw control or separator character: {line:?}"
            );
            assert!(
                !prints_non_finite(line),
                "{label}: a non-finite number in the message: {line:?}"
            );
        }
        other => panic!("{label}: exit code {other}; stderr: {}", run.stderr),
    }
    code
}

/// Asserts an error with `code` whose line contains every needle.
fn assert_error(run: &Run, code: i32, needles: &[&str], label: &str) {
    assert_eq!(assert_contract(run, label), code, "{label}: {}", run.stderr);
    for needle in needles {
        assert!(
            run.stderr.contains(needle),
            "{label}: lacks {needle:?}: {}",
            run.stderr
        );
    }
}

#[test]
fn twenty_thousand_out_of_range_literals_are_rejected_at_the_first() {
    // 117 KiB; the parser that re-read the text per literal needed 14 to 21 s
    // in a release build.
    let literals = vec!["1e999"; 20_000].join(",");
    let input = format!("{{\"factor\": \"plane\", \"comment\": [{literals}]}}");
    let run = eval(input.as_bytes(), "20,000 literals");
    assert_error(
        &run,
        BAD_INPUT,
        &["error: comment[0]: non-finite number: 1e999 is beyond the range of f64"],
        "20,000 literals",
    );
}

#[test]
fn large_inputs_are_parsed_whole_in_one_pass() {
    // About 10 MiB of finite numbers in an unknown field: the whole text is
    // parsed before the field is judged.
    let numbers = vec!["-1.25e-3"; 1_200_000].join(",");
    let input = format!("{{\"comment\": [{numbers}], \"factor\": \"plane\"}}");
    assert!(input.len() < MAX_INPUT_BYTES);
    let run = eval(input.as_bytes(), "10 MiB");
    assert_error(
        &run,
        BAD_INPUT,
        &["error: comment: unknown field"],
        "10 MiB",
    );
}

#[test]
fn endless_and_non_utf8_sources_fail_fast() {
    let run = run(&["eval", "/dev/urandom"], b"", "/dev/urandom");
    assert_error(
        &run,
        BAD_INPUT,
        &["error: /dev/urandom: invalid UTF-8 at byte "],
        "/dev/urandom",
    );

    let run = self::run(&["eval", "/dev/zero"], b"", "/dev/zero");
    assert_error(
        &run,
        BAD_INPUT,
        &["error: /dev/zero: input is larger than 16 MiB"],
        "/dev/zero",
    );

    // Invalid UTF-8 after valid text is found where it is.
    let mut input = b"{\"factor\": \"pla".to_vec();
    input.extend_from_slice(&[0xff, b'"', b'}']);
    let run = eval(&input, "0xff");
    assert_error(
        &run,
        BAD_INPUT,
        &["error: <stdin>: invalid UTF-8 at byte 15"],
        "0xff",
    );
}

#[test]
fn the_input_cap_is_exact() {
    let at_cap = format!("{{{}}}", " ".repeat(MAX_INPUT_BYTES - 2));
    let run = eval(at_cap.as_bytes(), "at the cap");
    assert_error(
        &run,
        BAD_INPUT,
        &["error: factor: missing field"],
        "at the cap",
    );

    let over = format!("{{{}}}", " ".repeat(MAX_INPUT_BYTES - 1));
    let run = eval(over.as_bytes(), "over the cap");
    assert_error(
        &run,
        BAD_INPUT,
        &["error: <stdin>: input is larger than 16 MiB (16777216 bytes)"],
        "over the cap",
    );
}

/// Text spliced into inputs: JSON that is hostile to a reader, and bytes that are not JSON.
const TOKENS: &[&[u8]] = &[
    b"1e999",
    b"-1e999",
    b"1e-999",
    b"4.9e-324",
    b"1.7976931348623157e308",
    b"-0",
    b"123456789012345678901234567890",
    b"1.",
    b".5",
    b"-",
    b"NaN",
    b"Infinity",
    b"null",
    b"true",
    b"\"\\u0000\"",
    b"\"\\u001b[31mred\"",
    b"\"\\ud800\"",
    b"\"\xe2\x80\xa8\"",
    b"\"\xc2\x85\"",
    b"\"\x1b[2J\"",
    b"\"a\nb\"",
    b"{\"\": 0}",
    b"{\"a\": 1, \"a\": 2}",
    b"[[[[[[[[",
    b"]]]]",
    b"}",
    b",",
    b":",
    b"\"",
    b"\\",
    b"\xff",
    b"\xc3",
    b"\xef\xbb\xbf",
    b"\0",
];

/// Text edits of an example's pretty-printed JSON.
fn mutate_text(text: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut bytes = text.to_vec();
    for _ in 0..1 + rng.below(3) {
        let at = rng.below(bytes.len() + 1);
        match rng.below(5) {
            0 if !bytes.is_empty() => {
                let i = rng.below(bytes.len());
                bytes[i] = rng.next() as u8;
            }
            1 => {
                let token = *rng.pick(TOKENS);
                bytes.splice(at..at, token.iter().copied());
            }
            2 => {
                let end = (at + 1 + rng.below(16)).min(bytes.len());
                bytes.drain(at.min(end)..end);
            }
            3 => {
                // Repeat a line: a duplicate key, or broken syntax.
                let lines: Vec<&[u8]> = text.split(|&b| b == b'\n').collect();
                let line = rng.pick(&lines).to_vec();
                let start = bytes[..at]
                    .iter()
                    .rposition(|&b| b == b'\n')
                    .map_or(0, |i| i + 1);
                bytes.splice(start..start, line.into_iter().chain([b'\n']));
            }
            _ => {
                let end = (at + 1 + rng.below(32)).min(bytes.len());
                let copy = bytes[at.min(end)..end].to_vec();
                bytes.splice(at..at, copy);
            }
        }
    }
    bytes
}

/// A value hostile to the decoder or the factor.
fn hostile_value(rng: &mut Rng) -> Value {
    let numbers = [
        0.0, -0.0, 1.0, -1.0, 1e308, -1e308, 5e-324, 1e-300, 1e-12, 1e12, 0.5,
    ];
    match rng.below(8) {
        0 => Value::from(*rng.pick(&numbers)),
        1 => Value::from(vec![*rng.pick(&numbers); 1 + rng.below(5)]),
        2 => Value::from(vec![
            *rng.pick(&numbers),
            *rng.pick(&numbers),
            *rng.pick(&numbers),
            *rng.pick(&numbers),
        ]),
        3 => Value::from(*rng.pick(&["", "\u{1b}[31m", "a\u{2028}b", "\u{0}", "\u{85}", "é"])),
        4 => serde_json::json!({"": 1, "\n": 2}),
        5 => Value::Null,
        6 => Value::from(vec![Value::from("x"); 3]),
        _ => serde_json::json!([[1.0], {"a": []}]),
    }
}

/// Edits a random node of `value`: a number is negated, scaled or zeroed, an
/// array of four (a quaternion) rotated to `[w, x, y, z]`, any node replaced
/// by a hostile value. Most edits keep the input well formed, so that the
/// factors' validation and evaluation are reached too.
fn mutate_value(value: &mut Value, rng: &mut Rng) {
    let here = rng.below(6) == 0;
    match value {
        Value::Object(map) if !map.is_empty() && !here => {
            let key = map.keys().nth(rng.below(map.len())).expect("key").clone();
            mutate_value(map.get_mut(&key).expect("value"), rng);
        }
        Value::Array(items) if items.len() == 4 && rng.below(4) == 0 => items.rotate_right(1),
        Value::Array(items) if !items.is_empty() && !here => {
            let i = rng.below(items.len());
            mutate_value(&mut items[i], rng);
        }
        Value::Number(n) if rng.below(4) != 0 => {
            let x = n.as_f64().expect("finite");
            let scale = *rng.pick(&[-1.0, 0.0, 1e-9, 1e-3, 10.0, 1e6, 1e300]);
            *value = Value::from(x * scale);
        }
        _ => *value = hostile_value(rng),
    }
}

fn examples() -> Vec<(String, Vec<u8>)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/inputs");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("examples/inputs")
        .map(|entry| entry.expect("entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    assert!(files.len() >= 5, "examples in {}", dir.display());
    files
        .into_iter()
        .map(|path| {
            let name = path
                .file_stem()
                .expect("name")
                .to_string_lossy()
                .into_owned();
            (name, std::fs::read(&path).expect("example"))
        })
        .collect()
}

/// 60 mutated inputs per example (half text edits, half value edits), each
/// evaluated with one of the three methods: the contract holds, and the
/// mutations reach every exit code.
#[test]
fn fuzzed_examples_keep_the_contract() {
    let mut rng = Rng(0x5eed_51a3_ac00_0001);
    let methods = ["generated", "dual", "numeric"];
    let mut codes = [0usize; 3];
    for (name, text) in examples() {
        let original: Value = serde_json::from_slice(&text).expect("example is JSON");
        for case in 0..60 {
            let input = if case % 2 == 0 {
                mutate_text(&text, &mut rng)
            } else {
                let mut value = original.clone();
                mutate_value(&mut value, &mut rng);
                serde_json::to_vec_pretty(&value).expect("serialisable")
            };
            let method = methods[case % 3];
            let label = format!(
                "{name} case {case} ({method}): {}",
                String::from_utf8_lossy(&input).escape_debug()
            );
            let run = run(&["eval", "-", "--method", method], &input, &label);
            codes[assert_contract(&run, &label) as usize] += 1;
        }
    }
    assert!(
        codes.iter().all(|&n| n > 0),
        "exit codes 0, 1, 2 seen {codes:?} times"
    );
}

/// Deeply nested, very long, and control-character-laden inputs.
#[test]
fn hostile_files_keep_the_contract() {
    let mut rng = Rng(0xbad_f11e);
    let random: Vec<u8> = (0..4096).map(|_| rng.next() as u8).collect();
    let long_key = "k".repeat(1 << 20);
    let long_number = "9".repeat(100_000);
    let control_keys: Vec<String> = (0u8..0x20)
        .map(|b| format!("\"\\u{b:04x}\": {b}"))
        .collect();
    let control_keys = format!("{{{}}}", control_keys.join(", "));
    let cases: Vec<(&str, Vec<u8>, &[&str])> = vec![
        ("random bytes", random, &["error: <stdin>: "]),
        ("empty", Vec::new(), &["error: <stdin>: invalid JSON"]),
        (
            "NUL bytes",
            vec![0; 1000],
            &["error: <stdin>: invalid JSON"],
        ),
        (
            // A leading byte-order mark is skipped (RFC 8259 allows it).
            "byte-order mark",
            b"\xef\xbb\xbf{}".to_vec(),
            &["error: factor: missing field"],
        ),
        (
            "nested arrays",
            "[".repeat(100_000).into_bytes(),
            &["error: <stdin>: invalid JSON"],
        ),
        (
            "nested objects",
            "{\"a\":".repeat(100_000).into_bytes(),
            &["error: <stdin>: invalid JSON"],
        ),
        (
            "long key",
            format!("{{\"factor\": \"plane\", \"{long_key}\": 1}}").into_bytes(),
            &["error: \"kkkkkkkk", "k…\": unknown field"],
        ),
        (
            "long factor name",
            format!("{{\"factor\": \"{long_key}\", \"variables\": {{}}, \"constants\": {{}}}}")
                .into_bytes(),
            &[
                "error: factor: unknown factor \"kkkk",
                "k…\"; known factors",
            ],
        ),
        (
            "long number",
            format!("{{\"factor\": {long_number}}}").into_bytes(),
            &["error: factor: non-finite number: 99999999", "9…"],
        ),
        (
            "long finite number",
            format!("{{\"factor\": 0.{long_number}, \"variables\": {{}}, \"constants\": {{}}}}")
                .into_bytes(),
            &["error: factor: expected a string, found a number"],
        ),
        (
            "control characters in keys",
            control_keys.into_bytes(),
            &["error: \"\\u0000\": unknown field"],
        ),
        (
            "duplicate keys",
            b"{\"variables\": {}, \"variables\": {}}".to_vec(),
            &["error: variables: duplicate key"],
        ),
        (
            "out-of-range literals",
            b"[1e400, -1e400]".to_vec(),
            &["error: input[0]: non-finite number: 1e400 is beyond the range of f64"],
        ),
    ];
    for (label, input, needles) in cases {
        let run = eval(&input, label);
        assert_error(&run, BAD_INPUT, needles, label);
    }
}

/// `eval` on `input` (a JSON value) with `method`, under the contract.
fn eval_value(input: &Value, method: &str, label: &str) -> (i32, Run) {
    let run = run(
        &["eval", "-", "--method", method],
        input.to_string().as_bytes(),
        label,
    );
    (assert_contract(&run, label), run)
}

/// The residual and Jacobian entries of a successful run, in order.
fn outputs(run: &Run) -> Vec<f64> {
    let output: Value = serde_json::from_slice(&run.stdout).expect("JSON");
    let mut numbers: Vec<f64> = output["residual"]
        .as_array()
        .expect("residual")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect();
    for block in output["jacobians"].as_object().expect("jacobians").values() {
        for row in block.as_array().expect("rows") {
            numbers.extend(
                row.as_array()
                    .expect("row")
                    .iter()
                    .map(|x| x.as_f64().expect("number")),
            );
        }
    }
    numbers
}

/// Multiplies every number in `value` by `scale`.
fn scaled(value: &Value, scale: f64) -> Value {
    match value {
        Value::Number(n) => Value::from(n.as_f64().expect("finite") * scale),
        Value::Array(items) => items.iter().map(|v| scaled(v, scale)).collect(),
        Value::Object(map) => map
            .iter()
            .map(|(k, v)| (k.clone(), scaled(v, scale)))
            .collect(),
        other => other.clone(),
    }
}

/// The scales of issue 9: the whole f64 range, by factors of 1e50.
const SCALES: [f64; 12] = [
    1e-300, 1e-250, 1e-200, 1e-150, 1e-100, 1e-50, 1e50, 1e100, 1e150, 1e200, 1e250, 1e300,
];

/// Inputs the README says may have any scale (the plane landmark and the
/// measured plane, the Plücker coordinates of an orthonormal line, the
/// bearing vectors) give the same output at every scale of the f64 range.
/// Before, planes failed outside about [1e-100, 1e150] of scale (a
/// non-finite Jacobian at 1e-120, "norm 0" at 1e160), a measured plane at
/// 1e160 gave a zero residual and zero Jacobians with exit 0, and a line at
/// 1e200 was refused with "n · v = NaN".
#[test]
fn scale_invariant_inputs_work_over_the_whole_f64_range() {
    let example = |name: &str| -> Value {
        let path =
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("examples/inputs/{name}.json"));
        serde_json::from_slice(&std::fs::read(path).expect("example")).expect("JSON")
    };
    let cases: [(&str, &[&[&str]]); 4] = [
        ("plane", &[&["variables", "plane"]]),
        ("plane", &[&["constants", "measured"]]),
        ("line_reprojection", &[&["variables", "line"]]),
        (
            "free_line",
            &[
                &["constants", "bearing_start"],
                &["constants", "bearing_end"],
            ],
        ),
    ];
    for (name, fields) in cases {
        let original = example(name);
        for method in ["generated", "dual"] {
            let (code, run) = eval_value(&original, method, name);
            assert_eq!(code, 0, "{name}: {}", run.stderr);
            let expected = outputs(&run);
            for scale in SCALES {
                let mut input = original.clone();
                for path in fields {
                    let field = &mut input[path[0]][path[1]];
                    *field = scaled(field, scale);
                }
                let label = format!("{name} {fields:?} × {scale:e} ({method})");
                let (code, run) = eval_value(&input, method, &label);
                assert_eq!(code, 0, "{label}: {}", run.stderr);
                let got = outputs(&run);
                let size = expected.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
                let worst = got
                    .iter()
                    .zip(&expected)
                    .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
                assert!(worst <= 1e-12 * size, "{label}: differs by {worst:e}");
            }
        }
    }
}

/// Every number of every example scaled by the same factor, over the whole
/// f64 range: the contract holds (no panic, no non-finite output or
/// message), whether the factor accepts the result or not.
#[test]
fn every_number_scaled_keeps_the_contract() {
    for (name, text) in examples() {
        let original: Value = serde_json::from_slice(&text).expect("example is JSON");
        for scale in SCALES {
            let mut input = original.clone();
            for part in ["variables", "constants"] {
                input[part] = scaled(&input[part], scale);
            }
            for method in ["generated", "numeric"] {
                eval_value(&input, method, &format!("{name} × {scale:e} ({method})"));
            }
        }
    }
}

/// Values given to `synth-bal`'s options: counts at and beyond every cap and
/// type limit, negative, non-finite and malformed numbers, and text with
/// characters that must not reach the terminal raw.
const SYNTH_VALUES: &[&str] = &[
    "0",
    "1",
    "2",
    "3",
    "7",
    "-1",
    "-0",
    "0.5",
    "1e3",
    "1e300",
    "-1e300",
    "nan",
    "inf",
    "-inf",
    "1000001",
    "1000000000",
    "100000001",
    "18446744073709551615",
    "18446744073709551616",
    "0x10",
    "+5",
    " 5",
    "",
    "\u{feff}3",
    "3\u{200b}",
    "\u{1b}[2J",
    "a\nb",
];

/// `synth-bal` with fuzzed option values: exit 0 with a BAL file whose
/// counts line is the one reported, or exit 2 with one printable line and
/// no file (cameras and points stay small enough, when accepted, for the
/// file to be written in milliseconds: a run that would write more is
/// refused by the observation cap before anything is generated).
#[test]
fn fuzzed_synth_bal_arguments_keep_the_contract() {
    let mut rng = Rng(0x05e1_7ba1);
    let options = [
        "--cameras",
        "--points",
        "--views",
        "--seed",
        "--outliers",
        "--noise",
    ];
    for case in 0..160 {
        let out = temp_path("synth").with_extension("txt");
        let out_text = out.to_str().expect("UTF-8").to_owned();
        let mut values = vec!["5", "40", "3", "1", "0.05", "1"];
        for _ in 0..1 + rng.below(2) {
            let slot = rng.below(values.len());
            values[slot] = *rng.pick(SYNTH_VALUES);
        }
        // Keep accepted runs small: at most 1000 points.
        if values[1]
            .parse::<u64>()
            .is_ok_and(|p| (1001..=20_000_000).contains(&p))
        {
            values[1] = "1000";
        }
        let mut args = vec!["synth-bal"];
        for (option, value) in options.iter().zip(&values) {
            args.extend_from_slice(&[option, value]);
        }
        args.extend_from_slice(&["--output", &out_text]);
        let label = format!("synth-bal case {case}: {values:?}");
        let result = run(&args, b"", &label);
        let code = result.code.unwrap_or_else(|| panic!("{label}: signal"));
        let line = result.stderr.strip_suffix('\n').unwrap_or(&result.stderr);
        match code {
            0 => {
                let written = std::fs::read_to_string(&out).expect("the file is written");
                let counts = written.lines().next().expect("a counts line");
                let report = String::from_utf8_lossy(&result.stdout);
                let [c, p, o]: [&str; 3] = counts
                    .split(' ')
                    .collect::<Vec<_>>()
                    .try_into()
                    .unwrap_or_else(|_| panic!("{label}: counts {counts}"));
                assert!(
                    report.contains(&format!("{c} cameras, {p} points, {o} observations")),
                    "{label}: {report}"
                );
                let _ = std::fs::remove_file(&out);
            }
            BAD_INPUT => {
                assert!(
                    line.starts_with("error: ") && !line.contains('\n'),
                    "{label}: {line}"
                );
                assert!(!line.chars().any(unprintable), "{label}: {line:?}");
                assert!(!out.exists(), "{label}: a file after an error");
            }
            other => panic!("{label}: exit {other}: {line}"),
        }
    }
}
