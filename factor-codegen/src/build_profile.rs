//! Whether the generator was built fast enough to generate in seconds.
//!
//! Tracing a factor (crate `factor-symbolic`) and compiling its kernel
//! (this crate) take several times longer unoptimised, and a debug build
//! optimises no dependency unless the workspace's root `Cargo.toml` says so:
//! profile entries are read from the workspace root only, so a user's
//! workspace needs [`PROFILE_ENTRIES`] of its own (`slamjac init` writes
//! them). [`unoptimized_warning`] says when they are missing; generators
//! print it beside their report.

/// The optimisation level this crate was built at.
pub const OPT_LEVEL: &str = env!("FACTOR_CODEGEN_OPT_LEVEL");

/// What a workspace's root `Cargo.toml` needs so that debug builds generate
/// in seconds: the symbolic engine and the generator optimised (both small
/// crates, compiled once).
pub const PROFILE_ENTRIES: &str = "[profile.dev.package.factor-symbolic]\n\
                                   opt-level = 3\n\
                                   \n\
                                   [profile.dev.package.factor-codegen]\n\
                                   opt-level = 3\n";

/// The crates of the generator built at `opt-level = 0`, if any (named as
/// in `Cargo.toml`).
pub fn unoptimized() -> Vec<&'static str> {
    [
        ("factor-symbolic", factor_symbolic::OPT_LEVEL),
        ("factor-codegen", OPT_LEVEL),
    ]
    .into_iter()
    .filter(|(_, level)| *level == "0")
    .map(|(name, _)| name)
    .collect()
}

/// A warning naming the unoptimised crates of the generator, followed by
/// the [`PROFILE_ENTRIES`] to add, or `None` when both are optimised.
pub fn unoptimized_warning() -> Option<String> {
    let slow = unoptimized();
    if slow.is_empty() {
        return None;
    }
    Some(format!(
        "warning: {} built at opt-level 0, which makes generation several times slower; add to \
         the workspace's root Cargo.toml (Cargo reads profiles from there only):\n{}",
        slow.join(" and "),
        PROFILE_ENTRIES.trim_end()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn this_workspace_builds_the_generator_optimised() {
        // The workspace's root Cargo.toml has the entries, for every profile.
        assert_eq!(unoptimized(), Vec::<&str>::new());
        assert_eq!(unoptimized_warning(), None);
        let root =
            std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../Cargo.toml")).unwrap();
        assert!(root.contains(PROFILE_ENTRIES), "{PROFILE_ENTRIES}");
    }
}
