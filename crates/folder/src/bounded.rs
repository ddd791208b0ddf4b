//! Reading a file whose name or content someone else may have chosen (a
//! recipe, a build folder's marker or state file) without being steered by
//! it: opened without waiting (a FIFO does not hang the run), never read
//! unless it is a regular file, and never read past a limit (a link to
//! /dev/zero does not fill the memory).

use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

/// Whether the last component of the path may be a symbolic link.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Links {
    /// Followed (a recipe given on the command line may be a link).
    Follow,
    /// Refused: the file must be there itself (a build folder's entries).
    Refuse,
}

/// The bytes of the regular file at `path`, at most `limit` of them: an
/// error says what it is instead (a folder, a FIFO, a device), or that it
/// is larger than the limit (kinds `IsADirectory`, `InvalidInput`,
/// `FileTooLarge`).
pub fn read_plain(path: &Path, limit: u64, links: Links) -> io::Result<Vec<u8>> {
    let file = open_plain(path, links)?;
    let mut bytes = Vec::new();
    file.take(limit + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(io::Error::new(
            io::ErrorKind::FileTooLarge,
            format!(
                "the file is larger than the limit of {}",
                shown_bytes(limit)
            ),
        ));
    }
    Ok(bytes)
}

/// Open the regular file at `path` for reading (see `read_plain`).
pub fn open_plain(path: &Path, links: Links) -> io::Result<File> {
    let file = open(path, links)?;
    let kind = file.metadata()?.file_type();
    if kind.is_file() {
        return Ok(file);
    }
    let why = if kind.is_dir() {
        io::ErrorKind::IsADirectory
    } else {
        io::ErrorKind::InvalidInput
    };
    Err(io::Error::new(
        why,
        format!("it is {}, not a regular file", what(&kind)),
    ))
}

#[cfg(unix)]
fn open(path: &Path, links: Links) -> io::Result<File> {
    use rustix::fs::{Mode, OFlags};
    // NONBLOCK: opening a FIFO would otherwise wait for a writer; it has
    // no effect on the reads of a regular file.
    let mut flags = OFlags::RDONLY | OFlags::CLOEXEC | OFlags::NONBLOCK | OFlags::NOCTTY;
    if links == Links::Refuse {
        flags |= OFlags::NOFOLLOW;
    }
    match rustix::fs::open(path, flags, Mode::empty()) {
        Ok(fd) => Ok(File::from(fd)),
        Err(e) if e == rustix::io::Errno::LOOP && links == Links::Refuse => Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "it is a symbolic link, not a regular file",
        )),
        Err(e) => Err(e.into()),
    }
}

#[cfg(not(unix))]
fn open(path: &Path, links: Links) -> io::Result<File> {
    if links == Links::Refuse && std::fs::symlink_metadata(path)?.file_type().is_symlink() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "it is a symbolic link, not a regular file",
        ));
    }
    File::open(path)
}

/// What a file that is not a regular file is, for a message.
fn what(kind: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if kind.is_char_device() || kind.is_block_device() {
            return "a device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() {
        "a folder"
    } else if kind.is_symlink() {
        "a symbolic link"
    } else {
        "not a regular file"
    }
}

/// `bytes` in KiB or MiB, as limits are stated.
fn shown_bytes(bytes: u64) -> String {
    if bytes >= 1 << 20 {
        format!("{} MiB", bytes >> 20)
    } else {
        format!("{} KiB", bytes >> 10)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    #[test]
    fn reads_only_regular_files_within_the_limit() {
        let dir = std::env::temp_dir().join(format!("karigami-bounded-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        let file = dir.join("f");
        fs::write(&file, "12345").unwrap();
        assert_eq!(read_plain(&file, 5, Links::Refuse).unwrap(), b"12345");
        let big = read_plain(&file, 4, Links::Refuse).unwrap_err();
        assert!(big.to_string().contains("larger than the limit"), "{big}");
        let folder = read_plain(&dir, 5, Links::Follow).unwrap_err();
        assert!(folder.to_string().contains("a folder"), "{folder}");
        #[cfg(unix)]
        {
            let link = dir.join("l");
            std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
            let refused = read_plain(&link, 5, Links::Refuse).unwrap_err();
            assert!(refused.to_string().contains("symbolic link"), "{refused}");
            let device = read_plain(&link, 5, Links::Follow).unwrap_err();
            assert!(device.to_string().contains("a device"), "{device}");
        }
        fs::remove_dir_all(&dir).unwrap();
    }
}
