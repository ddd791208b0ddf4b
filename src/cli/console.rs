//! Standard output and standard error, whose failures are not lost: a
//! full disk or a failing device behind either (`check --json > f` on a
//! full disk) makes the run fail with a message, where an ignored error
//! left an empty file and exit 0 (issue 36, finding 5). A closed pipe
//! (`karigami check --json | head`) is no failure: what was asked for has
//! been read, and the rest is not wanted.

use std::io::{self, Write};
use std::sync::Mutex;

/// The first failed write, said as the user is told of it.
static FAILED: Mutex<Option<String>> = Mutex::new(None);

/// Which stream a write went to.
#[derive(Clone, Copy)]
pub(crate) enum Stream {
    Out,
    Err,
}

/// Take note of the outcome of a write to `stream` (the `out!`, `outln!`,
/// `err!` and `errln!` macros); a closed pipe is not a failure.
pub(crate) fn noted(written: io::Result<()>, stream: Stream) {
    let Err(e) = written else {
        return;
    };
    if e.kind() == io::ErrorKind::BrokenPipe {
        return;
    }
    let name = match stream {
        Stream::Out => "standard output",
        Stream::Err => "standard error",
    };
    let mut failed = FAILED.lock().unwrap_or_else(|e| e.into_inner());
    failed.get_or_insert_with(|| format!("cannot write to {name}: {e}"));
}

/// The exit code of a run that would exit with `code`: after flushing
/// both streams, 3 (an I/O error) if any write to them failed, with a
/// message on standard error (which may itself be what failed).
pub(crate) fn exit_code(code: i32) -> i32 {
    noted(io::stdout().flush(), Stream::Out);
    noted(io::stderr().flush(), Stream::Err);
    let failed = FAILED.lock().unwrap_or_else(|e| e.into_inner()).take();
    let Some(why) = failed else {
        return code;
    };
    let _ = writeln!(io::stderr(), "karigami: {why}; the output is incomplete");
    if code == 0 { 3 } else { code }
}
