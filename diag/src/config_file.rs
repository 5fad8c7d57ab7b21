//! Reading a machine's configuration files (`io.toml`, `sim.toml`, `interface.toml`, `nc/DIALECT`,
//! `nc/CONSTANTS`, `nc/MACROVARS`, the tables `TAB0.KOR` and `TAB0.POS`, token and user files)
//! with a size limit.
//!
//! These files are read whole and parsed into trees that take tens of times their size (a TOML
//! document of 4 MB of small tables takes about 300 MB once parsed), so a file of any size would
//! need memory linear in it before its first error could be reported (issue 23: 50 MB of
//! well-formed `[[at]]` tables took 12 s and 4.3 GB). They are written by hand and are a few
//! kilobytes long: a file over [`CONFIG_MAX_BYTES`] is refused with an error naming its size and
//! the limit, after reading at most the limit plus one byte. Long input sequences belong in
//! traces, which are streamed.

use std::io::Read;
use std::path::Path;

/// The largest machine configuration file read, in bytes (1 MiB).
pub const CONFIG_MAX_BYTES: u64 = 1 << 20;

/// The bytes of the configuration file `path`, or an error: the file's own I/O error, or one of
/// kind [`std::io::ErrorKind::FileTooLarge`] when it holds more than [`CONFIG_MAX_BYTES`].
pub fn read_config_bytes(path: &Path) -> std::io::Result<Vec<u8>> {
    read_capped(path, CONFIG_MAX_BYTES)
}

/// [`read_config_bytes`] as UTF-8 text (invalid UTF-8 is an error of kind `InvalidData`, as with
/// [`std::fs::read_to_string`]).
pub fn read_config(path: &Path) -> std::io::Result<String> {
    String::from_utf8(read_config_bytes(path)?).map_err(|_| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "stream did not contain valid UTF-8",
        )
    })
}

/// The bytes of `path` when it holds at most `max`; reads at most `max + 1` bytes whatever the
/// file's size (a file that grows while it is read is caught too).
fn read_capped(path: &Path, max: u64) -> std::io::Result<Vec<u8>> {
    let file = std::fs::File::open(path)?;
    let size = file.metadata().map(|m| m.len()).unwrap_or(0);
    if size > max {
        return Err(too_large(Some(size), max));
    }
    let mut bytes = Vec::with_capacity(usize::try_from(size).unwrap_or(0));
    file.take(max + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max {
        return Err(too_large(None, max));
    }
    Ok(bytes)
}

/// The error of a file over the limit `max`: `size` bytes (as its metadata says) or, when it
/// grew while it was read, more than `max`.
fn too_large(size: Option<u64>, max: u64) -> std::io::Error {
    let has = match size {
        Some(n) => format!("{n} bytes"),
        None => format!("more than {max} bytes"),
    };
    std::io::Error::new(
        std::io::ErrorKind::FileTooLarge,
        format!(
            "the file has {has}; a machine configuration file is read whole and may have at most {max} bytes"
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_up_to_the_limit_is_read_and_one_byte_more_is_refused() {
        let dir = std::env::temp_dir().join(format!("diag-config-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("io.toml");
        std::fs::write(&path, vec![b'#'; 10]).expect("write");
        assert_eq!(read_capped(&path, 10).expect("read").len(), 10);
        let e = read_capped(&path, 9).expect_err("too large");
        assert_eq!(e.kind(), std::io::ErrorKind::FileTooLarge);
        assert_eq!(
            e.to_string(),
            "the file has 10 bytes; a machine configuration file is read whole and may have at most 9 bytes"
        );
        std::fs::write(&path, [0xff, b'a']).expect("write");
        assert_eq!(
            read_config(&path).expect_err("not UTF-8").kind(),
            std::io::ErrorKind::InvalidData
        );
        let missing = read_config(&dir.join("missing.toml")).expect_err("missing");
        assert_eq!(missing.kind(), std::io::ErrorKind::NotFound);
        std::fs::remove_dir_all(&dir).expect("clean");
    }
}
