//! Every engine item the docs name (`physics::hertz::exact`, `model::Model::new`, ...)
//! exists at that path, so `docs/reference/model.md` keeps mapping the paper to real functions
//! when code moves; and every relative link in `README.md` and `docs/**/*.md` resolves.

use std::path::{Path, PathBuf};

const ENGINE: &str = "crates/bearing-core/src";
const DOCS: &[&str] = &["docs/reference/model.md", "docs/reference/architecture.md"];

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

/// Every Markdown file whose relative links `relative_links_resolve` checks: the README and
/// everything under `docs/`.
fn markdown_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            markdown_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "md") {
            out.push(path);
        }
    }
}

/// The targets of the inline links `[text](target)` and images in `text`, outside fenced
/// code blocks, with the line each is on.
fn link_targets(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut fenced = false;
    for (n, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        for piece in line.split("](").skip(1) {
            if let Some(end) = piece.find(')') {
                out.push((n + 1, piece[..end].to_string()));
            }
        }
    }
    out
}

/// A link left pointing at a moved or renamed file fails here rather than in a reader's
/// browser.
#[test]
fn relative_links_resolve() {
    let base = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![base.join("README.md")];
    markdown_files(&base.join("docs"), &mut files);
    let (mut checked, mut broken) = (0, Vec::new());
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for (line, target) in link_targets(&text) {
            let path = target.split('#').next().unwrap_or("");
            // external (scheme:), in-page (#...) and site-absolute links are not files here
            if path.is_empty() || path.contains(':') || path.starts_with('/') {
                continue;
            }
            checked += 1;
            if !file.parent().unwrap().join(path).exists() {
                let rel = file.strip_prefix(base).unwrap_or(file);
                broken.push(format!(
                    "{}:{line}: `{target}` does not exist",
                    rel.display()
                ));
            }
        }
    }
    assert!(
        checked > 30,
        "only {checked} links found: is the scan still reading the docs?"
    );
    assert!(broken.is_empty(), "{}", broken.join("\n"));
}

#[test]
fn link_targets_skip_code_and_keep_anchors() {
    let text =
        "See [a](x.md#s) and ![b](img/p.png).\n```sh\ncurl [c](no.md)\n```\n[d](https://e.org)";
    let got: Vec<(usize, String)> = link_targets(text);
    let want = [(1, "x.md#s"), (1, "img/p.png"), (5, "https://e.org")];
    assert_eq!(
        got,
        want.map(|(n, t)| (n, t.to_string())).to_vec(),
        "targets with their lines"
    );
}
