//! The vocabulary: which commands and letter runs are functions, symbols,
//! relations, operators, fonts and accents, and how each is written back.
//! Each table is read in both directions, so parser and renderer agree.

use crate::ast::{Accent, Font, MulOp, Rel};

/// Function names recognised as a run of plain letters (`Exp(ω)`, `sinc`).
/// A run of letters that is not one of these is a product of symbols.
pub const FUNCTION_WORDS: &[&str] = &[
    "sinc", "sin", "cos", "tan", "cot", "sec", "csc", "sinh", "cosh", "tanh", "exp", "log", "Exp",
    "Log", "det", "arccos", "arcsin", "arctan", "acos", "asin", "atan", "ln", "diag",
];

/// Names read as a function inside `\mathrm{…}` and `\text{…}` (besides
/// the [`FUNCTION_WORDS`]) but never in a bare run of letters, where `ad`
/// may be a product: the adjoints `Ad`, `ad`, the trace, the sign.
pub const OPERATOR_WORDS: &[&str] = &["Ad", "ad", "tr", "sgn", "sign", "skew", "vec"];

/// Function names that LaTeX writes as a command (`\sin`); the others are
/// written `\operatorname{…}`.
pub const FUNCTION_COMMANDS: &[&str] = &[
    "sin", "cos", "tan", "cot", "sec", "csc", "exp", "log", "det", "arccos", "arcsin", "arctan",
    "ln", "sinh", "cosh", "tanh", "coth",
];

/// Commands that stand for one symbol: Greek letters and a few others.
pub const SYMBOL_COMMANDS: &[&str] = &[
    "alpha",
    "beta",
    "gamma",
    "delta",
    "epsilon",
    "varepsilon",
    "zeta",
    "eta",
    "theta",
    "vartheta",
    "iota",
    "kappa",
    "lambda",
    "mu",
    "nu",
    "xi",
    "pi",
    "varpi",
    "rho",
    "varrho",
    "sigma",
    "varsigma",
    "tau",
    "upsilon",
    "phi",
    "varphi",
    "chi",
    "psi",
    "omega",
    "Gamma",
    "Delta",
    "Theta",
    "Lambda",
    "Xi",
    "Pi",
    "Sigma",
    "Upsilon",
    "Phi",
    "Psi",
    "Omega",
    "varGamma",
    "varDelta",
    "varTheta",
    "varLambda",
    "varXi",
    "varPi",
    "varSigma",
    "varUpsilon",
    "varPhi",
    "varPsi",
    "varOmega",
    "ell",
    "infty",
    "nabla",
    "emptyset",
    "hbar",
    "imath",
    "jmath",
];

/// Relation commands and their meaning (synonyms map to one [`Rel`]; the
/// first entry of a [`Rel`] is how it is written back).
pub const RELATION_COMMANDS: &[(&str, Rel)] = &[
    ("approx", Rel::Approx),
    ("doteq", Rel::Doteq),
    ("equiv", Rel::Equiv),
    ("sim", Rel::Sim),
    ("simeq", Rel::Simeq),
    ("cong", Rel::Cong),
    ("in", Rel::In),
    ("notin", Rel::NotIn),
    ("subset", Rel::Subset),
    ("subseteq", Rel::SubsetEq),
    ("leftarrow", Rel::LeftArrow),
    ("gets", Rel::LeftArrow),
    ("to", Rel::To),
    ("rightarrow", Rel::To),
    ("Rightarrow", Rel::Implies),
    ("implies", Rel::Implies),
    ("Leftrightarrow", Rel::Iff),
    ("iff", Rel::Iff),
    ("mapsto", Rel::MapsTo),
    ("leq", Rel::Le),
    ("le", Rel::Le),
    ("geq", Rel::Ge),
    ("ge", Rel::Ge),
    ("neq", Rel::Neq),
    ("ne", Rel::Neq),
    ("propto", Rel::Propto),
    ("triangleq", Rel::Define),
    ("coloneqq", Rel::Define),
    ("defeq", Rel::Define),
    ("eqqcolon", Rel::Define),
    ("longrightarrow", Rel::To),
    ("Longrightarrow", Rel::Implies),
    ("Longleftrightarrow", Rel::Iff),
    ("longmapsto", Rel::MapsTo),
    ("leqslant", Rel::Le),
    ("geqslant", Rel::Ge),
];

/// Explicit product-level operators written as commands.
pub const MULOP_COMMANDS: &[(&str, MulOp)] = &[
    ("cdot", MulOp::Cdot),
    ("times", MulOp::Times),
    ("otimes", MulOp::Otimes),
    ("oplus", MulOp::Oplus),
    ("ominus", MulOp::Ominus),
    ("boxplus", MulOp::Boxplus),
    ("boxminus", MulOp::Boxminus),
    ("circ", MulOp::Circ),
    ("odot", MulOp::Odot),
    ("wedge", MulOp::Wedge),
    ("ast", MulOp::Star),
];

/// Font commands (the first entry of a [`Font`] is how it is written back).
pub const FONT_COMMANDS: &[(&str, Font)] = &[
    ("boldsymbol", Font::Bold),
    ("mathbf", Font::Bold),
    ("bm", Font::Bold),
    ("pmb", Font::Bold),
    ("mathcal", Font::Calligraphic),
    ("mathscr", Font::Calligraphic),
    ("mathbb", Font::Blackboard),
    ("mathds", Font::Blackboard),
    ("mathbbm", Font::Blackboard),
    ("mathrm", Font::Roman),
    ("mathsf", Font::SansSerif),
    ("mathfrak", Font::Fraktur),
    ("mathit", Font::Plain),
    ("mathnormal", Font::Plain),
];

/// The font of `outer` written over a symbol already in `inner`
/// (`\bm{\mathcal{J}}`), when the two combine.
pub fn combined_font(outer: Font, inner: Font) -> Option<Font> {
    match (outer, inner) {
        (o, Font::Plain) => Some(o),
        (Font::Plain, i) => Some(i),
        (o, i) if o == i => Some(o),
        (Font::Bold, Font::Calligraphic) | (Font::Calligraphic, Font::Bold) => {
            Some(Font::BoldCalligraphic)
        }
        (Font::Bold, Font::BoldCalligraphic) => Some(Font::BoldCalligraphic),
        (Font::Bold, Font::Roman) | (Font::Roman, Font::Bold) => Some(Font::Bold),
        // `\mathfrak{\mathbb{R}}` (as LyX writes the reals): blackboard.
        (Font::Fraktur, Font::Blackboard) => Some(Font::Blackboard),
        _ => None,
    }
}

/// Accent commands (the first entry of an [`Accent`] is how it is written
/// back).
pub const ACCENT_COMMANDS: &[(&str, Accent)] = &[
    ("hat", Accent::Hat),
    ("widehat", Accent::Hat),
    ("tilde", Accent::Tilde),
    ("widetilde", Accent::Tilde),
    ("bar", Accent::Bar),
    ("overline", Accent::Bar),
    ("dot", Accent::Dot),
    ("ddot", Accent::DDot),
    ("vec", Accent::Vec),
    ("overrightarrow", Accent::Vec),
    ("check", Accent::Check),
    ("breve", Accent::Breve),
];

/// Environments read as a matrix (`array` takes a column specification).
pub const MATRIX_ENVIRONMENTS: &[&str] = &[
    "matrix",
    "pmatrix",
    "bmatrix",
    "Bmatrix",
    "smallmatrix",
    "array",
    "subarray",
];

/// Environments read as cases (`value & condition` rows).
pub const CASES_ENVIRONMENTS: &[&str] = &["cases", "dcases", "rcases"];

/// Environments whose rows are the lines of a multi-line formula; allowed
/// only as a whole display.
pub const ALIGNMENT_ENVIRONMENTS: &[&str] = &[
    "aligned",
    "split",
    "align",
    "align*",
    "gather",
    "gather*",
    "gathered",
    "multline",
    "multline*",
    "eqnarray",
    "eqnarray*",
    "subeqnarray",
    "alignat",
    "alignat*",
    "alignedat",
];

/// The first value of `table` stored under `name`.
pub fn lookup<T: Copy>(table: &[(&str, T)], name: &str) -> Option<T> {
    table.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)
}

/// The first name `table` stores `value` under.
pub fn name_of<T: Copy + PartialEq>(table: &[(&'static str, T)], value: T) -> &'static str {
    table
        .iter()
        .find(|(_, v)| *v == value)
        .map(|(n, _)| *n)
        .expect("every value has a name in its table")
}

/// `name` as a function name when it is one (`\sin` → `sin`).
pub fn function_command(name: &str) -> Option<&'static str> {
    FUNCTION_COMMANDS.iter().copied().find(|f| *f == name)
}

/// `name` as a symbol command when it is one.
pub fn symbol_command(name: &str) -> Option<&'static str> {
    SYMBOL_COMMANDS.iter().copied().find(|f| *f == name)
}

/// `word` as a function name written in letters when it is one.
pub fn function_word(word: &str) -> Option<&'static str> {
    FUNCTION_WORDS.iter().copied().find(|f| *f == word)
}

/// `word` as a function name inside `\mathrm{…}` or `\text{…}`.
pub fn operator_word(word: &str) -> Option<&'static str> {
    function_word(word).or_else(|| OPERATOR_WORDS.iter().copied().find(|f| *f == word))
}

/// The operators a superscript may hold (`p^\odot`, `x^*`): the command
/// names, and `*`, `+` as characters.
pub const POSTFIX_OPERATORS: &[&str] = &[
    "odot",
    "ast",
    "star",
    "dagger",
    "ddagger",
    "circledast",
    "bullet",
    "sharp",
    "flat",
    "boxplus",
    "boxminus",
    "oplus",
    "ominus",
    "otimes",
    "circledcirc",
    "diamond",
    "natural",
    "perp",
    "*",
    "+",
];

/// `name` as a postfix operator when it is one.
pub fn postfix_operator(name: &str) -> Option<&'static str> {
    POSTFIX_OPERATORS.iter().copied().find(|f| *f == name)
}

/// LaTeX of a relation.
pub fn relation_latex(rel: Rel) -> String {
    match rel {
        Rel::Eq => "=".into(),
        Rel::Lt => "<".into(),
        Rel::Gt => ">".into(),
        Rel::Colon => ":".into(),
        other => format!("\\{}", name_of(RELATION_COMMANDS, other)),
    }
}

/// LaTeX of an explicit product operator (a space for the implicit one).
pub fn mulop_latex(op: MulOp) -> String {
    match op {
        MulOp::Implicit => " ".into(),
        MulOp::Star => "*".into(),
        MulOp::Slash => "/".into(),
        other => format!("\\{}", name_of(MULOP_COMMANDS, other)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_relation_and_operator_is_written_back_as_one_of_its_names() {
        for (name, rel) in RELATION_COMMANDS {
            let back = relation_latex(*rel);
            assert_eq!(lookup(RELATION_COMMANDS, &back[1..]), Some(*rel), "{name}");
        }
        for (name, op) in MULOP_COMMANDS {
            let back = mulop_latex(*op);
            let parsed = if back == "*" {
                Some(MulOp::Star)
            } else {
                lookup(MULOP_COMMANDS, &back[1..])
            };
            assert_eq!(parsed, Some(*op), "{name}");
        }
    }
}
