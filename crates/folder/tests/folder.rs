//! The build folder's transactions through the crate's face: a staged
//! build committed whole or not at all, the lock, markers that are not to
//! be trusted, edits kept aside, and reads that a FIFO cannot hang
//! (karigami's docs/build-folders.md). karigami's tests/safety.rs runs the
//! same through the binary, with kills and full disks.

use karigami_folder::{
    Error, Host, Links, MARKER, OutDir, Staged, Untrusted, interrupt, read_plain, set_host,
};
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The warnings commits gave, for the tests to read.
static WARNINGS: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// A fresh folder for one test, and the host set (once a process).
fn scratch(name: &str) -> PathBuf {
    set_host(Host {
        program: "karigami-folder-tests 0",
        warn: |line| WARNINGS.lock().unwrap().push(line.to_string()),
    });
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("folder-{}", std::process::id()))
        .join(name);
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

fn files(list: &[(&str, &str)]) -> Vec<(String, Vec<u8>)> {
    list.iter()
        .map(|(n, t)| (n.to_string(), t.as_bytes().to_vec()))
        .collect()
}

/// Build `list` into `out` and commit it.
fn build(out: &Path, list: &[(&str, &str)]) {
    let dir = OutDir::open(out, &[], false).unwrap();
    let staged = Staged::new(&dir, "single").unwrap();
    staged
        .write_build("", &files(list), Some(7), &"report")
        .unwrap();
    staged.commit().unwrap();
}

/// Every entry beside `out` (its parent's names), sorted.
fn beside(out: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(out.parent().unwrap())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn a_commit_replaces_the_folder_whole_and_leaves_nothing_beside_it() {
    let out = scratch("commit").join("out");
    build(&out, &[("a.svg", "one"), ("sub/b.pdf", "two")]);
    assert_eq!(fs::read_to_string(out.join("sub/b.pdf")).unwrap(), "two");
    let marker = fs::read_to_string(out.join(MARKER)).unwrap();
    assert!(marker.starts_with("karigami build folder\nformat 1\nkind single\n"));
    assert!(
        marker.contains("written by karigami-folder-tests 0;"),
        "{marker}"
    );
    assert!(marker.contains("files:\na.svg\nsub/b.pdf\n\n"), "{marker}");
    // A rebuild with other files: none of the first build's stays.
    build(&out, &[("c.svg", "three")]);
    assert!(!out.join("a.svg").exists() && !out.join("sub").exists());
    assert_eq!(fs::read_to_string(out.join("c.svg")).unwrap(), "three");
    // No lock, staging folder or set-aside build is left beside it.
    assert_eq!(beside(&out), ["out"]);
}

#[test]
fn a_build_not_committed_leaves_the_folder_as_it_was() {
    let out = scratch("rollback").join("out");
    build(&out, &[("a.svg", "one")]);
    let dir = OutDir::open(&out, &[], false).unwrap();
    let staged = Staged::new(&dir, "single").unwrap();
    staged.write("", &files(&[("a.svg", "new")])).unwrap();
    // A path that leaves the folder is refused, and written nowhere.
    let refused = staged.write("", &files(&[("../x.svg", "out")]));
    assert!(
        refused
            .unwrap_err()
            .to_string()
            .contains("not a plain path")
    );
    let staging: Vec<PathBuf> = interrupt::registered();
    assert!(
        staging
            .iter()
            .any(|p| p.to_string_lossy().contains(".out.karigami-new-"))
    );
    drop(staged);
    assert_eq!(dir.kept(), format!("{} was left as it was", out.display()));
    drop(dir);
    assert_eq!(fs::read_to_string(out.join("a.svg")).unwrap(), "one");
    assert!(!out.parent().unwrap().join("x.svg").exists());
    assert_eq!(beside(&out), ["out"]);
    // What the interrupt handler would remove is let go with the run.
    let left = interrupt::registered();
    assert!(!left.iter().any(|p| p.starts_with(out.parent().unwrap())));
}

#[test]
fn a_second_run_is_refused_while_the_first_holds_the_lock() {
    let out = scratch("lock").join("out");
    let first = OutDir::open(&out, &[], false).unwrap();
    let lock = out.parent().unwrap().join(".out.karigami-lock");
    assert!(interrupt::registered().contains(&lock));
    match OutDir::open(&out, &[], false) {
        Err(Error::Locked { lock: held, .. }) => assert_eq!(held, lock),
        Err(e) => panic!("not refused as locked: {e}"),
        Ok(_) => panic!("a second run took the lock"),
    }
    drop(first);
    assert!(!lock.exists());
    OutDir::open(&out, &[], false).unwrap();
}

#[test]
fn a_marker_listing_paths_outside_the_folder_is_not_trusted() {
    let base = scratch("marker");
    fs::write(base.join("precious"), "mine").unwrap();
    for (name, bad) in [("up", "../precious"), ("far", "/etc/passwd")] {
        let out = base.join(name);
        fs::create_dir_all(&out).unwrap();
        let marker = format!("karigami build folder\nformat 1\nfiles:\n{bad}\n\n");
        fs::write(out.join(MARKER), marker).unwrap();
        match OutDir::open(&out, &[], false) {
            Err(e @ Error::NotABuildFolder { .. }) => {
                let Error::NotABuildFolder { why, files, .. } = &e else {
                    unreachable!()
                };
                assert!(matches!(why, Untrusted::ListsOutside(p) if p == bad));
                assert_eq!(*files, 1);
                assert!(e.to_string().contains("a path outside the folder"), "{e}");
            }
            Err(e) => panic!("refused for another reason: {e}"),
            Ok(_) => panic!("{bad} was trusted"),
        }
        // With --force it is replaced as a folder of someone's, and the
        // file it named outside is not touched.
        build_forced(&out);
        assert_eq!(fs::read_to_string(base.join("precious")).unwrap(), "mine");
    }
}

fn build_forced(out: &Path) {
    let dir = OutDir::open(out, &[], true).unwrap();
    assert!(dir.force_warning().is_some());
    let staged = Staged::new(&dir, "single").unwrap();
    staged.write("", &files(&[("a.svg", "x")])).unwrap();
    staged.commit().unwrap();
}

#[test]
fn a_file_edited_since_the_build_is_kept_aside_by_the_rebuild() {
    let out = scratch("edited").join("out");
    build(&out, &[("a.svg", "one"), ("b.svg", "two")]);
    fs::write(out.join("a.svg"), "edited by hand").unwrap();
    build(&out, &[("a.svg", "one again")]);
    let kept = out.with_file_name("out.karigami-kept-1");
    assert_eq!(
        fs::read_to_string(kept.join("a.svg")).unwrap(),
        "edited by hand"
    );
    assert!(!kept.join("b.svg").exists(), "an unedited file was kept");
    assert_eq!(fs::read_to_string(out.join("a.svg")).unwrap(), "one again");
    let warnings = WARNINGS.lock().unwrap().clone();
    let said = format!(
        "warning: 1 file of the earlier build of {} changed since karigami wrote it (a.svg); the rebuild replaced it, and it is kept in {}",
        out.display(),
        kept.display()
    );
    assert!(warnings.contains(&said), "{warnings:?}");
}

#[test]
fn unchanged_files_are_kept_from_the_earlier_build() {
    let out = scratch("keep").join("out");
    build(&out, &[("a.svg", "one")]);
    let dir = OutDir::open(&out, &[], false).unwrap();
    let staged = Staged::new(&dir, "single").unwrap();
    assert_eq!(staged.keep::<String>(&dir, "", Some(8)).unwrap(), None);
    let kept = staged.keep::<String>(&dir, "", Some(7)).unwrap();
    assert_eq!(kept.as_deref(), Some("report"));
    assert_eq!(staged.written(), ["a.svg"]);
    staged.commit().unwrap();
    assert_eq!(fs::read_to_string(out.join("a.svg")).unwrap(), "one");
}

#[cfg(unix)]
fn fifo(path: &Path) {
    let made = std::process::Command::new("mkfifo").arg(path).status();
    assert!(made.unwrap().success(), "mkfifo {}", path.display());
}

#[cfg(unix)]
#[test]
fn bounded_reads_refuse_fifos_without_waiting() {
    let base = scratch("fifo");
    let pipe = base.join("pipe");
    fifo(&pipe);
    // No writer ever comes: a read that waited would hang the test.
    for links in [Links::Follow, Links::Refuse] {
        let e = read_plain(&pipe, 100, links).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
        assert!(e.to_string().contains("a FIFO (named pipe)"), "{e}");
    }
    // A marker that is a FIFO is no marker: the folder is not a build's.
    let out = base.join("out");
    fs::create_dir_all(&out).unwrap();
    fifo(&out.join(MARKER));
    match OutDir::open(&out, &[], false) {
        Err(Error::NotABuildFolder { why, .. }) => {
            assert!(matches!(why, Untrusted::NoMarker { older: false }));
        }
        Err(e) => panic!("refused for another reason: {e}"),
        Ok(_) => panic!("a FIFO was taken for a marker"),
    }
}

#[test]
fn reads_stop_at_their_limit() {
    let base = scratch("limit");
    let file = base.join("f");
    fs::write(&file, "12345").unwrap();
    assert_eq!(read_plain(&file, 5, Links::Refuse).unwrap(), b"12345");
    let e = read_plain(&file, 4, Links::Refuse).unwrap_err();
    assert_eq!(e.kind(), std::io::ErrorKind::FileTooLarge);
}
