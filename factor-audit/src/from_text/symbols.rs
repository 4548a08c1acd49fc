//! The symbols file (TOML): what a document's symbols mean and what each
//! audited equation claims. Read with `serde` and `toml`; every error names
//! the symbol or the claim it is about, on one line.
//!
//! ```toml
//! # Optional: the document this file describes (its file name).
//! document = "notes.md"
//!
//! [context.icp]                 # a set of symbols and how they are sampled
//! factor = "point_reprojection" # optional: a shipped factor whose samples give the fields
//!
//! [context.icp.symbols]
//! "T" = { sample = "pose" }                 # a sampled free variable
//! "R" = { field = "pose.rotation" }         # a factor's field, or a part of one
//! "P_c" = "R X_w + t"                        # a definition: LaTeX over other symbols
//! "P" = { latex = "\\operatorname{transform}(T, X)", components = ["P_x", "P_y", "P_z"] }
//! "J_l" = { function = "left_jacobian" }    # a function symbol: J_l(ω)
//! "\\xi" = { perturbs = "T", side = "left", parts = ["\\delta\\phi", "\\delta\\rho"] }
//! "\\varepsilon" = { residual = [1] }       # components of the factor's residual
//!
//! [[claim]]
//! id = "(2)"            # the name in the report
//! context = "icp"
//! label = "(2)"         # or anchor = "a piece of the formula's LaTeX"
//! ```
//!
//! The module documentation of [`crate::from_text`] lists every key.

use std::collections::BTreeMap;

use serde::Deserialize;

use super::TextError;

/// Longest symbols file read, in bytes.
pub const MAX_SYMBOLS_BYTES: usize = 1 << 20;
/// Most claims a symbols file may state.
pub const MAX_CLAIMS: usize = 200;
/// Most symbols a context (with its claims' own) may define.
pub const MAX_SYMBOLS: usize = 2000;

/// The whole file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SymbolsFile {
    /// The document's file name, when given (informational).
    pub document: Option<String>,
    /// `"latex"` for a LaTeX source (`%` comments), `"markdown"` otherwise;
    /// by default from the document's extension (`.tex` is LaTeX).
    pub syntax: Option<String>,
    /// Words the document uses as function names (`between(a, b)`), besides
    /// the built-in ones.
    #[serde(default)]
    pub words: Vec<String>,
    /// The document's quaternion convention: `"hamilton"` (the default) or
    /// `"jpl"` (`q ⊗ p` is JPL's product, `rotation(q)` JPL's `C(q)`).
    pub quaternions: Option<Quaternions>,
    /// The contexts, by name.
    #[serde(default)]
    pub context: BTreeMap<String, ContextSpec>,
    /// The audited claims, in order.
    #[serde(default, rename = "claim")]
    pub claims: Vec<ClaimSpec>,
}

/// A document's quaternion convention.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quaternions {
    /// Hamilton's product; `rotation(q)` the active rotation `q v q⁻¹`.
    Hamilton,
    /// JPL's (Trawny and Roumeliotis): `q ⊗ p` is Hamilton's `p ⊗ q`, and
    /// `C(q)` is Hamilton's rotation transposed.
    Jpl,
}

/// A context: the symbols of a part of the document and what samples them.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContextSpec {
    /// A shipped factor (`slamjac list`) whose samples give the fields.
    pub factor: Option<String>,
    /// Symbol (LaTeX) to meaning.
    #[serde(default)]
    pub symbols: BTreeMap<String, toml::Value>,
    /// Operators and function words the document defines: `"\\boxminus"`,
    /// `"^\\odot"`, `"between"` to `{ args = ["a", "b"], latex = "…" }`.
    #[serde(default)]
    pub operators: BTreeMap<String, TemplateSpec>,
    /// Chain-rule links the document states only in words: derivatives
    /// (as chain rules print them) whose value is the true derivative.
    #[serde(default, rename = "link")]
    pub links: Vec<LinkSpec>,
}

/// An operator or function defined by LaTeX over its arguments.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TemplateSpec {
    /// The names of its arguments, as written in `latex`.
    pub args: Vec<String>,
    /// The name its printed subscript is bound to, for a function whose
    /// subscript is an argument (`\Phi_{R_0}(θ)`: `sub = "A"` binds `A` to
    /// `R_0`); the function is keyed without its subscript.
    #[serde(default)]
    pub sub: Option<String>,
    /// Its value, LaTeX over the arguments and the context's symbols.
    pub latex: String,
}

/// A chain-rule link stated in words: `lhs` (the derivative as printed in
/// the chain rules) is the true derivative of `of` by `wrt`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinkSpec {
    /// The derivative as the chain rules print it.
    pub lhs: String,
    /// The map differentiated.
    pub of: String,
    /// The variable.
    pub wrt: String,
    /// The side a group variable is perturbed on.
    pub side: Option<Side>,
    /// The local coordinates a group-valued map is read in.
    pub output: Option<Side>,
    /// The other arguments the partial holds (symbols kept at their values
    /// while `wrt` moves, though they depend on it).
    #[serde(default)]
    pub holding: Vec<String>,
}

/// What a claim says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ClaimKind {
    /// The printed matrix is the Jacobian of `of` w.r.t. `wrt`.
    Jacobian,
    /// The printed value is the value of `of`.
    Value,
    /// The printed right side agrees with `of` to first order in `wrt`
    /// (`≈`): their Jacobians w.r.t. `wrt` are compared.
    FirstOrder,
    /// The printed right side is the differential: the Jacobian applied to
    /// the tangent `wrt` (`ω = J φ̇`, `D f(ξ)`), linear in it.
    Differential,
}

/// A perturbation side.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// `x ← Exp(δ) x`.
    Left,
    /// `x ← x Exp(δ)`.
    Right,
}

/// One audited claim.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClaimSpec {
    /// Its name in reports.
    pub id: String,
    /// The context whose symbols it uses.
    pub context: String,
    /// The printed equation label (`"(5)"`).
    pub label: Option<String>,
    /// A piece of the formula's LaTeX (or of the prose just before it).
    pub anchor: Option<String>,
    /// A piece of the prose just before the formula: the first display
    /// after it (said explicitly, never a fallback of `anchor`).
    pub after: Option<String>,
    /// A piece of the heading of the section the formula is in: `label`,
    /// `anchor` and `after` are looked for there only (to the next heading
    /// of the same or a higher level).
    pub section: Option<String>,
    /// Which of the places `anchor` or `after` matches (1-based, in the
    /// document's order), when it matches several.
    pub occurrence: Option<usize>,
    /// Which line of the formula (1-based).
    pub line: Option<usize>,
    /// Which statement of the line (1-based: the line's claim, then what
    /// follows it after `\\quad`, `,` or words such as `\\mbox{ and }`).
    pub statement: Option<usize>,
    /// Which right side of a chain of equalities `a = b = c` on the line
    /// (1-based: `b`, then `c`; by default the last).
    pub step: Option<usize>,
    /// Follow the chain of equalities from the located line to its end.
    #[serde(default)]
    pub chain: bool,
    /// Which row of a `cases` right side (1-based).
    pub case: Option<usize>,
    /// What it claims; by default a Jacobian when the left side is a
    /// derivative, else a value.
    pub kind: Option<ClaimKind>,
    /// The map (LaTeX); by default what the left side differentiates.
    pub of: Option<String>,
    /// The variable (LaTeX); by default what the left side differentiates by.
    pub wrt: Option<String>,
    /// The side a group variable named in `wrt` is perturbed on.
    pub side: Option<Side>,
    /// The variable's update, LaTeX in it and `\\delta` (`"\\operatorname{Exp}(-\\delta) R"`
    /// for the error `R ← Exp(−δ) R`), instead of a side.
    pub update: Option<String>,
    /// The local coordinates a group-valued map is read in: `Log(f₀⁻¹ f)`
    /// on the right, `Log(f f₀⁻¹)` on the left (by default the variable's
    /// side).
    pub output: Option<Side>,
    /// Differentiate at the variable's zero instead of its sampled value.
    #[serde(default)]
    pub at_zero: bool,
    /// The other arguments the claim's partial derivative holds: symbols
    /// kept at their values while the variable moves, though they depend on
    /// it (`∂h/∂x` of `h(x, r(x))` holding `r`).
    #[serde(default)]
    pub holding: Vec<String>,
    /// How other formulas write this derivative in chain rules (LaTeX); by
    /// default its printed left side.
    pub lhs: Option<String>,
    /// The verdict the gate expects (`correct` unless stated).
    pub expected: Option<String>,
    /// A note on a known erratum, recorded by a reader (reports show it
    /// apart from the engine's own diagnosis).
    pub erratum: Option<String>,
    /// The claim in words; by default the printed left side.
    pub claim: Option<String>,
    /// The convention the document states, in words.
    pub convention: Option<String>,
    /// Read every fraction of the printed right side as the column
    /// `[above; below]` (documents converted from PDF print stacked blocks
    /// as `\left(\frac{…}{…}\right)`); a difference quotient over a
    /// tangent stays one.
    #[serde(default)]
    pub stacked_fractions: bool,
    /// Readings of symbols in this formula only.
    #[serde(default)]
    pub symbols: BTreeMap<String, toml::Value>,
    /// Other conventions to try when the claim is not right as stated.
    #[serde(default)]
    pub conventions: Vec<ConventionSpec>,
}

/// A convention to try: the same claim with the variable perturbed on
/// another side, updated by another expression, or another map.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConventionSpec {
    /// What it is, in words (reports say the formula is right under it).
    pub description: String,
    /// Perturb the variable on this side instead.
    pub side: Option<Side>,
    /// The variable's update, LaTeX in the variable and `\delta` (for
    /// `u ← log(exp(δ) ⊕ exp(u))`: `"\\log(\\exp(\\delta) \\oplus \\exp(u))"`).
    pub update: Option<String>,
    /// Another map.
    pub of: Option<String>,
    /// Another variable.
    pub wrt: Option<String>,
}

/// How a derivative by a stored symbol perturbs it when the claim does
/// not say: on a side, or by an update expression.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Perturbed {
    /// The side.
    pub side: Option<Side>,
    /// The update, LaTeX in the symbol and `\\delta`.
    pub update: Option<String>,
}

/// A symbol's meaning as the file writes it.
#[derive(Debug, Clone, PartialEq)]
pub enum SymbolSpec {
    /// A definition, LaTeX over other symbols; `components` name its entries.
    Latex {
        /// The LaTeX.
        latex: String,
        /// Symbols for its entries, in order.
        components: Vec<String>,
    },
    /// A field of the context's factor, or a part of one (`pose.rotation`);
    /// `components` name its entries.
    Field {
        /// The layout path.
        path: String,
        /// Symbols for its entries, in order.
        components: Vec<String>,
        /// The default perturbation.
        perturbation: Perturbed,
    },
    /// A sampled free variable (`rotation_vector`, `pose`, …, `vector` of
    /// `size` entries in `range`, `scalar` in `range`), perturbed by default
    /// on `side` or by `update`.
    Sample {
        /// The sampler.
        name: String,
        /// Entries of a `vector`.
        size: Option<usize>,
        /// Rows and columns of a `matrix`.
        shape: Option<[usize; 2]>,
        /// Where entries are drawn.
        range: Option<[f64; 2]>,
        /// Symbols for its entries, in order.
        components: Vec<String>,
        /// The default perturbation.
        perturbation: Perturbed,
    },
    /// A function symbol defined by LaTeX over its arguments
    /// (`{ args = ["p"], latex = "\\lfloor -p \\rfloor_\\times" }`).
    Template(TemplateSpec),
    /// A function symbol (`left_jacobian`, `normalize`, …).
    Function(String),
    /// A perturbation of another symbol.
    Tangent {
        /// The symbol perturbed.
        perturbs: String,
        /// On which side (groups only).
        side: Option<Side>,
        /// Or by which update (LaTeX in the symbol and `\\delta`).
        update: Option<String>,
        /// Symbols for equal slices of it (`[δφ, δρ]`).
        parts: Vec<String>,
        /// Which tangent coordinates (1-based), by default all.
        coordinates: Option<Vec<usize>>,
    },
    /// Components (1-based) of the context factor's residual.
    Residual(Vec<usize>),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SymbolTable {
    latex: Option<String>,
    #[serde(default)]
    components: Vec<String>,
    args: Option<Vec<String>>,
    sub: Option<String>,
    field: Option<String>,
    sample: Option<String>,
    size: Option<usize>,
    shape: Option<[usize; 2]>,
    range: Option<[f64; 2]>,
    function: Option<String>,
    perturbs: Option<String>,
    side: Option<Side>,
    update: Option<String>,
    #[serde(default)]
    parts: Vec<String>,
    coordinates: Option<Vec<usize>>,
    residual: Option<Vec<usize>>,
}

impl SymbolSpec {
    /// The meaning of `symbol` written as `value`.
    pub fn read(symbol: &str, value: &toml::Value) -> Result<Self, TextError> {
        let bad = |message: String| TextError::Symbol {
            symbol: symbol.to_string(),
            equation: None,
            message,
        };
        let table = match value {
            toml::Value::String(latex) => {
                return Ok(SymbolSpec::Latex {
                    latex: latex.clone(),
                    components: Vec::new(),
                });
            }
            toml::Value::Table(t) => t.clone(),
            other => {
                return Err(bad(format!(
                    "a meaning is a LaTeX string or a table, not a {}",
                    other.type_str()
                )));
            }
        };
        let t: SymbolTable = toml::Value::Table(table)
            .try_into()
            .map_err(|e: toml::de::Error| bad(one_line(e.message())))?;
        let given = [
            t.latex.is_some(),
            t.field.is_some(),
            t.sample.is_some(),
            t.function.is_some(),
            t.perturbs.is_some(),
            t.residual.is_some(),
        ];
        if given.iter().filter(|g| **g).count() != 1 {
            return Err(bad(
                "give exactly one of `latex`, `field`, `sample`, `function`, `perturbs`, `residual`"
                    .into(),
            ));
        }
        let stored = t.field.is_some() || t.sample.is_some();
        if t.perturbs.is_none() && (!t.parts.is_empty() || t.coordinates.is_some()) {
            return Err(bad("`parts` and `coordinates` go with `perturbs`".into()));
        }
        if t.perturbs.is_none() && !stored && (t.side.is_some() || t.update.is_some()) {
            return Err(bad(
                "`side` and `update` go with `perturbs`, `field` or `sample`".into(),
            ));
        }
        if t.latex.is_none() && !stored && !t.components.is_empty() {
            return Err(bad(
                "`components` goes with `latex`, `field` or `sample`".into()
            ));
        }
        if t.sample.is_none() && (t.size.is_some() || t.shape.is_some() || t.range.is_some()) {
            return Err(bad("`size`, `shape` and `range` go with `sample`".into()));
        }
        if t.latex.is_none() && t.args.is_some() {
            return Err(bad("`args` goes with `latex`".into()));
        }
        if t.args.is_none() && t.sub.is_some() {
            return Err(bad("`sub` goes with `args` and `latex`".into()));
        }
        let perturbation = Perturbed {
            side: t.side,
            update: t.update.clone(),
        };
        Ok(if let (Some(latex), Some(args)) = (&t.latex, &t.args) {
            SymbolSpec::Template(TemplateSpec {
                args: args.clone(),
                sub: t.sub.clone(),
                latex: latex.clone(),
            })
        } else if let Some(latex) = t.latex {
            SymbolSpec::Latex {
                latex,
                components: t.components,
            }
        } else if let Some(path) = t.field {
            SymbolSpec::Field {
                path,
                components: t.components,
                perturbation,
            }
        } else if let Some(name) = t.sample {
            SymbolSpec::Sample {
                name,
                size: t.size,
                shape: t.shape,
                range: t.range,
                components: t.components,
                perturbation,
            }
        } else if let Some(f) = t.function {
            SymbolSpec::Function(f)
        } else if let Some(r) = t.residual {
            SymbolSpec::Residual(r)
        } else {
            SymbolSpec::Tangent {
                perturbs: t.perturbs.unwrap_or_default(),
                side: t.side,
                update: t.update,
                parts: t.parts,
                coordinates: t.coordinates,
            }
        })
    }
}

/// `s` on one line: runs of white space become one space, other
/// unprintable characters are escaped (`\u001b`, `\ufeff`:
/// `slamjac_io::printable`), so an error quoting the input keeps its
/// one-line shape and cannot drive a terminal.
pub fn one_line(s: &str) -> String {
    let collapsed = s.split_whitespace().collect::<Vec<_>>().join(" ");
    slamjac_io::printable::escape(&collapsed).into_owned()
}

impl SymbolsFile {
    /// Reads a symbols file; an error names the line of the TOML at fault.
    pub fn parse(text: &str) -> Result<Self, TextError> {
        if text.len() > MAX_SYMBOLS_BYTES {
            return Err(TextError::TooLarge {
                what: "symbols file",
                limit: MAX_SYMBOLS_BYTES,
            });
        }
        let file: SymbolsFile = toml::from_str(text).map_err(|e| {
            let line = e
                .span()
                .map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
            TextError::Toml {
                line,
                message: one_line(e.message()),
            }
        })?;
        if file.claims.len() > MAX_CLAIMS {
            return Err(TextError::TooManyClaims { limit: MAX_CLAIMS });
        }
        if file.claims.is_empty() {
            return Err(TextError::NoClaims);
        }
        Ok(file)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meanings_are_read_with_errors_naming_the_symbol() {
        let v: toml::Value = toml::from_str("a = { field = \"pose\" }").unwrap();
        assert_eq!(
            SymbolSpec::read("T", &v["a"]).unwrap(),
            SymbolSpec::Field {
                path: "pose".into(),
                components: Vec::new(),
                perturbation: Perturbed::default(),
            }
        );
        let v: toml::Value = toml::from_str("a = { field = \"pose\", sample = \"pose\" }").unwrap();
        let e = SymbolSpec::read("T", &v["a"]).unwrap_err().to_string();
        assert!(e.contains("`T`") && e.contains("exactly one"), "{e}");
        let v: toml::Value = toml::from_str("a = { feld = \"pose\" }").unwrap();
        let e = SymbolSpec::read("T", &v["a"]).unwrap_err().to_string();
        assert!(e.contains("`T`") && e.contains("feld"), "{e}");
    }

    #[test]
    fn toml_errors_give_their_line() {
        let e = SymbolsFile::parse("document = \"x\"\n[[claim]]\nid = 3\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 3"), "{e}");
        assert!(!e.contains('\n'));
    }
}
