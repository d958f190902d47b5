//! The key identical points share a run by: SHA-256 of the build's digests and the scene's
//! canonical JSON (the validated scene serialized with its fields in declaration order).
//!
//! The digests are in the key because a stored run is only the same run for a build with
//! the same engine (`bearing_core::ENGINE_DIGEST`: the physics, its defaults, the analysis)
//! and the same record code ([`RECORD_DIGEST`]): a study submitted after an upgrade that
//! changed either must not reuse the old numbers. The worker that finishes a run writes
//! the key under its own build (`store::Outcome::Succeeded`), so during a rolling upgrade a
//! run an older worker computed is reused only by the older build's studies. Jobs stored
//! before the digests were in the key are reused by no build.

use bearing_core::scene::ValidScene;
use bearing_core::ENGINE_DIGEST;
use sha2::{Digest, Sha256};

/// The digest of the service's record code (`src/jobs`, by the workspace's `build.rs`):
/// what turns an engine result into the stored record and artifacts. 16 hex digits.
pub const RECORD_DIGEST: &str = env!("BEARING_SIM_RECORD_DIGEST");

/// Hex SHA-256 of this build's engine and record digests and the scene's canonical JSON.
pub fn scene_key(scene: &ValidScene) -> String {
    scene_key_for(scene, ENGINE_DIGEST, RECORD_DIGEST)
}

/// [`scene_key`] under the engine digest `engine` and the record digest `record`.
fn scene_key_for(scene: &ValidScene, engine: &str, record: &str) -> String {
    let text = serde_json::to_string(scene.scene()).expect("a scene serializes");
    let mut h = Sha256::new();
    for part in [engine, record] {
        h.update(part.as_bytes());
        h.update([0]);
    }
    h.update(text.as_bytes());
    hex(&h.finalize())
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use bearing_core::scene::{fault_case_scene, FaultCase};

    /// The worker parses the stored scene back from its JSON text and writes the key of
    /// what it parsed (`jobs::simulation_job`): that key must be the API's, also for a
    /// 17-digit value such as 7 deg in radians, which serde_json's default float parser
    /// reads back an ulp off (0.12217304763960307 as ...309) and `float_roundtrip` does not.
    #[test]
    fn a_stored_scene_parses_back_to_the_same_key() {
        let mut scene = fault_case_scene("h7005c", FaultCase::Outer).expect("a preset");
        scene.operating.radial_load_angle = 7.0 * std::f64::consts::PI / 180.0;
        let valid = scene.validated().expect("valid");
        let text = serde_json::to_string(&valid).unwrap();
        let back: ValidScene = serde_json::from_str(&text).unwrap();
        assert_eq!(
            back.scene().operating.radial_load_angle.to_bits(),
            valid.scene().operating.radial_load_angle.to_bits()
        );
        assert_eq!(scene_key(&back), scene_key(&valid));
    }

    fn preset() -> ValidScene {
        fault_case_scene("h7005c", FaultCase::Compound)
            .expect("a preset")
            .validated()
            .expect("the preset validates")
    }

    #[test]
    fn a_scene_has_one_key_per_build() {
        let s = preset();
        let (a, b) = ("0123456789abcdef", "fedcba9876543210");
        assert_eq!(
            scene_key(&s),
            scene_key_for(&s, ENGINE_DIGEST, RECORD_DIGEST)
        );
        assert_ne!(scene_key_for(&s, a, a), scene_key_for(&s, b, a), "engine");
        assert_ne!(
            scene_key_for(&s, a, a),
            scene_key_for(&s, a, b),
            "record code"
        );
        // nor the key the scene had before the digests were in it, so no old row matches
        let text = serde_json::to_string(s.scene()).unwrap();
        assert_ne!(scene_key(&s), hex(&Sha256::digest(text.as_bytes())));
        for d in [ENGINE_DIGEST, RECORD_DIGEST] {
            assert_eq!(d.len(), 16);
            assert!(d.bytes().all(|b| b.is_ascii_hexdigit()));
        }
    }
}
