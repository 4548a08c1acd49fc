//! `slamjac init DIR [--name NAME]`: a new project for factors of your own,
//! complete the first time.
//!
//! DIR becomes a Cargo workspace of three crates that depend on this
//! checkout by path:
//!
//! | crate | what |
//! | --- | --- |
//! | `NAME-factors` | the factors (one example, `PositionPrior`, and a test of its Jacobians and of its kernel against its current definition); depends on `factor-core` only, and on `NAME-kernels` through its default feature `kernels` |
//! | `NAME-kernels` | the generated kernels: its `Cargo.toml` declares the feature `lanes` the sources use ([`factor_codegen::manifest`]); until the first generation its `src/lib.rs` is a compile error naming the command |
//! | `NAME-cli` | the command line, binary `NAME`: `list`, `eval`, `generate`, `check`, and with its feature `solve`, `solve` of problem files ([`crate::cli`]); the code generator is its dependency, not the factors' |
//!
//! The workspace's `Cargo.toml` holds the profile entries that make
//! generation take seconds in a debug build
//! ([`factor_codegen::build_profile::PROFILE_ENTRIES`]). `generate` runs as
//! `cargo run -p NAME-cli --no-default-features -- generate`: without the
//! feature `kernels` the factors build without their kernels, so the one
//! command works when they are missing or stale. docs/guide/kernels.md
//! walks through the project.

use std::path::{Path, PathBuf};

use factor_codegen::build_profile::PROFILE_ENTRIES;
use factor_codegen::manifest::{Membership, manifest, placeholder_lib, toml_escaped};
use slamjac_problem::InputError;
use slamjac_problem::field_path::{quoted, shown_path};

use crate::error::CliError;

/// The checkout this binary was built from, which the project depends on.
const CHECKOUT: &str = env!("CARGO_MANIFEST_DIR");

/// The workspace's `Cargo.toml`.
const WORKSPACE: &str = r#"# Factors of your own, with generated kernels and a command line (written by
# `slamjac init`). The crates depend on the slamjac checkout at
# @CHECKOUT@ by path.

[workspace]
members = ["@NAME@-factors", "@NAME@-kernels", "@NAME@-cli"]
resolver = "3"

# `generate` traces each factor and compiles its kernel: the symbolic engine
# and the generator are optimised even in debug builds, which makes it take
# seconds instead of a minute. Cargo reads profiles from this file only.
@PROFILE@"#;

/// `NAME-factors/Cargo.toml`.
const FACTORS_MANIFEST: &str = r#"[package]
name = "@NAME@-factors"
version = "0.1.0"
edition = "2024"
publish = false

[dependencies]
factor-core = { path = "@CHECKOUT@/factor-core" }
@NAME@-kernels = { path = "../@NAME@-kernels", optional = true }

[features]
# `linearize()` goes through the generated kernels of `@NAME@-kernels`.
# Without it the factors linearize by dual numbers, which is how
# `@GENERATE@` builds them.
default = ["kernels"]
kernels = ["dep:@NAME@-kernels"]

[dev-dependencies]
# `assert_correct_jacobians`: each factor's Jacobians against central
# differences on its variables' manifolds; `assert_generated_matches_dual`:
# its kernel against the current definition (tests/jacobians.rs).
factor-testing = { path = "@CHECKOUT@/factor-testing" }
"#;

/// `NAME-factors/tests/jacobians.rs`: the example factor's Jacobians
/// checked, and its kernel against the current definition.
const FACTORS_TEST: &str = r#"//! Each factor's Jacobians by dual numbers against central differences on
//! its variables' manifolds, and (with the feature `kernels`, the default)
//! its generated kernel against dual numbers through the current
//! definition: a residual edited without regenerating the kernels fails
//! here, naming the command that regenerates them.

use factor_core::nalgebra::Vector3;
use factor_testing::{DEFAULT_TOLERANCE, assert_correct_jacobians};
use @IDENT@_factors::PositionPrior;

#[test]
fn position_prior_jacobians_are_correct() {
    let f = PositionPrior {
        measured: Vector3::new(1.5, 2.0, 2.5),
        position: Vector3::new(1.0, 2.0, 3.0),
    };
    assert_correct_jacobians(&f, DEFAULT_TOLERANCE);
    #[cfg(feature = "kernels")]
    factor_testing::assert_generated_matches_dual(&f, factor_testing::GENERATED_TOLERANCE);
}
"#;

/// `NAME-cli/tests/kernels_are_current.rs`: every registered factor's
/// kernel against its current definition, through the command line's
/// `check`.
const CLI_TEST: &str = r#"//! Every factor `src/main.rs` registers with a kernel: its kernel in
//! `@NAME@-kernels` is what its current definition generates (the command
//! line's `check`). A residual, a function it calls or a retraction edited
//! without regenerating fails here, for a factor added later too, with no
//! test of its own.

use std::process::Command;

#[test]
fn the_kernels_are_current() {
    let check = Command::new(env!("CARGO_BIN_EXE_@NAME@"))
        .arg("check")
        .output()
        .expect("the command line runs");
    assert!(
        check.status.success(),
        "{}",
        String::from_utf8_lossy(&check.stderr)
    );
}
"#;

/// `NAME-factors/src/lib.rs`: one example factor.
const FACTORS_LIB: &str = r#"//! The factors of `@NAME@`. Each has a kernel in `@NAME@-kernels`, written by
//! `@GENERATE@`.

use factor_core::nalgebra::Vector3;
use factor_core::{Factor, Scalar};

/// A position prior: the position `p` measured as `m`, `r = p − m`.
#[derive(Clone, Debug, Factor)]
#[factor(residual = position_prior_residual, dim = 3)]
#[cfg_attr(
    feature = "kernels",
    factor(
        kernel = @IDENT@_kernels::position_prior::position_prior,
        regenerate = "@GENERATE@"
    )
)]
pub struct PositionPrior<S: Scalar = f64> {
    /// The measured position `m`.
    pub measured: Vector3<S>,
    /// The position `p`.
    #[variable]
    pub position: Vector3<S>,
}

/// `r = p − m`.
pub fn position_prior_residual<S: Scalar>(f: &PositionPrior<S>) -> Vector3<S> {
    f.position - f.measured
}
"#;

/// `NAME-cli/Cargo.toml`.
const CLI_MANIFEST: &str = r#"[package]
name = "@NAME@-cli"
version = "0.1.0"
edition = "2024"
publish = false

[[bin]]
name = "@NAME@"
path = "src/main.rs"

[dependencies]
slamjac = { path = "@CHECKOUT@", default-features = false }
@NAME@-factors = { path = "../@NAME@-factors", default-features = false }

[features]
# `eval` runs the generated kernels. `--no-default-features` builds the
# factors without them: `generate` then works when they are missing or stale.
default = ["kernels"]
kernels = ["@NAME@-factors/kernels"]
# `@NAME@ solve PROBLEM.json`: problem files solved by apex-solver (its first
# build takes minutes; build with `--release --features solve`).
solve = ["slamjac/solve", "kernels"]
"#;

/// `NAME-cli/src/main.rs`.
const CLI_MAIN: &str = r#"//! `@NAME@`: list the factors of `@NAME@-factors`, evaluate them from JSON,
//! generate or check their kernels in `@NAME@-kernels`, and (feature `solve`)
//! solve problem files of them.

use std::process::ExitCode;

use slamjac::cli::{CommandLine, KernelCrate, KernelSpec, Provenance, Registry};

/// The crate `generate` writes and `check` compares.
const KERNELS: KernelCrate = KernelCrate {
    package: "@NAME@-kernels",
    dir: concat!(env!("CARGO_MANIFEST_DIR"), "/../@NAME@-kernels"),
    provenance: Provenance::new(
        "Residual-and-Jacobian kernels of the factors of `@NAME@-factors`.",
        "@GENERATE@",
        "@CHECK@",
    ),
};

fn main() -> ExitCode {
    Registry::new()
        // `list`, `eval`, and its kernel in what `generate` writes; with
        // `generate --lang cpp`, its C++ with a Ceres cost function.
        .with_kernel::<@IDENT@_factors::PositionPrior>()
        .with_spec(KernelSpec::of::<@IDENT@_factors::PositionPrior>().with_ceres())
        // `solve`: problem files, linearized by dual numbers in
        // apex-solver's chart. A factor with `hosts(apex)` and a kernel
        // generated for that host (`.with_spec(KernelSpec::of::<F>()
        // .with_host(HostSpec::of::<F, Apex>()))`) is solved through it
        // with `.solve_with_kernel::<F>()` (in builds with the kernels).
        .solve_with_dual::<@IDENT@_factors::PositionPrior>()
        .with_kernel_crate(KERNELS)
        .run("@NAME@")
}
"#;

/// `inputs/position_prior.json`: an `eval` input.
const INPUT: &str = r#"{"factor": "position_prior",
 "variables": {"position": [1.0, 2.0, 3.0]},
 "constants": {"measured": [1.5, 2.0, 2.5]}}
"#;

/// `inputs/position_problem.json`: a problem file for `solve`, two
/// measurements of one position (solved: their mean).
const PROBLEM: &str = r#"{"slamjac_problem": 1,
 "variables": {"p": {"type": "Vector3", "value": [0.0, 0.0, 0.0]}},
 "factors": [
  {"factor": "position_prior", "variables": {"position": "p"},
   "constants": {"measured": [1.0, 2.0, 3.0]}, "noise": {"sigma": 0.1}},
  {"factor": "position_prior", "variables": {"position": "p"},
   "constants": {"measured": [1.2, 2.0, 2.6]}, "noise": {"sigma": 0.1}}
 ]}
"#;

/// `README.md`.
const README: &str = r#"# @NAME@

Factors with generated kernels and a command line, written by `slamjac init`.

```sh
cargo run -p @NAME@-cli --no-default-features -- generate   # (re)write @NAME@-kernels/src
cargo run -p @NAME@-cli -- list                             # the factors, their inputs and kernels
cargo run -p @NAME@-cli -- eval inputs/position_prior.json  # residual and Jacobians
cargo run -p @NAME@-cli --no-default-features -- generate --lang cpp   # and C++ in @NAME@-kernels/cpp
cargo run -p @NAME@-cli --no-default-features -- check      # exit 1 when the kernels are stale (CI)
cargo test                                                   # the Jacobians against central differences, the kernels against the definitions
cargo run --release -p @NAME@-cli --features solve -- solve inputs/position_problem.json
```

Add a factor to `@NAME@-factors/src/lib.rs` (with its
`#[cfg_attr(feature = "kernels", factor(kernel = ..., regenerate = ...))]`),
register it in `@NAME@-cli/src/main.rs` with `.with_kernel::<YourFactor>()`
(and `.solve_with_dual::<YourFactor>()` for `solve`), then generate, and
give it a test beside the example's in `@NAME@-factors/tests/jacobians.rs`
(`cargo test` checks every registered kernel against its definition
already, in `@NAME@-cli/tests/kernels_are_current.rs`). The slamjac
guide's chapters "Writing a factor", "Kernels of your own factors" and
"Kernels in C++ solvers" say more.
"#;

/// `.gitignore`.
const GITIGNORE: &str = "/target\n";

/// Whether `name` can prefix the crates' names: a lowercase letter, then
/// lowercase letters, digits, `-` or `_`, not ending in `-` or `_`.
fn valid_name(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_ascii_lowercase())
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' || c == '_')
        && !name.ends_with(['-', '_'])
}

/// The project's files for `name`, as `(path relative to DIR, contents)`.
pub fn files(name: &str) -> Vec<(String, String)> {
    let generate = format!("cargo run -p {name}-cli --no-default-features -- generate");
    let check = format!("cargo run -p {name}-cli --no-default-features -- check");
    let fill = |template: &str| {
        template
            .replace("@NAME@", name)
            .replace("@IDENT@", &name.replace('-', "_"))
            .replace("@CHECKOUT@", &toml_escaped(CHECKOUT))
            .replace("@GENERATE@", &generate)
            .replace("@CHECK@", &check)
            .replace("@PROFILE@", PROFILE_ENTRIES)
    };
    let kernels = format!("{name}-kernels");
    vec![
        ("Cargo.toml".into(), fill(WORKSPACE)),
        (".gitignore".into(), GITIGNORE.into()),
        ("README.md".into(), fill(README)),
        ("inputs/position_prior.json".into(), INPUT.into()),
        ("inputs/position_problem.json".into(), PROBLEM.into()),
        (format!("{name}-factors/Cargo.toml"), fill(FACTORS_MANIFEST)),
        (format!("{name}-factors/src/lib.rs"), fill(FACTORS_LIB)),
        (
            format!("{name}-factors/tests/jacobians.rs"),
            fill(FACTORS_TEST),
        ),
        (
            format!("{kernels}/Cargo.toml"),
            manifest(&kernels, &generate, &check, Membership::Member),
        ),
        (format!("{kernels}/src/lib.rs"), placeholder_lib(&generate)),
        (format!("{name}-cli/Cargo.toml"), fill(CLI_MANIFEST)),
        (format!("{name}-cli/src/main.rs"), fill(CLI_MAIN)),
        (
            format!("{name}-cli/tests/kernels_are_current.rs"),
            fill(CLI_TEST),
        ),
    ]
}

/// `slamjac init DIR [--name NAME]`: writes [`files`] into DIR, which must
/// be new or empty; NAME defaults to DIR's name. The project is written
/// whole or not at all ([`slamjac_io::atomic::write_tree`]): a failure (a
/// name too long for the file system, a file-size limit) or an
/// interruption leaves DIR as it was.
pub fn run(dir: &Path, name: Option<&str>) -> Result<String, CliError> {
    let at = |message: String| -> CliError {
        InputError::new(dir.display().to_string(), message).into()
    };
    let name = match name {
        Some(name) => name.to_owned(),
        None => dir
            .file_name()
            .map(|n| n.to_string_lossy().to_lowercase())
            .unwrap_or_default(),
    };
    if !valid_name(&name) {
        return Err(CliError::Usage(format!(
            "init: {} cannot name the crates: give --name NAME, a lowercase letter then \
             lowercase letters, digits, `-` or `_`",
            quoted(&name)
        )));
    }
    match std::fs::read_dir(dir) {
        Ok(entries) => {
            if entries.into_iter().next().is_some() {
                return Err(at(
                    "refused: init writes into a new or empty directory".into()
                ));
            }
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(at(format!("cannot read: {e}"))),
    }
    let files: Vec<(PathBuf, Vec<u8>)> = files(&name)
        .into_iter()
        .map(|(path, contents)| (path.into(), contents.into_bytes()))
        .collect();
    // All or nothing: staged beside DIR and renamed into place.
    slamjac_io::atomic::write_tree(dir, &files).map_err(|e| at(format!("cannot write: {e}")))?;
    let shown = shown_path(dir);
    Ok(format!(
        "wrote {} files into {shown}: the crates {name}-factors, {name}-kernels and {name}-cli\n\
         next, in {shown}:\n  \
         cargo run -p {name}-cli --no-default-features -- generate\n  \
         cargo run -p {name}-cli -- eval inputs/position_prior.json",
        files.len(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_crate_name_prefixes() {
        for good in ["vio", "my-vio", "a1_b"] {
            assert!(valid_name(good), "{good}");
        }
        for bad in ["", "Vio", "1vio", "vio-", "my vio", "vio/x"] {
            assert!(!valid_name(bad), "{bad}");
        }
    }

    #[test]
    fn every_placeholder_is_filled() {
        for (path, contents) in files("my-vio") {
            assert!(!contents.contains('@'), "{path}: {contents}");
        }
        let files = files("my-vio");
        let main = &files
            .iter()
            .find(|(p, _)| p == "my-vio-cli/src/main.rs")
            .unwrap()
            .1;
        assert!(main.contains(".with_kernel::<my_vio_factors::PositionPrior>()"));
        let lib = &files
            .iter()
            .find(|(p, _)| p == "my-vio-factors/src/lib.rs")
            .unwrap()
            .1;
        assert!(lib.contains("kernel = my_vio_kernels::position_prior::position_prior"));
    }

    #[test]
    fn a_directory_with_files_is_refused_untouched() {
        let dir = Path::new(CHECKOUT).join("src");
        let error = run(&dir, Some("x")).unwrap_err().to_string();
        assert!(error.ends_with("refused: init writes into a new or empty directory"));
    }
}
