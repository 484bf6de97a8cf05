//! Reads the text files drivescript is given (recipes, included files, dictionaries, bench
//! limits) with a size limit that holds before the file is read whole, so a wrong path such
//! as `/dev/zero` or a huge generated file cannot fill the memory. Only reads bytes and
//! checks they are UTF-8; it must not know what the text means or how it is shown.

use super::source::Source;
use std::fs::File;
use std::io::Read;
use std::path::Path;
use std::sync::Arc;

/// The most drivescript reads from one recipe, included file, dictionary or limits file.
/// The largest real ones are a few tens of kilobytes; 8 MiB leaves room for generated
/// recipes while keeping a mistaken path from costing more than a moment and a few MiB.
pub const MAX_TEXT_FILE_BYTES: u64 = 8 * 1024 * 1024;

/// Why a text file was not read.
#[derive(Debug, thiserror::Error)]
pub enum TextFileError {
    /// Opening or reading failed (missing file, no permission, …).
    #[error("{0}")]
    Io(std::io::Error),
    /// Larger than [`MAX_TEXT_FILE_BYTES`].
    #[error("larger than {}", limit_text())]
    TooLarge,
    /// A directory, device or socket: `a directory`, `a device`, `a socket`.
    #[error("{0}, not a file")]
    NotAFile(&'static str),
    /// Bytes that are not UTF-8 (a binary file, or text saved in another encoding).
    #[error("not UTF-8 text")]
    NotUtf8,
}

impl TextFileError {
    /// One sentence naming the file as `what` (`the recipe x.yaml`, `the dictionary file`).
    pub fn sentence(&self, what: &str) -> String {
        match self {
            TextFileError::Io(e) => format!("cannot read {what}: {e}"),
            TextFileError::TooLarge => format!(
                "{what} is larger than {}, the limit for one recipe, included file, dictionary or limits file",
                limit_text()
            ),
            TextFileError::NotAFile(kind) => format!("{what} is {kind}, not a file"),
            TextFileError::NotUtf8 => format!(
                "{what} is not UTF-8 text (it was probably saved as Windows-1252 or Latin-1: umlauts, °, µ and ± are stored differently there)"
            ),
        }
    }

    /// What to do about it; `None` for I/O errors, whose help depends on the caller.
    pub fn help(&self) -> Option<String> {
        match self {
            TextFileError::Io(_) => None,
            TextFileError::TooLarge => Some(
                "check that the path names the file you meant (recipes and dictionaries are a few kilobytes of YAML); split a generated recipe into included files"
                    .into(),
            ),
            TextFileError::NotAFile(_) => Some("give the path of a YAML file".into()),
            TextFileError::NotUtf8 => Some(
                "save it as UTF-8 (in the editor's Save As dialog: Encoding UTF-8), or convert it: iconv -f WINDOWS-1252 -t UTF-8 FILE > NEW"
                    .into(),
            ),
        }
    }
}

fn limit_text() -> String {
    format!("{} MiB", MAX_TEXT_FILE_BYTES / (1024 * 1024))
}

/// Reads `path` as UTF-8 text of at most [`MAX_TEXT_FILE_BYTES`]. Directories, devices and
/// sockets are refused before reading; pipes (`<(…)`) are read up to the limit, since their
/// size is not known in advance (and `/dev/zero`-like sources report size 0).
pub fn read_text_file(path: &Path) -> Result<String, TextFileError> {
    String::from_utf8(read_bytes(path)?).map_err(|_| TextFileError::NotUtf8)
}

/// [`read_text_file`] for files that vendor tools write in Windows-1252 (EDS/DCF): UTF-8
/// when the bytes are UTF-8, otherwise each byte as its Windows-1252 character; `true`
/// when it was read so.
pub fn read_text_or_windows_1252(path: &Path) -> Result<(String, bool), TextFileError> {
    let bytes = read_bytes(path)?;
    match String::from_utf8(bytes) {
        Ok(text) => Ok((text, false)),
        Err(e) => Ok((windows_1252(e.as_bytes()), true)),
    }
}

/// Windows-1252 bytes as text: Latin-1 but for 0x80..0x9F, which hold typographic marks;
/// the five bytes it leaves undefined keep their C1 code points.
pub fn windows_1252(bytes: &[u8]) -> String {
    const HIGH: [u16; 32] = [
        0x20AC, 0x81, 0x201A, 0x0192, 0x201E, 0x2026, 0x2020, 0x2021, 0x02C6, 0x2030, 0x0160, 0x2039, 0x0152,
        0x8D, 0x017D, 0x8F, 0x90, 0x2018, 0x2019, 0x201C, 0x201D, 0x2022, 0x2013, 0x2014, 0x02DC, 0x2122,
        0x0161, 0x203A, 0x0153, 0x9D, 0x017E, 0x0178,
    ];
    bytes
        .iter()
        .map(|&b| match b {
            0x80..=0x9F => char::from_u32(u32::from(HIGH[usize::from(b - 0x80)])).unwrap_or('\u{FFFD}'),
            _ => char::from(b),
        })
        .collect()
}

/// The bytes of `path`, at most [`MAX_TEXT_FILE_BYTES`] (see [`read_text_file`]).
fn read_bytes(path: &Path) -> Result<Vec<u8>, TextFileError> {
    // Windows does not open a directory at all: what it is is said instead of the
    // refusal ("Access is denied").
    let file = File::open(path).map_err(|e| {
        match std::fs::metadata(path)
            .ok()
            .and_then(|m| not_a_file(&m.file_type()))
        {
            Some(kind) => TextFileError::NotAFile(kind),
            None => TextFileError::Io(e),
        }
    })?;
    let meta = file.metadata().map_err(TextFileError::Io)?;
    if let Some(kind) = not_a_file(&meta.file_type()) {
        return Err(TextFileError::NotAFile(kind));
    }
    if meta.is_file() && meta.len() > MAX_TEXT_FILE_BYTES {
        return Err(TextFileError::TooLarge);
    }
    read_bounded(file, MAX_TEXT_FILE_BYTES)
}

/// [`read_text_file`] as a [`Source`] named as the path is shown.
pub fn read_source(path: &Path) -> Result<Arc<Source>, TextFileError> {
    let text = read_text_file(path)?;
    Ok(Source::new(path.display().to_string(), text))
}

/// Reads at most `limit` bytes of `source`; more is [`TextFileError::TooLarge`].
fn read_bounded(source: impl Read, limit: u64) -> Result<Vec<u8>, TextFileError> {
    let mut bytes = Vec::new();
    source
        .take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(TextFileError::Io)?;
    if bytes.len() as u64 > limit {
        return Err(TextFileError::TooLarge);
    }
    Ok(bytes)
}

fn not_a_file(file_type: &std::fs::FileType) -> Option<&'static str> {
    if file_type.is_dir() {
        return Some("a directory");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_char_device() || file_type.is_block_device() {
            return Some("a device");
        }
        if file_type.is_socket() {
            return Some("a socket");
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_small_files_and_refuses_what_is_not_a_file() {
        let dir = crate::scratch_dir::scratch_dir("text-file");
        let path = dir.join("r.yaml");
        std::fs::write(&path, "name: x\n").unwrap();
        assert_eq!(read_text_file(&path).unwrap(), "name: x\n");
        assert!(matches!(
            read_text_file(&dir),
            Err(TextFileError::NotAFile("a directory"))
        ));
        assert!(matches!(
            read_text_file(&dir.join("missing.yaml")),
            Err(TextFileError::Io(_))
        ));
        std::fs::write(&path, [0xff, 0xfe, 0x00]).unwrap();
        assert!(matches!(read_text_file(&path), Err(TextFileError::NotUtf8)));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[cfg(unix)]
    #[test]
    fn devices_are_refused_before_reading() {
        let e = read_text_file(Path::new("/dev/zero")).unwrap_err();
        assert_eq!(
            e.sentence("the recipe /dev/zero"),
            "the recipe /dev/zero is a device, not a file"
        );
    }

    #[test]
    fn an_endless_source_stops_at_the_limit() {
        let e = read_bounded(std::io::repeat(b'a'), 1000).unwrap_err();
        assert!(matches!(e, TextFileError::TooLarge));
        assert_eq!(read_bounded(&b"abc"[..], 3).unwrap(), b"abc");
        assert_eq!(
            TextFileError::TooLarge.sentence("the recipe x.yaml"),
            "the recipe x.yaml is larger than 8 MiB, the limit for one recipe, included file, dictionary or limits file"
        );
    }
}
