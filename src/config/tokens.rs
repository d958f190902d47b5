//! API tokens: each has a name (the tenant that owns what it creates) and is kept only as
//! its SHA-256. Tokens are random 256-bit strings made by `bearing-sim token`, so a plain
//! hash is enough at rest: there is no dictionary to try against it (a password hash
//! such as Argon2 exists for low-entropy secrets).

use sha2::{Digest, Sha256};
use std::collections::HashMap;

/// The configured tokens, by hash.
#[derive(Debug, Clone, Default)]
pub struct Tokens {
    by_hash: HashMap<String, String>,
}

/// Hex SHA-256 of a token, as the tokens file keeps it.
pub fn hash_token(token: &str) -> String {
    Sha256::digest(token.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

impl Tokens {
    /// Parse `name:sha256hex` entries, one per line or comma-separated; blank lines and
    /// `#` comments are skipped. Names are letters, digits, `-`, `_` and `.`, unique.
    pub fn parse(text: &str, source: &str) -> Result<Tokens, String> {
        let mut t = Tokens::default();
        for (i, raw) in text.lines().enumerate() {
            let line = raw.split('#').next().unwrap_or("").trim();
            for entry in line.split(',').map(str::trim).filter(|e| !e.is_empty()) {
                let at = format!("{source}, line {}", i + 1);
                let (name, hash) = entry
                    .split_once(':')
                    .ok_or_else(|| format!("{at}: expected name:sha256hex, got {entry:?}"))?;
                let (name, hash) = (name.trim(), hash.trim().to_ascii_lowercase());
                let name_ok = !name.is_empty()
                    && name.len() <= 64
                    && name
                        .chars()
                        .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c));
                if !name_ok {
                    return Err(format!(
                        "{at}: token name {name:?} must be 1-64 letters, digits, '-', '_' or '.'"
                    ));
                }
                if hash.len() != 64 || !hash.chars().all(|c| c.is_ascii_hexdigit()) {
                    return Err(format!(
                        "{at}: the hash of token {name:?} must be 64 hex digits (SHA-256; `bearing-sim token {name}` prints one)"
                    ));
                }
                if t.by_hash.values().any(|n| n == name) {
                    return Err(format!("{at}: token name {name:?} appears twice"));
                }
                if t.by_hash.insert(hash, name.to_string()).is_some() {
                    return Err(format!("{at}: the same token is listed twice"));
                }
            }
        }
        Ok(t)
    }

    /// Add the entries of another source.
    pub fn merge(&mut self, other: Tokens) -> Result<(), String> {
        for (hash, name) in other.by_hash {
            if self.by_hash.values().any(|n| *n == name) || self.by_hash.contains_key(&hash) {
                return Err(format!("token {name:?} is configured twice"));
            }
            self.by_hash.insert(hash, name);
        }
        Ok(())
    }

    pub fn is_empty(&self) -> bool {
        self.by_hash.is_empty()
    }

    pub fn len(&self) -> usize {
        self.by_hash.len()
    }

    /// The name of a presented token, if it is configured.
    pub fn name_of(&self, token: &str) -> Option<&str> {
        self.by_hash.get(&hash_token(token)).map(String::as_str)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_token_is_known_by_its_hash_only() {
        let line = format!(
            "lab-a:{}  # the lab\nlab-b:{}",
            hash_token("s3cret-a"),
            hash_token("s3cret-b")
        );
        let t = Tokens::parse(&line, "tokens").unwrap();
        assert_eq!(t.name_of("s3cret-a"), Some("lab-a"));
        assert_eq!(t.name_of("s3cret-b"), Some("lab-b"));
        assert_eq!(t.name_of("s3cret-c"), None);
        assert!(!line.contains("s3cret"));
    }

    #[test]
    fn bad_entries_are_refused_with_their_line() {
        let e = Tokens::parse("\n a b", "f").unwrap_err();
        assert!(e.contains("f, line 2"), "{e}");
        let e = Tokens::parse("x:abc", "f").unwrap_err();
        assert!(e.contains("64 hex digits"), "{e}");
        let h = hash_token("t");
        let e = Tokens::parse(&format!("x:{h}\nx:{}", hash_token("u")), "f").unwrap_err();
        assert!(e.contains("twice"), "{e}");
    }
}
