//! Sheets of `karigami design` (docs/design.md, "What it reaches"): each
//! seed is searched with more than one scan of leg angles, and what the
//! search finds does not depend on the threads.

use karigami::designing::{self, DesignAsk};
use std::sync::Arc;

/// The search's designs for a small saddle with `jobs` threads: each
/// one's seed note and its lattice text.
fn searched(jobs: usize) -> Vec<(String, String)> {
    let text = "[target]\nfamily = \"saddle\"\nwidth = 200.0\nlength = 200.0\nheight = 20.0\n";
    let t = karigami::targets::read("t.toml", text.as_bytes(), None).unwrap();
    let base = karigami::parse(designing::STUB, "t").unwrap();
    let ask = DesignAsk {
        target: Arc::new(t.canonical()),
        base: &base,
        edge: 50.0,
        deadline: None,
        jobs: karigami::Jobs::new(jobs),
    };
    let found = designing::search(&ask, &mut |_| {}).unwrap().found;
    found.into_iter().map(|f| (f.seed, f.lattice)).collect()
}

/// A saddle's sheets come from both scans, 31 and 29 leg angles, and
/// the two scans grow different rows; one thread or two, the same
/// designs in the same order.
#[test]
fn a_saddles_seeds_are_searched_with_two_scans_alike_for_any_jobs() {
    let two = searched(2);
    let of = |n: &str| -> Vec<&String> {
        two.iter()
            .filter(|(seed, _)| seed.contains(&format!("scanned over {n} leg angles")))
            .map(|(_, lattice)| lattice)
            .collect()
    };
    let (a, b) = (of("31"), of("29"));
    assert!(!a.is_empty() && !b.is_empty(), "{two:?}");
    assert!(
        a.iter().all(|l| !b.contains(l)),
        "the scans grew the same rows"
    );
    assert_eq!(searched(1), two);
}
