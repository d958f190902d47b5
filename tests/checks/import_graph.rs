//! Import-graph checks over the source files: no import cycles between files, and every
//! dependency follows the layer order declared below, which the layer tables of
//! docs/reference/architecture.md state too (checked). Standard library only: the parser
//! blanks comments and literals, then reads `use` trees and inline paths (`crate::`,
//! `super::`, `self::`, the library's extern name, and child modules declared with `mod x;`).
//!
//! Run alone: `cargo test --test checks import_graph -- --nocapture`.

use std::collections::{BTreeMap, BTreeSet, HashMap, VecDeque};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Crates to check: (name, source root relative to the manifest dir, extern name of the
/// library whose `lib.rs` is in that root). With the extern name, `bearing_sim::x::y` in the
/// binary's files (`main.rs` and the modules it declares) resolves like `crate::x::y`.
/// A root that does not exist fails the test.
const CRATES: &[(&str, &str, Option<&str>)] = &[
    ("service", "src", Some("bearing_sim")),
    ("engine", "crates/bearing-core/src", Some("bearing_core")),
];

/// Name of the top-level "module" of the crate root files (`lib.rs`, `main.rs`).
const ROOT: &str = "<root>";

/// Intended layering of one crate, by top-level module (the first segment of a module path:
/// `jobs` for `src/jobs/runner.rs`, [`ROOT`] for `lib.rs` and `main.rs`). The layer tables
/// of [`LAYER_DOC`] state the same ranks and pairs; `doc_layer_table_matches_layers` fails
/// when the two differ.
///
/// Dependencies point down. A file in a module of rank `r` may use:
/// - any file of its own top-level module;
/// - modules of a lower rank;
/// - another module of the same rank only if `(from, to)` is in `allowed`.
///
/// `(from, to)` in `forbidden` is rejected whatever the ranks say. Every top-level module
/// found in the crate must have a rank: a missing one fails the test, so the table stays
/// complete. To change the intended design, edit the numbers; gaps between ranks are free.
struct Layers {
    krate: &'static str,
    ranks: &'static [(&'static str, u32)],
    allowed: &'static [(&'static str, &'static str)],
    forbidden: &'static [(&'static str, &'static str)],
}

const LAYERS: &[Layers] = &[
    Layers {
        krate: "engine",
        ranks: &[
            ("json_float", 0),
            // Merge patches and pointer assignments on scene documents (requests, designs).
            ("json_doc", 0),
            // The generic ODE solver: it imports nothing of the engine (forbidden pairs below).
            ("ode", 1),
            ("scene", 1),
            ("physics", 2),
            // Signal analysis knows bearings (scene) and nothing of the models.
            ("signal", 2),
            ("model", 3),
            // The integrator starts from a state vector it is given: it does not know the
            // quasi-static solver, nor the solver the integrator (same rank, no pair allowed).
            ("quasi_static", 4),
            ("dynamics", 4),
            ("simulation", 5),
            // The glue that analyses a simulated signal sits above both.
            ("simulation_analysis", 6),
            // A simulated run written as a measured recording (needs its shaft angle).
            ("run_recording", 7),
            // The stress suite builds scenes, runs them and checks their results.
            ("stress", 6),
            // Where the stiffness is: a run's state and its Jacobian's spectrum (lab tool).
            ("stiffness", 6),
            // Study requests, designs and plans as data, and the table read from runs.
            ("study", 7),
            (ROOT, 10),
        ],
        allowed: &[],
        // The ODE module is generic whatever the ranks say: it never imports the bearing.
        forbidden: &[
            ("ode", "scene"),
            ("ode", "physics"),
            ("ode", "signal"),
            ("ode", "model"),
            ("ode", "quasi_static"),
            ("ode", "dynamics"),
        ],
    },
    Layers {
        krate: "service",
        ranks: &[
            ("store", 10),
            ("metrics", 11),
            // Plots draw engine types to SVG; the CLI and (later) the API use them.
            ("plots", 11),
            ("config", 12),
            // Study designs, tables and plots: the API queues their points, the CLI runs them.
            ("studies", 12),
            ("jobs", 13),
            ("api", 14),
            ("serve", 15),
            ("cli", 16),
            (ROOT, 20),
        ],
        allowed: &[],
        forbidden: &[
            // The CLI runs the engine in-process; it does not go through the service.
            ("cli", "api"),
            ("cli", "jobs"),
            ("cli", "store"),
        ],
    },
];

#[test]
fn no_import_cycles() {
    let mut report = String::new();
    for &(name, root, lib) in CRATES {
        let g = load(name, root, lib);
        let mut adj = vec![Vec::new(); g.files.len()];
        g.edges.keys().for_each(|&(a, b)| adj[a].push(b));
        for scc in sccs(&adj).into_iter().filter(|c| c.len() > 1) {
            let files: Vec<&str> = scc.iter().map(|&f| g.files[f].rel.as_str()).collect();
            let _ = writeln!(
                report,
                "crate `{name}`: import cycle among {} files: {}",
                scc.len(),
                files.join(", ")
            );
            let _ = writeln!(report, "  one cycle through them:");
            let path = cycle_through(scc[0], &scc, &adj);
            let on_path: BTreeSet<(usize, usize)> = (0..path.len())
                .map(|k| (path[k], path[(k + 1) % path.len()]))
                .collect();
            for k in 0..path.len() {
                let _ = writeln!(
                    report,
                    "    {}",
                    g.edge_text(path[k], path[(k + 1) % path.len()], true)
                );
            }
            // Every import between files of the component lies on some cycle.
            let others: Vec<_> = g
                .edges
                .keys()
                .filter(|e| scc.contains(&e.0) && scc.contains(&e.1) && !on_path.contains(e))
                .collect();
            if !others.is_empty() {
                let _ = writeln!(report, "  other imports inside it:");
            }
            for &(a, b) in others {
                let _ = writeln!(report, "    {}", g.edge_text(a, b, false));
            }
        }
    }
    assert!(report.is_empty(), "\n{report}\nBreak each cycle: move what both files need into a lower module, or invert one dependency.\n");
}

#[test]
fn layer_order_respected() {
    let mut report = String::new();
    for &(name, root, lib) in CRATES {
        let layers = LAYERS.iter().find(|l| l.krate == name);
        let layers = layers.unwrap_or_else(|| {
            panic!("crate `{name}` has no entry in LAYERS (tests/checks/import_graph.rs); add one")
        });
        let g = load(name, root, lib);
        let rank = |m: &str| layers.ranks.iter().find(|r| r.0 == m).map(|r| r.1);
        let has =
            |pairs: &[(&str, &str)], a: &str, b: &str| pairs.iter().any(|p| p.0 == a && p.1 == b);

        let mut missing: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
        for f in g.files.iter().filter(|f| rank(f.top()).is_none()) {
            missing.entry(f.top()).or_default().push(&f.rel);
        }
        for (m, files) in &missing {
            let _ = writeln!(report, "crate `{name}`: top-level module `{m}` ({}) has no rank: add (\"{m}\", <rank>) to its LAYERS entry", files.join(", "));
        }
        for &(a, b) in g.edges.keys() {
            let (ma, mb) = (g.files[a].top(), g.files[b].top());
            let (Some(ra), Some(rb)) = (rank(ma), rank(mb)) else {
                continue;
            };
            let why = if ma == mb {
                continue;
            } else if has(layers.forbidden, ma, mb) {
                "pair is forbidden"
            } else if rb > ra {
                "uses a higher layer"
            } else if rb == ra && !has(layers.allowed, ma, mb) {
                "same rank, pair not in `allowed`"
            } else {
                continue;
            };
            let _ = writeln!(
                report,
                "[{ma}, rank {ra}] -> [{mb}, rank {rb}] {why}: {}",
                g.edge_text(a, b, true)
            );
        }
    }
    assert!(report.is_empty(), "\n{report}\nFix the import, or change the intended layering in LAYERS (tests/checks/import_graph.rs).\n");
}

/// The page whose layer tables a reader sees. `doc_layer_table_matches_layers` keeps them
/// equal to [`LAYERS`], so changing the layering means editing both.
const LAYER_DOC: &str = "docs/reference/architecture.md";

/// The layering as a set of statements, one per rank (`crate engine: json_float rank 0`)
/// and per pair (`crate service: cli may not use api`), so a doc and `LAYERS` compare as sets.
fn rank_line(krate: &str, module: &str, rank: u32) -> String {
    format!("crate {krate}: {module} rank {rank}")
}

fn pair_line(krate: &str, from: &str, verb: &str, to: &str) -> String {
    format!("crate {krate}: {from} {verb} {to}")
}

/// The statements of the tables under `## Layers` in `doc`. A rank table has the header
/// `| crate | rank | module | ... |`; a pair table `| crate | module | may not use |`
/// (`forbidden`) or `| crate | module | may also use |` (`allowed`). A module cell is its
/// first word in backticks (`<root>` for the crate roots).
fn doc_layers(doc: &str) -> BTreeSet<String> {
    let start = doc
        .find("\n## Layers\n")
        .unwrap_or_else(|| panic!("{LAYER_DOC} has no `## Layers` section"));
    let section = &doc[start + 1..];
    let section = &section[..section[3..].find("\n## ").map_or(section.len(), |e| e + 3)];
    let module = |cell: &str| cell.split('`').nth(1).unwrap_or(cell).to_string();
    let mut out = BTreeSet::new();
    let mut header: Vec<String> = Vec::new();
    for line in section.lines().map(str::trim) {
        if !line.starts_with('|') {
            header.clear();
            continue;
        }
        let cells: Vec<String> = line
            .trim_matches('|')
            .split('|')
            .map(|c| c.trim().to_string())
            .collect();
        let separator = cells.iter().all(|c| c.chars().all(|ch| "-: ".contains(ch)));
        if header.is_empty() {
            header = cells;
            continue;
        } else if separator {
            continue;
        }
        match header
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>()
            .as_slice()
        {
            ["crate", "rank", "module", ..] => {
                let rank = cells[1].parse().unwrap_or_else(|_| {
                    panic!("{LAYER_DOC}: rank `{}` is not a number: {line}", cells[1])
                });
                out.insert(rank_line(&cells[0], &module(&cells[2]), rank));
            }
            ["crate", "module", verb @ ("may not use" | "may also use")] => {
                out.insert(pair_line(
                    &cells[0],
                    &module(&cells[1]),
                    verb,
                    &module(&cells[2]),
                ));
            }
            _ => {}
        }
    }
    out
}

#[test]
fn doc_layer_table_matches_layers() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(LAYER_DOC);
    let doc = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let in_doc = doc_layers(&doc);
    let mut in_layers = BTreeSet::new();
    for l in LAYERS {
        let k = l.krate;
        in_layers.extend(l.ranks.iter().map(|&(m, r)| rank_line(k, m, r)));
        in_layers.extend(
            l.forbidden
                .iter()
                .map(|&(a, b)| pair_line(k, a, "may not use", b)),
        );
        in_layers.extend(
            l.allowed
                .iter()
                .map(|&(a, b)| pair_line(k, a, "may also use", b)),
        );
    }
    assert!(
        in_layers.len() > 10,
        "only {} statements from LAYERS: is the comparison still reading them?",
        in_layers.len()
    );
    let mut report = String::new();
    for s in in_layers.difference(&in_doc) {
        let _ = writeln!(report, "in LAYERS, not in {LAYER_DOC}: {s}");
    }
    for s in in_doc.difference(&in_layers) {
        let _ = writeln!(report, "in {LAYER_DOC}, not in LAYERS: {s}");
    }
    assert!(report.is_empty(), "\n{report}\nThe layer tables of {LAYER_DOC} and LAYERS (tests/checks/import_graph.rs) must state the same layering: edit both.\n");
}

#[test]
fn doc_layer_parser_reads_tables() {
    let doc = "# A\n\n## Layers\n\nText.\n\n\
        | crate | rank | module | what |\n| --- | --- | --- | --- |\n\
        | engine | 0 | `a` | x |\n| engine | 10 | `<root>` | `lib.rs` |\n\n\
        | crate | module | may not use |\n| --- | --- | --- |\n| service | `cli` | `api` |\n\n\
        ## Next\n\n| crate | rank | module | what |\n| --- | --- | --- | --- |\n\
        | engine | 5 | `outside` | x |\n";
    let want = BTreeSet::from([
        rank_line("engine", "a", 0),
        rank_line("engine", ROOT, 10),
        pair_line("service", "cli", "may not use", "api"),
    ]);
    assert_eq!(doc_layers(doc), want);
}

// ---------------------------------------------------------------- file graph

struct SourceFile {
    /// Path relative to the manifest dir, for messages.
    rel: String,
    /// Module path; empty for the crate roots `lib.rs` and `main.rs`.
    module: Vec<String>,
    lines: Vec<String>,
    parsed: Parsed,
}

impl SourceFile {
    fn top(&self) -> &str {
        self.module.first().map_or(ROOT, String::as_str)
    }
}

struct Graph {
    files: Vec<SourceFile>,
    /// (from, to) file indices -> lines of `from` that make the edge.
    edges: BTreeMap<(usize, usize), BTreeSet<usize>>,
}

impl Graph {
    /// "src/a.rs:4 (also line 60) -> src/b.rs", and the source of the first line if `code`.
    fn edge_text(&self, a: usize, b: usize, code: bool) -> String {
        let (f, lines) = (&self.files[a], &self.edges[&(a, b)]);
        let first = *lines.iter().next().unwrap();
        let more: Vec<String> = lines.iter().skip(1).map(|l| l.to_string()).collect();
        let also = match more.len() {
            0 => String::new(),
            1 => format!(" (also line {})", more[0]),
            _ => format!(" (also lines {})", more.join(", ")),
        };
        let src = f.lines.get(first - 1).map_or("", |l| l.trim());
        let src = if code {
            format!("    `{src}`")
        } else {
            String::new()
        };
        format!("{}:{first}{also} -> {}{src}", f.rel, self.files[b].rel)
    }
}

fn load(name: &str, root: &str, lib_name: Option<&str>) -> Graph {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let dir = manifest.join(root);
    assert!(dir.is_dir(), "crate `{name}`: source root `{root}` ({}) does not exist; fix CRATES in tests/checks/import_graph.rs", dir.display());
    let mut paths = Vec::new();
    rs_files(&dir, &mut paths);

    let mut files: Vec<SourceFile> = Vec::new();
    let mut by_module: HashMap<Vec<String>, usize> = HashMap::new();
    let (mut lib, mut main) = (None, None);
    for p in paths {
        let in_root = p.strip_prefix(&dir).unwrap();
        let module = module_path(in_root);
        let rel = p
            .strip_prefix(&manifest)
            .unwrap_or(&p)
            .to_string_lossy()
            .replace('\\', "/");
        let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("cannot read {rel}: {e}"));
        let idx = files.len();
        if module.is_empty() {
            *(if in_root == Path::new("lib.rs") {
                &mut lib
            } else {
                &mut main
            }) = Some(idx);
        } else if let Some(&other) = by_module.get(&module) {
            panic!(
                "{} and {rel} are both module `{}`",
                files[other].rel,
                module.join("::")
            );
        } else {
            by_module.insert(module.clone(), idx);
        }
        let lines = text.lines().map(String::from).collect();
        files.push(SourceFile {
            rel,
            module,
            lines,
            parsed: parse(&text),
        });
    }

    let mut edges: BTreeMap<(usize, usize), BTreeSet<usize>> = BTreeMap::new();
    let is_module = |m: &[String]| by_module.contains_key(m);
    for (from, f) in files.iter().enumerate() {
        // `crate` is the root of this file's compilation unit: main.rs for the modules it
        // declares, else lib.rs. Both units share the directory, so modules are found by
        // path whichever root declares them.
        let unit_root = match f.module.first() {
            None => Some(from),
            Some(top) => match main {
                Some(m) if files[m].parsed.mods.contains(top) => Some(m),
                _ => lib.or(main),
            },
        };
        for p in &f.parsed.paths {
            let Some((module, via_lib, line)) =
                resolve(&f.module, &f.parsed.mods, lib_name, p, &is_module)
            else {
                continue;
            };
            let to = match (module.is_empty(), via_lib) {
                (false, _) => Some(by_module[&module]),
                (true, true) => lib,
                (true, false) => unit_root,
            };
            if let Some(to) = to.filter(|&to| to != from) {
                edges.entry((from, to)).or_default().insert(line);
            }
        }
    }
    Graph { files, edges }
}

fn rs_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let read =
        std::fs::read_dir(dir).unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()));
    let mut entries: Vec<PathBuf> = read.map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rs_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// `lib.rs`/`main.rs` -> crate root (empty); `a/mod.rs` and `a.rs` -> `a`; `a/b.rs` -> `a::b`.
fn module_path(in_root: &Path) -> Vec<String> {
    let mut segs: Vec<String> = in_root
        .with_extension("")
        .iter()
        .map(|s| s.to_string_lossy().into_owned())
        .collect();
    if segs.last().is_some_and(|s| s == "mod") {
        segs.pop();
    }
    if segs.len() == 1 && (segs[0] == "lib" || segs[0] == "main") {
        segs.clear();
    }
    segs
}

/// Kosaraju's strongly connected components, each sorted.
fn sccs(adj: &[Vec<usize>]) -> Vec<Vec<usize>> {
    // Depth-first from `v`, pushing each newly reached vertex after its successors.
    fn post_order(v: usize, adj: &[Vec<usize>], seen: &mut [bool], out: &mut Vec<usize>) {
        if !std::mem::replace(&mut seen[v], true) {
            adj[v].iter().for_each(|&w| post_order(w, adj, seen, out));
            out.push(v);
        }
    }
    let n = adj.len();
    let mut rev = vec![Vec::new(); n];
    for (v, ws) in adj.iter().enumerate() {
        ws.iter().for_each(|&w| rev[w].push(v));
    }
    let (mut seen, mut finish) = (vec![false; n], Vec::new());
    (0..n).for_each(|v| post_order(v, adj, &mut seen, &mut finish));
    // In decreasing finish time, what a vertex reaches in the reversed graph is its component.
    let mut seen = vec![false; n];
    let mut comps = Vec::new();
    for &v in finish.iter().rev() {
        let mut comp = Vec::new();
        post_order(v, &rev, &mut seen, &mut comp);
        if !comp.is_empty() {
            comp.sort();
            comps.push(comp);
        }
    }
    comps
}

/// A shortest cycle from `s` back to itself inside the component `scc` (breadth-first),
/// as the files it passes through, starting with `s`.
fn cycle_through(s: usize, scc: &[usize], adj: &[Vec<usize>]) -> Vec<usize> {
    let mut prev: HashMap<usize, usize> = HashMap::new();
    let mut queue = VecDeque::from([s]);
    while let Some(v) = queue.pop_front() {
        for &w in adj[v].iter().filter(|w| scc.contains(w)) {
            if w == s {
                let mut path = vec![v];
                while *path.last().unwrap() != s {
                    path.push(prev[path.last().unwrap()]);
                }
                path.reverse();
                return path;
            }
            if let std::collections::hash_map::Entry::Vacant(e) = prev.entry(w) {
                e.insert(v);
                queue.push_back(w);
            }
        }
    }
    unreachable!("a strongly connected component of several files has a cycle through each")
}

// ---------------------------------------------------------------- resolution

/// Resolves `path`, written in the file of module `here` that declares the child modules
/// `children`, to the longest prefix that is a module with its own file. Returns that module
/// (empty: the crate root; the library's if the `bool` is set) and the line of the path token
/// that names it. Re-exports are not followed: `crate::store::Artifact` lands in `store`.
/// `None` for paths outside the crate or inside the same file.
fn resolve(
    here: &[String],
    children: &[String],
    lib_name: Option<&str>,
    path: &RawPath,
    is_module: &dyn Fn(&[String]) -> bool,
) -> Option<(Vec<String>, bool, usize)> {
    let segs = &path.segs;
    let first = segs[0].0.as_str();
    let inline = path.inline_depth;
    let (base, skip, via_lib) = match first {
        "crate" => (Vec::new(), 1, false),
        _ if Some(first) == lib_name => (Vec::new(), 1, true),
        "self" if inline == 0 => (here.to_vec(), 1, false),
        "super" => {
            // Inside an inline `mod x { }` the first `super` only leaves that block.
            let n = segs.iter().take_while(|s| s.0 == "super").count();
            let up = n.checked_sub(inline).filter(|&u| u > 0)?;
            (here[..here.len().checked_sub(up)?].to_vec(), n, false)
        }
        // Edition 2018 relative path into a child module: `runner::worker_loop`.
        _ if inline == 0 && children.iter().any(|c| c == first) => (here.to_vec(), 0, false),
        _ => return None,
    };
    let mut full = base.clone();
    full.extend(segs[skip..].iter().map(|s| s.0.clone()));
    let k = (1..=full.len())
        .rev()
        .find(|&k| is_module(&full[..k]))
        .unwrap_or(0);
    let tok = if k > base.len() {
        skip + (k - base.len()) - 1
    } else {
        skip.saturating_sub(1)
    };
    Some((full[..k].to_vec(), via_lib, segs[tok.min(segs.len() - 1)].1))
}

// ---------------------------------------------------------------- parsing

/// A path as written, each segment with its line, and how many inline `mod x { }` blocks
/// enclose it.
struct RawPath {
    segs: Vec<(String, usize)>,
    inline_depth: usize,
}

struct Parsed {
    /// `mod x;` declarations at file level (not dependencies; needed for relative paths).
    mods: Vec<String>,
    paths: Vec<RawPath>,
}

#[derive(Clone)]
struct Tok {
    text: String,
    line: usize,
}

fn parse(src: &str) -> Parsed {
    let toks = without_cfg_test(tokenize(src));
    let mut parsed = Parsed {
        mods: Vec::new(),
        paths: Vec::new(),
    };
    let text = |i: usize| toks.get(i).map_or("", |t| t.text.as_str());
    let (mut depth, mut inline, mut i) = (0usize, Vec::<usize>::new(), 0);
    while i < toks.len() {
        let t = text(i);
        match t {
            "{" => depth += 1,
            "}" => {
                if inline.last() == Some(&depth) {
                    inline.pop();
                }
                depth = depth.saturating_sub(1);
            }
            "mod" if text(i + 2) == ";" && inline.is_empty() => {
                parsed.mods.push(text(i + 1).to_string())
            }
            "mod" if text(i + 2) == "{" => inline.push(depth + 1),
            "use" if text(i + 1) != "<" => {
                let mut trees = Vec::new();
                i = use_tree(&toks, i + 1, Vec::new(), &mut trees);
                parsed.paths.extend(trees.into_iter().map(|segs| RawPath {
                    segs,
                    inline_depth: inline.len(),
                }));
                continue;
            }
            _ if is_ident(t) && text(i + 1) == "::" && is_ident(text(i + 2)) => {
                // Inline path `a::b::c`. Not the tail of a longer path, a method turbofish or
                // `pub(in crate::x)` (a visibility, not a dependency).
                let prev = if i > 0 { text(i - 1) } else { "" };
                let keep =
                    prev != "::" && prev != "." && !(prev == "in" && i >= 2 && text(i - 2) == "(");
                let mut segs = vec![(t.to_string(), toks[i].line)];
                i += 1;
                while text(i) == "::" && is_ident(text(i + 1)) {
                    segs.push((text(i + 1).to_string(), toks[i + 1].line));
                    i += 2;
                }
                if keep {
                    parsed.paths.push(RawPath {
                        segs,
                        inline_depth: inline.len(),
                    });
                }
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    parsed
}

/// Reads one use tree from `i` under `prefix`, pushing each leaf path (`a::{b, c::*, d as e,
/// self}` gives `a::b`, `a::c`, `a::d`, `a`). Returns the index of the token after the tree.
fn use_tree(
    toks: &[Tok],
    mut i: usize,
    mut prefix: Vec<(String, usize)>,
    out: &mut Vec<Vec<(String, usize)>>,
) -> usize {
    while let Some(t) = toks.get(i) {
        match t.text.as_str() {
            // `::std::x`: a path from the extern prelude, never this crate.
            "::" if prefix.is_empty() => prefix.push(("::".into(), t.line)),
            "::" | "self" if !prefix.is_empty() => {} // `a::{self}` names `a`
            "{" => {
                i += 1;
                while let Some(t) = toks.get(i) {
                    match t.text.as_str() {
                        "}" => return i + 1,
                        "," => i += 1,
                        _ => match use_tree(toks, i, prefix.clone(), out) {
                            j if j == i => return i, // malformed: stop
                            j => i = j,
                        },
                    }
                }
                return i;
            }
            "*" => {
                out.push(prefix);
                return i + 1;
            }
            "as" => i += 1, // skip the new name
            s if is_ident(s) => prefix.push((s.to_string(), t.line)),
            _ => {
                // `,` `}` `;` end the tree.
                if !prefix.is_empty() {
                    out.push(prefix);
                }
                return i;
            }
        }
        i += 1;
    }
    i
}

/// Drops every item marked `#[cfg(test)]` (mostly `mod tests { }`, also test-only imports and
/// helpers): test code may import freely, and `super::` in `mod tests` means the file itself.
/// A file marked `#![cfg(test)]` gives no tokens at all.
fn without_cfg_test(toks: Vec<Tok>) -> Vec<Tok> {
    let is = |i: usize, s: &str| toks.get(i).is_some_and(|t| t.text == s);
    let (mut out, mut i) = (Vec::new(), 0);
    while i < toks.len() {
        let inner = is(i + 1, "!");
        let a = i + 1 + inner as usize;
        if !(is(i, "#")
            && ["[", "cfg", "(", "test", ")", "]"]
                .iter()
                .enumerate()
                .all(|(k, s)| is(a + k, s)))
        {
            out.push(toks[i].clone());
            i += 1;
            continue;
        } else if inner {
            return Vec::new();
        }
        // Skip the item: up to a `;` outside brackets or the `}` that closes its body.
        let mut depth = 0;
        i = a + 6;
        while let Some(t) = toks.get(i) {
            i += 1;
            match t.text.as_str() {
                "(" | "[" | "{" => depth += 1,
                ")" | "]" => depth -= 1,
                "}" if depth <= 1 => break,
                "}" => depth -= 1,
                ";" if depth == 0 => break,
                _ => {}
            }
        }
    }
    out
}

/// Splits source into identifiers, keywords and numbers (raw identifiers keep their `r#`),
/// `::` and single characters. Comments (line, nested block, doc) are dropped and each string
/// or char literal (plain, byte, C, raw) becomes one `"` token: text in them is not code.
fn tokenize(src: &str) -> Vec<Tok> {
    let c: Vec<char> = src.chars().collect();
    let ident_end = |i: usize| i + c[i..].iter().take_while(|&&ch| is_ident_char(ch)).count();
    let (mut toks, mut line, mut i) = (Vec::new(), 1, 0);
    while i < c.len() {
        let mut end = i + 1;
        if c[i..].starts_with(&['/', '/']) {
            end = i + c[i..].iter().take_while(|&&ch| ch != '\n').count();
        } else if c[i..].starts_with(&['/', '*']) {
            let mut depth = 0;
            end = i;
            while end < c.len() && (end == i || depth > 0) {
                let (open, close) = (
                    c[end..].starts_with(&['/', '*']),
                    c[end..].starts_with(&['*', '/']),
                );
                depth += open as i32 - close as i32;
                end += if open || close { 2 } else { 1 };
            }
        } else if let Some(e) = literal_end(&c, i) {
            toks.push(Tok {
                text: "\"".into(),
                line,
            });
            end = e.min(c.len());
        } else if !c[i].is_whitespace() {
            if is_ident_char(c[i]) {
                end = ident_end(i);
                if c[i..end] == ['r']
                    && c.get(end) == Some(&'#')
                    && c.get(end + 1).is_some_and(|&ch| is_ident_char(ch))
                {
                    end = ident_end(end + 1);
                }
            } else if c[i..].starts_with(&[':', ':']) {
                end = i + 2;
            }
            toks.push(Tok {
                text: c[i..end].iter().collect(),
                line,
            });
        }
        line += c[i..end.min(c.len())]
            .iter()
            .filter(|&&ch| ch == '\n')
            .count();
        i = end;
    }
    toks
}

fn is_ident_char(ch: char) -> bool {
    ch.is_alphanumeric() || ch == '_'
}

fn is_ident(s: &str) -> bool {
    s.chars()
        .next()
        .is_some_and(|ch| ch.is_alphabetic() || ch == '_')
}

/// End of the literal starting at `i`, if one does: "..", b"..", c"..", r#".."#, br"..",
/// 'x', '\n', b'x'. A lifetime or label ('a) is not a literal.
fn literal_end(c: &[char], i: usize) -> Option<usize> {
    let at = |k: usize| c.get(k).copied().unwrap_or('\0');
    let mut j = i + matches!(at(i), 'b' | 'c') as usize;
    if at(j) == 'r' {
        let hashes = c[j + 1..].iter().take_while(|&&ch| ch == '#').count();
        j += 1 + hashes;
        if at(j) != '"' {
            return None; // an identifier, or a raw identifier r#name
        }
        let close: Vec<char> = std::iter::once('"')
            .chain(std::iter::repeat_n('#', hashes))
            .collect();
        return Some(
            (j + 1..c.len())
                .find(|&k| c[k..].starts_with(&close))
                .map_or(c.len(), |k| k + close.len()),
        );
    }
    let quote = at(j);
    let is_char =
        quote == '\'' && (j == i || at(i) == 'b') && (at(j + 1) == '\\' || at(j + 2) == '\'');
    if quote != '"' && !is_char {
        return None; // an identifier, a lifetime or a label
    }
    let mut k = j + 1;
    while k < c.len() && c[k] != quote {
        k += if c[k] == '\\' { 2 } else { 1 };
    }
    Some(k + 1)
}

// ---------------------------------------------------------------- parser tests

#[test]
fn parser_reads_dependency_paths() {
    let cases: &[(&str, &str, &[&str])] = &[
        ("grouped and nested use", "use crate::{a::b, c::d as e, f::{self, g::*}};\nuse std::sync::Arc;", &["crate::a::b", "crate::c::d", "crate::f", "crate::f::g"]),
        ("pub, pub(crate), self", "pub(crate) use super::x::{\n    Y,\n};\npub use self::z;", &["super::x::Y", "self::z"]),
        ("super::super", "use super::super::a::B;\nfn f() { super::super::c(); }", &["super::super::a::B", "super::super::c"]),
        (
            "inline paths",
            "fn f(kind: u8) {\n    let x = crate::signal::spectrum::band_rms(1);\n    super::views::collection(kind);\n    let v = Vec::<u8>::new();\n    v.iter().collect::<Vec<_>>();\n}\npub(in crate::a) fn g() {}",
            &["crate::signal::spectrum::band_rms", "super::views::collection"],
        ),
        (
            "comments and strings",
            "// use crate::a;\n/* crate::b /* nested crate::c */ crate::c2 */\n/// crate::d\n//! crate::d2\nconst S: &str = \"crate::e \\\" crate::e2\";\nconst C: char = '\"';\nconst Q: char = '\\'';\nfn f<'a>(x: &'a str) -> &'a str { crate::f::g(x) }",
            &["crate::f::g"],
        ),
        (
            "raw strings",
            "const R: &str = r#\"crate::a \"quoted\" crate::b\"#;\nconst B: &[u8] = br\"crate::c\";\nconst N: &str = r\"crate::d\";\nlet r#type = crate::ok::y;",
            &["crate::ok::y"],
        ),
        (
            "cfg(test) items",
            "use crate::a::X;\n#[cfg(test)]\nmod tests {\n    use super::*;\n    use crate::b::Y;\n    fn f() { crate::c::z(); }\n}\n#[cfg(test)]\nuse crate::e::T;\nfn g() { crate::d::w(); }",
            &["crate::a::X", "crate::d::w"],
        ),
        ("cfg(test) file", "#![cfg(test)]\nuse crate::a::X;", &[]),
    ];
    for (name, src, want) in cases {
        let got: Vec<String> = parse(src)
            .paths
            .into_iter()
            .map(|p| {
                p.segs
                    .into_iter()
                    .map(|s| s.0)
                    .collect::<Vec<_>>()
                    .join("::")
            })
            .collect();
        let got: Vec<&String> = got
            .iter()
            .filter(|p| ["crate", "super", "self"].contains(&p.split("::").next().unwrap()))
            .collect();
        assert_eq!(got, *want, "case: {name}");
    }
    // A path in a multi-line group carries the line of its leaf.
    let p = parse("use crate::x::{\n    Y,\n};");
    assert_eq!(p.paths[0].segs.last().unwrap(), &("Y".to_string(), 2));
}

#[test]
fn mod_declarations_are_not_dependencies() {
    let p = parse("mod foo;\npub mod bar;\npub(crate) mod baz { fn f() {} }\n");
    assert_eq!(p.mods, ["foo", "bar"]);
    assert!(p.paths.is_empty());
}

#[test]
fn resolves_to_longest_module_prefix() {
    let v = |s: &str| {
        s.split("::")
            .filter(|x| !x.is_empty())
            .map(String::from)
            .collect::<Vec<_>>()
    };
    let modules = [
        "dynamics",
        "dynamics::model",
        "store",
        "signal",
        "signal::frequencies",
        "signal::dtcwt",
        "signal::dtcwt::transform",
        "jobs",
        "jobs::runner",
    ];
    let is_module = |m: &[String]| modules.contains(&m.join("::").as_str());
    let target = |here: &str, children: &[&str], src: &str| {
        let children: Vec<String> = children.iter().map(|c| c.to_string()).collect();
        let r = resolve(
            &v(here),
            &children,
            Some("bearing_sim"),
            &parse(src).paths[0],
            &is_module,
        );
        r.map(|(m, via_lib, _)| (m.join("::"), via_lib))
    };
    let m = |s: &str, lib: bool| Some((s.to_string(), lib));
    assert_eq!(
        target("store", &[], "use crate::dynamics::model::Model;"),
        m("dynamics::model", false)
    );
    assert_eq!(
        target("jobs", &[], "use crate::store::Artifact;"),
        m("store", false)
    );
    assert_eq!(
        target(
            "signal::dtcwt::transform",
            &[],
            "fn f() { super::super::frequencies::k(); }"
        ),
        m("signal::frequencies", false)
    );
    assert_eq!(
        target("signal::dtcwt::transform", &[], "use super::super::*;"),
        m("signal", false)
    );
    assert_eq!(
        target("jobs::runner", &[], "use super::WorkerEnv;"),
        m("jobs", false)
    );
    assert_eq!(
        target("jobs", &["runner"], "fn f() { runner::worker_loop(); }"),
        m("jobs::runner", false)
    );
    assert_eq!(
        target("jobs", &[], "use bearing_sim::scene::Scene;"),
        m("", true)
    );
    assert_eq!(target("", &[], "use crate::Thing;"), m("", false));
    assert_eq!(target("", &[], "use tokio::sync::Notify;"), None);
    // `super` inside an inline module only leaves the block: same file.
    assert_eq!(target("jobs", &[], "mod inner { use super::X; }"), None);
    assert_eq!(
        target(
            "jobs::runner",
            &[],
            "mod inner { use super::super::WorkerEnv; }"
        ),
        m("jobs", false)
    );
}
