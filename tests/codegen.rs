//! Code generation is deterministic, and the committed `generated/` is what
//! the current factor definitions generate (what `slamjac check` verifies).

use std::path::Path;

use factor_codegen::GeneratedCrate;
use slamjac::kernels::{PROVENANCE, generate_all, shipped_kernels};

/// Regenerating from unchanged definitions is byte-identical. Two kernels
/// stand for all (every shipped kernel takes the same path; generating all
/// of them twice would cost a minute): the point's, and the plane's with
/// its branches, both with normal equations and apex's chart. The
/// committed crate, written by another process, being current (below) says
/// the same of every kernel across processes.
#[test]
fn generation_is_deterministic() {
    let specs: Vec<_> = shipped_kernels()
        .into_iter()
        .filter(|spec| ["point_reprojection", "plane"].contains(&spec.name))
        .collect();
    assert_eq!(specs.len(), 2);
    let first = GeneratedCrate::generate(PROVENANCE, &specs).expect("the kernels generate");
    let second = GeneratedCrate::generate(PROVENANCE, &specs).expect("the kernels generate");
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
