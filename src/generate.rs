//! `generate` and `check`: write a kernel crate's sources from the current
//! factor definitions, or compare them with what is on disk, for the
//! kernels of a [`Registry`] (`slamjac`'s own: the workspace's `generated/`).
//!
//! **Where.** `--out DIR` (`generate`) or `--dir DIR` (`check`), else the
//! registry's [`KernelCrate::dir`], fixed when the binary was built, not
//! the current directory. When that directory is gone (the workspace moved
//! or deleted since the build), both commands say so and ask for the flag.
//!
//! **What.** A *kernel crate* is a directory whose `Cargo.toml` names the
//! registry's [`KernelCrate::package`] in its `[package]` table. Only its
//! `src/*.rs` is written or compared; its `Cargo.toml` is hand-written.
//! - `check` needs a kernel crate: a missing directory is "not found", any
//!   other one "not a generated crate" (exit 2). A file it cannot read is a
//!   read error (exit 2), not stale; missing, differing and extra `src/*.rs`
//!   files are stale (exit 1).
//! - `generate` writes into a kernel crate, or into a directory that does
//!   not exist yet or is empty: there it first writes a standalone
//!   `Cargo.toml` naming the package
//!   ([`factor_codegen::manifest::manifest`]: no dependencies but the
//!   optional `factor-lanes` of its feature `lanes`), so that the directory
//!   becomes one. Any other directory is refused untouched, since writing
//!   removes the `.rs` files of `src/` that it did not generate.
//! - `generate` prints each kernel's operation counts and generation time,
//!   and a warning when the generator was built unoptimised
//!   ([`factor_codegen::build_profile`]).
//!
//! **Which languages.** `--lang rust` is the crate's `src/*.rs`, `--lang
//! cpp` its header-only C++ library in `cpp/` ([`factor_codegen::cpp`]);
//! without `--lang`, both commands take Rust, and C++ when the crate has a
//! `cpp/` directory (so that a crate once generated with C++ keeps both
//! current). C++ alone is written only beside an existing kernel crate.

use std::io;
use std::path::{Component, Path, PathBuf};
use std::time::{Duration, Instant};

use factor_codegen::OpCounts;
use factor_codegen::build_profile::unoptimized_warning;
use factor_codegen::manifest::{Membership, manifest};
use factor_codegen::{
    self as codegen, CodegenError, CppLibrary, GeneratedCrate, GeneratedModule, KernelSpec,
    Provenance, SymbolicKernel,
};
use slamjac_problem::InputError;
use slamjac_problem::field_path::shown_path;

use crate::error::CliError;
use crate::registry::{KernelCrate, Registry};

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

/// `path` without `.` and without `dir/..` pairs, lexically: how
/// `concat!(env!("CARGO_MANIFEST_DIR"), "/../my-kernels")` is shown.
fn normalized(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir
                if matches!(out.components().next_back(), Some(Component::Normal(_))) =>
            {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// The directory given with `flag`, else `default` (the registry's
/// [`KernelCrate::dir`]) if it still exists.
fn locate(given: Option<&Path>, default: &Path, flag: &str) -> Result<PathBuf, CliError> {
    if let Some(dir) = given {
        return Ok(dir.to_path_buf());
    }
    let dir = normalized(default);
    if dir.exists() {
        Ok(dir)
    } else {
        Err(error_at(
            &dir,
            format!(
                "not found: the kernel crate is gone since this binary was built; pass {flag} DIR"
            ),
        ))
    }
}

/// The registry's kernel crate, or a usage error for a command line
/// without one.
fn kernel_crate<'a>(registry: &'a Registry, command: &str) -> Result<&'a KernelCrate, CliError> {
    registry.kernel_crate().ok_or_else(|| {
        CliError::Usage(format!(
            "{command}: this command line names no kernel crate (`Registry::with_kernel_crate`)"
        ))
    })
}

/// Whether `manifest` (a `Cargo.toml`) names the package `package`.
fn names_package(manifest: &str, package: &str) -> bool {
    let mut in_package = false;
    manifest.lines().map(str::trim).any(|line| {
        if line.starts_with('[') {
            in_package = line == "[package]";
            return false;
        }
        in_package
            && line.split_once('=').is_some_and(|(key, value)| {
                key.trim() == "name" && value.trim() == format!("\"{package}\"")
            })
    })
}

/// What `dir` is (a kernel crate named `package`, ...); an error when it
/// cannot be read.
fn inspect(dir: &Path, package: &str) -> Result<Found, CliError> {
    match std::fs::metadata(dir) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Found::Missing),
        Err(e) => return Err(cannot_read(dir, &e)),
        Ok(meta) if !meta.is_dir() => return Ok(Found::Other("not a directory")),
        Ok(_) => {}
    }
    let manifest = dir.join("Cargo.toml");
    match std::fs::read_to_string(&manifest) {
        Ok(text) if names_package(&text, package) => Ok(Found::Crate),
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
fn not_a_crate(dir: &Path, package: &str, why: &str, consequence: &str) -> CliError {
    error_at(
        dir,
        format!(
            "not a generated crate ({why}; a generated crate's Cargo.toml names the package \
             {package}); {consequence}"
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

/// The kernel of every spec, traced once for both languages.
fn trace_all(specs: &[KernelSpec]) -> Vec<SymbolicKernel> {
    specs.iter().map(|spec| (spec.trace)()).collect()
}

/// Generates the kernel of every spec for `provenance`'s crate from its
/// trace, timing each (its trace included).
///
/// # Errors
///
/// As [`codegen::generate_module`].
pub fn generate_timed(
    specs: &[KernelSpec],
    provenance: &Provenance,
) -> Result<(Vec<Timed>, Vec<SymbolicKernel>), CodegenError> {
    let mut timed = Vec::with_capacity(specs.len());
    let mut kernels = Vec::with_capacity(specs.len());
    for spec in specs {
        let start = Instant::now();
        let kernel = (spec.trace)();
        let module = codegen::generate_module(&kernel, spec, provenance)?;
        timed.push(Timed {
            module,
            elapsed: start.elapsed(),
        });
        kernels.push(kernel);
    }
    Ok((timed, kernels))
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

/// `--lang`: a language `generate` writes and `check` compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Lang {
    /// The Rust crate's sources, `src/*.rs`.
    Rust,
    /// The header-only C++17 library, `cpp/<namespace>/*.h`.
    Cpp,
}

/// Which of Rust and C++ to take: those `given`, or without any Rust, and
/// C++ when `dir` has a `cpp/` directory.
fn languages(given: &[Lang], dir: &Path) -> (bool, bool) {
    if given.is_empty() {
        (true, dir.join("cpp").is_dir())
    } else {
        (given.contains(&Lang::Rust), given.contains(&Lang::Cpp))
    }
}

/// `generate [--out DIR] [--lang LANG]`: writes the sources of the
/// registry's kernel crate (see the module docs for which directories and
/// languages) and reports, per kernel, its operation counts and generation
/// time, then the totals.
pub fn run_generate(
    registry: &Registry,
    out: Option<&Path>,
    lang: &[Lang],
) -> Result<String, CliError> {
    let krate = kernel_crate(registry, "generate")?;
    let dir = locate(out, Path::new(krate.dir), "--out")?;
    let (rust, cpp) = languages(lang, &dir);
    let new_crate = match inspect(&dir, krate.package)? {
        Found::Crate => false,
        Found::Missing | Found::Empty if rust => true,
        Found::Missing | Found::Empty => {
            return Err(error_at(
                &dir,
                format!(
                    "not a generated crate yet: `--lang cpp` writes beside a kernel crate's Rust \
                     sources; generate them first (`{}`)",
                    krate.provenance.generate
                ),
            ));
        }
        Found::Other(why) => {
            return Err(not_a_crate(
                &dir,
                krate.package,
                why,
                "refused: generate writes only into a generated crate or a new or empty \
                 directory",
            ));
        }
    };
    let cannot_write =
        |e: io::Error| error_at(&dir, format!("cannot write the generated crate: {e}"));
    let mut lines = Vec::new();
    if new_crate {
        let path = dir.join("Cargo.toml");
        let toml = manifest(
            krate.package,
            krate.provenance.generate,
            krate.provenance.check,
            Membership::Standalone,
        );
        std::fs::create_dir_all(&dir)
            .and_then(|()| slamjac_io::atomic::write(&path, toml))
            .map_err(cannot_write)?;
        lines.push(format!("new crate: wrote {}", shown_path(&path)));
    }
    let mut kernels = None;
    if rust {
        let start = Instant::now();
        let (timed, traced) = generate_timed(registry.specs(), &krate.provenance)?;
        kernels = Some(traced);
        let generation = start.elapsed();
        let modules: Vec<GeneratedModule> = timed.iter().map(|t| t.module.clone()).collect();
        let count = modules.len();
        let generated = GeneratedCrate::from_modules(krate.provenance, modules)?;
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
    }
    if cpp {
        let start = Instant::now();
        let kernels = kernels.unwrap_or_else(|| trace_all(registry.specs()));
        let library =
            CppLibrary::from_kernels(krate.package, &krate.provenance, registry.specs(), &kernels)?;
        let generation = start.elapsed();
        library.write(&dir).map_err(cannot_write)?;
        lines.push(format!(
            "generated {} C++ headers ({} for Ceres) into {} in {}",
            library.files.len(),
            library
                .files
                .iter()
                .filter(|(path, _)| path.contains("/ceres"))
                .count(),
            shown_path(&dir.join("cpp").join(&library.namespace)),
            milliseconds(generation),
        ));
    }
    lines.extend(unoptimized_warning());
    Ok(lines.join("\n"))
}

/// `check [--dir DIR] [--lang LANG]`: `Ok` when the kernel crate's sources
/// (of the languages taken, see the module docs) are what `generate` would
/// write, else [`CliError::Stale`] naming the files, or a read error for the
/// first file that cannot be read.
pub fn run_check(
    registry: &Registry,
    dir: Option<&Path>,
    lang: &[Lang],
) -> Result<String, CliError> {
    let krate = kernel_crate(registry, "check")?;
    let dir = locate(dir, Path::new(krate.dir), "--dir")?;
    match inspect(&dir, krate.package)? {
        Found::Crate => {}
        Found::Missing => return Err(error_at(&dir, "not found")),
        Found::Empty => {
            return Err(not_a_crate(
                &dir,
                krate.package,
                "it is empty",
                &format!("`{} --out DIR` makes one", krate.provenance.generate),
            ));
        }
        Found::Other(why) => {
            return Err(not_a_crate(&dir, krate.package, why, "nothing to check"));
        }
    }
    let (rust, cpp) = languages(lang, &dir);
    let mut current = Vec::new();
    let (mut stale, mut stale_languages) = (Vec::new(), Vec::new());
    let specs = registry.specs();
    let kernels = trace_all(specs);
    if rust {
        let src = dir.join("src");
        if let Err(e) = std::fs::read_dir(&src)
            && e.kind() != io::ErrorKind::NotFound
        {
            return Err(cannot_read(&src, &e));
        }
        let modules = specs
            .iter()
            .zip(&kernels)
            .map(|(spec, kernel)| codegen::generate_module(kernel, spec, &krate.provenance))
            .collect::<Result<Vec<_>, _>>()?;
        let generated = GeneratedCrate::from_modules(krate.provenance, modules)?;
        match generated.check(&dir) {
            Ok(()) => current.push(format!(
                "{} is up to date ({} kernels)",
                shown_path(&src),
                generated.modules.len()
            )),
            Err(files) => {
                stale.extend(files);
                stale_languages.push("rust");
            }
        }
    }
    if cpp {
        let library = CppLibrary::from_kernels(krate.package, &krate.provenance, specs, &kernels)?;
        match library.check(&dir) {
            Ok(()) => current.push(format!(
                "{} is up to date ({} headers)",
                shown_path(&dir.join("cpp").join(&library.namespace)),
                library.files.len()
            )),
            Err(files) => {
                stale.extend(files);
                stale_languages.push("cpp");
            }
        }
    }
    if stale.is_empty() {
        return Ok(current.join("\n"));
    }
    // A missing file is stale; one that is there but unreadable is not.
    for file in &stale {
        if let Err(e) = std::fs::read(file)
            && e.kind() != io::ErrorKind::NotFound
        {
            return Err(cannot_read(file, &e));
        }
    }
    let generate = match stale_languages.as_slice() {
        ["rust"] => krate.provenance.generate.to_owned(),
        languages => format!(
            "{} --lang {}",
            krate.provenance.generate,
            languages.join(",")
        ),
    };
    Err(CliError::Stale {
        files: stale,
        generate,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::KERNEL_CRATE;

    const PACKAGE: &str = KERNEL_CRATE.package;

    #[test]
    fn only_the_package_name_makes_a_generated_crate() {
        assert!(names_package(
            "[package]\nname = \"factor-generated\"\n",
            PACKAGE
        ));
        assert!(names_package(
            "# x\n[package]\n  name=\"factor-generated\"  \n",
            PACKAGE
        ));
        let provenance = KERNEL_CRATE.provenance;
        let standalone = manifest(
            PACKAGE,
            provenance.generate,
            provenance.check,
            Membership::Standalone,
        );
        assert!(names_package(&standalone, PACKAGE));
        assert!(!names_package(&standalone, "mine"));
        assert!(!names_package("[package]\nname = \"mine\"\n", PACKAGE));
        assert!(!names_package(
            "[dependencies]\nname = \"factor-generated\"\n",
            PACKAGE
        ));
        assert!(!names_package("", PACKAGE));
    }

    #[test]
    fn the_workspace_crate_is_found_from_the_build_and_is_a_generated_crate() {
        let workspace = Path::new(KERNEL_CRATE.dir);
        let dir = locate(None, workspace, "--dir").unwrap();
        assert_eq!(dir, Path::new(env!("CARGO_MANIFEST_DIR")).join("generated"));
        assert_eq!(inspect(&dir, PACKAGE).unwrap(), Found::Crate);
        let given = locate(Some(Path::new("elsewhere")), workspace, "--dir").unwrap();
        assert_eq!(given, Path::new("elsewhere"));
    }

    #[test]
    fn a_vanished_workspace_crate_asks_for_the_flag() {
        let gone = Path::new(KERNEL_CRATE.dir).join("no-such-directory");
        let error = locate(None, &gone, "--out").unwrap_err().to_string();
        assert!(
            error.starts_with(&format!("{}: not found", gone.display())),
            "{error}"
        );
        assert!(error.ends_with("pass --out DIR"), "{error}");
    }

    #[test]
    fn default_directories_are_shown_without_dot_dot() {
        assert_eq!(normalized(Path::new("/a/b/../c/./d")), Path::new("/a/c/d"));
        assert_eq!(normalized(Path::new("../x/..")), Path::new(".."));
    }

    #[test]
    fn a_registry_without_a_kernel_crate_cannot_generate() {
        let error = run_check(&Registry::new(), None, &[]).unwrap_err();
        assert_eq!(error.exit_code(), crate::error::EXIT_BAD_INPUT);
        assert!(
            error.to_string().contains("names no kernel crate"),
            "{error}"
        );
    }
}
