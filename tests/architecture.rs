//! The shape of the code: dependencies between the crate's top-level modules point one way, down a
//! declared order of layers, and the dependencies between the submodules of each of them point one
//! way too.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

type Graph = BTreeMap<String, BTreeSet<String>>;

/// The lower-case names that follow `prefix` in `text`: `prefix` then a name, or `prefix{a, b::c}`
/// (each item's first segment).
fn names_after(text: &str, prefix: &str, found: &mut BTreeSet<String>) {
    let name = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == '_')
            .collect()
    };
    for (k, _) in text.match_indices(prefix) {
        // Not the tail of a longer path (`super::super::x` is not `super::x`).
        if text[..k].ends_with("::") {
            continue;
        }
        let rest = &text[k + prefix.len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let group = &group[..group.find('}').unwrap_or(group.len())];
            for item in group.split(',') {
                let first = name(item.trim());
                if !first.is_empty() {
                    found.insert(first);
                }
            }
        } else {
            let first = name(rest);
            if !first.is_empty() {
                found.insert(first);
            }
        }
    }
}

/// Every `crate::<module>` named in the files under `path`.
fn uses(path: &Path, found: &mut BTreeSet<String>) {
    if path.is_dir() {
        for entry in std::fs::read_dir(path).unwrap() {
            uses(&entry.unwrap().path(), found);
        }
    } else if path.extension().is_some_and(|e| e == "rs") {
        names_after(&std::fs::read_to_string(path).unwrap(), "crate::", found);
    }
}

/// Panics naming a cycle of `graph` (edges to names outside it are ignored), if there is one.
fn assert_acyclic(graph: &Graph, what: &str) {
    fn visit(
        node: &str,
        graph: &Graph,
        state: &mut BTreeMap<String, u8>,
        path: &mut Vec<String>,
        what: &str,
    ) {
        match state.get(node) {
            Some(2) => return,
            Some(1) => panic!(
                "a dependency cycle in {what}: {} -> {node}",
                path.join(" -> ")
            ),
            _ => {}
        }
        state.insert(node.to_string(), 1);
        path.push(node.to_string());
        for next in graph[node].iter().filter(|n| graph.contains_key(*n)) {
            visit(next, graph, state, path, what);
        }
        path.pop();
        state.insert(node.to_string(), 2);
    }
    let mut state = BTreeMap::new();
    for node in graph.keys() {
        visit(node, graph, &mut state, &mut Vec::new(), what);
    }
}

fn src() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn stem(path: &Path) -> String {
    path.file_stem().unwrap().to_string_lossy().to_string()
}

/// The crate's top-level modules from the bottom up: a module may use only the modules of the
/// layers below its own. Foundations; plane geometry and errors; the table; what prices and stores
/// it; the shared problem and the camera's view of the table; the planning stages (grasps and
/// riders, pushes, clusters); the plan and its verifier; the executors that carry a plan out; the
/// policy that plans trip by trip and the pictures; the experiments; the file formats' schemas.
const LAYERS: &[&[&str]] = &[
    &["id", "outcome", "random", "stats"],
    &["error", "geometry"],
    &["scene"],
    &["json", "time_model"],
    &["perception", "problem"],
    &["grasp", "stack"],
    &["push"],
    &["cluster"],
    &["plan"],
    &["exec"],
    &["policy", "render"],
    &["experiment"],
    &["schema"],
];

/// The top-level modules and the modules each one names.
fn module_graph() -> Graph {
    let mut graph = Graph::new();
    for entry in std::fs::read_dir(src()).unwrap() {
        let path = entry.unwrap().path();
        let name = stem(&path);
        if name == "lib" || name == "bin" {
            continue;
        }
        let mut found = BTreeSet::new();
        uses(&path, &mut found);
        found.remove(&name);
        graph.insert(name, found);
    }
    graph
}

#[test]
fn the_module_graph_has_no_cycles() {
    let graph = module_graph();
    assert!(graph.len() > 10, "{graph:?}");
    assert_acyclic(&graph, "the crate");
}

/// Panics naming the first module of `graph` that is in no layer, or that uses a module of its own
/// layer or of one above.
fn assert_layered(graph: &Graph, layers: &[&[&str]]) {
    let layer_of = |name: &str| layers.iter().position(|layer| layer.contains(&name));
    for (module, used) in graph {
        let Some(own) = layer_of(module) else {
            panic!("{module} is in no layer: place it in LAYERS (tests/architecture.rs)");
        };
        for other in used.iter().filter(|n| graph.contains_key(*n)) {
            let theirs = layer_of(other).unwrap_or(usize::MAX);
            assert!(
                theirs < own,
                "{module} uses {other}, which is not in a layer below it"
            );
        }
    }
}

#[test]
fn every_module_uses_only_the_layers_below_it() {
    assert_layered(&module_graph(), LAYERS);
}

/// The layer check finds a use that points up.
#[test]
#[should_panic(expected = "scene uses policy, which is not in a layer below it")]
fn a_use_that_points_up_is_found() {
    let mut graph = Graph::new();
    graph.insert("scene".into(), ["policy".to_string()].into());
    graph.insert("policy".into(), ["scene".to_string()].into());
    assert_layered(&graph, LAYERS);
}

/// The siblings a file of the module `module` (a path such as `exec::sim`) names:
/// `crate::<module>::x`, and `super::x` from a file of `module` itself, `super::super::x` from a
/// file one folder further down (or `super::x` from its `mod.rs`), and so on.
fn sibling_uses(path: &Path, module: &str, depth: usize, found: &mut BTreeSet<String>) {
    if path.is_dir() {
        for entry in std::fs::read_dir(path).unwrap() {
            sibling_uses(&entry.unwrap().path(), module, depth + 1, found);
        }
    } else if path.extension().is_some_and(|e| e == "rs") {
        let text = std::fs::read_to_string(path).unwrap();
        let levels = if stem(path) == "mod" {
            depth - 1
        } else {
            depth
        };
        names_after(&text, &"super::".repeat(levels), found);
        names_after(&text, &format!("crate::{module}::"), found);
    }
}

/// Panics naming a cycle among the submodules of the module in folder `dir` (named `module`,
/// a path such as `exec::sim`), then checks each of its folders the same way; returns how many
/// submodules were checked.
fn check_submodules(dir: &Path, module: &str) -> usize {
    let mut graph = Graph::new();
    let mut checked = 0;
    for child in std::fs::read_dir(dir).unwrap() {
        let path = child.unwrap().path();
        let name = stem(&path);
        if name == "mod" {
            continue;
        }
        let mut found = BTreeSet::new();
        sibling_uses(&path, module, 1, &mut found);
        found.remove(&name);
        graph.insert(name.clone(), found);
        if path.is_dir() {
            checked += check_submodules(&path, &format!("{module}::{name}"));
        }
    }
    assert_acyclic(&graph, &format!("src/{}/", module.replace("::", "/")));
    checked + graph.len()
}

/// Within every module with a folder, at any depth, its submodules (files and folders beside its
/// `mod.rs`, which re-exports them and is left out) depend on each other one way too.
#[test]
fn no_module_has_a_cycle_among_its_submodules() {
    let mut checked = 0;
    for entry in std::fs::read_dir(src()).unwrap() {
        let dir = entry.unwrap().path();
        let top = stem(&dir);
        if !dir.is_dir() || top == "bin" {
            continue;
        }
        checked += check_submodules(&dir, &top);
    }
    assert!(checked > 50, "{checked} submodules");
}

/// The test finds a cycle where there is one.
#[test]
#[should_panic(expected = "a dependency cycle in example: a -> b -> a")]
fn a_cycle_is_found() {
    let mut graph = Graph::new();
    graph.insert("a".into(), ["b".to_string()].into());
    graph.insert("b".into(), ["a".to_string(), "outside".to_string()].into());
    assert_acyclic(&graph, "example");
}
