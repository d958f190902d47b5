//! The key identical points share a run by: SHA-256 of the engine's digest and the scene's
//! canonical JSON (the validated scene serialized with its fields in declaration order).
//!
//! The digest is in the key because a stored run is only the same run for the build that
//! computed it: a study submitted after an upgrade that changed the physics, its defaults
//! (a scene's absent traction node count, say) or the analysis must not reuse the old
//! numbers. Jobs stored before the digest was in the key are reused by no build.

use bearing_core::scene::ValidScene;
use bearing_core::ENGINE_DIGEST;
use sha2::{Digest, Sha256};

/// Hex SHA-256 of this build's engine digest and the scene's canonical JSON.
pub fn scene_key(scene: &ValidScene) -> String {
    scene_key_for(scene, ENGINE_DIGEST)
}

/// [`scene_key`] under the engine digest `engine`.
fn scene_key_for(scene: &ValidScene, engine: &str) -> String {
    let text = serde_json::to_string(scene.scene()).expect("a scene serializes");
    let mut h = Sha256::new();
    h.update(engine.as_bytes());
    h.update([0]);
    h.update(text.as_bytes());
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use bearing_core::scene::{fault_case_scene, FaultCase};

    fn preset() -> ValidScene {
        fault_case_scene("h7005c", FaultCase::Compound)
            .expect("a preset")
            .validated()
            .expect("the preset validates")
    }

    #[test]
    fn a_scene_has_one_key_per_engine() {
        let s = preset();
        assert_eq!(scene_key(&s), scene_key_for(&s, ENGINE_DIGEST));
        assert_eq!(
            scene_key_for(&s, "0123456789abcdef"),
            scene_key_for(&s, "0123456789abcdef")
        );
        assert_ne!(
            scene_key_for(&s, "0123456789abcdef"),
            scene_key_for(&s, "fedcba9876543210")
        );
        assert_eq!(ENGINE_DIGEST.len(), 16);
        assert!(ENGINE_DIGEST.bytes().all(|b| b.is_ascii_hexdigit()));
    }
}
