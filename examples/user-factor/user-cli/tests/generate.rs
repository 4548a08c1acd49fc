//! The checked-in `user-kernels/src` is what the factor definitions
//! generate (`user-cli check`). Needs no generated kernel: also runs
//! without the feature `kernels`.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs `user-cli` with `args`: exit code, stdout, stderr.
fn user_cli(args: &[&str]) -> (Option<i32>, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_user-cli"))
        .args(args)
        .output()
        .expect("the binary runs");
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

/// The sibling crate `user-kernels`, which `generate` writes by default.
fn kernel_crate() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../user-kernels")
}

/// `check` reports the checked-in kernels current: they are what the
/// factor definitions generate. (It generates every kernel anew, seconds in
/// a debug build; `generate --out` and `check` of an edited crate are
/// slamjac's own command line's tests, `tests/cli.rs`.) On failure: `cargo
/// run -p user-cli --no-default-features -- generate`.
#[test]
fn check_reports_user_kernels_current() {
    let (code, stdout, stderr) = user_cli(&["check"]);
    assert_eq!(code, Some(0), "stderr: {stderr}");
    let src = kernel_crate().join("src");
    assert!(stdout.contains("up to date"), "{stdout}");
    assert!(src.join("relative_sim3.rs").is_file());
}

#[test]
fn bad_arguments_exit_2() {
    let (code, _, stderr) = user_cli(&["--frobnicate"]);
    assert_eq!(code, Some(2));
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert_eq!(user_cli(&["generate", "--out"]).0, Some(2));
}
