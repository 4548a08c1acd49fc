//! What the Ceres host benchmark's C++ reads, in plain text (numbers in
//! Rust's shortest round-trip form, which `strtod` reads back exactly):
//!
//! ```text
//! ceres-host-export samples DIR [COUNT]   # DIR/<factor>.txt: seeded configurations
//! ceres-host-export problem FILE.json OUT # a problem file of shipped or user factors
//! ceres-host-export user-problem OUT.json # a problem file of the user crate's factors
//! ```
//!
//! - `samples`: for every factor with a generated Ceres cost function (the
//!   shipped ones of `generated/cpp` and the five of
//!   `examples/user-factor/user-kernels/cpp`), `COUNT` (default 100) seeded
//!   configurations: a line `COUNT SCALARS`, a line of the fields in order
//!   (`constant 4 constant 2 variable 7 variable 3`), then one line per
//!   configuration, the factor's stored scalars in field order.
//! - `problem`: the variables (`name type fixed n` and their stored
//!   scalars, converted from the file's JSON form by the factor that first
//!   uses them), then the factors (`factor k` and the indices of their
//!   variables, `c` and their constants' stored scalars in field order,
//!   `r` and the square root of their information, `r × r` row-major).
//! - `user-problem`: a seeded problem file of all five factors of the
//!   example user crate ([`user_problem`]), for `user-cli solve` and, through
//!   `problem`, for Ceres.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;
use std::process::ExitCode;

use factor_core::lie::{Se3, So3};
use factor_core::{Factor, Layout, Storage};
use factor_testing::samples::Sampler;
use nalgebra::Vector3;
use serde_json::{Map, Value, json};
use slamjac::kernels::shipped;
use slamjac::registry::Registry;
use slamjac_problem::decode::stored_scalars;
use slamjac_problem::document::Document;
use slamjac_problem::input::Object;
use user_factors::sim3::Sim3;
use user_factors::unit_vector::UnitVector3;
use user_factors::{Direction, PointToPlane, RelativePose, RelativeSim3, ScaledRangeBearing};

type Failure = Box<dyn std::error::Error>;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.iter().map(String::as_str).collect::<Vec<_>>().as_slice() {
        ["samples", dir] => samples(Path::new(dir), 100),
        ["samples", dir, count] => count
            .parse()
            .map_err(|_| "COUNT: a number".into())
            .and_then(|n| samples(Path::new(dir), n)),
        ["problem", file, out] => problem(Path::new(file), Path::new(out)),
        ["user-problem", out] => user_problem(Path::new(out)),
        _ => Err("usage: ceres-host-export samples DIR [COUNT] | problem FILE.json OUT | \
                  user-problem OUT.json"
            .into()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// `values` separated by spaces, each in its shortest round-trip form.
fn line(values: &[f64]) -> String {
    let mut out = String::new();
    for (k, v) in values.iter().enumerate() {
        let _ = write!(out, "{}{v:?}", if k == 0 { "" } else { " " });
    }
    out
}

/// `COUNT` configurations of `F` from `sample`, as `samples` writes them.
fn write_samples<F: Factor>(
    dir: &Path,
    count: usize,
    seed: u64,
    mut sample: impl FnMut(&mut Sampler) -> F,
) -> Result<(), Failure> {
    let mut sampler = Sampler::new(seed);
    let fields: Vec<String> = F::fields()
        .iter()
        .map(|f| {
            let kind = if f.variable.is_some() { "variable" } else { "constant" };
            format!("{kind} {}", f.scalars)
        })
        .collect();
    let mut out = format!("{count} {}\n{}\n", F::SCALARS, fields.join(" "));
    for _ in 0..count {
        let factor = sample(&mut sampler);
        factor.validate()?;
        out.push_str(&line(&factor.to_scalars()));
        out.push('\n');
    }
    std::fs::write(dir.join(format!("{}.txt", F::NAME)), out)?;
    Ok(())
}

/// A direction uniform on the sphere.
fn unit(sampler: &mut Sampler) -> Vector3<f64> {
    loop {
        let v = sampler.vector3(1.0);
        if (0.1..1.0).contains(&v.norm()) {
            return v.normalize();
        }
    }
}

/// A similarity: a uniform rotation, a translation within 2, a log-scale
/// within ±0.5.
fn similarity(sampler: &mut Sampler) -> Sim3<f64> {
    let (rotation, translation) = (sampler.rotation(), sampler.vector3(2.0));
    Sim3::new(rotation, translation, sampler.uniform(-0.5, 0.5))
}

fn samples(dir: &Path, count: usize) -> Result<(), Failure> {
    use slam_factors::{
        BetweenFactor, FreeLineFactor, G2oSe3Edge, LineObservation, LineReprojection, PlaneFactor,
        PluckerLineReprojection, PointReprojection, SnavelyReprojection, StereoReprojection,
    };
    std::fs::create_dir_all(dir)?;
    write_samples::<PointReprojection>(dir, count, 1, Sampler::point_reprojection)?;
    write_samples::<LineReprojection>(dir, count, 2, Sampler::line_reprojection)?;
    write_samples::<PluckerLineReprojection>(dir, count, 3, Sampler::plucker_line_reprojection)?;
    write_samples::<PlaneFactor>(dir, count, 4, Sampler::plane)?;
    write_samples::<LineObservation>(dir, count, 5, Sampler::line_observation)?;
    write_samples::<FreeLineFactor>(dir, count, 6, Sampler::free_line)?;
    write_samples::<SnavelyReprojection>(dir, count, 7, Sampler::snavely_reprojection)?;
    write_samples::<StereoReprojection>(dir, count, 8, Sampler::stereo_reprojection)?;
    write_samples::<BetweenFactor>(dir, count, 9, Sampler::between)?;
    write_samples::<G2oSe3Edge>(dir, count, 10, Sampler::g2o_se3)?;
    write_samples(dir, count, 11, |s| RelativePose {
        measured: s.pose(),
        pose_i: s.pose(),
        pose_j: s.pose(),
    })?;
    write_samples(dir, count, 12, |s| PointToPlane {
        point: s.vector3(5.0),
        plane_point: s.vector3(5.0),
        normal: unit(s),
        pose: s.pose(),
    })?;
    write_samples(dir, count, 13, |s| {
        let pose: Se3<f64> = s.pose();
        let seen = Vector3::new(s.uniform(0.5, 10.0), s.uniform(-5.0, 5.0), s.uniform(-5.0, 5.0));
        ScaledRangeBearing {
            landmark: pose.inverse().transform_point(&seen),
            measured: s.vector3(0.5),
            pose,
            log_scale: s.uniform(-1.0, 1.0),
        }
    })?;
    write_samples(dir, count, 14, |s| Direction {
        measured: UnitVector3::from_unit(unit(s)),
        orientation: s.rotation(),
        direction: UnitVector3::from_unit(unit(s)),
    })?;
    write_samples(dir, count, 15, |s| RelativeSim3 {
        measured: similarity(s),
        sim_i: similarity(s),
        sim_j: similarity(s),
    })?;
    Ok(())
}

/// The registry of every factor a problem file may name here: the shipped
/// ones and the example user crate's.
fn registry() -> Registry {
    shipped()
        .with::<RelativePose>()
        .with::<PointToPlane>()
        .with::<ScaledRangeBearing>()
        .with::<Direction>()
        .with::<RelativeSim3>()
}

/// `S` (`r × r`, row-major) of a noise model `{"sigma"}`, `{"sigmas"}` or
/// `{"sqrt_information"}`, or the identity without one.
fn sqrt_information(noise: Option<&Value>, r: usize) -> Result<Vec<f64>, Failure> {
    let mut s = vec![0.0; r * r];
    let number = |v: &Value| v.as_f64().ok_or("noise: expected numbers");
    match noise {
        None => (0..r).for_each(|i| s[i * r + i] = 1.0),
        Some(noise) => {
            if let Some(sigma) = noise.get("sigma") {
                let sigma = number(sigma)?;
                (0..r).for_each(|i| s[i * r + i] = 1.0 / sigma);
            } else if let Some(sigmas) = noise.get("sigmas").and_then(Value::as_array) {
                for (i, sigma) in sigmas.iter().enumerate() {
                    s[i * r + i] = 1.0 / number(sigma)?;
                }
            } else if let Some(rows) = noise.get("sqrt_information").and_then(Value::as_array) {
                for (i, row) in rows.iter().enumerate() {
                    for (j, v) in row.as_array().ok_or("noise: rows")?.iter().enumerate() {
                        s[i * r + j] = number(v)?;
                    }
                }
            } else {
                return Err("noise: sigma, sigmas or sqrt_information".into());
            }
        }
    }
    Ok(s)
}

fn problem(file: &Path, out: &Path) -> Result<(), Failure> {
    let json: Value = serde_json::from_str(&std::fs::read_to_string(file)?)?;
    let declared = json["variables"].as_object().ok_or("variables: an object")?;
    let registry = registry();
    let mut index: HashMap<String, usize> = HashMap::new();
    let mut variables = String::new();
    let mut factors = String::new();
    let entries = json["factors"].as_array().ok_or("factors: an array")?;
    for (k, spec) in entries.iter().enumerate() {
        let path = format!("factors[{k}]");
        if spec.get("robust").is_some() {
            return Err(format!("{path}: robust losses are not exported").into());
        }
        let name = spec["factor"].as_str().ok_or("factor: a string")?;
        let entry = registry.find(name, &format!("{path}.factor"))?;
        let fields = (entry.fields)();
        let named = &spec["variables"];
        let mut values = Map::new();
        let mut used = Vec::new();
        for info in (entry.variables)() {
            let variable = named[info.name].as_str().ok_or("variables: names")?;
            let declared = declared.get(variable).ok_or("an undeclared variable")?;
            values.insert(info.name.to_owned(), declared["value"].clone());
            used.push(variable.to_owned());
        }
        let values = Document::from_value(&Value::Object(values));
        let keys: Vec<&str> = (entry.variables)().iter().map(|v| v.name).collect();
        let variables_object = Object::new(values.root(), &format!("{path}.variables"), &keys)?;
        let constant_keys: Vec<&str> = entry.json_fields(false).into_iter().map(|(n, _)| n).collect();
        let given_constants = Document::from_value(&spec["constants"]);
        let constants_object =
            Object::new(given_constants.root(), &format!("{path}.constants"), &constant_keys)?;
        let stored = stored_scalars(&fields, &variables_object, &constants_object)?;
        let (mut offset, mut constants, mut indices) = (0, Vec::new(), Vec::new());
        for field in &fields {
            let scalars = &stored[offset..offset + field.scalars];
            offset += field.scalars;
            let Some(v) = field.variable else {
                constants.extend_from_slice(scalars);
                continue;
            };
            let variable = &used[v];
            let next = index.len();
            let at = *index.entry(variable.clone()).or_insert_with(|| {
                let spec = &declared[variable];
                let fixed = spec.get("fixed").and_then(Value::as_bool).unwrap_or(false);
                let _ = writeln!(
                    variables,
                    "{variable} {} {} {} {}",
                    spec["type"].as_str().unwrap_or("?"),
                    u8::from(fixed),
                    scalars.len(),
                    line(scalars)
                );
                next
            });
            indices.push(at.to_string());
        }
        let r = entry.residual_dim;
        let s = sqrt_information(spec.get("noise"), r)?;
        let _ = writeln!(
            factors,
            "{name} {} {} {} {} {r} {}",
            indices.len(),
            indices.join(" "),
            constants.len(),
            line(&constants),
            line(&s)
        );
    }
    let text = format!(
        "ceres-host-problem 1\nvariables {}\n{variables}factors {}\n{factors}",
        index.len(),
        entries.len()
    );
    std::fs::write(out, text)?;
    Ok(())
}

/// `values` (stored scalars) in the JSON form of `layout`.
fn json_of(layout: &Layout, values: &[f64]) -> Value {
    match layout {
        Layout::Scalar => json!(values[0]),
        Layout::Array(_) => json!(values),
        Layout::Record(parts) => {
            let mut map = Map::new();
            let mut at = 0;
            for (key, part) in parts {
                let n = part.scalars();
                map.insert((*key).to_owned(), json_of(part, &values[at..at + n]));
                at += n;
            }
            Value::Object(map)
        }
    }
}

/// A value in the JSON form a problem file gives it (its stored scalars in
/// its layout: the user crate's types are written as stored).
fn value<T: Storage<f64>>(v: &T) -> Value {
    assert_eq!(T::layout(), T::input_layout(), "written as stored");
    json_of(&T::layout(), &v.to_scalars())
}

/// `Exp` of a step of up to `size` per coordinate, composed on the right.
fn nudged(sampler: &mut Sampler, pose: &Se3<f64>, size: f64) -> Se3<f64> {
    let step = Se3::new(
        So3::exp(&sampler.vector3(size)),
        sampler.vector3(size),
    );
    pose.compose(&step)
}

/// A similarity moved by a step of up to `size` per coordinate.
fn nudged_sim3(sampler: &mut Sampler, s: &Sim3<f64>, size: f64) -> Sim3<f64> {
    let step = Sim3::new(
        So3::exp(&sampler.vector3(size)),
        sampler.vector3(size),
        sampler.uniform(-size, size),
    );
    s.compose(&step)
}

/// A seeded problem of the example user crate's five factors, measurements
/// made from a true configuration with small errors, initial values moved
/// away from it:
///
/// - six poses `T0…T5` (`T0` fixed) in a ring of `relative_pose` factors,
///   each pose seeing six points on three map planes (`point_to_plane`) and
///   four known landmarks (`scaled_range_bearing`, with one unknown range
///   scale `lambda`);
/// - three orientations `R0…R2` (`R0` fixed) each seeing five directions
///   `d0…d4` on S² (`direction`);
/// - five similarities `S0…S4` (`S0` fixed) in a ring of `relative_sim3`
///   factors.
fn user_problem(out: &Path) -> Result<(), Failure> {
    let mut s = Sampler::new(2029);
    let mut variables = Map::new();
    let mut factors = Vec::new();
    let mut variable = |name: &str, kind: &str, v: Value, fixed: bool| {
        variables.insert(name.to_owned(), json!({"type": kind, "value": v, "fixed": fixed}));
    };
    let sigma = json!({"sigma": 0.01});
    let poses: Vec<Se3<f64>> = (0..6).map(|_| s.pose()).collect();
    for (k, pose) in poses.iter().enumerate() {
        let start = if k == 0 { *pose } else { nudged(&mut s, pose, 0.05) };
        variable(&format!("T{k}"), "Se3", value(&start), k == 0);
    }
    for k in 0..6 {
        let (i, j) = (k, (k + 1) % 6);
        let truth = poses[i].inverse().compose(&poses[j]);
        factors.push(json!({"factor": "relative_pose",
            "variables": {"pose_i": format!("T{i}"), "pose_j": format!("T{j}")},
            "constants": {"measured": value(&nudged(&mut s, &truth, 0.005))},
            "noise": sigma}));
    }
    let planes: Vec<(Vector3<f64>, Vector3<f64>)> =
        (0..3).map(|_| (unit(&mut s), s.vector3(3.0))).collect();
    let lambda: f64 = 0.3;
    variable("lambda", "S", json!(0.0), false);
    for (k, pose) in poses.iter().enumerate() {
        for (normal, plane_point) in planes.iter().cycle().take(6) {
            let along = s.vector3(2.0);
            let world = plane_point + along - normal * normal.dot(&along);
            let point = pose.inverse().transform_point(&world) + s.vector3(0.003);
            factors.push(json!({"factor": "point_to_plane",
                "variables": {"pose": format!("T{k}")},
                "constants": {"point": value(&point), "plane_point": value(plane_point),
                              "normal": value(normal)},
                "noise": sigma}));
        }
        for _ in 0..4 {
            let seen = Vector3::new(s.uniform(1.0, 8.0), s.uniform(-3.0, 3.0), s.uniform(-3.0, 3.0));
            let landmark = pose.inverse().transform_point(&seen);
            let zero = ScaledRangeBearing {
                landmark,
                measured: Vector3::zeros(),
                pose: *pose,
                log_scale: lambda,
            };
            let predicted = user_factors::scaled_range_bearing_residual(&zero);
            factors.push(json!({"factor": "scaled_range_bearing",
                "variables": {"pose": format!("T{k}"), "log_scale": "lambda"},
                "constants": {"landmark": value(&landmark),
                              "measured": value(&(predicted + s.vector3(0.005)))},
                "noise": sigma}));
        }
    }
    let orientations: Vec<So3<f64>> = (0..3).map(|_| s.rotation()).collect();
    let directions: Vec<Vector3<f64>> = (0..5).map(|_| unit(&mut s)).collect();
    for (k, r) in orientations.iter().enumerate() {
        let start = if k == 0 { *r } else { So3::exp(&s.vector3(0.05)).compose(r) };
        variable(&format!("R{k}"), "So3", value(&start), k == 0);
    }
    for (j, d) in directions.iter().enumerate() {
        let start = UnitVector3::from_direction(&(d + s.vector3(0.05)));
        variable(&format!("d{j}"), "UnitVector3", value(&start), false);
        for (k, r) in orientations.iter().enumerate() {
            let measured = UnitVector3::from_direction(&(r.rotate(d) + s.vector3(0.005)));
            factors.push(json!({"factor": "direction",
                "variables": {"orientation": format!("R{k}"), "direction": format!("d{j}")},
                "constants": {"measured": value(&measured)},
                "noise": sigma}));
        }
    }
    let sims: Vec<Sim3<f64>> = (0..5).map(|_| similarity(&mut s)).collect();
    for (k, sim) in sims.iter().enumerate() {
        let start = if k == 0 { *sim } else { nudged_sim3(&mut s, sim, 0.05) };
        variable(&format!("S{k}"), "Sim3", value(&start), k == 0);
    }
    for k in 0..5 {
        let (i, j) = (k, (k + 1) % 5);
        let truth = sims[i].inverse().compose(&sims[j]);
        factors.push(json!({"factor": "relative_sim3",
            "variables": {"sim_i": format!("S{i}"), "sim_j": format!("S{j}")},
            "constants": {"measured": value(&nudged_sim3(&mut s, &truth, 0.005))},
            "noise": sigma}));
    }
    let problem = json!({"slamjac_problem": 1, "variables": variables, "factors": factors});
    std::fs::write(out, serde_json::to_string_pretty(&problem)?)?;
    Ok(())
}
