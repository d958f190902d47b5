//! The key identical points share a run by: SHA-256 of the scene's canonical JSON (the
//! validated scene serialized with its fields in declaration order).

use bearing_core::scene::ValidScene;
use sha2::{Digest, Sha256};

/// Hex SHA-256 of the scene's canonical JSON.
pub fn scene_key(scene: &ValidScene) -> String {
    let text = serde_json::to_string(scene.scene()).expect("a scene serializes");
    let digest = Sha256::digest(text.as_bytes());
    digest.iter().map(|b| format!("{b:02x}")).collect()
}
