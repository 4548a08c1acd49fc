//! `list`: a registry's factors, their variables and tangents, and their
//! generated kernels with operation counts, as a table or as JSON.

use factor_codegen as codegen;
use factor_codegen::OpCounts;
use serde_json::{Value, json};

use crate::generate::counts_text;
use crate::registry::{FactorEntry, Registry, SolvedBy};

/// The operation counts of the kernel `registry` generates for `entry`, as
/// the current definitions generate it: the whole kernel and the residual
/// alone (traced and lowered in process).
fn kernel_counts(registry: &Registry, entry: &FactorEntry) -> Option<(OpCounts, OpCounts)> {
    registry.spec(entry.name).map(codegen::operation_counts)
}

/// The `kernel:` line of the table.
fn kernel_line(registry: &Registry, entry: &FactorEntry) -> String {
    let counts = kernel_counts(registry, entry).map(|(all, residual)| {
        format!(
            "{} operations ({}); residual only {}",
            all.total(),
            counts_text(&all),
            residual.total()
        )
    });
    match (entry.kernel, counts) {
        (Some(path), Some(counts)) => format!("  kernel: {path}, {counts}\n"),
        (Some(path), None) => format!("  kernel: {path}\n"),
        (None, Some(counts)) => format!(
            "  kernel: none in this build (`eval` uses dual numbers); generated: {counts}\n"
        ),
        (None, None) => "  kernel: none (`eval` uses dual numbers)\n".to_string(),
    }
}

fn counts_json(c: &OpCounts) -> Value {
    json!({
        "add": c.add,
        "mul": c.mul,
        "div": c.div,
        "neg": c.neg,
        "sqrt": c.sqrt,
        "func": c.func,
        "branch": c.branch,
        "total": c.total(),
    })
}

/// A readable table: per factor its name and residual dimension, then one
/// row per variable (type, tangent dimension, perturbation and columns) and
/// the JSON fields of the input.
pub fn table(registry: &Registry) -> String {
    let mut out = String::new();
    for (i, entry) in registry.factors().iter().enumerate() {
        if i > 0 {
            out.push('\n');
        }
        out.push_str(&factor_table(registry, entry));
    }
    out
}

fn factor_table(registry: &Registry, entry: &FactorEntry) -> String {
    let variables = (entry.variables)();
    let mut rows = vec![[
        "variable".to_string(),
        "type".into(),
        "dim".into(),
        "tangent".into(),
    ]];
    for v in &variables {
        rows.push([
            v.name.into(),
            v.type_name.into(),
            v.tangent_dim.to_string(),
            v.tangent.into(),
        ]);
    }
    let width = |c: usize| rows.iter().map(|r| r[c].chars().count()).max().unwrap_or(0);
    let widths = [width(0), width(1), width(2)];
    let mut out = format!(
        "{}  (residual dimension {})\n",
        entry.name, entry.residual_dim
    );
    for row in &rows {
        let mut line = String::from("  ");
        for (cell, w) in row.iter().zip(widths) {
            line.push_str(&format!("{cell:<w$}  "));
        }
        line.push_str(&row[3]);
        out.push_str(line.trim_end());
        out.push('\n');
    }
    let fields = |variables: bool| {
        entry
            .json_fields(variables)
            .iter()
            .map(|(name, shape)| format!("{name} {shape}"))
            .collect::<Vec<_>>()
            .join("; ")
    };
    out.push_str(&format!("  variables: {}\n", fields(true)));
    out.push_str(&format!("  constants: {}\n", fields(false)));
    out.push_str(&kernel_line(registry, entry));
    if let Some(line) = solve_line(entry) {
        out.push_str(&line);
    }
    out
}

/// How `solve` linearizes the factor (the `solve:` line of the table), if
/// it is registered for `solve`: by the Schur-complement solver where it
/// is registered for it, else (and with `--solver apex`) by apex-solver.
fn solve_line(entry: &FactorEntry) -> Option<String> {
    let how = match entry.solved_by? {
        SolvedBy::Kernel => "its kernel in apex-solver's chart",
        SolvedBy::Dual => "dual numbers in apex-solver's chart",
    };
    Some(match schur_words(entry) {
        Some(schur) => format!(
            "  solve: problem files, by the Schur-complement solver through {schur}; with \
             --solver apex through {how}\n"
        ),
        None => format!("  solve: problem files, through {how}\n"),
    })
}

/// How the Schur-complement solver linearizes the factor, when it is
/// registered for it.
#[cfg(feature = "solve")]
fn schur_words(entry: &FactorEntry) -> Option<&'static str> {
    entry.schur.map(|(_, linearized)| linearized.describe())
}

#[cfg(not(feature = "solve"))]
fn schur_words(_entry: &FactorEntry) -> Option<&'static str> {
    None
}

/// [`FactorEntry::solved_by`] in the JSON list.
fn solved_by_json(entry: &FactorEntry) -> Value {
    match entry.solved_by {
        Some(SolvedBy::Kernel) => json!("kernel"),
        Some(SolvedBy::Dual) => json!("dual"),
        None => Value::Null,
    }
}

/// `tangent` states the perturbation side (or "additive") and the column
/// order in words; `json` is the variable's shape in the `eval` input;
/// `kernel` is the generated kernel `eval` uses (`null` when it uses dual
/// numbers) and `operations` the counts by kind of the kernel the current
/// definitions generate (`residual_operations`: the residual alone);
/// `solve` is how `solve` linearizes the factor in problem files
/// (`"kernel"`, `"dual"`, or `null` when it does not solve it).
///
/// `{"factors": [{"name", "residual_dim", "variables": [{"name", "type",
/// "tangent_dim", "tangent", "json"}], "constants": [{"name", "json"}],
/// "kernel", "operations": {"add", "mul", "div", "neg", "sqrt", "func",
/// "branch", "total"}, "residual_operations", "solve"}]}`.
pub fn json(registry: &Registry) -> Value {
    let factors: Vec<Value> = registry
        .factors()
        .iter()
        .map(|entry| {
            let shapes = entry.json_fields(true).into_iter().map(|(_, shape)| shape);
            let variables: Vec<Value> = (entry.variables)()
                .iter()
                .zip(shapes)
                .map(|(v, shape)| {
                    json!({
                        "name": v.name,
                        "type": v.type_name,
                        "tangent_dim": v.tangent_dim,
                        "tangent": v.tangent,
                        "json": shape,
                    })
                })
                .collect();
            let constants: Vec<Value> = entry
                .json_fields(false)
                .iter()
                .map(|(name, shape)| json!({"name": name, "json": shape}))
                .collect();
            let counts = kernel_counts(registry, entry);
            json!({
                "name": entry.name,
                "residual_dim": entry.residual_dim,
                "variables": variables,
                "constants": constants,
                "kernel": entry.kernel,
                "operations": counts.as_ref().map(|(all, _)| counts_json(all)),
                "residual_operations": counts.as_ref().map(|(_, residual)| residual.total()),
                "solve": solved_by_json(entry),
            })
        })
        .collect();
    json!({ "factors": factors })
}
