//! The engine's identity (`bearing_core::ENGINE_DIGEST`): a digest of what decides the
//! numbers a run computes, so that a result stored by one build is never taken for
//! another's.
//!
//! Hashed: the files under `src/` (`build_digest.rs`), this crate's manifest (its
//! features), the workspace's lock file when there is one (the exact versions of
//! nalgebra, rustfft and the rest), the compiler's version, the target and the compiler
//! flags. Generous on purpose: a change to a comment or to a dependency only the service
//! uses also gives a new digest, which costs a rerun and never a stale result.

use sha2::{Digest, Sha256};
use std::path::PathBuf;
use std::process::Command;

include!("build_digest.rs");

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let mut h = Sha256::new();
    digest_tree(&mut h, &root, &["src"]);
    h.update(std::fs::read(root.join("Cargo.toml")).expect("the manifest reads"));
    // absent when the crate is built outside this workspace (then the versions are whatever
    // that build resolves, and the digest cannot vouch for them)
    let lock = root.join("../../Cargo.lock");
    match std::fs::read(&lock) {
        Ok(text) => {
            h.update(text);
            println!("cargo:rerun-if-changed={}", lock.display());
        }
        Err(_) => h.update(b"no lock file"),
    }
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let version = Command::new(rustc)
        .arg("-V")
        .output()
        .expect("the compiler runs");
    h.update(version.stdout);
    for var in ["TARGET", "CARGO_ENCODED_RUSTFLAGS"] {
        h.update(std::env::var(var).unwrap_or_default().as_bytes());
        h.update([0]);
    }
    println!(
        "cargo:rustc-env=BEARING_CORE_ENGINE_DIGEST={}",
        digest_hex(h)
    );
    println!("cargo:rerun-if-changed=Cargo.toml");
    println!("cargo:rerun-if-changed=build_digest.rs");
}
