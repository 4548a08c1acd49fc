//! The checked-in `user-kernels/src` is what the factor definitions generate,
//! and the `generate-kernels` binary writes (`--out DIR`) and checks
//! (`--check`) it. Needs no generated kernel: also runs without the feature
//! `kernels`.

use std::path::{Path, PathBuf};
use std::process::Command;

use user_factors::codegen;

/// Runs the `generate-kernels` binary with `args`: exit code, stdout, stderr.
fn generate_kernels(args: &[&str]) -> (Option<i32>, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_generate-kernels"))
        .args(args)
        .output()
        .expect("the binary runs");
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

/// `--check` reports the checked-in kernels current: they are what the factor
/// definitions generate. On failure: `cargo run -p user-factors --bin
/// generate-kernels`. (Each run generates every kernel anew: the tests run
/// the binary three times, no more.)
#[test]
fn check_mode_reports_user_kernels_current() {
    let (code, stdout, stderr) = generate_kernels(&["--check"]);
    assert_eq!(code, Some(0), "stderr: {stderr}");
    let src = codegen::default_dir().join("src");
    assert_eq!(
        stdout,
        format!("{} is up to date (5 kernels)\n", src.display())
    );
}

/// A scratch directory, removed on drop.
struct Scratch(PathBuf);

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// `--out DIR` writes the same sources as the checked-in ones (current, by
/// the tests above), and `--check --out DIR` fails with exit 1 naming an
/// edited file. (Each run generates anew: a few seconds in a debug build.)
#[test]
fn out_writes_and_check_detects_stale() {
    let dir =
        Scratch(std::env::temp_dir().join(format!("user-kernels-test-{}", std::process::id())));
    let out = dir.0.to_str().expect("UTF-8 temporary directory");
    let (code, stdout, stderr) = generate_kernels(&["--out", out]);
    assert_eq!(code, Some(0), "stderr: {stderr}");
    assert!(stdout.contains("generated 5 kernels into"), "{stdout}");
    for file in [
        "lib.rs",
        "real.rs",
        "relative_pose.rs",
        "point_to_plane.rs",
        "scaled_range_bearing.rs",
        "direction.rs",
        "relative_sim3.rs",
    ] {
        let written = std::fs::read(dir.0.join("src").join(file)).expect("written");
        let committed =
            std::fs::read(codegen::default_dir().join("src").join(file)).expect("committed");
        assert!(
            written == committed,
            "{file} differs from the checked-in one"
        );
    }

    let edited = dir.0.join("src").join("point_to_plane.rs");
    std::fs::write(&edited, "// edited\n").expect("writable");
    let (code, _, stderr) = generate_kernels(&["--out", out, "--check"]);
    assert_eq!(code, Some(1));
    assert!(
        stderr.contains(&edited.display().to_string()),
        "names the stale file: {stderr}"
    );
}

#[test]
fn bad_arguments_exit_2() {
    let (code, _, stderr) = generate_kernels(&["--frobnicate"]);
    assert_eq!(code, Some(2));
    assert!(stderr.starts_with("error: unexpected argument `--frobnicate`"));
    assert_eq!(generate_kernels(&["--out"]).0, Some(2));
}

/// Where the binary writes by default: the sibling crate of this one.
#[test]
fn default_dir_is_the_sibling_crate() {
    let dir = codegen::default_dir();
    assert_eq!(dir.file_name(), Some("user-kernels".as_ref()));
    assert!(Path::new(&dir).join("Cargo.toml").is_file());
}
