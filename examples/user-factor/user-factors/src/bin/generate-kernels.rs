//! `generate-kernels [--out DIR] [--check]`: writes the generated kernels of
//! this crate's factors into the crate at `DIR` (default: the sibling crate
//! `user-kernels`), or with `--check` exits 1, naming the files, when they
//! are not what the factor definitions generate.
//!
//! Only `DIR/src/*.rs` is written or compared; `DIR/Cargo.toml` is
//! hand-written. Build without the feature `kernels` when the generated
//! crate is stale and no longer compiles:
//!
//! ```sh
//! cargo run -p user-factors --no-default-features --bin generate-kernels
//! ```

use std::path::PathBuf;
use std::process::ExitCode;

use user_factors::codegen;

const USAGE: &str = "usage: generate-kernels [--out DIR] [--check]";

/// The parsed command line.
struct Args {
    out: PathBuf,
    check: bool,
}

fn parse(mut args: impl Iterator<Item = String>) -> Result<Args, String> {
    let mut parsed = Args {
        out: codegen::default_dir(),
        check: false,
    };
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--check" => parsed.check = true,
            "--out" => {
                parsed.out = args
                    .next()
                    .map(PathBuf::from)
                    .ok_or("--out needs a directory")?;
            }
            "-h" | "--help" => return Err(String::new()),
            other => return Err(format!("unexpected argument `{other}`")),
        }
    }
    Ok(parsed)
}

fn main() -> ExitCode {
    let args = match parse(std::env::args().skip(1)) {
        Ok(args) => args,
        Err(message) if message.is_empty() => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        Err(message) => {
            eprintln!("error: {message}\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    let src = args.out.join("src");
    let generated = match codegen::generate() {
        Ok(generated) => generated,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    };
    let count = generated.modules.len();
    if args.check {
        match generated.check(&args.out) {
            Ok(()) => {
                println!("{} is up to date ({count} kernels)", src.display());
                ExitCode::SUCCESS
            }
            Err(stale) => {
                let files: Vec<String> = stale.iter().map(|f| f.display().to_string()).collect();
                eprintln!(
                    "error: stale generated kernels: {}; run `{}`",
                    files.join(", "),
                    codegen::PROVENANCE.generate
                );
                ExitCode::from(1)
            }
        }
    } else {
        match generated.write(&args.out) {
            Ok(()) => {
                for m in &generated.modules {
                    println!(
                        "{}: {} ops, residual only {}",
                        m.name,
                        m.counts.total(),
                        m.residual_counts.total()
                    );
                }
                println!("generated {count} kernels into {}", src.display());
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!(
                    "error: {}: cannot write the generated crate: {e}",
                    args.out.display()
                );
                ExitCode::from(1)
            }
        }
    }
}
