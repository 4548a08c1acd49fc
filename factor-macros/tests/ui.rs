//! Compile-fail tests: every misuse of `#[derive(Factor)]` is a compile error
//! at the offending tokens. Regenerate the expected output with
//! `TRYBUILD=overwrite cargo test -p factor-macros --test ui`. The accepted
//! forms are an ordinary test (`tests/forms.rs`): a pass case here would make
//! trybuild build every case one at a time instead of checking them all in
//! one `cargo check`.

#[test]
fn ui() {
    trybuild::TestCases::new().compile_fail("tests/ui/fail_*.rs");
}
