//! The engine's identity (`bearing_core::ENGINE_DIGEST`): a digest of everything that
//! decides the numbers a run computes, so that two builds with the same digest compute the
//! same numbers and a stored result is never taken for another build's.
//!
//! Hashed: every file under `src/` (path and content, in path order), this crate's
//! manifest (its features), the workspace's lock file when there is one (the exact
//! versions of nalgebra, rustfft and the rest) and the compiler's version. Generous on
//! purpose: a change to a comment or to a dependency only the service uses also gives a new
//! digest, which costs a rerun and never a stale result.

use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    let dir = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let mut files = Vec::new();
    collect(&dir.join("src"), &mut files);
    files.sort();
    let mut h = Sha256::new();
    for f in &files {
        let rel = f.strip_prefix(&dir).expect("under the crate");
        h.update(rel.to_string_lossy().as_bytes());
        h.update([0]);
        h.update(std::fs::read(f).expect("a source file reads"));
        h.update([0]);
    }
    h.update(std::fs::read(dir.join("Cargo.toml")).expect("the manifest reads"));
    let lock = dir.join("../../Cargo.lock");
    if let Ok(text) = std::fs::read(&lock) {
        h.update(text);
        println!("cargo:rerun-if-changed={}", lock.display());
    }
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    if let Ok(out) = Command::new(rustc).arg("-V").output() {
        h.update(out.stdout);
    }
    let hex: String = h.finalize()[..8]
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    println!("cargo:rustc-env=BEARING_CORE_ENGINE_DIGEST={hex}");
    println!("cargo:rerun-if-changed=src");
    println!("cargo:rerun-if-changed=Cargo.toml");
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("src reads") {
        let path = entry.expect("a directory entry").path();
        if path.is_dir() {
            collect(&path, out);
        } else {
            out.push(path);
        }
    }
}
