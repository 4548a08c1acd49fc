//! The workspace keeps its architecture: the runtime crate an embedder
//! depends on pulls in nothing the generator needs, the solvers' shared
//! vocabulary and the Schur-complement solver pull in no other solver
//! (apex-solver stays an integration), and no crate has a cycle
//! among its modules' imports (`crate::a` using `crate::b` using `crate::a`).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn workspace() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The direct `[dependencies]` of a crate's manifest (not dev or build).
fn dependencies(manifest: &Path) -> BTreeSet<String> {
    let text = std::fs::read_to_string(manifest).expect("manifest exists");
    let mut in_dependencies = false;
    let mut names = BTreeSet::new();
    for line in text.lines().map(str::trim) {
        if line.starts_with('[') {
            in_dependencies = line == "[dependencies]";
            continue;
        }
        if in_dependencies && let Some((name, _)) = line.split_once('=') {
            let name = name.trim().trim_end_matches(".workspace");
            if !name.is_empty() && !name.starts_with('#') {
                names.insert(name.to_owned());
            }
        }
    }
    names
}

/// Asserts that the crate of `manifest` (relative to the workspace) has
/// exactly the `[dependencies]` `expected`.
fn depends_exactly_on(manifest: &str, expected: &[&str]) {
    let found = dependencies(&workspace().join(manifest));
    let expected: BTreeSet<String> = expected.iter().map(|d| d.to_string()).collect();
    assert_eq!(found, expected, "{manifest}");
}

#[test]
fn the_runtime_crate_depends_only_on_what_runs_in_an_estimator() {
    depends_exactly_on(
        "factor-core/Cargo.toml",
        &[
            "nalgebra",
            "num-dual",
            "num-traits",
            "thiserror",
            "factor-macros",
        ],
    );
    let macros = dependencies(&workspace().join("factor-macros/Cargo.toml"));
    assert!(
        macros
            .iter()
            .all(|d| ["syn", "quote", "proc-macro2"].contains(&d.as_str())),
        "{macros:?}"
    );
}

/// `slam-problems` (robust losses, kernels, the data sets' factors) holds
/// no solver, and `factor-schur` builds on it, not on the apex-solver
/// adapter, which stays one of its dev-dependencies (agreement tests).
#[test]
fn the_solvers_vocabulary_depends_on_no_solver() {
    depends_exactly_on(
        "slam-problems/Cargo.toml",
        &[
            "factor-core",
            "slam-factors",
            "slam-data",
            "nalgebra",
            "thiserror",
        ],
    );
    let schur = dependencies(&workspace().join("integrations/schur/Cargo.toml"));
    assert!(schur.contains("slam-problems"), "{schur:?}");
    for solver in ["factor-apex", "apex-solver"] {
        assert!(!schur.contains(solver), "factor-schur depends on {solver}");
    }
}

/// The factors a command line knows (`slamjac-registry`) are a library:
/// the input layer, the generator's specs and, for problem files (feature
/// `solve`, optional), the solvers' problems; no printing (progress bars,
/// plots) and no command line but clap's value enum (feature `clap`).
#[test]
fn the_registry_is_a_library_of_the_command_line() {
    depends_exactly_on(
        "slamjac-registry/Cargo.toml",
        &[
            "factor-core",
            "factor-codegen",
            "slamjac-problem",
            "serde_json",
            "thiserror",
            "clap",
            "factor-apex",
            "factor-schur",
            "factor-lanes",
            "slam-problems",
            "slam-factors",
        ],
    );
    let root = dependencies(&workspace().join("Cargo.toml"));
    assert!(root.contains("slamjac-registry"), "{root:?}");
}

/// The problem files' pipeline (`slamjac-solve`) prints nothing (no
/// progress bar, no plot, no command line), and its solvers are optional
/// (feature `solve`): without it the crate holds its error alone.
#[test]
fn the_problem_files_pipeline_is_a_library_of_the_command_line() {
    depends_exactly_on(
        "slamjac-solve/Cargo.toml",
        &[
            "slamjac-problem",
            "serde_json",
            "thiserror",
            "slamjac-registry",
            "factor-apex",
            "factor-schur",
            "factor-minimizer",
            "slam-problems",
            "slam-data",
            "nalgebra",
            "factor-core",
            "slam-factors",
            "factor-tracking",
        ],
    );
}

/// Every `.rs` file under `src` (outside `#[cfg(test)]` modules) as the
/// top-level module it belongs to and the top-level modules it names as
/// `crate::name`.
fn module_imports(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("readable") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let relative = path.strip_prefix(src).expect("under src");
            let top = relative
                .components()
                .next()
                .and_then(|c| c.as_os_str().to_str())
                .expect("a name")
                .trim_end_matches(".rs")
                .to_owned();
            let text = std::fs::read_to_string(&path).expect("readable");
            let code = text.split("#[cfg(test)]").next().unwrap_or_default();
            let used = graph.entry(top.clone()).or_default();
            for line in code.lines().filter(|l| !l.trim_start().starts_with("//")) {
                used.extend(crate_paths(line).into_iter().filter(|m| *m != top));
            }
        }
    }
    graph
}

/// The modules a line names: `crate::a::…` and `use crate::{a, b::c}`.
fn crate_paths(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(at) = rest.find("crate::") {
        rest = &rest[at + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let end = group.find('}').unwrap_or(group.len());
            for item in group[..end].split(',') {
                let name: String = item
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if !name.is_empty() {
                    out.push(name);
                }
            }
        } else {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if name.chars().next().is_some_and(char::is_lowercase) {
                out.push(name);
            }
        }
    }
    out
}

/// A cycle of `graph`, if it has one.
fn cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(start) = path.iter().position(|n| n == node) {
            let mut found = path[start..].to_vec();
            found.push(node.to_owned());
            return Some(found);
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_owned());
        for next in graph.get(node).into_iter().flatten() {
            if let Some(found) = visit(next, graph, path, done) {
                return Some(found);
            }
        }
        path.pop();
        done.insert(node.to_owned());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|node| visit(node, graph, &mut Vec::new(), &mut done))
}

#[test]
fn no_crate_has_a_cycle_among_its_modules() {
    let crates = [
        "src",
        "factor-core/src",
        "factor-macros/src",
        "factor-symbolic/src",
        "factor-codegen/src",
        "factor-testing/src",
        "factor-audit/src",
        "slam-factors/src",
        "slam-data/src",
        "slamjac-io/src",
        "slamjac-problem/src",
        "slamjac-registry/src",
        "slamjac-solve/src",
        "doc-latex/src",
        "factor-batch/src",
        "factor-lanes/src",
        "factor-tracking/src",
        "factor-minimizer/src",
        "slam-problems/src",
        // The solvers' crates, in their own workspaces.
        "integrations/apex/src",
        "integrations/schur/src",
    ];
    for src in crates {
        let graph = module_imports(&workspace().join(src));
        assert!(graph.len() > 1, "{src}: no modules found");
        if let Some(found) = cycle(&graph) {
            panic!(
                "{src}: the modules {} import each other in a cycle",
                found.join(" → ")
            );
        }
    }
}

#[test]
fn the_cycle_finder_finds_a_cycle() {
    let graph: BTreeMap<String, BTreeSet<String>> = [
        ("a", vec!["b"]),
        ("b", vec!["c"]),
        ("c", vec!["a"]),
        ("d", vec![]),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_owned(), v.into_iter().map(String::from).collect()))
    .collect();
    assert_eq!(cycle(&graph).map(|c| c.len()), Some(4));
    assert_eq!(
        crate_paths("use crate::{pretty, registry::find, w_first};"),
        ["pretty", "registry", "w_first"]
    );
}

/// The `path`s of a manifest's `[[test]]` tables, relative to its crate.
fn test_targets(manifest: &str) -> Vec<String> {
    let mut in_test = false;
    let mut paths = Vec::new();
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            in_test = line == "[[test]]";
            continue;
        }
        if in_test && let Some(("path", value)) = line.split_once('=').map(|(k, v)| (k.trim(), v)) {
            paths.push(value.trim().trim_matches('"').to_owned());
        }
    }
    paths
}

/// A crate whose integration tests are one binary (`autotests = false`, a
/// `[[test]]` root declaring each file as a module) runs every file of its
/// `tests/`: a file added there without its `mod` line would never run.
#[test]
fn every_integration_test_file_is_compiled() {
    let members = std::fs::read_to_string(workspace().join("Cargo.toml")).expect("manifest");
    let mut checked = 0;
    // The root package (".") and every member.
    for member in std::iter::once(".").chain(
        members
            .lines()
            .map(str::trim)
            .filter_map(|l| l.strip_prefix('"')?.strip_suffix("\",")),
    ) {
        let dir = workspace().join(member);
        let Ok(manifest) = std::fs::read_to_string(dir.join("Cargo.toml")) else {
            continue;
        };
        if !manifest.lines().any(|l| l.trim() == "autotests = false") {
            continue;
        }
        let roots = test_targets(&manifest);
        let declared: String = roots
            .iter()
            .map(|root| std::fs::read_to_string(dir.join(root)).expect("test root"))
            .collect();
        for entry in std::fs::read_dir(dir.join("tests")).expect("tests/") {
            let path = entry.expect("entry").path();
            let Some(stem) = path.file_stem().and_then(|s| s.to_str()) else {
                continue;
            };
            let relative = format!("tests/{stem}.rs");
            if path.extension().is_none_or(|e| e != "rs") || roots.contains(&relative) {
                continue;
            }
            assert!(
                declared.contains(&format!("mod {stem};")),
                "{member}/{relative} is not a module of a test binary: add `mod {stem};` to {}",
                roots.join(" or ")
            );
            checked += 1;
        }
    }
    assert!(checked > 0, "no crate with autotests = false was found");
}

#[test]
fn test_targets_are_read_from_manifests() {
    let manifest = "[package]\nautotests = false\n\n[[test]]\nname = \"t\"\npath = \"tests/t.rs\"\n\n\
                    [[bench]]\npath = \"benches/b.rs\"\n";
    assert_eq!(test_targets(manifest), ["tests/t.rs"]);
}
