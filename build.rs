//! The digest of the service's record code (`BEARING_SIM_RECORD_DIGEST`): `src/jobs`
//! turns an engine result into the stored record and artifacts, with the artifacts'
//! encoding and metadata from `src/store/blob.rs` and `src/store/model.rs`; so a stored run
//! is the same run only for builds with the same engine (`bearing_core::ENGINE_DIGEST`) and
//! the same record code. The study scene key hashes both (`studies::scene_key`).

use sha2::{Digest, Sha256};
use std::path::PathBuf;

include!("crates/bearing-core/build_digest.rs");

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let mut h = Sha256::new();
    digest_tree(
        &mut h,
        &root,
        &["src/jobs", "src/store/blob.rs", "src/store/model.rs"],
    );
    println!(
        "cargo:rustc-env=BEARING_SIM_RECORD_DIGEST={}",
        digest_hex(h)
    );
    println!("cargo:rerun-if-changed=crates/bearing-core/build_digest.rs");
}
