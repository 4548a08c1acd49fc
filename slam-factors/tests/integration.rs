//! The crate's integration tests, one binary (see `Cargo.toml`): each file
//! of `tests/` is a module here.

mod accuracy_envelope;
mod analytic;
mod degenerate;
mod estimation;
mod g2o_documents;
mod g2o_graphs;
mod g2o_slam3d;
mod generated;
mod host_charts;
mod jacobians;
mod line_observation;
mod numeric_accuracy;
