//! The crate's modules import each other without cycles: each concept depends only on the ones
//! below it (the driver's table in `driver/mod.rs` lists them in that order).
//!
//! The graph is read from the sources: every `use crate::…`, `use super::…` (and a parent's
//! `use child::…`), and every `crate::…`/`super::…` path in code, resolved to the longest
//! prefix that is a module; test code (`#[cfg(test)]` items and test-only modules) is left
//! out, since tests may reach across.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

type Module = Vec<String>;
type Graph = BTreeMap<Module, BTreeSet<Module>>;

/// Every module of the crate under `src` (path from the crate root), with its source text.
fn modules(src: &Path) -> BTreeMap<Module, String> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).expect("readable source tree") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    let mut files = vec![];
    walk(src, &mut files);
    files
        .into_iter()
        .map(|f| {
            let rel = f.strip_prefix(src).expect("under src").with_extension("");
            let mut parts: Module = rel.iter().map(|p| p.to_string_lossy().into_owned()).collect();
            if matches!(parts.last().map(String::as_str), Some("mod" | "lib")) {
                parts.pop();
            }
            (parts, std::fs::read_to_string(&f).expect("readable file"))
        })
        .collect()
}

/// The text without comments, string literals and `#[cfg(test)]` items.
fn code_only(text: &str) -> String {
    let mut out = String::new();
    for line in text.lines() {
        let line = line.split("//").next().unwrap_or("");
        out.push_str(line);
        out.push('\n');
    }
    let mut code = String::new();
    let mut in_string = false;
    let mut chars = out.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if in_string => {
                chars.next();
            }
            '"' => in_string = !in_string,
            _ if !in_string => code.push(c),
            _ => {}
        }
    }
    // Drop `#[cfg(test)]` items: the attribute and the item after it up to its end (`;` or the
    // matching closing brace).
    while let Some(at) = code.find("#[cfg(test)]") {
        let rest = &code[at..];
        let mut depth = 0usize;
        let mut end = rest.len();
        for (i, c) in rest.char_indices().skip("#[cfg(test)]".len()) {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = i + 1;
                        break;
                    }
                }
                ';' if depth == 0 => {
                    end = i + 1;
                    break;
                }
                _ => {}
            }
        }
        code.replace_range(at..at + end, "");
    }
    code
}

/// The modules declared `#[cfg(test)] mod name;` in a parent's text.
fn test_only_children(text: &str) -> Vec<String> {
    let words: Vec<&str> = text.split_whitespace().collect();
    words
        .windows(3)
        .filter(|w| w[0] == "#[cfg(test)]" && w[1] == "mod")
        .map(|w| w[2].trim_end_matches(';').to_string())
        .collect()
}

/// The paths a use tree names: `a::{b, c::{d, e}}` → a::b, a::c::d, a::c::e.
fn expand(tree: &str) -> Vec<String> {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        return vec![tree.split(" as ").next().unwrap_or(tree).trim().to_string()];
    };
    let prefix = tree[..open].trim_end_matches("::").trim();
    let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
    let (mut items, mut depth, mut start) = (vec![], 0, 0);
    for (i, c) in inner.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(&inner[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    items.push(&inner[start..]);
    items
        .into_iter()
        .filter(|i| !i.trim().is_empty())
        .flat_map(expand)
        .map(|p| if prefix.is_empty() { p } else { format!("{prefix}::{p}") })
        .collect()
}

/// The module a path names from module `here`: crate-absolute, relative to the parent
/// (`super`), or a child of `here`; the longest prefix that is a module.
fn resolve(path: &str, here: &Module, known: &BTreeMap<Module, String>) -> Option<Module> {
    let segments: Vec<&str> = path.split("::").map(str::trim).collect();
    let mut base: Module = match segments[0] {
        "crate" => vec![],
        "super" => here[..here.len().saturating_sub(1)].to_vec(),
        "self" => here.clone(),
        first => {
            let child: Module = here.iter().cloned().chain([first.to_string()]).collect();
            if !known.contains_key(&child) {
                return None;
            }
            here.clone()
        }
    };
    let mut rest = &segments[usize::from(matches!(segments[0], "crate" | "super" | "self"))..];
    while rest.first() == Some(&"super") {
        base.pop();
        rest = &rest[1..];
    }
    let mut best = None;
    let mut module = base.clone();
    for s in rest {
        module.push(s.to_string());
        if known.contains_key(&module) {
            best = Some(module.clone());
        }
    }
    best.or_else(|| (!base.is_empty() && known.contains_key(&base)).then_some(base))
}

/// The crate's module graph, test code left out.
fn graph(src: &Path) -> Graph {
    let mut known = modules(src);
    let test_only: Vec<Module> = known
        .iter()
        .flat_map(|(m, text)| {
            test_only_children(text)
                .into_iter()
                .map(move |c| m.iter().cloned().chain([c]).collect())
        })
        .collect();
    test_only.iter().for_each(|m| {
        known.remove(m);
    });
    let mut g = Graph::new();
    for (here, text) in &known {
        let code = code_only(text);
        let mut paths = vec![];
        for statement in code.split(';') {
            let s = statement.trim_start();
            let s = s
                .strip_prefix("pub(super) ")
                .or_else(|| s.strip_prefix("pub(crate) "))
                .or_else(|| s.strip_prefix("pub "))
                .unwrap_or(s);
            if let Some(tree) = s.strip_prefix("use ") {
                paths.extend(expand(tree));
            }
        }
        for root in ["crate::", "super::"] {
            let mut rest = code.as_str();
            while let Some(at) = rest.find(root) {
                let tail = &rest[at..];
                let end = tail
                    .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                    .unwrap_or(tail.len());
                paths.push(tail[..end].trim_end_matches(':').to_string());
                rest = &tail[root.len()..];
            }
        }
        let edges = g.entry(here.clone()).or_default();
        for p in paths {
            if let Some(target) = resolve(&p, here, &known) {
                if &target != here && !target.is_empty() {
                    edges.insert(target);
                }
            }
        }
    }
    g
}

/// A cycle of the graph, if it has one (as the modules along it).
fn find_cycle(g: &Graph) -> Option<Vec<Module>> {
    fn visit(
        m: &Module,
        g: &Graph,
        state: &mut BTreeMap<Module, u8>,
        path: &mut Vec<Module>,
    ) -> Option<Vec<Module>> {
        state.insert(m.clone(), 1);
        path.push(m.clone());
        for next in g.get(m).into_iter().flatten() {
            match state.get(next).copied().unwrap_or(0) {
                1 => {
                    let from = path.iter().position(|x| x == next).unwrap_or(0);
                    return Some(path[from..].iter().cloned().chain([next.clone()]).collect());
                }
                0 => {
                    if let Some(cycle) = visit(next, g, state, path) {
                        return Some(cycle);
                    }
                }
                _ => {}
            }
        }
        path.pop();
        state.insert(m.clone(), 2);
        None
    }
    let mut state = BTreeMap::new();
    g.keys().find_map(|m| {
        if state.contains_key(m) {
            None
        } else {
            visit(m, g, &mut state, &mut vec![])
        }
    })
}

fn name(m: &Module) -> String {
    if m.is_empty() {
        "crate".into()
    } else {
        m.join("::")
    }
}

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

#[test]
fn the_crates_modules_import_each_other_without_cycles() {
    let g = graph(&src());
    if let Some(cycle) = find_cycle(&g) {
        panic!("module cycle: {}", cycle.iter().map(name).collect::<Vec<_>>().join(" -> "));
    }
}

/// The reader sees the imports the driver is built on (so the test above is not vacuous), and
/// the detector finds a cycle where there is one.
#[test]
fn the_reader_sees_known_imports_and_the_detector_finds_a_cycle() {
    let g = graph(&src());
    let m = |s: &str| -> Module { s.split("::").map(String::from).collect() };
    for (from, to) in [
        ("driver::trial", "driver::engine"),
        ("driver::window", "driver::selection"),
        ("driver", "driver::window"),
        ("low_rank", "factor"),
        ("driver::recording", "driver::checks"),
    ] {
        assert!(
            g.get(&m(from)).is_some_and(|e| e.contains(&m(to))),
            "{from} -> {to} not read; edges of {from}: {:?}",
            g.get(&m(from))
        );
    }
    let mut looped = g.clone();
    looped.entry(m("driver::engine")).or_default().insert(m("driver::window"));
    let cycle = find_cycle(&looped).expect("engine -> window -> ... -> engine is a cycle");
    assert!(cycle.contains(&m("driver::engine")) && cycle.first() == cycle.last(), "{cycle:?}");
}

#[test]
fn use_trees_expand_to_every_path() {
    assert_eq!(expand("super::{a::{B, C}, d as e}"), ["super::a::B", "super::a::C", "super::d"]);
    assert_eq!(expand("crate::x::Y"), ["crate::x::Y"]);
}
