//! Keeping an earlier build's files (karigami's docs/commands.md, "Build
//! folders"): the marker of a build folder records, for each build in it
//! (the folder itself, or each subfolder of a batch), a fingerprint of everything its files are
//! made from and the length and hash of each file. A rebuild whose inputs
//! have the same fingerprint, into a folder whose files still have their
//! recorded lengths and hashes, links those files into the new folder
//! instead of making them again: the files a fresh build would write, to
//! the byte, since the program, the recipe and the options are the same.
//! Anything that does not check out (other inputs, a file edited, cut
//! short, deleted or replaced by a link) is made and written as usual.

use crate::bounded::{Links, open_plain};
use crate::staged::{RECORDS_HEAD, make_folders, stays_inside};
use crate::{OutDir, Staged, fault};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use xxhash_rust::xxh3::{Xxh3, xxh3_64};

/// One build's record: a line of JSON in the marker.
#[derive(Serialize, Deserialize)]
struct Record {
    /// The build's subfolder; empty for a single build.
    folder: String,
    /// The fingerprint of the inputs (`inputs`), in hex.
    inputs: String,
    /// Each file (relative to `folder`), its length and its hash in hex.
    files: Vec<(String, u64, String)>,
    /// What the build reports (the caller's, kept as it was).
    report: serde_json::Value,
}

/// The records of an earlier build folder, each with its line as written.
pub(crate) struct Earlier(Vec<(Record, String)>);

/// Each file a marker's records name (its path in the build folder), with
/// its length and hash as recorded.
pub(crate) type Recorded<'a> = BTreeMap<String, (u64, &'a str)>;

impl Earlier {
    /// The records in a marker's text; lines that do not parse are left out
    /// (their builds are made again).
    pub(crate) fn parse(marker: &str) -> Self {
        let records = marker
            .split_once(&format!("\n\n{RECORDS_HEAD}\n"))
            .map_or("", |(_, r)| r);
        Self(
            records
                .lines()
                .filter_map(|l| Some((serde_json::from_str(l).ok()?, l.to_string())))
                .collect(),
        )
    }
}

impl Earlier {
    /// Every file the records name, as `Recorded`.
    pub(crate) fn recorded(&self) -> Recorded<'_> {
        let mut out = Recorded::new();
        for (record, _) in &self.0 {
            for (name, len, hash) in &record.files {
                let rel = Path::new(&record.folder).join(name);
                out.insert(rel.display().to_string(), (*len, hash.as_str()));
            }
        }
        out
    }
}

/// Whether the file at `path` is a regular file (not a link) of `len`
/// bytes whose hash is `hash`: a build's file as it was written.
pub(crate) fn unchanged(path: &Path, (len, hash): (u64, &str), buf: &mut [u8]) -> bool {
    let Ok(file) = open_plain(path, Links::Refuse) else {
        return false;
    };
    file.metadata().is_ok_and(|m| m.len() == len)
        && hash_read(file, buf).is_ok_and(|h| hex(h) == hash)
}

fn hex(x: u64) -> String {
    format!("{x:016x}")
}

/// A fingerprint of the running program, worked out once a run: the GNU
/// build ID of its executable where it has one (the linker's hash of the
/// whole file, at its start), else the xxh3 hash of its bytes (57 MB for
/// a release build: about 0.05 s of CPU). None where the file cannot be
/// read (nothing is then kept).
fn program() -> Option<u64> {
    static PROGRAM: OnceLock<Option<u64>> = OnceLock::new();
    *PROGRAM.get_or_init(|| {
        // /proc/self/exe is the file this process runs even if the one at
        // its path was replaced since.
        let exe = if cfg!(target_os = "linux") {
            PathBuf::from("/proc/self/exe")
        } else {
            std::env::current_exe().ok()?
        };
        if let Some(id) = build_id(&exe) {
            return Some(xxh3_64(&[b"build-id ".as_slice(), &id].concat()));
        }
        hash_file(&exe, &mut vec![0; BUFFER]).ok()
    })
}

/// The GNU build ID of a 64-bit little-endian ELF file: the descriptor of
/// its note of type 3 (`NT_GNU_BUILD_ID`) owned by "GNU", found through
/// the program headers' `PT_NOTE` segments, which lie in the file's first
/// pages.
fn build_id(path: &Path) -> Option<Vec<u8>> {
    let mut head = vec![0; 64 << 10];
    let n = io::Read::read(&mut fs::File::open(path).ok()?, &mut head).ok()?;
    let head = &head[..n];
    let u16_at = |at: usize| Some(u16::from_le_bytes(head.get(at..at + 2)?.try_into().ok()?));
    let u32_at = |at: usize| Some(u32::from_le_bytes(head.get(at..at + 4)?.try_into().ok()?));
    let u64_at = |at: usize| {
        let word = u64::from_le_bytes(head.get(at..at + 8)?.try_into().ok()?);
        usize::try_from(word).ok()
    };
    // ELF magic, 64-bit, little-endian.
    if head.get(..6)? != b"\x7fELF\x02\x01" {
        return None;
    }
    let (phoff, phsize, phnum) = (u64_at(0x20)?, usize::from(u16_at(0x36)?), u16_at(0x38)?);
    for i in 0..usize::from(phnum) {
        let ph = phoff.checked_add(i.checked_mul(phsize)?)?;
        if u32_at(ph)? != 4 {
            continue;
        }
        let (mut at, end) = (
            u64_at(ph + 8)?,
            u64_at(ph + 8)?.checked_add(u64_at(ph + 32)?)?,
        );
        while at.checked_add(12)? <= end {
            let (name, desc, kind) = (
                u32_at(at)? as usize,
                u32_at(at + 4)? as usize,
                u32_at(at + 8)?,
            );
            let name_at = at + 12;
            let desc_at = name_at.checked_add(name.checked_add(3)? & !3)?;
            let next = desc_at.checked_add(desc.checked_add(3)? & !3)?;
            if kind == 3 && head.get(name_at..name_at + name)? == b"GNU\0" && desc >= 8 {
                return head.get(desc_at..desc_at + desc).map(<[u8]>::to_vec);
            }
            at = next;
        }
    }
    None
}

/// The piece of a file read at a time.
pub(crate) const BUFFER: usize = 1 << 20;

/// The xxh3-64 hash of a file's bytes, read a piece at a time into `buf`:
/// a large file read whole would cost more in fresh memory than in
/// hashing.
fn hash_file(path: &Path, buf: &mut [u8]) -> io::Result<u64> {
    hash_read(fs::File::open(path)?, buf)
}

fn hash_read(mut file: fs::File, buf: &mut [u8]) -> io::Result<u64> {
    let mut h = Xxh3::new();
    loop {
        match io::Read::read(&mut file, buf) {
            Ok(0) => return Ok(h.digest()),
            Ok(n) => h.update(&buf[..n]),
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
}

/// Start hashing the program on a thread of its own, so that a build's
/// other work overlaps it (`inputs` then waits for it, if need be).
pub fn start_program_hash() {
    std::thread::spawn(program);
}

/// The fingerprint of a build's inputs: the program and `parts` (the
/// recipe's text, its name, the options...), each with its length so that
/// no two lists give the same stream. None where the program cannot be
/// read.
pub fn inputs(parts: &[&[u8]]) -> Option<u64> {
    let mut h = Xxh3::new();
    h.update(&program()?.to_le_bytes());
    for p in parts {
        h.update(&(p.len() as u64).to_le_bytes());
        h.update(p);
    }
    Some(h.digest())
}

/// The record line of a build just made; an error is a report that does
/// not serialise (a map with keys that are not text).
pub(crate) fn line(
    folder: &str,
    inputs: Option<u64>,
    files: &[(String, Vec<u8>)],
    report: &impl Serialize,
) -> io::Result<String> {
    let record = Record {
        folder: folder.to_string(),
        inputs: inputs.map_or_else(String::new, hex),
        files: files
            .iter()
            .map(|(name, bytes)| (name.clone(), bytes.len() as u64, hex(xxh3_64(bytes))))
            .collect(),
        report: serde_json::to_value(report)?,
    };
    Ok(serde_json::to_string(&record)?)
}

impl Staged<'_> {
    /// Write the files of one build (`write`) and record what they are made
    /// from (`inputs`, see `record::inputs`) and what the build reported,
    /// so that a rebuild can keep them (`keep`).
    pub fn write_build(
        &self,
        sub: &str,
        files: &[(String, Vec<u8>)],
        inputs: Option<u64>,
        report: &impl serde::Serialize,
    ) -> io::Result<()> {
        self.write(sub, files)?;
        self.add_record(line(sub, inputs, files, report)?);
        Ok(())
    }

    /// Keep the earlier build of `folder` if it was made from the same
    /// `inputs` and each of its files still checks out: each is linked into
    /// the new folder and checked there (what is checked is what is
    /// committed), and its record is carried over. Returns the build's
    /// report; None when anything does not check out, after undoing what it
    /// linked (the caller then builds). An error is a write that failed (a
    /// full disk), as writing the files would have.
    pub fn keep<R: DeserializeOwned>(
        &self,
        out: &OutDir,
        folder: &str,
        inputs: Option<u64>,
    ) -> io::Result<Option<R>> {
        let Some(inputs) = inputs.map(hex) else {
            return Ok(None);
        };
        let Some((record, line)) = out.earlier.as_ref().and_then(|e| {
            e.0.iter()
                .find(|(r, _)| r.folder == folder && r.inputs == inputs)
        }) else {
            return Ok(None);
        };
        let Ok(report) = R::deserialize(&record.report) else {
            return Ok(None);
        };
        let mut made = Made::default();
        let mut buf = vec![0; BUFFER];
        for (name, len, hash) in &record.files {
            let rel = Path::new(folder).join(name);
            if let Err(e) = fault::write(&rel.display().to_string()) {
                made.undo();
                return Err(e);
            }
            if !self.link(out, &rel, (*len, hash), &mut buf, &mut made) {
                made.undo();
                return Ok(None);
            }
        }
        let mut written = self.written.lock().unwrap_or_else(|e| e.into_inner());
        for (name, _, _) in &record.files {
            written.push(Path::new(folder).join(name).display().to_string());
        }
        drop(written);
        self.add_record(line.clone());
        Ok(Some(report))
    }

    /// Link the earlier build's `rel` into the new folder and check it: a
    /// plain file of `len` bytes whose hash is `hash`.
    fn link(
        &self,
        out: &OutDir,
        rel: &Path,
        (len, hash): (u64, &str),
        buf: &mut [u8],
        made: &mut Made,
    ) -> bool {
        if !stays_inside(rel) {
            return false;
        }
        let Some(from) = out.plain_file(rel) else {
            return false;
        };
        let to = self.fresh.join(rel);
        if let Some(dir) = to.parent() {
            let missing: Vec<PathBuf> = dir
                .ancestors()
                .take_while(|d| d.starts_with(&self.fresh) && *d != self.fresh && !d.exists())
                .map(Path::to_path_buf)
                .collect();
            let inside = dir.strip_prefix(&self.fresh).ok();
            if make_folders(&self.fresh, inside).is_err() {
                return false;
            }
            made.dirs.extend(missing.into_iter().rev());
        }
        if fs::hard_link(&from, &to).is_err() {
            return false;
        }
        made.files.push(to.clone());
        fs::symlink_metadata(&to).is_ok_and(|m| m.is_file() && m.len() == len)
            && hash_file(&to, buf).is_ok_and(|h| hex(h) == hash)
    }
}

/// What a `keep` linked and created in the new folder, to undo it.
#[derive(Default)]
struct Made {
    files: Vec<PathBuf>,
    /// Outermost first.
    dirs: Vec<PathBuf>,
}

impl Made {
    fn undo(&self) {
        for f in &self.files {
            let _ = fs::remove_file(f);
        }
        for d in self.dirs.iter().rev() {
            let _ = fs::remove_dir(d);
        }
    }
}
