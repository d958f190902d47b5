//! Every engine item the docs name (`physics::hertz::exact`, `model::Model::new`, ...)
//! exists at that path, so `docs/model.md` keeps mapping the paper to real functions when
//! code moves.

use std::path::{Path, PathBuf};

const ENGINE: &str = "crates/bearing-core/src";
const DOCS: &[&str] = &["docs/model.md", "docs/architecture.md"];

/// The file of module `segments` (relative to the engine root), if there is one.
fn module_file(root: &Path, segments: &[&str]) -> Option<PathBuf> {
    let rel: PathBuf = segments.iter().collect();
    let file = root.join(&rel).with_extension("rs");
    let dir = root.join(&rel).join("mod.rs");
    [file, dir].into_iter().find(|p| p.is_file())
}

/// Every module path of the engine, e.g. `["physics", "hertz"]`.
fn modules(root: &Path, prefix: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    for entry in std::fs::read_dir(root.join(prefix.iter().collect::<PathBuf>())).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        if path.is_dir() {
            prefix.push(name);
            out.push(prefix.clone());
            modules(root, prefix, out);
            prefix.pop();
        } else if path.extension().is_some_and(|e| e == "rs") && name != "mod" && name != "lib" {
            let mut m = prefix.clone();
            m.push(name);
            out.push(m);
        }
    }
}

/// Is `name` declared in `source` (as an item, a method, or a re-export)?
fn declares(source: &str, name: &str) -> bool {
    let kinds = [
        "fn", "struct", "enum", "mod", "type", "const", "trait", "static",
    ];
    source.lines().any(|l| {
        let l = l.trim_start();
        let words: Vec<&str> = l
            .split(|c: char| !(c.is_alphanumeric() || c == '_'))
            .filter(|w| !w.is_empty())
            .collect();
        words
            .windows(2)
            .any(|w| kinds.contains(&w[0]) && w[1] == name)
            || (l.starts_with("pub use") && words.contains(&name))
    })
}

/// `a::b::{c, d}` -> `a::b::c`, `a::b::d`.
fn expand(path: &str) -> Vec<String> {
    match path.split_once("::{") {
        Some((head, tail)) => tail
            .trim_end_matches('}')
            .split(',')
            .map(|t| format!("{head}::{}", t.trim()))
            .collect(),
        None => vec![path.to_string()],
    }
}

/// Why `path` does not resolve, or `None` if it does.
fn check(root: &Path, all: &[Vec<String>], path: &str) -> Option<String> {
    let segs: Vec<&str> = path.split("::").collect();
    // the module: the path's own prefix from the engine root, or else a module whose path
    // ends with the path's first segments (docs say `race_contact::contact_geometry`)
    for take in (1..=segs.len()).rev() {
        let head = &segs[..take];
        let candidates: Vec<&Vec<String>> = all
            .iter()
            .filter(|m| m.len() >= head.len() && m[m.len() - head.len()..] == *head)
            .collect();
        let module = match candidates.as_slice() {
            [one] => *one,
            [] => continue,
            many => match many.iter().find(|m| m.len() == head.len()) {
                Some(m) => *m,
                None => return Some(format!("`{path}`: `{}` is ambiguous", head.join("::"))),
            },
        };
        let rest = &segs[take..];
        let file = module_file(root, &module.iter().map(String::as_str).collect::<Vec<_>>())?;
        let source = std::fs::read_to_string(&file).unwrap();
        return match rest {
            [] => None,
            [item] | [_, item] if declares(&source, item) => None,
            _ => Some(format!(
                "`{path}`: `{}` is not declared in {}",
                rest.join("::"),
                file.display()
            )),
        };
    }
    Some(format!("`{path}`: no engine module matches"))
}

#[test]
fn docs_name_engine_items_that_exist() {
    let base = Path::new(env!("CARGO_MANIFEST_DIR"));
    let root = base.join(ENGINE);
    let mut all = Vec::new();
    modules(&root, &mut Vec::new(), &mut all);
    let mut problems = Vec::new();
    let mut checked = 0;
    for doc in DOCS {
        let text = std::fs::read_to_string(base.join(doc)).unwrap();
        for (n, line) in text.lines().enumerate() {
            for (i, span) in line.split('`').enumerate() {
                // odd pieces are inside backticks; engine paths start with a module name
                let first = span.split("::").next().unwrap_or("");
                let is_path = i % 2 == 1
                    && span.contains("::")
                    && span
                        .chars()
                        .all(|c| c.is_alphanumeric() || "_:{}, ".contains(c))
                    && all.iter().any(|m| m.last().is_some_and(|l| l == first));
                if !is_path {
                    continue;
                }
                for p in expand(span) {
                    checked += 1;
                    if let Some(why) = check(&root, &all, &p) {
                        problems.push(format!("{doc}:{}: {why}", n + 1));
                    }
                }
            }
        }
    }
    assert!(
        checked > 30,
        "only {checked} paths found: is the scan still reading the docs?"
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
