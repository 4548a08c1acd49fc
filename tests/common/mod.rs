//! What the command-line tests share.

use std::io::Write;
use std::process::{Command, Output, Stdio};

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
