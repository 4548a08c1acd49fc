//! `slamjac generate` and `slamjac check`: write the generated crate's
//! sources from the current factor definitions, or compare them with what is
//! on disk.
//!
//! The directory defaults to the workspace's `generated/`: under `cargo run`
//! (which sets `CARGO_MANIFEST_DIR` to the workspace root) that is
//! `$CARGO_MANIFEST_DIR/generated`, otherwise `generated/` in the current
//! directory. Only `src/*.rs` is written or compared; the crate's
//! `Cargo.toml` is hand-written.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use factor_codegen::OpCounts;
use factor_codegen::{self as codegen, CodegenError, GeneratedCrate, GeneratedModule, KernelSpec};

use crate::error::{CliError, InputError};
use crate::kernels;

/// The default directory of the generated crate (see the module docs).
pub fn default_dir() -> PathBuf {
    match std::env::var_os("CARGO_MANIFEST_DIR") {
        Some(root) => PathBuf::from(root).join("generated"),
        None => PathBuf::from("generated"),
    }
}

/// One kernel generated in process, with the time it took.
#[derive(Debug, Clone)]
pub struct Timed {
    /// The module.
    pub module: GeneratedModule,
    /// Trace, lowering, scheduling, emission and formatting.
    pub elapsed: Duration,
}

/// Generates every document kernel, timing each.
///
/// # Errors
///
/// As [`codegen::generate_with`].
pub fn generate_timed() -> Result<Vec<Timed>, CodegenError> {
    kernels::document_kernels()
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

/// `slamjac generate [--out DIR]`: writes the crate's sources and reports,
/// per kernel, its operation counts and generation time, then the total.
pub fn run_generate(out: Option<&Path>) -> Result<String, CliError> {
    let dir = out.map_or_else(default_dir, Path::to_path_buf);
    let start = Instant::now();
    let timed = generate_timed()?;
    let generation = start.elapsed();
    let modules: Vec<GeneratedModule> = timed.iter().map(|t| t.module.clone()).collect();
    let count = modules.len();
    let generated = GeneratedCrate::from_modules(kernels::PROVENANCE, modules)?;
    generated.write(&dir).map_err(|e| {
        InputError::new(
            dir.display().to_string(),
            format!("cannot write the generated crate: {e}"),
        )
    })?;
    let width = timed.iter().map(|t| t.module.name.len()).max().unwrap_or(0);
    let mut lines = Vec::new();
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
        dir.join("src").display(),
        milliseconds(generation),
    ));
    Ok(lines.join("\n"))
}

/// `slamjac check [--dir DIR]`: `Ok` when the crate's sources are what
/// `generate` would write, else [`CliError::Stale`] naming the files.
pub fn run_check(dir: Option<&Path>) -> Result<String, CliError> {
    let dir = dir.map_or_else(default_dir, Path::to_path_buf);
    let generated = kernels::generate_all()?;
    match generated.check(&dir) {
        Ok(()) => Ok(format!(
            "{} is up to date ({} kernels)",
            dir.join("src").display(),
            generated.modules.len()
        )),
        Err(files) => Err(CliError::Stale(files)),
    }
}
