//! Verdicts: the printed formula against the truth at many sampled points.
//!
//! - `correct`: agrees at every sample (relative Frobenius error ≤ 1e-6);
//! - `convention`: disagrees, but agrees with the truth under another
//!   convention the derivation offers (perturbation side, normalisation), with
//!   its tangent blocks swapped, or with a homogeneous coordinate kept;
//! - `wrong`: agrees with nothing; the largest error is reported with a
//!   guess at the erratum (sign, constant factor, transpose, which columns);
//! - `malformed`: the printed formula cannot be evaluated as printed;
//! - `ambiguous` (audits from a document's text): wrong or malformed as
//!   read by default, right under another reading of its notation.

use nalgebra::DMatrix;

use crate::derivation::{Derivation, Label, Printed, truth};
use crate::latex::corrected_latex;
use factor_core::factor::relative_frobenius_error;
use factor_testing::samples::Sampler;

/// Agreement threshold (relative Frobenius error at each sample).
pub const TOLERANCE: f64 = 1e-6;

/// The audit's verdict on one formula.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Right as printed.
    Correct,
    /// Right under another convention (described).
    Convention(String),
    /// Wrong; the suspected erratum, when one of the simple ones fits.
    Wrong(Option<String>),
    /// Not well formed as printed; why.
    Malformed(String),
    /// Wrong or malformed as the notation is read by default, but right
    /// under another reading of it the document may mean (a script's
    /// scope, a function's argument, a grouping): that reading, in words,
    /// with every grouping explicit. Never reported as `wrong`: the audit
    /// cannot tell which reading the author meant.
    Ambiguous(String),
}

impl Verdict {
    /// The JSON vocabulary: `correct`, `convention`, `wrong`, `malformed`,
    /// `ambiguous`.
    pub fn keyword(&self) -> &'static str {
        match self {
            Verdict::Correct => "correct",
            Verdict::Convention(_) => "convention",
            Verdict::Wrong(_) => "wrong",
            Verdict::Malformed(_) => "malformed",
            Verdict::Ambiguous(_) => "ambiguous",
        }
    }
}

/// The audit of one formula.
#[derive(Debug, Clone, PartialEq)]
pub struct Finding {
    /// What was audited.
    pub label: Label,
    /// The verdict.
    pub verdict: Verdict,
    /// Largest relative Frobenius error of the printed formula against the
    /// truth over the samples (`None` when malformed).
    pub max_relative_error: Option<f64>,
    /// The correct expression as LaTeX, for wrong and malformed formulas.
    pub corrected_latex: Option<String>,
    /// Number of sampled points.
    pub samples: usize,
    /// For a composed formula of a chain rule that is not correct: which
    /// links are wrong ([`crate::chain::localise`]).
    pub localisation: Option<String>,
}

impl Finding {
    /// Whether this finding should fail a gated run: a disagreement that is
    /// not a known erratum.
    pub fn is_unexpected(&self) -> bool {
        !matches!(self.verdict, Verdict::Correct) && self.label.known_erratum.is_none()
    }
}

/// Swaps the two halves of the columns (`[ω, ρ]` ↔ `[ρ, ω]`), if even.
fn swap_column_halves(m: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let n = m.ncols();
    (n >= 2 && n.is_multiple_of(2)).then(|| {
        let h = n / 2;
        DMatrix::from_fn(m.nrows(), n, |r, c| m[(r, (c + h) % n)])
    })
}

/// The printed matrix without a homogeneous coordinate it kept: its last
/// row, when that row is zero and the truth has one row fewer.
fn without_homogeneous_row(printed: &DMatrix<f64>, truth: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let rows = printed.nrows();
    (rows == truth.nrows() + 1
        && printed.ncols() == truth.ncols()
        && printed.row(rows - 1).norm() == 0.0)
        .then(|| printed.rows(0, rows - 1).into_owned())
}

fn agree(a: &DMatrix<f64>, b: &DMatrix<f64>) -> bool {
    a.shape() == b.shape() && relative_frobenius_error(a, b, 1e-9) <= TOLERANCE
}

/// Simple errata that turn the printed matrix into the truth, in words.
fn suspected_erratum(printed: &DMatrix<f64>, truth: &DMatrix<f64>) -> Option<String> {
    if printed.shape() == truth.shape() {
        if agree(&(-printed), truth) {
            return Some("opposite sign".into());
        }
        for factor in [2.0, 0.5, -2.0, -0.5, 4.0, 0.25] {
            if agree(&(printed * factor), truth) {
                return Some(format!(
                    "off by a constant factor {factor} (printed × {factor} = truth)"
                ));
            }
        }
        let wrong_columns: Vec<usize> = (0..truth.ncols())
            .filter(|&c| {
                let (p, t) = (printed.column(c), truth.column(c));
                (p - t).norm() > TOLERANCE * truth.norm().max(1e-9)
            })
            .collect();
        if !wrong_columns.is_empty() && wrong_columns.len() < truth.ncols() {
            return Some(only_some_wrong("column", &wrong_columns));
        }
        let wrong_rows: Vec<usize> = (0..truth.nrows())
            .filter(|&r| {
                let (p, t) = (printed.row(r), truth.row(r));
                (p - t).norm() > TOLERANCE * truth.norm().max(1e-9)
            })
            .collect();
        if !wrong_rows.is_empty() && wrong_rows.len() < truth.nrows() {
            return Some(only_some_wrong("row", &wrong_rows));
        }
    }
    if printed.transpose().shape() == truth.shape() && agree(&printed.transpose(), truth) {
        return Some("transposed".into());
    }
    None
}

/// Audits a derivation type at `samples` points drawn from `sample`.
pub fn audit<D: Derivation>(
    mut sample: impl FnMut(&mut Sampler) -> D,
    samples: usize,
    seed: u64,
) -> Finding {
    let mut sampler = Sampler::new(seed);
    let first = sample(&mut sampler);
    let label = first.label();

    let mut worst: f64 = 0.0;
    let mut worst_pair: Option<(DMatrix<f64>, DMatrix<f64>)> = None;
    // Conventions that have held at every sample so far (by description).
    let mut conventions: Option<Vec<String>> = None;
    let mut halves_swapped = true;
    let mut homogeneous = true;
    // A first-order claim whose sides differ at the point.
    let mut gap = None;
    // The samples are drawn and judged one at a time (nothing is kept per
    // sample), so the memory does not grow with `samples`.
    for index in 0..samples.max(1) {
        let drawn;
        let d = if index == 0 {
            &first
        } else {
            drawn = sample(&mut sampler);
            &drawn
        };
        let t = truth(d);
        if gap.is_none() {
            gap = d.gap();
        }
        let p = match d.printed() {
            Printed::Evaluated(p) => p,
            Printed::Malformed(reason) => {
                return Finding {
                    label,
                    verdict: Verdict::Malformed(reason),
                    max_relative_error: None,
                    corrected_latex: Some(corrected_latex(&first)),
                    samples,
                    localisation: None,
                };
            }
        };
        let error = if p.shape() == t.shape() {
            relative_frobenius_error(&p, &t, 1e-9)
        } else {
            f64::INFINITY
        };
        if error > worst || worst_pair.is_none() {
            worst = worst.max(error);
            worst_pair = Some((p.clone(), t.clone()));
        }
        let holding: Vec<String> = d
            .conventions()
            .into_iter()
            .filter(|(_, alt)| agree(&p, alt))
            .map(|(name, _)| name)
            .collect();
        conventions = Some(match conventions {
            None => holding,
            Some(previous) => previous
                .into_iter()
                .filter(|n| holding.contains(n))
                .collect(),
        });
        halves_swapped &= swap_column_halves(&t).is_some_and(|s| agree(&p, &s));
        homogeneous &= without_homogeneous_row(&p, &t).is_some_and(|q| agree(&q, &t));
    }
    let verdict = if let Some(gap) = gap {
        Verdict::Wrong(Some(gap))
    } else if worst <= TOLERANCE {
        Verdict::Correct
    } else if let Some(name) = conventions.unwrap_or_default().first() {
        Verdict::Convention(name.clone())
    } else if homogeneous {
        Verdict::Convention(
            "right with the homogeneous coordinate kept (an extra zero last row)".into(),
        )
    } else if halves_swapped {
        Verdict::Convention(
            "right with the two halves of the tangent swapped (e.g. [δρ, δω] instead of [δω, δρ])"
                .into(),
        )
    } else {
        let (p, t) = worst_pair.expect("at least one sample");
        Verdict::Wrong(suspected_erratum(&p, &t))
    };
    let corrected_latex = matches!(verdict, Verdict::Wrong(_)).then(|| corrected_latex(&first));
    Finding {
        label,
        verdict,
        max_relative_error: Some(worst),
        corrected_latex,
        samples,
        localisation: None,
    }
}

/// "column 3 is wrong, the others right", "rows 4, 5, 6 are wrong, …"
/// (`which` 0-based).
fn only_some_wrong(what: &str, which: &[usize]) -> String {
    let list: Vec<String> = which.iter().map(|k| (k + 1).to_string()).collect();
    match list.as_slice() {
        [one] => format!("{what} {one} is wrong, the others right"),
        many => format!("{what}s {} are wrong, the others right", many.join(", ")),
    }
}
