//! Compile-fail tests: every misuse of `#[derive(Factor)]` is a compile error
//! at the offending tokens. Regenerate the expected output with
//! `TRYBUILD=overwrite cargo test -p factor-macros --test ui`.

#[test]
fn ui() {
    let cases = trybuild::TestCases::new();
    cases.pass("tests/ui/pass_*.rs");
    cases.compile_fail("tests/ui/fail_*.rs");
}
