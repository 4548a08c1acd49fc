//! The kernel crate's files that [`crate::GeneratedCrate`] does not keep up
//! to date: its `Cargo.toml` ([`manifest`]), written once and then the
//! user's, and the `src/lib.rs` it holds until the first generation
//! ([`placeholder_lib`]). `slamjac init` writes both into a new project;
//! `slamjac generate --out DIR` writes the manifest into a new directory.

use std::path::{Path, PathBuf};

/// How the kernel crate relates to the Cargo workspace around it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Membership {
    /// A member of the workspace that lists it.
    Member,
    /// A workspace of its own (an empty `[workspace]` table), so it builds
    /// wherever it is written.
    Standalone,
}

/// The path of `factor-lanes` beside this crate, for the optional
/// dependency of the `lanes` feature.
fn factor_lanes() -> PathBuf {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    here.parent().unwrap_or(here).join("factor-lanes")
}

/// The `Cargo.toml` of a kernel crate named `package` whose sources the
/// commands `generate` and `check` write and check (those of its
/// [`crate::Provenance`]): no dependencies, the feature
/// `lanes` the sources test declared (with its optional dependency
/// `factor-lanes`, so no `unexpected cfg condition value` warning), and an
/// explicit `[lib] path`, so the workspace loads before `src/` exists.
///
/// ```
/// use factor_codegen::manifest::{Membership, manifest};
///
/// let toml = manifest("my-kernels", "my-cli generate", "my-cli check", Membership::Member);
/// assert!(toml.contains("name = \"my-kernels\""));
/// assert!(toml.contains("lanes = [\"dep:factor-lanes\"]"));
/// assert!(!toml.contains("[workspace]"));
/// ```
pub fn manifest(package: &str, generate: &str, check: &str, membership: Membership) -> String {
    let lib = package.replace('-', "_");
    let lanes = toml_escaped(&factor_lanes().display().to_string());
    let mut toml = format!(
        "# The crate of generated kernels. Everything under `src/` is written by\n\
         # `{generate}` and checked by\n\
         # `{check}`; this file is yours to edit.\n\
         \n\
         [package]\n\
         name = \"{package}\"\n\
         version = \"0.1.0\"\n\
         edition = \"2024\"\n\
         publish = false\n\
         \n\
         # Explicit, so that the workspace loads before `src/` is generated.\n\
         [lib]\n\
         name = \"{lib}\"\n\
         path = \"src/lib.rs\"\n\
         \n\
         # The kernels have no dependencies; the feature `lanes` runs them on the\n\
         # SIMD lane types of `factor-lanes`.\n\
         [dependencies]\n\
         factor-lanes = {{ path = \"{lanes}\", optional = true }}\n\
         \n\
         [features]\n\
         lanes = [\"dep:factor-lanes\"]\n"
    );
    if membership == Membership::Standalone {
        toml.push_str(
            "\n\
             # A workspace of its own; remove this table to make the crate a member of\n\
             # an enclosing one.\n\
             [workspace]\n",
        );
    }
    toml
}

/// `text` as the inside of a TOML basic string (`"…"`).
pub fn toml_escaped(text: &str) -> String {
    text.replace('\\', "\\\\").replace('"', "\\\"")
}

/// The `src/lib.rs` of a kernel crate before its first generation: a
/// compile error that names the command `generate` that generates it,
/// instead of `couldn't read src/lib.rs`. The generator replaces it.
pub fn placeholder_lib(generate: &str) -> String {
    format!(
        "//! No kernels generated yet: `{generate}` writes them.\n\
         \n\
         compile_error!(\n    \
             \"no kernels generated yet: run `{generate}` (it builds the factors without \
         their kernels and writes this crate's sources)\"\n\
         );\n"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_standalone_manifest_is_a_workspace_of_its_own() {
        let member = manifest("k", "gen", "gen --check", Membership::Member);
        let standalone = manifest("k", "gen", "gen --check", Membership::Standalone);
        assert!(standalone.starts_with(&member));
        assert!(standalone.ends_with("[workspace]\n"));
        assert!(member.contains("name = \"k\"\n"));
        assert!(member.contains("`gen` and checked by\n# `gen --check`"));
    }

    #[test]
    fn the_lanes_dependency_is_this_workspace_s() {
        let path = factor_lanes().join("Cargo.toml");
        let toml = std::fs::read_to_string(path).unwrap();
        assert!(toml.contains("name = \"factor-lanes\""));
    }

    #[test]
    fn toml_strings_escape_quotes_and_backslashes() {
        assert_eq!(toml_escaped(r#"C:\a "b""#), r#"C:\\a \"b\""#);
    }

    #[test]
    fn the_placeholder_names_the_command() {
        let lib = placeholder_lib("gen");
        assert!(lib.contains("compile_error!("));
        assert!(lib.contains("run `gen`"));
    }
}
