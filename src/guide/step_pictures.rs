//! The step pages' pictures of the lattice: shared symbols for the rows
//! so far, the camera, and zoomed pictures of wide rows.

use super::NEW;
use super::labels::Placer;
use super::stacking;
use super::step_labels::{LABEL_ROOM, Shown, step_labels};
use crate::assembly::Step;
use crate::drawing::flow::{FAINT, MARGIN, PageFlow};
use crate::drawing::picture::{Camera, Fit, RodStyle, crossing_rods, pivots_and_vertices, rods};
use crate::drawing::{Place, Symbol};
use crate::pipeline::Build;
use glam::DVec2;

/// The height of a step page's picture of the lattice (mm).
pub(super) const STEP_PICTURE: f64 = 84.0;

/// The step pages' pictures of the lattice, as shared symbols: step k shows
/// rows 0..k grey (faint), row k in colour on top, then the dots at the
/// pivots and vertices of rows 0..=k. Each row's grey rods and its dots are
/// one symbol each, drawn once; blocks of about sqrt(steps) consecutive
/// rows are symbols too, so that a page places at most about 2 sqrt(steps)
/// symbols and the whole guide grows with the cells, not rows x cells.
pub(super) struct StepPictures {
    pub(super) symbols: Vec<Symbol>,
    /// Symbol of each row's grey rods, and of its dots.
    pub(super) faint: Vec<usize>,
    pub(super) dots: Vec<usize>,
    /// Symbols of whole blocks of `block` rows: grey rods, dots.
    pub(super) faint_blocks: Vec<usize>,
    pub(super) dot_blocks: Vec<usize>,
    pub(super) block: usize,
    /// Rod width of the grey rods (mm); the new row's is 1.3 times wider.
    pub(super) width: f64,
}

impl StepPictures {
    pub(super) fn new(b: &Build, steps: &[Step], size: DVec2) -> Self {
        let lattice = &b.assembled;
        // Symbols are drawn with the picture box's top-left corner at 0.
        let fit = Self::fit(b, DVec2::ZERO, size);
        let width = Self::rod_width(b, &fit);
        // Each vertex's dot belongs to the first step that shows it.
        let mut first = vec![usize::MAX; lattice.vertices.len()];
        let mut new_vertices: Vec<Vec<usize>> = vec![Vec::new(); steps.len()];
        for (k, step) in steps.iter().enumerate() {
            for &c in &step.cells {
                let cell = &lattice.cells[c];
                for v in cell.corner_ids() {
                    if first[v as usize] == usize::MAX {
                        first[v as usize] = k;
                        new_vertices[k].push(v as usize);
                    }
                }
            }
            new_vertices[k].sort_unstable();
        }
        let mut symbols = Vec::with_capacity(2 * steps.len() + 16);
        let (mut faint, mut dots) = (Vec::new(), Vec::new());
        for (step, vertices) in steps.iter().zip(&new_vertices) {
            let style = |_| {
                Some(RodStyle {
                    colour: FAINT,
                    width,
                })
            };
            faint.push(symbols.len());
            symbols.push(Symbol {
                uses: Vec::new(),
                items: rods(lattice, &fit, &step.cells, style),
            });
            dots.push(symbols.len());
            symbols.push(Symbol {
                uses: Vec::new(),
                items: pivots_and_vertices(lattice, &fit, &step.cells, vertices, width * 0.8),
            });
        }
        let block = (steps.len() as f64).sqrt().ceil().max(1.0) as usize;
        let (mut faint_blocks, mut dot_blocks) = (Vec::new(), Vec::new());
        for start in (0..steps.len()).step_by(block) {
            if start + block > steps.len() {
                break;
            }
            for (rows, blocks) in [(&faint, &mut faint_blocks), (&dots, &mut dot_blocks)] {
                blocks.push(symbols.len());
                symbols.push(Symbol {
                    uses: rows[start..start + block].to_vec(),
                    items: Vec::new(),
                });
            }
        }
        Self {
            symbols,
            faint,
            dots,
            faint_blocks,
            dot_blocks,
            block,
            width,
        }
    }

    pub(super) fn fit(b: &Build, origin: DVec2, size: DVec2) -> Fit {
        Fit::new(&b.assembled, step_camera(b), origin, size)
    }

    pub(super) fn rod_width(b: &Build, fit: &Fit) -> f64 {
        (0.6 * fit.scale() * b.design.fabrication.material.width).clamp(0.3, 1.4)
    }

    /// Symbols showing rows `0..end`, from `rows` and whole `blocks`.
    pub(super) fn prefix(
        &self,
        rows: &[usize],
        blocks: &[usize],
        end: usize,
        at: DVec2,
    ) -> Vec<Place> {
        let whole = (end / self.block).min(blocks.len());
        blocks[..whole]
            .iter()
            .chain(&rows[whole * self.block..end])
            .map(|&symbol| Place { symbol, at })
            .collect()
    }
}

/// The corner vertices of `cells`, sorted, each once.
pub(super) fn corners(l: &crate::lattice::Lattice, cells: &[usize]) -> Vec<usize> {
    let mut vertices: Vec<usize> = cells
        .iter()
        .flat_map(|&c| {
            let cell = &l.cells[c];
            cell.corner_ids().map(|v| v as usize)
        })
        .collect();
    vertices.sort_unstable();
    vertices.dedup();
    vertices
}

/// Step pictures of a lattice built flat look square on at it.
pub(super) fn step_camera(b: &Build) -> Camera {
    if stacking::built_flat(&b.lattice) {
        Camera::face_on(&b.assembled)
    } else {
        Camera::for_lattice(&b.assembled)
    }
}

/// Cells in one zoomed picture of a wide row, and its height (mm).
pub(super) const DETAIL_CELLS: usize = 8;
pub(super) const DETAIL_HEIGHT: f64 = 42.0;

/// Zoomed pictures of a wide step, `DETAIL_CELLS` cells each: the row above
/// in grey and this row in colour, labelled like a whole-lattice picture.
/// Each joint is labelled in the first picture that shows it.
/// How many cells each zoomed picture of a step shows.
fn detail_chunk(b: &Build, step: &Step) -> usize {
    let l = &b.assembled;
    // On a 3-D loop a picture shows at most a quarter of the ring, so that
    // it is seen square on.
    let most = if l.dim == 3 && l.kind == crate::lattice::Kind::Loop {
        l.width.div_ceil(4).clamp(1, DETAIL_CELLS)
    } else {
        DETAIL_CELLS
    };
    let chunks = step.cells.len().div_ceil(most);
    step.cells.len().div_ceil(chunks.max(1)).max(1)
}

/// The tallest a zoomed picture grows (mm): long strips in a wide row
/// (the saddle ring's 558 mm strips) get tall panels, so their labels have
/// room beside them instead of piling up at one end.
const MAX_DETAIL_HEIGHT: f64 = 120.0;

/// One zoomed picture of a step: the row above's cells over `cells`, the
/// points it must show, its camera and its height (mm) at `width`.
fn panel(
    b: &Build,
    step: &Step,
    cells: &[usize],
    width: f64,
) -> (Vec<usize>, Vec<glam::DVec3>, Camera, f64) {
    let l = &b.assembled;
    let cols: Vec<u32> = cells.iter().map(|&c| l.cells[c].col).collect();
    let above: Vec<usize> = (0..l.cells.len())
        .filter(|&c| {
            let cell = &l.cells[c];
            step.row > 0 && cell.row + 1 == step.row && cols.contains(&cell.col)
        })
        .filter(|_| l.kind != crate::lattice::Kind::Helix)
        .collect();
    let points: Vec<glam::DVec3> = cells
        .iter()
        .chain(&above)
        .flat_map(|&c| {
            let cell = &l.cells[c];
            cell.corner_ids()
                .map(|v| l.vertex(v).pos)
                .into_iter()
                .chain([cell.pivot])
        })
        .collect();
    let camera = detail_camera(b, cells).unwrap_or_else(|| step_camera(b));
    let (lo, hi) = points.iter().map(|&p| camera.project(p)).fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), q| (lo.min(q), hi.max(q)),
    );
    let extent = (hi - lo).max(DVec2::splat(1e-9));
    let height = (width * extent.y / extent.x).clamp(DETAIL_HEIGHT, MAX_DETAIL_HEIGHT);
    (above, points, camera, height)
}

/// How far down the page a step's zoomed pictures reach (mm).
pub(super) fn details_height(b: &Build, step: &Step, width: f64) -> f64 {
    step.cells
        .chunks(detail_chunk(b, step))
        .map(|cells| panel(b, step, cells, width).3 + 2.0 * LABEL_ROOM + 2.0)
        .sum()
}

pub(super) fn details(w: &mut PageFlow, b: &Build, step: &Step, named: &[usize]) {
    let l = &b.assembled;
    let per = detail_chunk(b, step);
    let mut done = vec![false; step.joints.len()];
    for cells in step.cells.chunks(per) {
        let (above, points, camera, panel_h) = panel(b, step, cells, w.width());
        let height = panel_h + 2.0 * LABEL_ROOM;
        w.need(height + 2.0);
        let top = w.y;
        let at = DVec2::new(MARGIN, top + LABEL_ROOM);
        let fit = Fit::around(
            points.into_iter(),
            camera,
            at,
            DVec2::new(w.width(), panel_h),
        );
        let width = (0.6 * fit.scale() * b.design.fabrication.material.width).clamp(0.4, 2.0);
        let mut items = rods(l, &fit, &above, |_| {
            Some(RodStyle {
                colour: FAINT,
                width,
            })
        });
        items.extend(crossing_rods(l, &fit, cells, |_| {
            Some(RodStyle {
                colour: NEW,
                width: width * 1.3,
            })
        }));
        let all: Vec<usize> = cells.iter().chain(&above).copied().collect();
        let vertices = corners(l, &all);
        items.extend(pivots_and_vertices(l, &fit, &all, &vertices, width * 0.8));
        let mut joints = Vec::new();
        for (k, j) in step.joints.iter().enumerate() {
            if !done[k] && vertices.contains(&(j.vertex as usize)) {
                done[k] = true;
                joints.push(j);
            }
        }
        let mut placer = Placer::new(
            DVec2::new(MARGIN - 1.0, top),
            DVec2::new(MARGIN + w.width() + 1.0, top + height),
        );
        let shown = Shown {
            cells,
            joints,
            first_row: step.row.saturating_sub(1),
            vertices: Some(&vertices),
        };
        items.extend(step_labels(b, step, &fit, &mut placer, named, &shown));
        items.extend(placer.items);
        w.push(items);
        w.group_id = Some(format!("step-{}-labels", step.number));
        w.close_group();
        w.group_id = None;
        w.y = top + height + 2.0;
    }
}

/// A camera square on to a stretch of a loop's row, from outside, the row
/// above at the top; None for other lattices (their step camera serves).
pub(super) fn detail_camera(b: &Build, cells: &[usize]) -> Option<Camera> {
    let l = &b.assembled;
    if l.dim != 3 || l.kind == crate::lattice::Kind::Sheet {
        return None;
    }
    let (mut normal, mut up, mut centre) =
        (glam::DVec3::ZERO, glam::DVec3::ZERO, glam::DVec3::ZERO);
    for &c in cells {
        let [ul, ur, ll, lr] = l.corners(&l.cells[c]);
        normal += (ur - ul).cross(ll - ul).normalize_or_zero();
        up += (ul + ur - ll - lr).normalize_or_zero();
        centre += l.cells[c].pivot;
    }
    centre /= cells.len().max(1) as f64;
    let middle =
        l.vertices.iter().map(|v| v.pos).sum::<glam::DVec3>() / l.vertices.len().max(1) as f64;
    // Outward: away from the lattice's centre.
    let outward = if normal.dot(centre - middle) < 0.0 {
        -normal
    } else {
        normal
    };
    Camera::looking(-outward, up)
}
