//! The secret a browser shows before it may read or change anything on a server that
//! other machines can reach: generated at start (and printed) or read from a file the
//! operator keeps. Compared in constant time; never logged by the layer.

use super::WebError;
use std::path::Path;

/// At least this long (a generated token is 64 hex digits).
const MIN_LEN: usize = 16;
const MAX_LEN: usize = 256;

#[derive(Clone, PartialEq, Eq)]
pub struct AccessToken(String);

impl std::fmt::Debug for AccessToken {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("AccessToken(…)")
    }
}

impl AccessToken {
    /// A new random token: 256 bits from the hashers std seeds from the operating
    /// system's random source, through SHA-256 (no extra crate for one random number).
    pub fn generate() -> AccessToken {
        use sha2::{Digest, Sha256};
        use std::hash::{BuildHasher, Hasher};
        let mut digest = Sha256::new();
        for i in 0..4u64 {
            let mut h = std::collections::hash_map::RandomState::new().build_hasher();
            h.write_u64(i);
            h.write_u128(
                std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map(|d| d.as_nanos())
                    .unwrap_or_default(),
            );
            h.write_u32(std::process::id());
            digest.update(h.finish().to_le_bytes());
        }
        AccessToken(crate::hex::to_hex(&digest.finalize()).replace(' ', ""))
    }

    /// The token in `path`: its first line, trimmed.
    pub fn from_file(path: &Path) -> Result<AccessToken, WebError> {
        let text = std::fs::read_to_string(path).map_err(|source| WebError::TokenFile {
            path: path.to_path_buf(),
            source,
        })?;
        let line = text.lines().next().unwrap_or_default().trim();
        AccessToken::parse(line).map_err(|why| WebError::BadToken {
            path: path.to_path_buf(),
            why,
        })
    }

    fn parse(text: &str) -> Result<AccessToken, &'static str> {
        if text.len() < MIN_LEN {
            return Err("the token is empty or shorter than 16 characters");
        }
        if text.len() > MAX_LEN {
            return Err("the token is longer than 256 characters");
        }
        // Only characters that travel unchanged in a URL, a cookie and a header.
        if !text
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'-' | b'_' | b'.'))
        {
            return Err("the token holds characters other than letters, digits, `-`, `_` and `.`");
        }
        Ok(AccessToken(text.to_string()))
    }

    /// The token as the browser sends it.
    pub fn text(&self) -> &str {
        &self.0
    }

    /// Whether `offered` is this token, in time that does not depend on where they differ.
    pub fn matches(&self, offered: &str) -> bool {
        let (a, b) = (self.0.as_bytes(), offered.as_bytes());
        a.len() == b.len() && a.iter().zip(b).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_tokens_differ_and_are_long() {
        let (a, b) = (AccessToken::generate(), AccessToken::generate());
        assert_ne!(a, b);
        assert_eq!(a.text().len(), 64);
        assert!(a.matches(a.text()));
        assert!(!a.matches(b.text()));
        assert!(!a.matches(&a.text()[..63]));
        assert!(!a.matches(""));
    }

    #[test]
    fn a_token_file_takes_its_first_line_and_refuses_weak_or_odd_tokens() {
        let dir = crate::scratch_dir::scratch_dir("token");
        let file = dir.join("token");
        std::fs::write(&file, "  abcdefghijklmnop-_.0123  \nsecond line\n").unwrap_or_default();
        let token = AccessToken::from_file(&file).map(|t| t.text().to_string());
        assert_eq!(token.ok().as_deref(), Some("abcdefghijklmnop-_.0123"));
        for bad in [
            "",
            "short",
            "has a space in the middle",
            "semi;colon-is-not-allowed",
        ] {
            std::fs::write(&file, bad).unwrap_or_default();
            let e = AccessToken::from_file(&file).err().map(|e| e.to_string());
            assert!(e.is_some_and(|e| e.contains("token")), "{bad:?} accepted");
        }
        assert!(matches!(
            AccessToken::from_file(&dir.join("missing")),
            Err(WebError::TokenFile { .. })
        ));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
