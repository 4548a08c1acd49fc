//! `api-snapshot CRATE.json`: the public API of a library crate, read from
//! the JSON rustdoc writes for it (`cargo rustdoc -p CRATE --lib -- -Z
//! unstable-options --output-format json`), printed as sorted lines, one per
//! public item reachable from the crate's root: its path, its kind and its
//! signature (generics, bounds, fields' and arguments' types, attributes
//! such as `#[non_exhaustive]`, the traits a type implements), as rustdoc
//! describes them with the ids, spans and documentation left out. Two
//! snapshots differ exactly where the public API does.

use std::collections::BTreeSet;
use std::process::ExitCode;

use serde_json::{Map, Value};

/// The keys that are not API: ids (renumbered from build to build), source
/// spans, documentation and its links.
const NOT_API: [&str; 4] = ["id", "span", "docs", "links"];

/// `value` without [`NOT_API`] keys, at every depth.
fn canonical(value: &Value) -> Value {
    match value {
        Value::Object(map) => Value::Object(
            map.iter()
                .filter(|(k, _)| !NOT_API.contains(&k.as_str()))
                .map(|(k, v)| (k.clone(), canonical(v)))
                .collect(),
        ),
        Value::Array(items) => Value::Array(items.iter().map(canonical).collect()),
        other => other.clone(),
    }
}

/// Where an item's `inner` lists its children (fields, a tuple's fields,
/// variants, trait items) by id.
const CHILDREN: [&str; 5] = [
    "/kind/plain/fields",
    "/kind/tuple",
    "/kind/struct/fields",
    "/variants",
    "/items",
];

/// The crate's items by id, and the lines written so far.
struct Api<'a> {
    index: &'a Map<String, Value>,
    paths: &'a Map<String, Value>,
    lines: BTreeSet<String>,
}

impl<'a> Api<'a> {
    fn item(&self, id: &Value) -> Option<&'a Value> {
        self.index.get(&id.to_string())
    }

    /// The name of the item `id` (`None` for a stripped, private field).
    fn name(&self, id: &Value) -> Option<&'a str> {
        self.item(id).and_then(|item| item["name"].as_str())
    }

    /// One line: `path kind signature`.
    fn line(&mut self, path: &str, kind: &str, signature: &Value) {
        self.lines.insert(format!("{path} {kind} {signature}"));
    }

    /// The item `id` reached at `path`, and everything public below it.
    fn walk(&mut self, id: &Value, path: &str, depth: usize) {
        let Some(item) = self.item(id) else {
            // A re-export of another crate's item.
            let external = self
                .paths
                .get(&id.to_string())
                .map_or(Value::Null, |p| p["path"].clone());
            self.line(path, "external", &external);
            return;
        };
        if depth > 32 {
            return;
        }
        let Some((kind, inner)) = item["inner"].as_object().and_then(|m| m.iter().next()) else {
            return;
        };
        let mut signature = canonical(inner);
        let children = |key: &str| -> Vec<Value> {
            inner
                .pointer(key)
                .and_then(Value::as_array)
                .cloned()
                .unwrap_or_default()
        };
        match kind.as_str() {
            "module" => {
                self.line(path, kind, &Value::Null);
                for child in children("/items") {
                    self.child(&child, path, depth);
                }
                return;
            }
            "use" => {
                let target = &inner["id"];
                if inner["is_glob"] == Value::Bool(true) {
                    if let Some(module) = self.item(target) {
                        let items = module.pointer("/inner/module/items").cloned();
                        for child in items.and_then(|v| v.as_array().cloned()).unwrap_or_default() {
                            self.child(&child, path.rsplit_once("::").map_or(path, |p| p.0), depth);
                        }
                        return;
                    }
                }
                if target.is_null() {
                    self.line(path, kind, &inner["source"]);
                } else {
                    self.walk(target, path, depth + 1);
                }
                return;
            }
            _ => {}
        }
        // Fields, variants and trait items have lines of their own; the
        // signature keeps their names, in order, in place of their ids.
        for key in CHILDREN {
            for child in children(key) {
                self.child(&child, path, depth);
            }
            if let Some(list) = signature.pointer_mut(key).and_then(Value::as_array_mut) {
                for entry in list.iter_mut() {
                    *entry = self.name(entry).map_or(Value::Null, Value::from);
                }
            }
        }
        for implementation in children("/impls") {
            self.implementation(&implementation, path, depth);
        }
        // The impls, listed by id (a trait's implementors too): each impl
        // has its own line under the implementing type.
        if let Some(map) = signature.as_object_mut() {
            map.remove("impls");
            map.remove("implementations");
        }
        // Attributes that are API (`#[non_exhaustive]`, `#[repr(…)]`,
        // `#[must_use]`); others (`#[error("…")]`, a message) are not.
        let attrs: Vec<Value> = item["attrs"]
            .as_array()
            .map(|a| a.iter().filter(|a| a.get("other").is_none()).map(canonical).collect())
            .unwrap_or_default();
        self.line(path, kind, &Value::Array(vec![Value::Array(attrs), signature]));
    }

    /// A child item `id` of the item at `path`, under its own name.
    fn child(&mut self, id: &Value, path: &str, depth: usize) {
        let Some(item) = self.item(id) else {
            return;
        };
        let name = item["name"]
            .as_str()
            .or_else(|| item.pointer("/inner/use/name").and_then(Value::as_str))
            .unwrap_or("_");
        self.walk(id, &format!("{path}::{name}"), depth + 1);
    }

    /// An impl of the type at `path`: the trait it implements (or its
    /// inherent items), generics and bounds; blanket impls of other crates'
    /// traits (`impl<T> From<T> for T`) are the standard library's, not this
    /// crate's.
    fn implementation(&mut self, id: &Value, path: &str, depth: usize) {
        let Some(inner) = self.item(id).and_then(|i| i.pointer("/inner/impl")) else {
            return;
        };
        if !inner["blanket_impl"].is_null() {
            return;
        }
        let trait_ = canonical(&inner["trait"]);
        let generics = canonical(&inner["generics"]);
        let header = Value::Array(vec![trait_, generics, inner["is_unsafe"].clone()]);
        self.line(path, "impl", &header);
        if inner["trait"].is_null() {
            for child in inner["items"].as_array().cloned().unwrap_or_default() {
                self.child(&child, path, depth);
            }
        }
    }
}

fn main() -> ExitCode {
    let Some(file) = std::env::args().nth(1) else {
        eprintln!("usage: api-snapshot CRATE.json");
        return ExitCode::from(2);
    };
    let json: Value = match std::fs::read_to_string(&file)
        .map_err(|e| e.to_string())
        .and_then(|text| serde_json::from_str(&text).map_err(|e| e.to_string()))
    {
        Ok(json) => json,
        Err(e) => {
            eprintln!("error: {file}: {e}");
            return ExitCode::from(2);
        }
    };
    let (Some(index), Some(paths)) = (json["index"].as_object(), json["paths"].as_object()) else {
        eprintln!("error: {file}: not rustdoc's JSON (no `index` and `paths`)");
        return ExitCode::from(2);
    };
    let root = &json["root"];
    let name = index
        .get(&root.to_string())
        .and_then(|r| r["name"].as_str())
        .unwrap_or("crate")
        .to_owned();
    let mut api = Api {
        index,
        paths,
        lines: BTreeSet::new(),
    };
    api.walk(root, &name, 0);
    println!("# rustdoc JSON format {}", json["format_version"]);
    for line in &api.lines {
        println!("{line}");
    }
    ExitCode::SUCCESS
}
