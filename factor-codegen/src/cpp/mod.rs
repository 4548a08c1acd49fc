//! C++ emission: the kernels of a crate's specs as a header-only C++17
//! library, from the same traces, programs and schedules as the Rust
//! emitter ([`crate::emit`]); only the printing differs. Written beside the
//! Rust crate, in its `cpp/` directory ([`CppLibrary`]):
//!
//! - `<namespace>/<factor>.h`: the factor's kernel in its own chart, as a
//!   function template over plain arrays (`float`, `double`), and with
//!   Ceres ([`KernelSpec::with_ceres`]) its ambient kernel
//!   ([`crate::ambient`]); no dependency but the standard library;
//! - `<namespace>/charts/<chart>.h`: each variable type's own chart on its
//!   side ([`crate::chart`]), for the factors generated for Ceres;
//! - `<namespace>/ceres/<factor>.h` and `<namespace>/ceres/<chart>.h`: the
//!   factor's `ceres::SizedCostFunction` and each chart's `ceres::Manifold`
//!   (a Euclidean chart has none);
//! - `<namespace>/kernels.h` and `<namespace>/ceres.h`: every header of
//!   each kind, included.
//!
//! The namespace is the Rust crate's package name with `-` as `_`
//! (`factor_generated`). Output is deterministic, like the Rust crate's.

mod body;
mod ceres;
mod chart;
mod factor;
mod function;

use std::collections::BTreeMap;
use std::io;
use std::path::{Path, PathBuf};

use crate::chart::ChartTrace;
use crate::error::CodegenError;
use crate::kernel::SymbolicKernel;
use crate::lower::{LoweredKernel, lower};
use crate::spec::{KernelSpec, Provenance};
use crate::tree;

pub use ceres::{camel_case, cost_class, manifold_class};

/// A traced kernel and its program.
pub struct Lowered {
    /// The trace.
    pub kernel: SymbolicKernel,
    /// Its residual and blocks lowered into one program.
    pub lowered: LoweredKernel,
}

impl Lowered {
    /// Lowers `kernel`.
    pub fn of(kernel: SymbolicKernel) -> Lowered {
        let blocks: Vec<Vec<_>> = kernel.blocks.iter().map(|b| b.entries.clone()).collect();
        let lowered = lower(&kernel.graph, &kernel.residual, &blocks);
        Lowered { kernel, lowered }
    }
}

/// `// line` for each line (`//` for an empty one), then a blank line.
fn comment(lines: &[String]) -> String {
    let mut out = String::new();
    for line in lines {
        if line.is_empty() {
            out.push_str("//\n");
        } else {
            out.push_str("// ");
            out.push_str(line);
            out.push('\n');
        }
    }
    out.push('\n');
    out
}

/// The include guard of `<namespace>/<file>.h`.
fn guard(namespace: &str, file: &str) -> String {
    format!("{namespace}_{file}_h")
        .to_ascii_uppercase()
        .replace('/', "_")
}

fn guard_open(namespace: &str, file: &str) -> String {
    let guard = guard(namespace, file);
    format!("#ifndef {guard}\n#define {guard}\n\n")
}

fn guard_close(namespace: &str, file: &str) -> String {
    format!("#endif  // {}\n", guard(namespace, file))
}

/// C++17's keywords and alternative tokens: no field may be named so.
const KEYWORDS: &[&str] = &[
    "alignas",
    "alignof",
    "and",
    "and_eq",
    "asm",
    "auto",
    "bitand",
    "bitor",
    "bool",
    "break",
    "case",
    "catch",
    "char",
    "char16_t",
    "char32_t",
    "class",
    "compl",
    "const",
    "const_cast",
    "constexpr",
    "continue",
    "decltype",
    "default",
    "delete",
    "do",
    "double",
    "dynamic_cast",
    "else",
    "enum",
    "explicit",
    "export",
    "extern",
    "false",
    "float",
    "for",
    "friend",
    "goto",
    "if",
    "inline",
    "int",
    "long",
    "mutable",
    "namespace",
    "new",
    "noexcept",
    "not",
    "not_eq",
    "nullptr",
    "operator",
    "or",
    "or_eq",
    "private",
    "protected",
    "public",
    "register",
    "reinterpret_cast",
    "return",
    "short",
    "signed",
    "sizeof",
    "static",
    "static_assert",
    "static_cast",
    "struct",
    "switch",
    "template",
    "this",
    "thread_local",
    "throw",
    "true",
    "try",
    "typedef",
    "typeid",
    "typename",
    "union",
    "unsigned",
    "using",
    "virtual",
    "void",
    "volatile",
    "wchar_t",
    "while",
    "xor",
    "xor_eq",
];

/// Names the emitted code uses for itself where a field's name is in scope
/// too: the scalar type, the kernels' output, loop counters, the math
/// functions (called unqualified), the cost functions' members (a field
/// `f` is the member `f_`).
const RESERVED: &[&str] = &[
    "T",
    "residual",
    "k",
    "std",
    "sqrt",
    "sin",
    "cos",
    "atan2",
    "exp",
    "log",
    "acos",
    "asin",
    "atan",
    "whitening",
    "whitened",
];

/// Rejects fields whose names the C++ cannot take: keywords, the emitted
/// code's own names, a local `v<n>`, a Jacobian's `d_<variable>`.
fn check_names(kernel: &SymbolicKernel) -> Result<(), CodegenError> {
    let jacobians: Vec<String> = kernel
        .blocks
        .iter()
        .map(|b| format!("d_{}", b.variable.name))
        .collect();
    for field in &kernel.fields {
        let name = field.name;
        let local = name.len() > 1
            && name.starts_with('v')
            && name[1..].bytes().all(|b| b.is_ascii_digit());
        let what = if KEYWORDS.contains(&name) {
            Some("it is a C++ keyword")
        } else if RESERVED.contains(&name) || local || jacobians.iter().any(|j| j == name) {
            Some("the emitted code uses that name itself")
        } else if name.starts_with('_') || name.contains("__") {
            Some("C++ reserves names with a leading or a double underscore")
        } else {
            None
        };
        if let Some(what) = what {
            return Err(CodegenError::CppName {
                kernel: kernel.name,
                field: name,
                what,
            });
        }
    }
    Ok(())
}

/// The C++ library of a crate of kernels: its files under `cpp/`, by path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CppLibrary {
    /// The namespace, and the directory under `cpp/` the headers are in.
    pub namespace: String,
    /// Every file, `(path under cpp/, contents)`, sorted by path.
    pub files: Vec<(String, String)>,
}

/// The namespace of the crate named `package`: `factor-generated` →
/// `factor_generated`.
pub fn namespace_of(package: &str) -> String {
    package.replace('-', "_")
}

impl CppLibrary {
    /// The library of `specs` for the crate of package `package`, whose
    /// generator is `provenance`'s.
    ///
    /// # Errors
    ///
    /// [`CodegenError::CppName`] for a field the C++ cannot name,
    /// [`CodegenError::NoLocal`] for a factor generated for Ceres with a
    /// variable whose type has no inverse retraction,
    /// [`CodegenError::NotForCeres`] for one without variables,
    /// [`CodegenError::ChartCollision`] for two different charts of one
    /// name, [`CodegenError::Empty`] without specs.
    pub fn generate(
        package: &str,
        provenance: &Provenance,
        specs: &[KernelSpec],
    ) -> Result<CppLibrary, CodegenError> {
        let kernels: Vec<SymbolicKernel> = specs.iter().map(|spec| (spec.trace)()).collect();
        Self::from_kernels(package, provenance, specs, &kernels)
    }

    /// [`CppLibrary::generate`] from the specs' kernels traced already
    /// (`kernels[k]` is `(specs[k].trace)()`, as the Rust crate's modules
    /// were generated from: one trace serves both languages).
    ///
    /// # Errors
    ///
    /// As [`CppLibrary::generate`].
    ///
    /// # Panics
    ///
    /// If `kernels` and `specs` differ in length.
    pub fn from_kernels(
        package: &str,
        provenance: &Provenance,
        specs: &[KernelSpec],
        kernels: &[SymbolicKernel],
    ) -> Result<CppLibrary, CodegenError> {
        assert_eq!(kernels.len(), specs.len(), "one traced kernel per spec");
        if specs.is_empty() {
            return Err(CodegenError::Empty);
        }
        for reserved in ["kernels", "ceres"] {
            if specs.iter().any(|s| s.name == reserved) {
                return Err(CodegenError::ReservedName(reserved));
            }
        }
        let namespace = namespace_of(package);
        let mut files: BTreeMap<String, String> = BTreeMap::new();
        let mut charts: BTreeMap<String, String> = BTreeMap::new();
        let mut manifolds: BTreeMap<String, String> = BTreeMap::new();
        let mut costs = Vec::new();
        for (spec, kernel) in specs.iter().zip(kernels) {
            let own = Lowered::of(kernel.clone());
            check_names(&own.kernel)?;
            let ceres = if spec.ceres {
                let ambient = Lowered::of((spec.ambient)());
                let traces = (spec.charts)()?;
                if traces.is_empty() {
                    return Err(CodegenError::NotForCeres {
                        kernel: spec.name,
                        reason: "a factor without variables has no Ceres cost function (Ceres \
                                 needs a parameter block)"
                            .to_owned(),
                    });
                }
                Some((ambient, traces))
            } else {
                None
            };
            let header = factor::source(
                &namespace,
                spec,
                provenance,
                &own,
                ceres.as_ref().map(|(ambient, _)| ambient),
            );
            files.insert(format!("{namespace}/{}.h", spec.name), header);
            if let Some((ambient, traces)) = ceres {
                for trace in traces.iter().filter(|t| !t.euclidean) {
                    insert_chart(
                        &mut charts,
                        trace,
                        chart::source(&namespace, trace, provenance),
                    )?;
                    let manifold = ceres::manifold_source(&namespace, trace, provenance);
                    insert_chart(&mut manifolds, trace, manifold)?;
                }
                let cost =
                    ceres::cost_source(&namespace, spec, provenance, &ambient.kernel, &traces);
                costs.push(spec.name);
                files.insert(format!("{namespace}/ceres/{}.h", spec.name), cost);
            }
        }
        for (name, source) in &charts {
            files.insert(format!("{namespace}/charts/{name}.h"), source.clone());
        }
        for (name, source) in &manifolds {
            let path = format!("{namespace}/ceres/{name}.h");
            if files.contains_key(&path) {
                return Err(CodegenError::ChartCollision(name.clone()));
            }
            files.insert(path, source.clone());
        }
        let kernels: Vec<String> = specs
            .iter()
            .map(|s| format!("{}.h", s.name))
            .chain(charts.keys().map(|c| format!("charts/{c}.h")))
            .collect();
        files.insert(
            format!("{namespace}/kernels.h"),
            umbrella(
                &namespace,
                "kernels",
                provenance,
                &kernels,
                "every kernel and chart",
            ),
        );
        if !costs.is_empty() {
            let mut headers: Vec<String> = costs.iter().map(|c| format!("ceres/{c}.h")).collect();
            headers.extend(manifolds.keys().map(|m| format!("ceres/{m}.h")));
            files.insert(
                format!("{namespace}/ceres.h"),
                umbrella(
                    &namespace,
                    "ceres",
                    provenance,
                    &headers,
                    "every Ceres cost function and manifold (needs Ceres 2.1 or newer)",
                ),
            );
        }
        Ok(CppLibrary {
            namespace,
            files: files.into_iter().collect(),
        })
    }

    /// Writes the library under `dir/cpp` (created if missing): files whose
    /// contents differ are rewritten, `.h` files that are not generated are
    /// removed. Nothing outside `cpp/` is touched.
    ///
    /// # Errors
    ///
    /// Any I/O error.
    pub fn write(&self, dir: &Path) -> io::Result<()> {
        tree::write(&dir.join("cpp"), &self.files, "h", true)
    }

    /// Compares `dir/cpp` with what [`CppLibrary::write`] would write: `Ok`
    /// when identical, else every differing, missing or extra `.h` file,
    /// sorted.
    pub fn check(&self, dir: &Path) -> Result<(), Vec<PathBuf>> {
        tree::check(&dir.join("cpp"), &self.files, "h", true)
    }
}

/// Adds `trace`'s file `source` under its name, or fails when a different
/// chart of that name was added before.
fn insert_chart(
    files: &mut BTreeMap<String, String>,
    trace: &ChartTrace,
    source: String,
) -> Result<(), CodegenError> {
    match files.get(&trace.name) {
        Some(existing) if *existing != source => {
            Err(CodegenError::ChartCollision(trace.name.clone()))
        }
        Some(_) => Ok(()),
        None => {
            files.insert(trace.name.clone(), source);
            Ok(())
        }
    }
}

/// `<namespace>/<file>.h` including `headers` (paths under the namespace).
fn umbrella(
    namespace: &str,
    file: &str,
    provenance: &Provenance,
    headers: &[String],
    what: &str,
) -> String {
    let mut out = comment(&[
        format!("All of `{namespace}`'s headers of one kind: {what}."),
        String::new(),
        format!(
            "Generated by `{} --lang cpp`; do not edit.",
            provenance.generate
        ),
    ]);
    out.push_str(&guard_open(namespace, file));
    for header in headers {
        out.push_str(&format!("#include \"{namespace}/{header}\"\n"));
    }
    out.push('\n');
    out.push_str(&guard_close(namespace, file));
    out
}
