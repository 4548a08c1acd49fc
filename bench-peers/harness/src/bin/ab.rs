//! A/B-alternated timing against wrenfold's kernels, for a ratio steadier
//! than two separate criterion runs on a noisy machine.
//!
//! `cargo run --release --features generated --bin ab -- [ROUNDS]`
//!
//! For each factor, each round times 2000 passes over the 64 sampled
//! configurations with wrenfold's kernel, then with the contender (the order
//! flips every round, so drift in the machine's speed hits both), and
//! records the ratio contender / wrenfold of that round. Printed: the
//! minimum ns/call of each side over all rounds, and the median and
//! quartiles of the per-round ratios. Contenders: this project's generated
//! kernel (the comparison the README's benchmarks name), and for reference the hand-written
//! Jacobians of `slam_factors::analytic` (nalgebra outputs, no validation),
//! and the fewest-operations formulas as scalar code (`bound`).
//! The kernels are first checked against each other (and wrenfold against
//! `linearize_dual()`) exactly as in `benches/peers.rs`.

#[cfg(feature = "generated")]
fn main() {
    use std::hint::black_box;
    use std::time::Instant;

    use bench_peers_harness::bound;
    use bench_peers_harness::ours::{PluckerArrays, PointArrays};
    use bench_peers_harness::{PluckerInputs, PointInputs};
    use factor_testing::samples::Sampler;
    use slam_factors::analytic;

    const CONFIGURATIONS: usize = 64;
    const PASSES: usize = 2000;
    let rounds: usize = std::env::args()
        .nth(1)
        .map_or(41, |r| r.parse().expect("ROUNDS is a number"));

    let mut sampler = Sampler::new(1);
    let points: Vec<_> = (0..CONFIGURATIONS)
        .map(|_| sampler.point_reprojection())
        .collect();
    let mut sampler = Sampler::new(2);
    let lines: Vec<_> = (0..CONFIGURATIONS)
        .map(|_| sampler.plucker_line_reprojection())
        .collect();
    bench_peers_harness::check_point(&points, 1e-9).unwrap_or_else(|e| panic!("{e}"));
    bench_peers_harness::check_plucker(&lines, 1e-9).unwrap_or_else(|e| panic!("{e}"));
    bench_peers_harness::ours::check_point(&points, 1e-9).unwrap_or_else(|e| panic!("{e}"));
    bench_peers_harness::ours::check_plucker(&lines, 1e-9).unwrap_or_else(|e| panic!("{e}"));
    bench_peers_harness::bound::check_point(&points, 1e-9).unwrap_or_else(|e| panic!("{e}"));
    bench_peers_harness::bound::check_plucker(&lines, 1e-9).unwrap_or_else(|e| panic!("{e}"));

    /// ns per call of `f` over PASSES passes of the inputs.
    fn time<I, O>(inputs: &[I], f: impl Fn(&I) -> O) -> f64 {
        let start = Instant::now();
        for _ in 0..PASSES {
            for x in inputs {
                black_box(f(black_box(x)));
            }
        }
        start.elapsed().as_nanos() as f64 / (PASSES * inputs.len()) as f64
    }

    fn report<A, B, OA, OB>(
        name: &str,
        contender: &str,
        rounds: usize,
        a: &[A],
        fa: impl Fn(&A) -> OA,
        b: &[B],
        fb: impl Fn(&B) -> OB,
    ) {
        let (mut best_a, mut best_b) = (f64::INFINITY, f64::INFINITY);
        let mut ratios = Vec::with_capacity(rounds);
        for round in 0..rounds {
            let (ta, tb) = if round % 2 == 0 {
                let ta = time(a, &fa);
                (ta, time(b, &fb))
            } else {
                let tb = time(b, &fb);
                (time(a, &fa), tb)
            };
            best_a = best_a.min(ta);
            best_b = best_b.min(tb);
            ratios.push(tb / ta);
        }
        ratios.sort_by(f64::total_cmp);
        let q = |p: f64| ratios[((ratios.len() - 1) as f64 * p).round() as usize];
        println!(
            "{name}: wrenfold {best_a:.2} ns, {contender} {best_b:.2} ns (minimum over {rounds} \
             rounds); {contender}/wrenfold per round: median {:.3} (quartiles {:.3}–{:.3})",
            q(0.5),
            q(0.25),
            q(0.75)
        );
    }

    let point_w: Vec<_> = points.iter().map(PointInputs::new).collect();
    let point_g: Vec<_> = points.iter().map(PointArrays::new).collect();
    let line_w: Vec<_> = lines.iter().map(PluckerInputs::new).collect();
    let line_g: Vec<_> = lines.iter().map(PluckerArrays::new).collect();
    let (point, line) = ("point_reprojection", "plucker_line_reprojection");

    println!("-- kernels inlined into the timing loop (as in benches/peers.rs):");
    report(
        point,
        "generated",
        rounds,
        &point_w,
        PointInputs::wrenfold,
        &point_g,
        PointArrays::generated,
    );
    report(
        line,
        "generated",
        rounds,
        &line_w,
        PluckerInputs::wrenfold,
        &line_g,
        PluckerArrays::generated,
    );
    report(
        point,
        "hand-written",
        rounds,
        &point_w,
        PointInputs::wrenfold,
        &points,
        analytic::point_reprojection,
    );
    report(
        line,
        "hand-written",
        rounds,
        &line_w,
        PluckerInputs::wrenfold,
        &lines,
        analytic::plucker_line_reprojection,
    );
    report(
        point,
        "scalar bound",
        rounds,
        &point_w,
        PointInputs::wrenfold,
        &point_g,
        bound::point_reprojection,
    );
    report(
        line,
        "scalar bound",
        rounds,
        &line_w,
        PluckerInputs::wrenfold,
        &line_g,
        bound::plucker_line_reprojection,
    );

    // Each kernel compiled once, on its own, and called: immune to how the
    // optimiser happens to inline and lay out the timing loops.
    println!("-- kernels called out of line:");
    report(
        point,
        "generated",
        rounds,
        &point_w,
        called::wrenfold_point,
        &point_g,
        called::generated_point,
    );
    report(
        line,
        "generated",
        rounds,
        &line_w,
        called::wrenfold_plucker,
        &line_g,
        called::generated_plucker,
    );
    report(
        point,
        "scalar bound",
        rounds,
        &point_w,
        called::wrenfold_point,
        &point_g,
        called::bound_point,
    );
    report(
        line,
        "scalar bound",
        rounds,
        &line_w,
        called::wrenfold_plucker,
        &line_g,
        called::bound_plucker,
    );
}

/// Out-of-line wrappers, one per kernel.
#[cfg(feature = "generated")]
mod called {
    use bench_peers_harness::bound;
    use bench_peers_harness::ours::{
        PluckerArrayOutputs, PluckerArrays, PointArrayOutputs, PointArrays,
    };
    use bench_peers_harness::{PluckerInputs, PluckerOutputs, PointInputs, PointOutputs};

    #[inline(never)]
    pub fn wrenfold_point(x: &PointInputs) -> PointOutputs {
        x.wrenfold()
    }

    #[inline(never)]
    pub fn generated_point(x: &PointArrays) -> PointArrayOutputs {
        x.generated()
    }

    #[inline(never)]
    pub fn wrenfold_plucker(x: &PluckerInputs) -> PluckerOutputs {
        x.wrenfold()
    }

    #[inline(never)]
    pub fn generated_plucker(x: &PluckerArrays) -> PluckerArrayOutputs {
        x.generated()
    }

    #[inline(never)]
    pub fn bound_point(x: &PointArrays) -> PointArrayOutputs {
        bound::point_reprojection(x)
    }

    #[inline(never)]
    pub fn bound_plucker(x: &PluckerArrays) -> PluckerArrayOutputs {
        bound::plucker_line_reprojection(x)
    }
}

#[cfg(not(feature = "generated"))]
fn main() {
    eprintln!("error: build with --features generated");
    std::process::exit(2);
}
