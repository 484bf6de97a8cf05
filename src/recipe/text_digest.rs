//! The SHA-256 of the exact text a recipe ran with: its own file, then each included file
//! in the order the loader reads them (an include's own includes right after it, a file
//! included twice counted twice), separated by a NUL byte — which YAML text never holds,
//! so no two sets of files give the same input. A recipe without includes hashes as
//! `sha256sum` of its file. Hashing only; it must not read files.

use sha2::{Digest, Sha256};

#[derive(Debug, Default)]
pub(crate) struct TextDigest {
    hasher: Sha256,
    files: usize,
}

impl TextDigest {
    /// The next file's text, as read.
    pub fn add(&mut self, text: &str) {
        if self.files > 0 {
            self.hasher.update([0u8]);
        }
        self.hasher.update(text.as_bytes());
        self.files += 1;
    }

    /// The digest in lower-case hex.
    pub fn hex(self) -> String {
        self.hasher
            .finalize()
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_file_hashes_as_sha256sum_and_every_file_and_its_place_counts() {
        let mut one = TextDigest::default();
        one.add("abc");
        // sha256sum of `abc` (FIPS 180-2's example).
        assert_eq!(
            one.hex(),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        let of = |texts: &[&str]| {
            let mut d = TextDigest::default();
            texts.iter().for_each(|t| d.add(t));
            d.hex()
        };
        assert_ne!(of(&["ab", "c"]), of(&["a", "bc"]), "where a file ends counts");
        assert_ne!(of(&["a", "b"]), of(&["b", "a"]), "the order counts");
        assert_ne!(
            of(&["a", "b"]),
            of(&["a", "b", "b"]),
            "a file included twice counts twice"
        );
    }
}
