//! `eval`: a request read from a file or standard input, evaluated for a
//! factor of a registry ([`slamjac_registry::eval`], re-exported here), and
//! the output JSON printed.

pub use slamjac_registry::eval::*;

use slamjac_problem::source::read_source;
use slamjac_problem::strict_json::parse_json;

use crate::error::CliError;
use crate::method::Method;
use crate::pretty;
use crate::registry::Registry;

/// Reads the request from `source` (a path, or `-` for standard input),
/// evaluates it for a factor of `registry` and returns the pretty-printed
/// output JSON.
pub fn run(registry: &Registry, source: &str, method: Method) -> Result<String, CliError> {
    let text = read_source(source)?;
    let request = parse_json(&text, source)?;
    let evaluation = evaluate(registry, request.root(), method)?;
    Ok(pretty::to_string(&evaluation.to_json()))
}
