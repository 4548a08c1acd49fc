//! Generates a synthetic BAL problem and reports how long it took.
//!
//! ```sh
//! cargo run --release -p slam-data --example synthetic_bal -- OBSERVATIONS [SEED] [OUT.txt]
//! ```
//!
//! Prints the sizes, the generation time and, with `OUT.txt`, the times to
//! write the BAL file and to read it back (checked identical). Peak memory:
//! run it under `/usr/bin/time -v`.

use std::process::ExitCode;
use std::time::Instant;

use slam_data::bal;
use slam_data::synthetic::{SyntheticConfig, generate};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::from(2)
        }
    }
}

fn run(args: &[String]) -> Result<(), String> {
    let usage = "usage: synthetic_bal OBSERVATIONS [SEED] [OUT.txt]";
    let observations: usize = match args.first() {
        Some(n) => n
            .parse()
            .map_err(|_| format!("OBSERVATIONS: not a count: `{n}`; {usage}"))?,
        None => return Err(usage.into()),
    };
    let seed: u64 = match args.get(1) {
        Some(s) => s
            .parse()
            .map_err(|_| format!("SEED: not an integer: `{s}`; {usage}"))?,
        None => 0,
    };
    let config = SyntheticConfig::with_observations(observations, seed);
    let start = Instant::now();
    let synthetic = generate(&config).map_err(|e| e.to_string())?;
    let generated = start.elapsed();
    let p = &synthetic.problem;
    println!(
        "{} cameras, {} points, {} observations ({} outliers), seed {seed}: generated in {:.3} s",
        p.cameras.len(),
        p.points.len(),
        p.observations.len(),
        synthetic.outliers.len(),
        generated.as_secs_f64()
    );
    if let Some(out) = args.get(2) {
        let start = Instant::now();
        bal::write(p, out).map_err(|e| e.to_string())?;
        let bytes = std::fs::metadata(out).map(|m| m.len()).unwrap_or(0);
        println!(
            "wrote {out} ({:.1} MB) in {:.3} s",
            bytes as f64 / 1e6,
            start.elapsed().as_secs_f64()
        );
        let start = Instant::now();
        let back = bal::read(out).map_err(|e| e.to_string())?;
        let read = start.elapsed();
        if &back != p {
            return Err(format!("{out}: read back differently"));
        }
        println!("read it back, identical, in {:.3} s", read.as_secs_f64());
    }
    Ok(())
}
