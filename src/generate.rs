//! `slamjac generate` and `slamjac check`: write the generated crate's
//! sources from the current factor definitions, or compare them with what is
//! on disk.
//!
//! **Where.** `--out DIR` (`generate`) or `--dir DIR` (`check`), else the
//! workspace's `generated/`, found from where this binary was built
//! ([`WORKSPACE_CRATE`]), not from the current directory. When that directory
//! is gone (the workspace moved or deleted since the build), both commands
//! say so and ask for the flag.
//!
//! **What.** A *generated crate* is a directory whose `Cargo.toml` names the
//! package `factor-generated` in its `[package]` table. Only its `src/*.rs`
//! is written or compared; its `Cargo.toml` is hand-written.
//! - `check` needs a generated crate: a missing directory is "not found", any
//!   other one "not a generated crate" (exit 2). A file it cannot read is a
//!   read error (exit 2), not stale; missing, differing and extra `src/*.rs`
//!   files are stale (exit 1).
//! - `generate` writes into a generated crate, or into a directory that does
//!   not exist yet or is empty: there it first writes a minimal standalone
//!   `Cargo.toml` naming `factor-generated` (the kernels need no
//!   dependencies; its feature `lanes` adds `factor-lanes` from this
//!   workspace), so that the directory becomes one. Any other directory is
//!   refused untouched, since writing removes the `.rs` files of `src/` that
//!   it did not generate.

use std::io;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use factor_codegen::OpCounts;
use factor_codegen::{self as codegen, CodegenError, GeneratedCrate, GeneratedModule, KernelSpec};

use crate::error::{CliError, InputError};
use crate::field_path::shown_path;
use crate::kernels;

/// The workspace's generated crate, as this binary was built.
pub const WORKSPACE_CRATE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/generated");

/// The package name that makes a directory a generated crate.
const PACKAGE: &str = "factor-generated";

/// The `Cargo.toml` that `generate` writes into a new or empty directory.
const STANDALONE_MANIFEST: &str = concat!(
    "# Written by `slamjac generate` into a new directory. Everything under\n",
    "# `src/` is rewritten by `slamjac generate --out DIR` and checked by\n",
    "# `slamjac check --dir DIR`; this file is yours to edit.\n",
    "\n",
    "[package]\n",
    "name = \"factor-generated\"\n",
    "version = \"",
    env!("CARGO_PKG_VERSION"),
    "\"\n",
    "edition = \"2024\"\n",
    "publish = false\n",
    "\n",
    "[lib]\n",
    "name = \"factor_generated\"\n",
    "path = \"src/lib.rs\"\n",
    "\n",
    "# The kernels have no dependencies; the feature `lanes` runs them on the\n",
    "# SIMD lane types of `factor-lanes` (from the workspace that wrote this file).\n",
    "[dependencies]\n",
    "factor-lanes = { path = \"",
    env!("CARGO_MANIFEST_DIR"),
    "/factor-lanes\", optional = true }\n",
    "\n",
    "[features]\n",
    "lanes = [\"dep:factor-lanes\"]\n",
    "\n",
    "# A workspace of its own; remove this table to make the crate a member of\n",
    "# an enclosing one.\n",
    "[workspace]\n",
);

/// What a directory is, for `generate` and `check`.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Found {
    /// A generated crate.
    Crate,
    /// Nothing there yet.
    Missing,
    /// An empty directory.
    Empty,
    /// Something else, and why it is not a generated crate.
    Other(&'static str),
}

/// An error at `path` (a directory or file of the generated crate).
fn error_at(path: &Path, message: impl Into<String>) -> CliError {
    InputError::new(path.display().to_string(), message).into()
}

fn cannot_read(path: &Path, e: &io::Error) -> CliError {
    error_at(path, format!("cannot read: {e}"))
}

/// The directory given with `flag`, else `default` (the
/// [`WORKSPACE_CRATE`]) if it still exists.
fn locate(given: Option<&Path>, default: &Path, flag: &str) -> Result<PathBuf, CliError> {
    if let Some(dir) = given {
        return Ok(dir.to_path_buf());
    }
    let dir = default.to_path_buf();
    if dir.exists() {
        Ok(dir)
    } else {
        Err(error_at(
            &dir,
            format!(
                "not found: the workspace's generated crate is gone since this binary was \
                 built; pass {flag} DIR"
            ),
        ))
    }
}

/// Whether `manifest` (a `Cargo.toml`) names the package [`PACKAGE`].
fn names_package(manifest: &str) -> bool {
    let mut in_package = false;
    manifest.lines().map(str::trim).any(|line| {
        if line.starts_with('[') {
            in_package = line == "[package]";
            return false;
        }
        in_package
            && line.split_once('=').is_some_and(|(key, value)| {
                key.trim() == "name" && value.trim() == format!("\"{PACKAGE}\"")
            })
    })
}

/// What `dir` is; an error when it cannot be read.
fn inspect(dir: &Path) -> Result<Found, CliError> {
    match std::fs::metadata(dir) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Found::Missing),
        Err(e) => return Err(cannot_read(dir, &e)),
        Ok(meta) if !meta.is_dir() => return Ok(Found::Other("not a directory")),
        Ok(_) => {}
    }
    let manifest = dir.join("Cargo.toml");
    match std::fs::read_to_string(&manifest) {
        Ok(text) if names_package(&text) => Ok(Found::Crate),
        Ok(_) => Ok(Found::Other("its Cargo.toml names another package")),
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            let mut entries = std::fs::read_dir(dir).map_err(|e| cannot_read(dir, &e))?;
            Ok(if entries.next().is_none() {
                Found::Empty
            } else {
                Found::Other("it has no Cargo.toml")
            })
        }
        Err(e) => Err(cannot_read(&manifest, &e)),
    }
}

/// "not a generated crate (why)", and what follows from it.
fn not_a_crate(dir: &Path, why: &str, consequence: &str) -> CliError {
    error_at(
        dir,
        format!(
            "not a generated crate ({why}; a generated crate's Cargo.toml names the package \
             {PACKAGE}); {consequence}"
        ),
    )
}

/// One kernel generated in process, with the time it took.
#[derive(Debug, Clone)]
pub struct Timed {
    /// The module.
    pub module: GeneratedModule,
    /// Trace, lowering, scheduling, emission and formatting.
    pub elapsed: Duration,
}

/// Generates every shipped kernel, timing each.
///
/// # Errors
///
/// As [`codegen::generate_with`].
pub fn generate_timed() -> Result<Vec<Timed>, CodegenError> {
    kernels::shipped_kernels()
        .iter()
        .map(|spec: &KernelSpec| {
            let start = Instant::now();
            let module = codegen::generate_with(spec, &kernels::PROVENANCE)?;
            Ok(Timed {
                module,
                elapsed: start.elapsed(),
            })
        })
        .collect()
}

/// `add 12, mul 30, …` for a report.
pub fn counts_text(c: &OpCounts) -> String {
    format!(
        "add {}, mul {}, div {}, neg {}, sqrt {}, func {}, branch {}",
        c.add, c.mul, c.div, c.neg, c.sqrt, c.func, c.branch
    )
}

fn milliseconds(d: Duration) -> String {
    format!("{:.1} ms", d.as_secs_f64() * 1e3)
}

/// `slamjac generate [--out DIR]`: writes the crate's sources (see the module
/// docs for which directories) and reports, per kernel, its operation counts
/// and generation time, then the total.
pub fn run_generate(out: Option<&Path>) -> Result<String, CliError> {
    let dir = locate(out, Path::new(WORKSPACE_CRATE), "--out")?;
    let new_crate = match inspect(&dir)? {
        Found::Crate => false,
        Found::Missing | Found::Empty => true,
        Found::Other(why) => {
            return Err(not_a_crate(
                &dir,
                why,
                "refused: generate writes only into a generated crate or a new or empty \
                 directory",
            ));
        }
    };
    let start = Instant::now();
    let timed = generate_timed()?;
    let generation = start.elapsed();
    let modules: Vec<GeneratedModule> = timed.iter().map(|t| t.module.clone()).collect();
    let count = modules.len();
    let generated = GeneratedCrate::from_modules(kernels::PROVENANCE, modules)?;
    let cannot_write =
        |e: io::Error| error_at(&dir, format!("cannot write the generated crate: {e}"));
    let mut lines = Vec::new();
    if new_crate {
        let manifest = dir.join("Cargo.toml");
        std::fs::create_dir_all(&dir)
            .and_then(|()| slamjac_io::atomic::write(&manifest, STANDALONE_MANIFEST))
            .map_err(cannot_write)?;
        lines.push(format!("new crate: wrote {}", shown_path(&manifest)));
    }
    generated.write(&dir).map_err(cannot_write)?;
    let width = timed.iter().map(|t| t.module.name.len()).max().unwrap_or(0);
    for t in &timed {
        let m = &t.module;
        lines.push(format!(
            "{:<width$}  {:>4} ops ({}); residual only {}  {}",
            m.name,
            m.counts.total(),
            counts_text(&m.counts),
            m.residual_counts.total(),
            milliseconds(t.elapsed),
        ));
    }
    lines.push(format!(
        "generated {} kernels into {} in {} (trace, lower, emit and format, in process)",
        count,
        shown_path(&dir.join("src")),
        milliseconds(generation),
    ));
    Ok(lines.join("\n"))
}

/// `slamjac check [--dir DIR]`: `Ok` when the crate's sources are what
/// `generate` would write, else [`CliError::Stale`] naming the files, or a
/// read error for the first file that cannot be read.
pub fn run_check(dir: Option<&Path>) -> Result<String, CliError> {
    let dir = locate(dir, Path::new(WORKSPACE_CRATE), "--dir")?;
    match inspect(&dir)? {
        Found::Crate => {}
        Found::Missing => return Err(error_at(&dir, "not found")),
        Found::Empty => {
            return Err(not_a_crate(
                &dir,
                "it is empty",
                "`slamjac generate --out DIR` makes one",
            ));
        }
        Found::Other(why) => return Err(not_a_crate(&dir, why, "nothing to check")),
    }
    let src = dir.join("src");
    if let Err(e) = std::fs::read_dir(&src)
        && e.kind() != io::ErrorKind::NotFound
    {
        return Err(cannot_read(&src, &e));
    }
    let generated = kernels::generate_all()?;
    match generated.check(&dir) {
        Ok(()) => Ok(format!(
            "{} is up to date ({} kernels)",
            shown_path(&src),
            generated.modules.len()
        )),
        Err(files) => {
            // A missing file is stale; one that is there but unreadable is not.
            for file in &files {
                if let Err(e) = std::fs::read(file)
                    && e.kind() != io::ErrorKind::NotFound
                {
                    return Err(cannot_read(file, &e));
                }
            }
            Err(CliError::Stale(files))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_package_name_makes_a_generated_crate() {
        assert!(names_package("[package]\nname = \"factor-generated\"\n"));
        assert!(names_package(
            "# x\n[package]\n  name=\"factor-generated\"  \n"
        ));
        assert!(names_package(STANDALONE_MANIFEST));
        assert!(!names_package("[package]\nname = \"mine\"\n"));
        assert!(!names_package(
            "[dependencies]\nname = \"factor-generated\"\n"
        ));
        assert!(!names_package(""));
    }

    #[test]
    fn the_workspace_crate_is_found_from_the_build_and_is_a_generated_crate() {
        let workspace = Path::new(WORKSPACE_CRATE);
        let dir = locate(None, workspace, "--dir").unwrap();
        assert_eq!(dir, Path::new(env!("CARGO_MANIFEST_DIR")).join("generated"));
        assert_eq!(inspect(&dir).unwrap(), Found::Crate);
        let given = locate(Some(Path::new("elsewhere")), workspace, "--dir").unwrap();
        assert_eq!(given, Path::new("elsewhere"));
    }

    #[test]
    fn a_vanished_workspace_crate_asks_for_the_flag() {
        let gone = Path::new(WORKSPACE_CRATE).join("no-such-directory");
        let error = locate(None, &gone, "--out").unwrap_err().to_string();
        assert!(
            error.starts_with(&format!("{}: not found", gone.display())),
            "{error}"
        );
        assert!(error.ends_with("pass --out DIR"), "{error}");
    }
}
