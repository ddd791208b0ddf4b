//! Helpers the benches share (each bench is its own crate: `mod common;`).
/// Peak resident set size of this process in bytes (Linux VmHWM).
pub(crate) fn peak_rss() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// CPU time this thread has run, in seconds (Linux schedstat, ns).
pub(crate) fn cpu_seconds() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .map_or(f64::NAN, |ns| ns as f64 * 1e-9)
}

/// The benches' recipe: a flat sheet of `cols` x `rows` 20 mm cells grown
/// at 45 deg on a 3000 x 2000 mm sheet.
pub(crate) fn sheet_recipe(cols: usize, rows: usize) -> String {
    format!(
        "name = \"sheet-{cols}x{rows}\"\n[lattice]\nseed = \"sheet\"\nkappa = 0.0\n[lattice.line]\nfrom = [0.0, 0.0]\nto = [{}.0, 0.0]\ncells = {cols}\n[lattice.grow]\nrows = {rows}\nstart = {}\nangle = 45.0\n[sheet]\nwidth = 3000.0\nheight = 2000.0\n",
        20 * cols,
        cols / 2
    )
}

/// `CxR` as (cols, rows).
pub(crate) fn size(s: &str) -> Option<(usize, usize)> {
    let (c, r) = s.split_once('x')?;
    Some((c.parse().ok()?, r.parse().ok()?))
}
