// Shared by the build scripts of bearing-core (`build.rs`) and of the service (the
// workspace's `build.rs`, by `include!`): a digest of a source tree, so that a build knows
// which code computed the numbers it stores. Not a module of either crate.

/// Feed every file of `paths` (files, or directories taken whole; relative to `root`) into
/// `h`, in path order: its path from `root` (with `/` separators) and its bytes. Hidden
/// files and editors' leftovers (`~`, `.orig`, `.rej`, `.swp`) are not the tree's code and
/// are skipped, so a checkout with them gives the same digest as a clean clone.
fn digest_tree(h: &mut sha2::Sha256, root: &std::path::Path, paths: &[&str]) {
    use sha2::Digest;
    let mut files = Vec::new();
    for p in paths {
        let path = root.join(p);
        if path.is_dir() {
            collect_files(&path, &mut files);
        } else {
            files.push(path);
        }
        println!("cargo:rerun-if-changed={p}");
    }
    let mut named: Vec<(String, std::path::PathBuf)> = files
        .into_iter()
        .map(|f| {
            let rel = f.strip_prefix(root).expect("under the root");
            let parts: Vec<String> = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            (parts.join("/"), f)
        })
        .collect();
    named.sort();
    for (name, path) in named {
        h.update(name.as_bytes());
        h.update([0]);
        h.update(std::fs::read(&path).expect("a source file reads"));
        h.update([0]);
    }
}

fn collect_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("a source directory reads") {
        let path = entry.expect("a directory entry").path();
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let leftover = [".orig", ".rej", ".swp"].iter().any(|e| name.ends_with(e));
        if name.starts_with('.') || name.ends_with('~') || leftover {
            continue;
        }
        if path.is_dir() {
            collect_files(&path, out);
        } else {
            out.push(path);
        }
    }
}

/// The first 8 bytes of the digest, as 16 hex digits.
fn digest_hex(h: sha2::Sha256) -> String {
    use sha2::Digest;
    h.finalize()[..8]
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}
