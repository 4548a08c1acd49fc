//! Records the optimisation level this crate is built at (`OPT_LEVEL`,
//! which Cargo sets from the profile and its per-package overrides), so the
//! generator can say when a debug build without the `opt-level = 3` entries
//! makes generation slow (`factor_codegen::build_profile`).

fn main() {
    let level = std::env::var("OPT_LEVEL").unwrap_or_default();
    println!("cargo::rustc-env=FACTOR_CODEGEN_OPT_LEVEL={level}");
    println!("cargo::rerun-if-changed=build.rs");
}
