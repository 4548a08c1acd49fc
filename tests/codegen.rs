//! Code generation is deterministic, and the committed `generated/` is what
//! the current factor definitions generate (what `slamjac check` verifies).

use std::path::Path;

use slamjac::kernels::generate_all;

/// Regenerating from unchanged definitions is byte-identical.
#[test]
fn generation_is_deterministic() {
    let first = generate_all().expect("the document kernels generate");
    let second = generate_all().expect("the document kernels generate");
    assert_eq!(first, second);
    assert_eq!(first.files(), second.files());
}

/// The committed `generated/` is what the definitions generate (what
/// `slamjac check` verifies in CI). On failure, run
/// `cargo run --release --no-default-features -- generate`.
#[test]
fn committed_generated_crate_is_current() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("generated");
    let generated = generate_all().expect("the document kernels generate");
    if let Err(stale) = generated.check(&dir) {
        panic!("stale generated files (run `slamjac generate`): {stale:?}");
    }
}
