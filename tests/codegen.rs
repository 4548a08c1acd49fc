//! Code generation is deterministic, and the committed `generated/` is what
//! the current factor definitions generate (what `slamjac check` verifies).

use std::path::Path;

use factor_codegen as codegen;

/// Regenerating from unchanged definitions is byte-identical.
#[test]
fn generation_is_deterministic() {
    let first = slamjac::kernels::generate_all();
    let second = slamjac::kernels::generate_all();
    assert_eq!(first, second);
    let files = codegen::crate_writer::crate_files(&first);
    assert_eq!(files, codegen::crate_writer::crate_files(&second));
}

/// The committed `generated/` is what the definitions generate (what
/// `slamjac check` verifies in CI). On failure, run
/// `cargo run --release --no-default-features -- generate`.
#[test]
fn committed_generated_crate_is_current() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("generated");
    let modules = slamjac::kernels::generate_all();
    if let Err(stale) = codegen::check_crate(&dir, &modules) {
        panic!("stale generated files (run `slamjac generate`): {stale:?}");
    }
}
