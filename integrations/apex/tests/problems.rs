//! Problems built from the shipped data sets: with this project's factors
//! (generated kernels or dual numbers) and with apex-solver's own, the same
//! initial cost, the same iterations and the same final cost; the initial
//! cost known before the solve is apex's; the solution written back reads
//! as the same problem.

use factor_apex::Kernels;
use factor_apex::problems::{BuildOptions, FactorChoice, build};
use factor_apex::solve::{SolveOptions, solve};

fn data(file: &str) -> slam_data::Problem {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data")
        .join(file);
    slam_data::Problem::read(path, None).expect("a shipped data set")
}

/// `(initial cost known at build, apex's initial cost, final cost, iterations)`.
fn run(data: &slam_data::Problem, factors: FactorChoice) -> (f64, f64, f64, usize) {
    let options = BuildOptions {
        factors,
        robust: None,
        keep_blocks: false,
    };
    let mut built = build(data, &options).expect("builds");
    let known = built.initial_cost;
    let outcome = solve(&mut built, &SolveOptions::converged(200), |_| {}).expect("solves");
    (
        known,
        outcome.initial_cost,
        outcome.final_cost,
        outcome.iterations,
    )
}

/// Relative agreement; 1e-9 is far above the rounding of a sum of a few
/// thousand terms and far below any difference in the steps taken.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs()
}

/// apex's own factors have the same variables and tangents for these data
/// sets, so every solve takes the same steps.
#[test]
fn every_factor_choice_takes_the_same_steps() {
    for file in ["Balbianello.out", "pose3example.txt"] {
        let problem = data(file);
        let apex = run(&problem, FactorChoice::Apex);
        for kernels in [Kernels::Generated, Kernels::Dual] {
            let ours = run(&problem, FactorChoice::Ours(kernels));
            assert!(
                close(ours.0, ours.1),
                "{file}: cost known at build {} vs apex's {}",
                ours.0,
                ours.1
            );
            assert!(
                close(ours.1, apex.1),
                "{file} {kernels:?}: initial {} vs {}",
                ours.1,
                apex.1
            );
            assert!(
                close(ours.2, apex.2),
                "{file} {kernels:?}: final {} vs {}",
                ours.2,
                apex.2
            );
            assert_eq!(ours.3, apex.3, "{file} {kernels:?}: iterations");
        }
    }
}

/// The optimized problem, written back and read again, is what the solver
/// ended with: rebuilding it gives the final cost as its initial cost.
#[test]
fn written_back_problems_start_at_the_final_cost() {
    for file in [
        "dubrovnik-3-7-pre.txt",
        "Balbianello.out",
        "pose3example.txt",
        "VO_camera_poses_large.txt",
    ] {
        let problem = data(file);
        let options = BuildOptions {
            factors: FactorChoice::Ours(Kernels::Generated),
            robust: None,
            keep_blocks: false,
        };
        let mut built = build(&problem, &options).expect("builds");
        let outcome = solve(&mut built, &SolveOptions::default(), |_| {}).expect("solves");
        let solved = built.write_back(&problem, &outcome.values);
        assert_eq!(solved.format(), problem.format());
        let again = build(&solved, &options).expect("rebuilds");
        assert!(
            (again.initial_cost - outcome.final_cost).abs() <= 1e-9 * outcome.final_cost.max(1e-9),
            "{file}: {} vs {}",
            again.initial_cost,
            outcome.final_cost
        );
    }
}

/// The cost known at build applies the robust loss as apex does.
#[test]
fn robust_losses_change_the_known_initial_cost_as_apex_does() {
    let problem = data("Balbianello.out");
    for robust in ["huber:0.5", "cauchy:0.5"] {
        let options = BuildOptions {
            factors: FactorChoice::Ours(Kernels::Generated),
            robust: Some(robust.parse().expect("a loss")),
            keep_blocks: false,
        };
        let mut built = build(&problem, &options).expect("builds");
        let known = built.initial_cost;
        let outcome = solve(&mut built, &SolveOptions::default(), |_| {}).expect("solves");
        assert!(
            close(known, outcome.initial_cost),
            "{robust}: {known} vs {}",
            outcome.initial_cost
        );
    }
}
