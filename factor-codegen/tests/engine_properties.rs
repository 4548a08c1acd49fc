//! Property tests of the symbolic engine over random expression trees.
//!
//! Each tree is evaluated three ways: directly in `f64` (the reference,
//! without any simplification), as a canonical DAG built through the
//! symbolic scalar, and as the straight-line program compiled from the DAG.
//! Derivatives are compared with dual numbers evaluating the same tree.

use std::collections::HashMap;

use factor_codegen::compile::{STRATEGIES, compile_with};
use factor_core::Scalar;
use factor_symbolic::calculus::derivative;
use factor_symbolic::evaluate::evaluate;
use factor_symbolic::{Expr, Tracer};
use nalgebra::{Const, U1};
use num_dual::DualSVec64;
use proptest::prelude::*;

const INPUTS: usize = 3;

/// An expression tree; every operation is total on the sampled inputs
/// (denominators and square-root arguments are kept away from zero, the
/// arguments of `ln`, `acos` and `asin` inside their domains, and `exp`'s
/// bounded).
#[derive(Debug, Clone)]
enum Tree {
    Input(usize),
    Const(f64),
    Add(Box<Tree>, Box<Tree>),
    Sub(Box<Tree>, Box<Tree>),
    Mul(Box<Tree>, Box<Tree>),
    /// `a / (b² + 1)`.
    Div(Box<Tree>, Box<Tree>),
    Neg(Box<Tree>),
    /// `√(a² + 1)`.
    Sqrt(Box<Tree>),
    Sin(Box<Tree>),
    Cos(Box<Tree>),
    Atan2(Box<Tree>, Box<Tree>),
    /// `exp(a / √(a² + 1))`, the argument in `(−1, 1)`.
    Exp(Box<Tree>),
    /// `ln(a² + b² + ½)`.
    Ln(Box<Tree>, Box<Tree>),
    /// `acos(a / √(a² + 1))`, the argument in `(−1, 1)`.
    Acos(Box<Tree>),
    /// `asin(a / √(a² + 1))`.
    Asin(Box<Tree>),
    Atan(Box<Tree>),
    Select(Box<Tree>, Box<Tree>, Box<Tree>, Box<Tree>),
    /// The same subtree twice, so DAG sharing and cancellation are exercised.
    Twice(Box<Tree>, bool),
}

impl Tree {
    // `v − v` is deliberate: the DAG must cancel it exactly.
    #[allow(clippy::eq_op)]
    fn eval<S: Scalar>(&self, x: &[S]) -> S {
        let one = S::one();
        match self {
            Tree::Input(i) => x[*i],
            Tree::Const(c) => S::from_f64(*c),
            Tree::Add(a, b) => a.eval(x) + b.eval(x),
            Tree::Sub(a, b) => a.eval(x) - b.eval(x),
            Tree::Mul(a, b) => a.eval(x) * b.eval(x),
            Tree::Div(a, b) => {
                let d = b.eval(x);
                a.eval(x) / (d * d + one)
            }
            Tree::Neg(a) => -a.eval(x),
            Tree::Sqrt(a) => {
                let v = a.eval(x);
                (v * v + one).sqrt()
            }
            Tree::Sin(a) => a.eval(x).sin(),
            Tree::Cos(a) => a.eval(x).cos(),
            Tree::Atan2(a, b) => {
                let d = b.eval(x);
                a.eval(x).atan2(d * d + one)
            }
            Tree::Exp(a) => unit_interval(a.eval(x)).exp(),
            Tree::Ln(a, b) => {
                let (a, b) = (a.eval(x), b.eval(x));
                (a * a + b * b + S::from_f64(0.5)).ln()
            }
            Tree::Acos(a) => unit_interval(a.eval(x)).acos(),
            Tree::Asin(a) => unit_interval(a.eval(x)).asin(),
            Tree::Atan(a) => a.eval(x).atan(),
            Tree::Select(l, r, a, b) => S::select_lt(l.eval(x), r.eval(x), a.eval(x), b.eval(x)),
            Tree::Twice(a, subtract) => {
                let v = a.eval(x);
                if *subtract { v - v + v * v } else { v + v * v }
            }
        }
    }
}

impl Tree {
    /// Whether some `select_lt` compares two values within `1e-9` (relative)
    /// of each other at `x`: a tie in exact arithmetic (`asin(a/√(a²+1))`
    /// against `atan2(a, 1)`, say), whose branch rounding decides, so two
    /// correct evaluation orders may take different branches.
    fn has_near_tie(&self, x: &[f64]) -> bool {
        match self {
            Tree::Input(_) | Tree::Const(_) => false,
            Tree::Neg(a)
            | Tree::Sqrt(a)
            | Tree::Sin(a)
            | Tree::Cos(a)
            | Tree::Exp(a)
            | Tree::Acos(a)
            | Tree::Asin(a)
            | Tree::Atan(a)
            | Tree::Twice(a, _) => a.has_near_tie(x),
            Tree::Add(a, b)
            | Tree::Sub(a, b)
            | Tree::Mul(a, b)
            | Tree::Div(a, b)
            | Tree::Atan2(a, b)
            | Tree::Ln(a, b) => a.has_near_tie(x) || b.has_near_tie(x),
            Tree::Select(l, r, a, b) => {
                let (lv, rv) = (l.eval(x), r.eval(x));
                (lv - rv).abs() <= 1e-9 * lv.abs().max(rv.abs()).max(1.0)
                    || [l, r, a, b].iter().any(|t| t.has_near_tie(x))
            }
        }
    }
}

/// `v / √(v² + 1)`, in `(−1, 1)`: inside the domain of `acos` and `asin`,
/// and approaching its ends for large `|v|`.
fn unit_interval<S: Scalar>(v: S) -> S {
    v / (v * v + S::one()).sqrt()
}

fn tree() -> impl Strategy<Value = Tree> {
    let leaf = prop_oneof![
        (0..INPUTS).prop_map(Tree::Input),
        prop_oneof![Just(0.0), Just(1.0), Just(-1.0), Just(2.0), -2.0..2.0f64]
            .prop_map(Tree::Const),
    ];
    leaf.prop_recursive(5, 48, 4, |inner| {
        let b = || inner.clone().prop_map(Box::new);
        prop_oneof![
            (b(), b()).prop_map(|(a, c)| Tree::Add(a, c)),
            (b(), b()).prop_map(|(a, c)| Tree::Sub(a, c)),
            (b(), b()).prop_map(|(a, c)| Tree::Mul(a, c)),
            (b(), b()).prop_map(|(a, c)| Tree::Div(a, c)),
            b().prop_map(Tree::Neg),
            b().prop_map(Tree::Sqrt),
            b().prop_map(Tree::Sin),
            b().prop_map(Tree::Cos),
            (b(), b()).prop_map(|(a, c)| Tree::Atan2(a, c)),
            b().prop_map(Tree::Exp),
            (b(), b()).prop_map(|(a, c)| Tree::Ln(a, c)),
            b().prop_map(Tree::Acos),
            b().prop_map(Tree::Asin),
            b().prop_map(Tree::Atan),
            (b(), b(), b(), b()).prop_map(|(l, r, a, c)| Tree::Select(l, r, a, c)),
            (b(), any::<bool>()).prop_map(|(a, s)| Tree::Twice(a, s)),
        ]
    })
}

/// `|a − b| ≤ tol · (1 + |b|)`.
fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + b.abs()) || (a.is_nan() && b.is_nan())
}

fn inputs() -> impl Strategy<Value = [f64; INPUTS]> {
    [0.3..2.0f64, -2.0..-0.3f64, -1.5..1.5f64]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The canonical DAG evaluates to what the tree evaluates to.
    #[test]
    fn simplification_never_changes_a_value(t in tree(), x in inputs()) {
        let reference = t.eval(&x);
        prop_assume!(reference.is_finite() && reference.abs() < 1e6);
        prop_assume!(!t.has_near_tie(&x));
        let tracer = Tracer::new();
        let symbols: Vec<Expr> = (0..INPUTS as u32).map(Expr::input).collect();
        let e = t.eval(&symbols);
        let graph = tracer.finish();
        let value = evaluate(&graph, &x, &[e])[0];
        prop_assert!(close(value, reference, 1e-9), "{value} vs {reference}");
    }

    /// Symbolic derivatives equal dual-number derivatives of the same tree,
    /// and the compiled program (every strategy) equals the DAG.
    #[test]
    fn derivatives_and_programs_match(t in tree(), x in inputs()) {
        let duals: Vec<DualSVec64<INPUTS>> = (0..INPUTS)
            .map(|i| DualSVec64::from_re(x[i]).derivative(i))
            .collect();
        let d = t.eval(&duals);
        prop_assume!(d.re.is_finite() && d.re.abs() < 1e6);
        prop_assume!(!t.has_near_tie(&x));
        let gradient = d.eps.unwrap_generic(Const::<INPUTS>, U1);
        prop_assume!(gradient.iter().all(|g| g.is_finite() && g.abs() < 1e6));

        let tracer = Tracer::new();
        let symbols: Vec<Expr> = (0..INPUTS as u32).map(Expr::input).collect();
        let e = t.eval(&symbols);
        let mut outputs = vec![e];
        for s in &symbols {
            outputs.push(derivative(e, *s, &mut HashMap::new()));
        }
        let graph = tracer.finish();
        let values = evaluate(&graph, &x, &outputs);
        prop_assert!(close(values[0], d.re, 1e-9));
        for i in 0..INPUTS {
            prop_assert!(close(values[i + 1], gradient[i], 1e-8), "∂{i}: {} vs {}", values[i + 1], gradient[i]);
        }
        for strategy in STRATEGIES {
            let (program, out) = compile_with(&graph, &outputs, strategy);
            let compiled = program.evaluate(&x, &out);
            for (a, b) in compiled.iter().zip(&values) {
                prop_assert!(close(*a, *b, 1e-10), "{strategy:?}: {a} vs {b}");
            }
        }
    }
}

/// The identities the issue names, one by one.
#[test]
fn algebraic_identities_hold_by_construction() {
    let tracer = Tracer::new();
    let (x, y) = (Expr::input(0), Expr::input(1));
    let zero = Expr::constant(0.0);
    let one = Expr::constant(1.0);
    assert_eq!(x + zero, x);
    assert_eq!(x * one, x);
    assert_eq!(x * zero, zero);
    assert_eq!(-(-x), x);
    assert_eq!(x - x, zero);
    assert_eq!(
        (x + Expr::constant(2.0)) + Expr::constant(3.0),
        x + Expr::constant(5.0)
    );
    assert_eq!(x * x.recip(), one);
    assert_eq!(x * y / y, x);
    assert_eq!(x + y, y + x);
    assert_eq!(x * y, y * x);
    assert_eq!(x.sqrt() * x.sqrt(), x);
    assert_eq!((x * y).scale(2.0) + (x * y).scale(-2.0), zero);
    // A sum and its multiples share one node.
    let s = x * y + y * y;
    assert_eq!((s.scale(-2.0)).scale(-0.5), s);
    assert_eq!(Expr::select_lt(x, y, x, x), x);
    drop(tracer);
}

/// The math-library functions compile to one instruction each, counted in
/// the `func` column, and the compiled program evaluates them (and their
/// derivatives) as `f64` does: `exp' = exp`, `ln' = 1/x`,
/// `acos' = −1/√(1 − x²)`, `asin' = 1/√(1 − x²)`, `atan' = 1/(1 + x²)`.
#[test]
fn library_functions_compile_to_one_call_each() {
    let tracer = Tracer::new();
    let x = Expr::input(0);
    let functions = [x.exp(), x.ln(), x.acos(), x.asin(), x.atan()];
    let derivatives: Vec<Expr> = functions
        .iter()
        .map(|f| derivative(*f, x, &mut HashMap::new()))
        .collect();
    let graph = tracer.finish();
    let (program, values) = factor_codegen::compile::compile(&graph, &functions);
    assert_eq!(program.counts(&values).func, 5);
    assert_eq!(program.counts(&values).total(), 5);
    let (program_d, values_d) = factor_codegen::compile::compile(&graph, &derivatives);
    // exp' is exp itself; the other derivatives are arithmetic and square roots.
    assert_eq!(program_d.counts(&values_d).func, 1);
    for v in [0.3, 0.5, 0.9, 0.999_999] {
        let got = program.evaluate(&[v], &values);
        let want = [v.exp(), v.ln(), v.acos(), v.asin(), v.atan()];
        for (g, w) in got.iter().zip(want) {
            assert_eq!(*g, w);
        }
        let got = program_d.evaluate(&[v], &values_d);
        // Independent closed forms: acos' = −1/sin(acos x), asin' = 1/cos(asin x),
        // atan' = cos²(atan x).
        let want = [
            v.exp(),
            1.0 / v,
            -1.0 / v.acos().sin(),
            1.0 / v.asin().cos(),
            v.atan().cos().powi(2),
        ];
        for (g, w) in got.iter().zip(want) {
            assert!(close(*g, w, 1e-12), "{v}: {g} vs {w}");
        }
    }
}

/// Constants fold inside the functions' domains only; outside, the node is
/// kept (and evaluates to NaN, as `f64` does).
#[test]
fn library_functions_fold_constants_inside_their_domains() {
    let tracer = Tracer::new();
    let c = Expr::constant;
    assert_eq!(c(0.0).exp(), c(1.0));
    assert_eq!(c(1.0).ln(), c(0.0));
    assert_eq!(c(1.0).acos(), c(0.0));
    assert_eq!(
        c(1.0).asin().as_constant(),
        Some(std::f64::consts::FRAC_PI_2)
    );
    assert_eq!(
        c(1.0).atan().as_constant(),
        Some(std::f64::consts::FRAC_PI_4)
    );
    for outside in [c(-1.0).ln(), c(0.0).ln(), c(1.5).acos(), c(-1.5).asin()] {
        assert_eq!(outside.as_constant(), None);
    }
    let outside = [c(-1.0).ln(), c(1.5).acos(), c(-1.5).asin()];
    let graph = tracer.finish();
    assert!(evaluate(&graph, &[], &outside).iter().all(|v| v.is_nan()));
}

/// Found by `derivatives_and_programs_match`: `asin(a/√(a²+1))` and
/// `atan2(a, 1)` are both `atan(a)`, so a select between them is a tie that
/// rounding decides (the DAG's evaluation and `f64` took different branches
/// here). The property tests skip such ties; this one must be seen as one.
#[test]
fn a_select_between_equal_values_is_a_tie() {
    use Tree::*;
    let t = Select(
        Box::new(Asin(Box::new(Input(2)))),
        Box::new(Atan2(Box::new(Input(2)), Box::new(Const(0.0)))),
        Box::new(Input(1)),
        Box::new(Input(0)),
    );
    assert!(t.has_near_tie(&[0.3, -0.3, -0.46454744522046476]));
    let apart = Select(
        Box::new(Input(0)),
        Box::new(Input(1)),
        Box::new(Input(1)),
        Box::new(Input(0)),
    );
    assert!(!apart.has_near_tie(&[0.3, -0.3, -0.46454744522046476]));
}
