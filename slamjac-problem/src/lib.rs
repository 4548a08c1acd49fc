//! `slamjac-problem`, the input layer of the factor toolchain's command
//! line: `eval` requests and problem files read from their source, parsed
//! strictly, read as typed values and decoded into factors, every error one
//! line naming the field path or the source; the ground truth a solution
//! is measured against; and a synthetic room to solve. It depends on no solver.
//!
//! - [`source`]: reading an input file or standard input (16 MiB at most,
//!   UTF-8), or streaming a problem file (1 GiB at most);
//! - [`strict_json`]: JSON text → [`document::Document`], rejecting
//!   duplicate keys and out-of-range numbers at their field path;
//! - [`document`]: the parsed JSON in one arena, read through copied handles;
//! - [`input`]: JSON → typed values, errors naming the field path;
//! - [`field_path`]: how errors show field paths and input text (quoted,
//!   escaped, cut);
//! - [`checks`]: what every reader of a problem file checks before it
//!   builds anything (the top level, the version, each variable and
//!   factor entry, noise models, losses);
//! - [`decode`]: each factor's `variables` and `constants` → the factor;
//! - [`w_first`]: the hint for quaternions written `[w, x, y, z]`;
//! - [`observability`]: the directions a problem's residuals do not
//!   determine (a gauge left free, a rank deficiency), named;
//! - [`truth`]: a g2o line and plane graph's ground truth (`--truth`, or
//!   `STEM_truth.g2o` beside it) and the errors of a solution against it;
//! - [`file_truth`]: a problem file's `truth` object and the errors of a
//!   solution against it (trajectory, lines, planes);
//! - [`align`]: Umeyama's alignment of a trajectory to its truth;
//! - [`synthetic_room`]: a seeded point-line-plane room as a problem file
//!   with its truth (`slamjac synth-plp`);
//! - [`error`]: [`InputError`], the one error of the reading layer.

pub mod align;
pub mod checks;
pub mod decode;
pub mod document;
pub mod error;
pub mod field_path;
pub mod file_truth;
pub mod input;
pub mod observability;
pub mod source;
pub mod strict_json;
pub mod synthetic_room;
pub mod truth;
pub mod w_first;

pub use error::InputError;

/// The version of the problem file format (`slamjac_problem`) this build
/// reads (`slamjac solve`) and writes (`solve --output`, `synth-plp`).
pub const PROBLEM_FILE_VERSION: u64 = 1;
