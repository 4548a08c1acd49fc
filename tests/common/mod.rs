//! What the command-line tests share.

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Output, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};

/// `slamjac ARGS`, with nothing on its standard input.
#[allow(dead_code)] // not every test file runs it so
pub fn slamjac(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_slamjac"))
        .args(args)
        .output()
        .expect("slamjac runs")
}

/// A run's standard output.
#[allow(dead_code)] // not every test file reads it
pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// A run's standard error.
pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// A fresh path `slamjac-GROUP-PID-TAG-N` in the temporary directory,
/// nothing created there.
#[allow(dead_code)] // not every test file writes files
pub fn temp_path(group: &str, tag: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    std::env::temp_dir().join(format!("slamjac-{group}-{}-{tag}-{n}", std::process::id()))
}

/// A fresh directory [`temp_path`], created.
#[allow(dead_code)] // not every test file writes files
pub fn temp_dir(group: &str, tag: &str) -> PathBuf {
    let dir = temp_path(group, tag);
    std::fs::create_dir_all(&dir).expect("temporary directory");
    dir
}

/// `slamjac ARGS` with `stdin` piped in. A process that exits before
/// reading its input closes the pipe; that is fine.
#[allow(dead_code)] // not every test file pipes input
pub fn slamjac_with_stdin(args: &[&str], stdin: &[u8]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_slamjac"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("slamjac starts");
    let _ = child.stdin.take().expect("piped stdin").write_all(stdin);
    child.wait_with_output().expect("slamjac runs")
}

/// SplitMix64: a small seeded generator, so that every run fuzzes the same cases.
#[allow(dead_code)] // not every test file fuzzes
pub struct Rng(pub u64);

#[allow(dead_code)] // not every test file uses every method
impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// The names in `dir`, sorted.
#[allow(dead_code)] // not every test file lists directories
pub fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("readable")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}
