//! Fault injection for the safety tests, inert unless `KARIGAMI_FAULT` is
//! set. Every file write and every rename or removal of a build commit is a
//! numbered step; the variable (comma-separated) can
//! - `abort@K`: abort the process at step K, as a kill would (no cleanup);
//! - `enospc@K`: fail every write from step K on with "No space left on
//!   device", as a full disk would;
//! - `noexchange`: commit without the atomic folder swap, as on systems
//!   that lack it, to test the fallback and its recovery;
//! - `exdev`: --out cannot be moved (both the swap and a rename of it
//!   fail with EXDEV), as an overlay file system's folder from a lower
//!   layer, to test the commit in place;
//! - `nosync`: skip fsync, which guards against power loss, not the kills
//!   and full disks simulated here (hundreds of runs on a busy CI disk);
//! - `syncfail@K`: fail the K-th flush to the disk (fsync, counted apart
//!   from the steps) with an I/O error, as a failing disk would;
//! - `add@REL`, `addlate@REL`, `addgone@REL`: not a fault but a user:
//!   create REL (a file, a folder if it ends in `/`, a symbolic link to T
//!   if it is `NAME->T`) inside --out just
//!   before a commit checks what appeared in it while the build ran
//!   (`add`), just after that check, before the swap (`addlate`), or in
//!   the build swapped out, once it was checked again (`addgone`, as a
//!   program whose current folder is inside --out would), or into --out
//!   just after the swap, before the second check (`addnew`: a user
//!   writing into the new build);
//! - `edit`: not a fault but a user: append a line to the file `tune
//!   --out` writes, just before it is written (an edit made while tuning
//!   ran);
//! - `firstnote@MS`: not a fault but the tests' clock: a phase off a
//!   terminal prints its first progress line after MS milliseconds instead
//!   of 2 s, so that a test sees one however fast the machine builds.
//!
//! The variable is read only in a build with this crate's cargo feature
//! `fault-injection` (karigami's feature of the same name turns it on;
//! its scripts/test builds with it). Without it `inert.rs` stands in,
//! whose hooks are the plain operations: the shipped binary holds no
//! fault code, nor the variable's name.

#[cfg(feature = "fault-injection")]
mod injected;
#[cfg(feature = "fault-injection")]
use injected as hooks;

#[cfg(not(feature = "fault-injection"))]
mod inert;
#[cfg(not(feature = "fault-injection"))]
use inert as hooks;

pub(crate) use hooks::{
    Moment, add, commit, cross_device, no_exchange, rename_folder, sync, write,
};
pub use hooks::{edit, first_note};
