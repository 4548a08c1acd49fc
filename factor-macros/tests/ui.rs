//! Compile-fail tests: every misuse of `#[derive(Factor)]` is a compile error
//! at the offending tokens. Regenerate the expected output with
//! `TRYBUILD=overwrite cargo test -p factor-macros --test ui`. The accepted
//! forms are an ordinary test (`tests/forms.rs`): a pass case here would make
//! trybuild build every case one at a time instead of checking them all in
//! one `cargo check`.

#[test]
fn ui() {
    // trybuild checks its project's dependencies (factor-core, nalgebra, …)
    // twice: first alone, then with the cases and `--diagnostic-width=140`
    // added to its rustflags, which changes every dependency's fingerprint.
    // Cargo prefers `CARGO_ENCODED_RUSTFLAGS` to the `--config` rustflags
    // trybuild passes: set to its second set of flags (trybuild 1.0.122),
    // both checks use the same ones and the dependencies are checked once.
    // SAFETY: this is the binary's only test; no other thread reads the
    // environment.
    unsafe {
        std::env::set_var(
            "CARGO_ENCODED_RUSTFLAGS",
            [
                "--cfg",
                "trybuild",
                "--verbose",
                "-A",
                "dead_code",
                "--diagnostic-width=140",
            ]
            .join("\x1f"),
        );
    }
    trybuild::TestCases::new().compile_fail("tests/ui/fail_*.rs");
}
