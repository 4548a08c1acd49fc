//! A kernel crate's generated C++ (`generate --lang cpp`) against the Rust,
//! in tests: the C++ compiler of the machine, a driver that calls the
//! emitted function templates in `double` and in `float` on configurations
//! read from a file ([`Driver`], compiled in the background by
//! [`Driver::spawn`]), and the comparisons: [`expected`] computes the Rust
//! side (while the compiler runs), [`Expected::check`] runs the C++ and
//! compares.
//!
//! The driver is compiled with `-std=c++17 -Wall -Wextra -Werror -O1` and
//! instantiates every function it calls in both scalars, so a warning in
//! any emitted body fails the build. Each configuration is the call's input
//! arrays concatenated; its outputs are the output arrays concatenated,
//! first in `double`, then in `float` (widened to `double`).

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

use factor_core::Factor;
use factor_core::manifold::ChartMap;

use crate::generated::input_scale;
use num_dual::DualSVec64;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// The C++ compiler: `$CXX`, else `g++`, when it runs (`--version`).
pub fn compiler() -> Option<String> {
    let compiler = std::env::var("CXX").unwrap_or_else(|_| "g++".to_owned());
    let runs = Command::new(&compiler)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    runs.then_some(compiler)
}

/// One emitted function the driver calls: its name, its input arrays'
/// lengths and its output arrays' lengths (the unconditional one, then the
/// optional ones, all requested).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Call {
    /// The function, without its namespace.
    pub function: String,
    /// Each input array's length.
    pub inputs: Vec<usize>,
    /// Each output array's length.
    pub outputs: Vec<usize>,
}

/// `point[0]`-style offsets: the start of each of `sizes` in their
/// concatenation, and the total.
fn offsets(sizes: &[usize]) -> (Vec<usize>, usize) {
    let mut at = 0;
    let starts = sizes
        .iter()
        .map(|n| {
            at += n;
            at - n
        })
        .collect();
    (starts, at)
}

/// The driver's source: `driver CALL INPUT OUTPUT` runs call `CALL` on
/// every configuration of the file `INPUT` (a count, then the
/// configurations, little-endian) and writes the outputs to `OUTPUT`.
fn driver_source(header: &str, namespace: &str, calls: &[Call]) -> String {
    let mut cases = String::new();
    for (k, call) in calls.iter().enumerate() {
        let (inputs, input_len) = offsets(&call.inputs);
        let (outputs, output_len) = offsets(&call.outputs);
        let arguments = |ty: &str| {
            let mut arguments: Vec<String> = inputs
                .iter()
                .map(|at| format!("in_{ty}.data() + {at}"))
                .collect();
            arguments.extend(outputs.iter().map(|at| format!("out_{ty}.data() + {at}")));
            arguments.join(", ")
        };
        cases.push_str(&format!(
            "    case {k}:\n      return run({input_len}, {output_len}, input, output, \
             [](const std::vector<double>& in_double, std::vector<double>& out_double, \
             const std::vector<float>& in_float, std::vector<float>& out_float) {{\n        \
             {namespace}::{f}<double>({d});\n        {namespace}::{f}<float>({s});\n      }});\n",
            f = call.function,
            d = arguments("double"),
            s = arguments("float"),
        ));
    }
    format!(
        r#"// A test driver of `{header}`, written by factor_testing::cpp.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "{header}"

namespace {{

template <typename F>
int run(std::size_t inputs, std::size_t outputs, const char* input, const char* output, F call) {{
  std::FILE* in = std::fopen(input, "rb");
  std::FILE* out = std::fopen(output, "wb");
  if (in == nullptr || out == nullptr) {{
    return 2;
  }}
  std::uint64_t count = 0;
  if (std::fread(&count, sizeof count, 1, in) != 1) {{
    return 2;
  }}
  std::vector<double> in_double(inputs), out_double(outputs), widened(outputs);
  std::vector<float> in_float(inputs), out_float(outputs);
  for (std::uint64_t c = 0; c < count; ++c) {{
    if (std::fread(in_double.data(), sizeof(double), inputs, in) != inputs) {{
      return 2;
    }}
    for (std::size_t k = 0; k < inputs; ++k) {{
      in_float[k] = static_cast<float>(in_double[k]);
    }}
    call(in_double, out_double, in_float, out_float);
    for (std::size_t k = 0; k < outputs; ++k) {{
      widened[k] = static_cast<double>(out_float[k]);
    }}
    std::fwrite(out_double.data(), sizeof(double), outputs, out);
    std::fwrite(widened.data(), sizeof(double), outputs, out);
  }}
  return std::fclose(in) == 0 && std::fclose(out) == 0 ? 0 : 2;
}}

}}  // namespace

int main(int argc, char** argv) {{
  if (argc != 4) {{
    return 2;
  }}
  const char* input = argv[2];
  const char* output = argv[3];
  switch (std::atoi(argv[1])) {{
{cases}    default:
      return 2;
  }}
}}
"#
    )
}

/// A compiled driver.
#[derive(Debug)]
pub struct Driver {
    binary: PathBuf,
    dir: PathBuf,
    calls: Vec<Call>,
}

impl Driver {
    /// Writes the driver of `calls` (functions of `namespace` declared by
    /// `header`, found under `include`) into `dir` and starts compiling it
    /// with `compiler` in the background, so that the caller computes its
    /// references ([`expected`]) meanwhile; [`PendingDriver::wait`] ends it.
    ///
    /// # Errors
    ///
    /// When the source cannot be written or the compiler not started.
    pub fn spawn(
        compiler: &str,
        include: &Path,
        header: &str,
        namespace: &str,
        calls: Vec<Call>,
        dir: &Path,
    ) -> Result<PendingDriver, String> {
        std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
        let source = dir.join("driver.cc");
        std::fs::write(&source, driver_source(header, namespace, &calls))
            .map_err(|e| e.to_string())?;
        let binary = dir.join("driver");
        let child = Command::new(compiler)
            .args(["-std=c++17", "-Wall", "-Wextra", "-Werror", "-O1", "-I"])
            .arg(include)
            .arg(&source)
            .arg("-o")
            .arg(&binary)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| e.to_string())?;
        Ok(PendingDriver {
            child,
            driver: Driver {
                binary,
                dir: dir.to_path_buf(),
                calls,
            },
        })
    }

    /// The index of the call of `function`, if the driver has it.
    pub fn find(&self, function: &str) -> Option<usize> {
        self.calls.iter().position(|c| c.function == function)
    }

    /// The index of the call of `function`.
    ///
    /// # Panics
    ///
    /// When the driver has no such call.
    pub fn index(&self, function: &str) -> usize {
        self.find(function)
            .unwrap_or_else(|| panic!("the driver does not call `{function}`"))
    }

    /// Runs call `index` on `configurations` (each the call's inputs
    /// concatenated): per configuration, its outputs in `double` and in
    /// `float` (widened).
    ///
    /// # Panics
    ///
    /// When a configuration has the wrong length or the driver fails.
    pub fn run(&self, index: usize, configurations: &[Vec<f64>]) -> Vec<(Vec<f64>, Vec<f64>)> {
        let call = &self.calls[index];
        let (input_len, output_len) = (offsets(&call.inputs).1, offsets(&call.outputs).1);
        let (input, output) = (
            self.dir.join(format!("in_{index}")),
            self.dir.join(format!("out_{index}")),
        );
        let mut bytes = (configurations.len() as u64).to_le_bytes().to_vec();
        for configuration in configurations {
            assert_eq!(
                configuration.len(),
                input_len,
                "`{}`'s inputs",
                call.function
            );
            bytes.extend(configuration.iter().flat_map(|x| x.to_le_bytes()));
        }
        std::fs::File::create(&input)
            .and_then(|mut f| f.write_all(&bytes))
            .expect("the driver's input is written");
        let status = Command::new(&self.binary)
            .arg(index.to_string())
            .arg(&input)
            .arg(&output)
            .status()
            .expect("the driver runs");
        assert!(status.success(), "the driver failed on `{}`", call.function);
        let mut bytes = Vec::new();
        std::fs::File::open(&output)
            .and_then(|mut f| f.read_to_end(&mut bytes))
            .expect("the driver's output is read");
        let values: Vec<f64> = bytes
            .chunks_exact(8)
            .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
            .collect();
        assert_eq!(values.len(), configurations.len() * 2 * output_len);
        values
            .chunks_exact(2 * output_len)
            .map(|c| (c[..output_len].to_vec(), c[output_len..].to_vec()))
            .collect()
    }
}

/// A driver being compiled ([`Driver::spawn`]).
#[derive(Debug)]
pub struct PendingDriver {
    child: Child,
    driver: Driver,
}

impl PendingDriver {
    /// Waits for the compiler: the driver, or the compiler's diagnostics.
    ///
    /// # Errors
    ///
    /// The compiler's diagnostics (a warning is an error).
    pub fn wait(self) -> Result<Driver, String> {
        let output = self.child.wait_with_output().map_err(|e| e.to_string())?;
        if output.status.success() {
            Ok(self.driver)
        } else {
            Err(String::from_utf8_lossy(&output.stderr).into_owned())
        }
    }
}

/// `max |a − b| / max |b|` (`b`'s largest magnitude floored at the smallest
/// normal number, so that equal zeros give 0).
pub fn relative_error(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(f64::MIN_POSITIVE, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// The calls of factor `F`'s C++ in the library directory `library`
/// (`cpp/<namespace>`): its kernel, its ambient kernel, and the four maps
/// of each of its variables' charts that the library has
/// (`charts/<chart>.h`: a Euclidean chart has none), once each.
pub fn calls<F: Factor>(library: &Path) -> Vec<Call> {
    let fields = F::fields();
    let inputs: Vec<usize> = fields.iter().map(|f| f.scalars).collect();
    let r = F::RESIDUAL_DIM;
    let variables = F::variables();
    let mut own = vec![r];
    own.extend(variables.iter().map(|v| r * v.tangent_dim));
    let mut ambient = vec![r];
    ambient.extend(
        fields
            .iter()
            .filter(|f| f.variable.is_some())
            .map(|f| r * f.scalars),
    );
    let mut calls = vec![
        Call {
            function: F::NAME.to_owned(),
            inputs: inputs.clone(),
            outputs: own,
        },
        Call {
            function: format!("{}_ambient", F::NAME),
            inputs,
            outputs: ambient,
        },
    ];
    for (info, (n, d)) in variables.iter().zip(variable_sizes::<F>()) {
        let name = info.chart_name();
        let retract = format!("{name}_retract");
        let emitted = library.join("charts").join(format!("{name}.h")).is_file();
        if !emitted || calls.iter().any(|c| c.function == retract) {
            continue;
        }
        calls.extend([
            Call {
                function: retract,
                inputs: vec![n, d],
                outputs: vec![n],
            },
            Call {
                function: format!("{name}_retract_jacobian"),
                inputs: vec![n],
                outputs: vec![n * d],
            },
            Call {
                function: format!("{name}_local"),
                inputs: vec![n, n],
                outputs: vec![d],
            },
            Call {
                function: format!("{name}_local_jacobian"),
                inputs: vec![n],
                outputs: vec![d * n],
            },
        ]);
    }
    calls
}

/// Each variable's stored scalars and tangent dimension, in order.
fn variable_sizes<F: Factor>() -> Vec<(usize, usize)> {
    let variables = F::variables();
    F::fields()
        .iter()
        .filter_map(|f| f.variable.map(|v| (f.scalars, variables[v].tangent_dim)))
        .collect()
}

/// The worst relative errors ([`relative_error`], per output array) that
/// [`Expected::check`] found, each against its Rust reference.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CppCheck {
    /// The kernel in `double` against the Rust kernel
    /// (`Factor::linearize_stored_into`): each block's [`relative_error`],
    /// the residual's relative to the larger of its size and the factor's
    /// input scale ([`crate::generated::input_scale`]: residuals are
    /// differences of inputs, rounded at their scale, and may be zero).
    pub kernel: f64,
    /// The kernel in `float` against the Rust `f64` kernel at the inputs
    /// rounded to `float` (which decide its branches), measured alike.
    pub kernel_float: f64,
    /// The ambient kernel against dual numbers through the residual with
    /// every variable's stored scalars perturbed, measured as the kernel.
    pub ambient: f64,
    /// The charts' retraction against `Factor::chart_over::<f64>`.
    pub retract: f64,
    /// Its Jacobian against dual numbers through the first-order retraction.
    pub retract_jacobian: f64,
    /// The local coordinates against `Factor::chart_over::<f64>`.
    pub local: f64,
    /// Their Jacobian against dual numbers through `local` at `y = x`.
    pub local_jacobian: f64,
    /// `local_jacobian · retract_jacobian − I`, largest entry.
    pub inverse: f64,
    /// The configurations the kernel was compared at.
    pub configurations: usize,
}

impl CppCheck {
    /// The worst of every comparison of the `double` C++.
    pub fn worst_double(&self) -> f64 {
        [
            self.kernel,
            self.ambient,
            self.retract,
            self.retract_jacobian,
            self.local,
            self.local_jacobian,
            self.inverse,
        ]
        .into_iter()
        .fold(0.0, f64::max)
    }
}

/// Splits `values` into arrays of `sizes`.
fn split<'a>(values: &'a [f64], sizes: &[usize]) -> Vec<&'a [f64]> {
    let mut rest = values;
    sizes
        .iter()
        .map(|n| {
            let (head, tail) = rest.split_at(*n);
            rest = tail;
            head
        })
        .collect()
}

/// The worst [`relative_error`] over the arrays of `sizes` of `a` against
/// `b`.
fn worst_by_array(a: &[f64], b: &[f64], sizes: &[usize]) -> f64 {
    split(a, sizes)
        .into_iter()
        .zip(split(b, sizes))
        .fold(0.0, |m, (a, b)| m.max(relative_error(a, b)))
}

/// A kernel's outputs `a` (residual, then blocks of `sizes`) against `b`:
/// the worst of the residual's error relative to the larger of its size
/// and `scale` (the factor's [`input_scale`]: a residual is a difference of
/// inputs, rounded at their scale, and may be exactly zero) and each
/// block's [`relative_error`].
fn kernel_error(a: &[f64], b: &[f64], sizes: &[usize], scale: f64) -> f64 {
    let r = sizes[0];
    let residual_scale = b[..r].iter().fold(scale, |m, x| m.max(x.abs()));
    let residual = a[..r]
        .iter()
        .zip(&b[..r])
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
        / residual_scale;
    residual.max(worst_by_array(&a[r..], &b[r..], &sizes[1..]))
}

/// `∂ out/∂ argument[k]` for every `k`, by dual numbers: `f` maps the
/// argument (lifted) to `len` outputs; row-major `len × argument.len()`.
fn dual_jacobian(
    argument: &[f64],
    len: usize,
    f: impl Fn(&[DualSVec64<1>], &mut [DualSVec64<1>]),
) -> Vec<f64> {
    let mut jacobian = vec![0.0; len * argument.len()];
    for k in 0..argument.len() {
        let lifted: Vec<DualSVec64<1>> = argument
            .iter()
            .enumerate()
            .map(|(i, x)| {
                let d = DualSVec64::<1>::from_re(*x);
                if i == k { d.derivative(0) } else { d }
            })
            .collect();
        let mut out = vec![DualSVec64::<1>::from_re(0.0); len];
        f(&lifted, &mut out);
        for (row, value) in out.iter().enumerate() {
            jacobian[row * argument.len() + k] = value
                .eps
                .unwrap_generic(nalgebra::Const::<1>, nalgebra::Const::<1>)[0];
        }
    }
    jacobian
}

/// One chart's configurations and the Rust values the C++ must give there.
#[derive(Debug, Clone)]
struct ChartExpected {
    /// The chart's name (its functions' prefix).
    name: String,
    /// Stored scalars and tangent dimension.
    n: usize,
    d: usize,
    /// `[x, δ]` per configuration, and `retract(x, δ)`.
    steps: Vec<Vec<f64>>,
    retract: Vec<Vec<f64>>,
    /// `[x, y]` per configuration, and `local(x, y)`.
    pairs: Vec<Vec<f64>>,
    local: Vec<Vec<f64>>,
    /// The two Jacobians at `x`, by dual numbers.
    retract_jacobian: Vec<Vec<f64>>,
    local_jacobian: Vec<Vec<f64>>,
}

/// The Rust side of [`Expected::check`]: a factor's configurations and what
/// its C++ must give at them, computed before any C++ runs (so that a test
/// can compute it while the compiler builds the driver, [`Driver::spawn`]).
#[derive(Debug, Clone)]
pub struct Expected {
    name: &'static str,
    /// The output arrays' lengths of the kernel and of the ambient kernel.
    own_sizes: Vec<usize>,
    ambient_sizes: Vec<usize>,
    /// Per configuration: its stored scalars, its input scale, the Rust
    /// kernel's outputs there and at the inputs rounded to `float`.
    stored: Vec<Vec<f64>>,
    scales: Vec<f64>,
    kernel: Vec<Vec<f64>>,
    rounded: Vec<Vec<f64>>,
    /// The ambient kernel's reference at the first configurations.
    ambient: Vec<Vec<f64>>,
    /// Every variable's chart (the driver calls those the library has).
    charts: Vec<ChartExpected>,
}

/// The Rust side of the comparison of factor `F`'s C++ at `factors`: the
/// kernel at every one (through `Factor::linearize_stored_into`, after the
/// factor's validation), the ambient kernel and the charts at the first
/// `few` (by dual numbers, slower in a debug build). Each chart is
/// exercised at the variable's value with a seeded tangent step of up to
/// 0.5 per entry and a second point retracted from it by another.
///
/// # Panics
///
/// When a factor cannot be linearized (give valid configurations).
pub fn expected<F: Factor>(factors: &[F], few: usize) -> Expected {
    let r = F::RESIDUAL_DIM;
    let variables = F::variables();
    let fields = F::fields();
    let mut own_sizes = vec![r];
    own_sizes.extend(variables.iter().map(|v| r * v.tangent_dim));
    let mut ambient_sizes = vec![r];
    ambient_sizes.extend(
        fields
            .iter()
            .filter(|f| f.variable.is_some())
            .map(|f| r * f.scalars),
    );
    let rust = |stored: &[f64]| {
        let mut outputs = vec![0.0; own_sizes.iter().sum()];
        let (residual, mut rest) = outputs.split_at_mut(r);
        let mut blocks: Vec<Option<&mut [f64]>> = variables
            .iter()
            .map(|v| {
                let (head, tail) = std::mem::take(&mut rest).split_at_mut(r * v.tangent_dim);
                rest = tail;
                Some(head)
            })
            .collect();
        F::linearize_stored_into(stored, residual, &mut blocks)
            .unwrap_or_else(|e| panic!("{}: {e}", F::NAME));
        outputs
    };
    let stored: Vec<Vec<f64>> = factors.iter().map(|f| f.to_scalars()).collect();
    // `float` sees the inputs rounded to it, branch decisions included (a
    // direction's `z = 1e-300` is 0 there): its reference is the `f64`
    // kernel at those rounded inputs.
    let rounded: Vec<Vec<f64>> = stored
        .iter()
        .map(|s| rust(&s.iter().map(|x| f64::from(*x as f32)).collect::<Vec<_>>()))
        .collect();
    let few = &stored[..few.min(stored.len())];
    let ambient = few
        .iter()
        .map(|s| {
            let full = dual_jacobian(s, r, |x, out| {
                out.copy_from_slice(&F::residual_over(x));
            });
            let mut reference = F::residual_over(s);
            let mut offset = 0;
            for field in &fields {
                if field.variable.is_some() {
                    for row in 0..r {
                        let start = row * s.len() + offset;
                        reference.extend_from_slice(&full[start..start + field.scalars]);
                    }
                }
                offset += field.scalars;
            }
            reference
        })
        .collect();
    Expected {
        name: F::NAME,
        kernel: stored.iter().map(|s| rust(s)).collect(),
        scales: factors.iter().map(input_scale).collect(),
        charts: expected_charts::<F>(few),
        rounded,
        ambient,
        own_sizes,
        ambient_sizes,
        stored,
    }
}

/// Every variable's [`ChartExpected`] at the configurations `stored`.
fn expected_charts<F: Factor>(stored: &[Vec<f64>]) -> Vec<ChartExpected> {
    let fields = F::fields();
    let variables = F::variables();
    let mut rng = StdRng::seed_from_u64(29);
    let mut charts = Vec::new();
    let mut offset = 0;
    for field in &fields {
        let range = offset..offset + field.scalars;
        offset += field.scalars;
        let Some(variable) = field.variable else {
            continue;
        };
        let name = variables[variable].chart_name();
        let (n, d) = (field.scalars, variables[variable].tangent_dim);
        let map = |map: ChartMap, x: &[f64], argument: &[f64], len: usize| {
            let mut out = vec![0.0; len];
            // A type without `local` has no C++ chart: its references are
            // never read.
            let _ = F::chart_over::<f64>(variable, map, x, argument, &mut out);
            out
        };
        let mut chart = ChartExpected {
            name,
            n,
            d,
            steps: Vec::new(),
            retract: Vec::new(),
            pairs: Vec::new(),
            local: Vec::new(),
            retract_jacobian: Vec::new(),
            local_jacobian: Vec::new(),
        };
        for s in stored {
            let x = s[range.clone()].to_vec();
            let step = |rng: &mut StdRng| -> Vec<f64> {
                (0..d).map(|_| rng.random_range(-0.5..0.5)).collect()
            };
            let (delta, other) = (step(&mut rng), step(&mut rng));
            let y = map(ChartMap::Retract, &x, &other, n);
            chart.retract.push(map(ChartMap::Retract, &x, &delta, n));
            chart.local.push(map(ChartMap::Local, &x, &y, d));
            let lifted = |x: &[f64]| -> Vec<DualSVec64<1>> {
                x.iter().map(|v| DualSVec64::<1>::from_re(*v)).collect()
            };
            chart
                .retract_jacobian
                .push(dual_jacobian(&vec![0.0; d], n, |delta, out| {
                    let _ = F::chart_over(
                        variable,
                        ChartMap::RetractFirstOrder,
                        &lifted(&x),
                        delta,
                        out,
                    );
                }));
            chart.local_jacobian.push(dual_jacobian(&x, d, |y, out| {
                let _ = F::chart_over(variable, ChartMap::Local, &lifted(&x), y, out);
            }));
            chart.steps.push([x.clone(), delta].concat());
            chart.pairs.push([x, y].concat());
        }
        charts.push(chart);
    }
    charts
}

impl Expected {
    /// The factor's name.
    pub fn name(&self) -> &'static str {
        self.name
    }

    /// The factor's C++ (the calls of [`calls`] in `driver`) against these
    /// references: the worst errors found.
    ///
    /// # Panics
    ///
    /// When the driver fails or lacks the factor's kernels.
    pub fn check(&self, driver: &Driver) -> CppCheck {
        let mut check = CppCheck {
            configurations: self.stored.len(),
            ..CppCheck::default()
        };
        let cpp = driver.run(driver.index(self.name), &self.stored);
        for (k, (double, float)) in cpp.iter().enumerate() {
            let scale = self.scales[k];
            let own = &self.own_sizes;
            check.kernel = check
                .kernel
                .max(kernel_error(double, &self.kernel[k], own, scale));
            check.kernel_float =
                check
                    .kernel_float
                    .max(kernel_error(float, &self.rounded[k], own, scale));
        }
        let few = &self.stored[..self.ambient.len()];
        let cpp = driver.run(driver.index(&format!("{}_ambient", self.name)), few);
        for (k, (double, _)) in cpp.iter().enumerate() {
            let error = kernel_error(
                double,
                &self.ambient[k],
                &self.ambient_sizes,
                self.scales[k],
            );
            check.ambient = check.ambient.max(error);
        }
        for chart in &self.charts {
            let name = &chart.name;
            let Some(retract) = driver.find(&format!("{name}_retract")) else {
                continue; // Euclidean: no C++ of its own
            };
            let (n, d) = (chart.n, chart.d);
            let retract = driver.run(retract, &chart.steps);
            let local = driver.run(driver.index(&format!("{name}_local")), &chart.pairs);
            let points: Vec<Vec<f64>> = chart.pairs.iter().map(|p| p[..n].to_vec()).collect();
            let plus = driver.run(driver.index(&format!("{name}_retract_jacobian")), &points);
            let minus = driver.run(driver.index(&format!("{name}_local_jacobian")), &points);
            for k in 0..points.len() {
                let error = |a: &[f64], b: &[f64]| relative_error(a, b);
                check.retract = check.retract.max(error(&retract[k].0, &chart.retract[k]));
                check.local = check.local.max(error(&local[k].0, &chart.local[k]));
                check.retract_jacobian = check
                    .retract_jacobian
                    .max(error(&plus[k].0, &chart.retract_jacobian[k]));
                check.local_jacobian = check
                    .local_jacobian
                    .max(error(&minus[k].0, &chart.local_jacobian[k]));
                let (pj, mj) = (&plus[k].0, &minus[k].0);
                for i in 0..d {
                    for j in 0..d {
                        let product: f64 = (0..n).map(|a| mj[i * n + a] * pj[a * d + j]).sum();
                        let identity = if i == j { 1.0 } else { 0.0 };
                        check.inverse = check.inverse.max((product - identity).abs());
                    }
                }
            }
        }
        check
    }
}
