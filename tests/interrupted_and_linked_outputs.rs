//! Outputs under hostile conditions (issue 28), for the commands built
//! without the feature `solve` (`solve` and `track`: `tests/solve.rs`):
//!
//! - a writer interrupted by `SIGINT` or `SIGTERM` while it streams
//!   (`synth-bal`) ends by that signal, leaves no temporary file and the
//!   destination as it was (class B);
//! - a symbolic link as output has its target written and stays a link; a
//!   dangling one has its target created, `0666` less the umask; one whose
//!   target's directory is missing, and a path ending in `/`, are refused
//!   before anything is written (classes C and E);
//! - `init` writes its project whole or not at all (a name too long for the
//!   file system, a file-size limit) and echoes no control character raw
//!   (classes E and L).

use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::common;
use common::{listing, slamjac, stderr, stdout};

/// A fresh directory for this file's tests.
fn temp_dir(tag: &str) -> PathBuf {
    common::temp_dir("outputs", tag)
}

fn text(path: &Path) -> &str {
    path.to_str().expect("UTF-8 path")
}

/// Asserts exit 2 and one line `error: …` holding every needle.
fn assert_refused(output: &Output, needles: &[&str]) {
    let err = stderr(output);
    assert_eq!(output.status.code(), Some(2), "stderr: {err}");
    assert!(
        err.starts_with("error: ") && err.lines().count() == 1,
        "{err}"
    );
    for needle in needles {
        assert!(err.contains(needle), "`{err}` lacks `{needle}`");
    }
}

/// `synth-bal` streaming a problem far larger than it will get to write,
/// interrupted by `signal` once its temporary file exists: it ends by that
/// signal, the old file is whole and nothing else is left.
fn interrupt_a_streaming_writer(signal: &str, number: i32) {
    let dir = temp_dir(signal);
    let out = dir.join("problem.txt");
    std::fs::write(&out, "the user's data\n").unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_slamjac"))
        .args([
            "synth-bal",
            "--cameras",
            "1000",
            "--points",
            "20000000",
            "--output",
            text(&out),
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while listing(&dir).len() < 2 {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no temporary file appeared"
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "the writer ended early"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    // Some of it written: the interruption comes mid-stream.
    std::thread::sleep(Duration::from_millis(200));
    let killed = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(number), "{status:?}");
    assert_eq!(listing(&dir), ["problem.txt"], "a temporary was left");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "the user's data\n");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_interrupted_writer_leaves_no_temporary_and_the_old_file() {
    interrupt_a_streaming_writer("INT", 2);
    interrupt_a_streaming_writer("TERM", 15);
}

/// This process's umask, from `/proc/self/status` (reading it with
/// `umask(2)` would set it).
fn umask() -> u32 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let line = status.lines().find(|l| l.starts_with("Umask:")).unwrap();
    u32::from_str_radix(line["Umask:".len()..].trim(), 8).unwrap()
}

#[test]
fn links_are_written_through_and_bad_destinations_refused_before_any_work() {
    use std::os::unix::fs::PermissionsExt;
    let dir = temp_dir("links");
    std::fs::create_dir(dir.join("other")).unwrap();
    let link = dir.join("o.json");
    std::os::unix::fs::symlink("other/new.json", &link).unwrap();
    let output = slamjac(&["synth-plp", "--output", text(&link)]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(link.is_symlink(), "the link stays a link");
    let target = dir.join("other/new.json");
    let written = std::fs::read_to_string(&target).unwrap();
    assert!(
        written.starts_with("{\n  \"slamjac_problem\": 1"),
        "{written}"
    );
    let mode = std::fs::metadata(&target).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o666 & !umask());

    let nowhere = dir.join("nowhere.json");
    std::os::unix::fs::symlink("missing/new.json", &nowhere).unwrap();
    let output = slamjac(&["synth-plp", "--output", text(&nowhere)]);
    assert_refused(&output, &["--output: cannot write here", "does not exist"]);
    let slash = format!("{}/", text(&dir.join("x.json")));
    let output = slamjac(&["synth-plp", "--output", &slash]);
    assert_refused(
        &output,
        &["--output: cannot write here", "does not name a file"],
    );
    let output = slamjac(&[
        "synth-bal",
        "--cameras",
        "5",
        "--points",
        "10",
        "--output",
        &slash,
    ]);
    assert_refused(&output, &["does not name a file"]);
    assert_eq!(listing(&dir), ["nowhere.json", "o.json", "other"]);
    assert_eq!(listing(&dir.join("other")), ["new.json"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn init_writes_its_project_whole_or_not_at_all() {
    let dir = temp_dir("init");
    let project = dir.join("project");
    // `NAME-factors` is past 255 bytes, the file systems' limit on a name.
    let long = "n".repeat(250);
    let output = slamjac(&["init", text(&project), "--name", &long]);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(2), "{err}");
    assert!(
        err.contains("cannot write") && err.lines().count() == 1,
        "{err}"
    );
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
    // A file-size limit of one block: the first larger file fails.
    let limited = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -f 1; exec '{}' init '{}' --name vio",
            env!("CARGO_BIN_EXE_slamjac"),
            text(&project)
        ))
        .output()
        .unwrap();
    assert_eq!(limited.status.code(), Some(2), "{}", stderr(&limited));
    assert!(
        stderr(&limited).contains("File too large"),
        "{}",
        stderr(&limited)
    );
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
    // Whole, the next time.
    let output = slamjac(&["init", text(&project), "--name", "vio"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(listing(&dir), ["project"]);
    assert!(project.join("vio-cli/src/main.rs").is_file());

    // A directory name with an escape sequence and a line break: echoed
    // escaped, in the error and in the report.
    let odd = dir.join("odd\u{1b}[31m\nname");
    for (args, out) in [
        (vec!["init", text(&odd)], false),
        (vec!["init", text(&odd), "--name", "odd"], true),
    ] {
        let output = slamjac(&args);
        let shown = if out {
            stdout(&output)
        } else {
            stderr(&output)
        };
        assert!(!shown.contains('\u{1b}'), "{shown:?}");
        assert!(shown.contains("odd\\u001b[31m\\nname"), "{shown:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `init` and a writer over links, fuzzed: seeded names of hostile
/// characters and lengths, and outputs through seeded chains of links
/// (dangling, to missing directories, to directories, looping). Each run
/// ends 0 or 2 with one printable line on error; a refused `init` leaves
/// nothing; a written output is reached through its links and leaves no
/// temporary.
#[test]
fn init_and_outputs_over_links_fuzzed() {
    let mut rng = common::Rng(0x0028_11e5);
    let dir = temp_dir("fuzz");
    const PIECES: &[&str] = &[
        "a",
        "z9",
        "-",
        "_",
        "\u{1b}[2J",
        "\n",
        "\u{feff}",
        "\u{200b}",
        "é",
        " ",
        ".",
        "..",
        "A",
        "\t",
        "\u{7f}",
    ];
    for k in 0..24 {
        let mut name = String::new();
        for _ in 0..1 + rng.below(6) {
            let piece: &&str = rng.pick(PIECES);
            name.push_str(piece);
        }
        if rng.below(4) == 0 {
            name = name.repeat(1 + rng.below(80));
        }
        let project = dir.join(format!("p{k}"));
        let output = slamjac(&["init", text(&project), "--name", &name]);
        let err = stderr(&output);
        match output.status.code() {
            Some(0) => assert!(project.join("Cargo.toml").is_file(), "{name:?}"),
            Some(2) => {
                assert!(
                    err.starts_with("error: ") && err.lines().count() == 1,
                    "{err}"
                );
                assert!(
                    !err.contains('\u{1b}') && !err.contains('\u{feff}'),
                    "{err:?}"
                );
                assert!(
                    !project.exists(),
                    "{name:?}: a refused init left {project:?}"
                );
            }
            other => panic!("{name:?}: exit {other:?}: {err}"),
        }
    }
    let links = dir.join("links");
    std::fs::create_dir(&links).unwrap();
    std::fs::create_dir(links.join("sub")).unwrap();
    const TARGETS: &[&str] = &[
        "sub/new.json",
        "missing/new.json",
        "sub",
        "next",
        "sub/../o",
        ".",
    ];
    for k in 0..24 {
        let chain: Vec<String> = (0..1 + rng.below(3)).map(|i| format!("l{k}-{i}")).collect();
        for (i, link) in chain.iter().enumerate() {
            let target = match chain.get(i + 1) {
                Some(next) => next.clone(),
                None => {
                    let target: &&str = rng.pick(TARGETS);
                    target.replace("next", &chain[0])
                }
            };
            std::os::unix::fs::symlink(&target, links.join(link)).unwrap();
        }
        let first = links.join(&chain[0]);
        let output = slamjac(&["synth-plp", "--cameras", "8", "--output", text(&first)]);
        let err = stderr(&output);
        match output.status.code() {
            Some(0) => {
                assert!(first.is_symlink(), "{chain:?}");
                let written = std::fs::read_to_string(&first).unwrap();
                assert!(
                    written.starts_with("{\n  \"slamjac_problem\": 1"),
                    "{chain:?}"
                );
            }
            Some(2) => {
                assert!(
                    err.starts_with("error: ") && err.lines().count() == 1,
                    "{err}"
                );
            }
            other => panic!("{chain:?}: exit {other:?}: {err}"),
        }
        for place in [links.clone(), links.join("sub")] {
            assert!(
                listing(&place).iter().all(|n| !n.starts_with('.')),
                "{chain:?}: a temporary left in {place:?}: {:?}",
                listing(&place)
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
