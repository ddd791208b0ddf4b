//! The output files of a build: every file's path in the output folder and
//! its bytes. This sits above the pipeline (`pipeline`), the guide and the
//! reports, and is the only place that knows which writer makes which file.

use crate::guide::guide_showing;
use crate::jobs::Jobs;
use crate::lattice::Lattice;
use crate::parts::solid;
use crate::pipeline::Build;
use crate::write::{dxf, lattice_json, obj, part_types_csv, parts_csv, pdf, png, svg, viewer};

/// Resolution of the sheet pictures: 2 px/mm (a 600 mm sheet is 1200 px)...
pub(crate) const SHEET_PX_PER_MM: f64 = 2.0;
/// ...but at most this many pixels a side (a 5000 mm sheet gets 0.8 px/mm),
/// so that a picture never takes more than 64 MB to draw.
pub(crate) const SHEET_MAX_PX: f64 = 4000.0;
/// Resolution of preview.png: 8 px/mm on a 160 x 120 mm page (1280 x 960 px).
pub(crate) const PREVIEW_PX_PER_MM: f64 = 8.0;

/// Every output file: a path relative to the output folder and its bytes,
/// on every core the machine has (`files_on`).
pub fn files(b: &Build) -> Vec<(String, Vec<u8>)> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    files_on(b, Jobs::new(cores))
}

/// `files`, on `jobs` threads: the sheet pictures, the longest part, may
/// be drawn while the rest is written; the files are the same either way.
pub fn files_on(b: &Build, jobs: Jobs) -> Vec<(String, Vec<u8>)> {
    let (pictures, rest) = jobs.join(|_| sheet_pictures(b), |_| rest_of_files(b));
    let mut files = sheet_files(b, pictures);
    files.extend(rest);
    files
}

/// Each sheet's PNG picture.
fn sheet_pictures(b: &Build) -> Vec<Vec<u8>> {
    b.pages
        .iter()
        .map(|page| {
            png::write(
                page,
                SHEET_PX_PER_MM.min(SHEET_MAX_PX / page.width.max(page.height)),
                1.0,
            )
        })
        .collect()
}

/// lattice.json and every sheet's files, given the sheets' pictures.
fn sheet_files(b: &Build, pictures: Vec<Vec<u8>>) -> Vec<(String, Vec<u8>)> {
    let mut files = vec![("lattice.json".to_string(), lattice_json::write(&b.lattice))];
    for ((i, page), picture) in b.pages.iter().enumerate().zip(pictures) {
        // --flat: no <use>, no blocks (docs/fabrication.md, File size).
        let (svg, dxf) = if b.design.fabrication.plotter.is_some() {
            // A cutting plotter's SVG: cut and draw groups (docs/fabrication.md).
            (svg::write_plotter(page), dxf::write_flat(page))
        } else if b.design.fabrication.flat {
            (svg::write_flat(page), dxf::write_flat(page))
        } else {
            (svg::write(page), dxf::write(page))
        };
        files.push((format!("sheets/sheet-{:02}.svg", i + 1), svg));
        files.push((format!("sheets/sheet-{:02}.dxf", i + 1), dxf));
        files.push((
            format!("sheets/sheet-{:02}.lbrn2", i + 1),
            crate::write::lbrn2::write(page),
        ));
        files.push((format!("sheets/sheet-{:02}.png", i + 1), picture));
    }
    files
}

/// Every file after the sheets: the PDFs, the tables, the pictures, the
/// viewer, the deployed shape and the report.
fn rest_of_files(b: &Build) -> Vec<(String, Vec<u8>)> {
    let name = &b.design.name;
    let fab = &b.design.fabrication;
    let mut files = Vec::new();
    files.push((
        "cut.pdf".to_string(),
        pdf::write(&format!("{name} cut sheets"), &b.pages),
    ));
    files.push((
        "parts.csv".to_string(),
        parts_csv::write(&b.parts.strips, &b.layout),
    ));
    // The simulated shape is placed once, for the guide's cover, the
    // preview and the viewer.
    let simulated = simulated_shape(b);
    let g = guide_showing(b, simulated.as_ref());
    files.push((
        "parts-types.csv".to_string(),
        part_types_csv::write(&b.parts),
    ));
    files.push((
        "assembly.pdf".to_string(),
        pdf::write_with_symbols(&format!("{name} assembly guide"), &g.pages, &g.symbols),
    ));
    let picture = match &simulated {
        Some(placed) => crate::drawing::picture::preview_captioned(
            placed,
            fab.material.width,
            name,
            Some(
                "shown: the simulated deployed shape, elastic strips joined by eyelets (deployed.obj)",
            ),
        ),
        // Not simulated: a planar true mechanism, whose design is its
        // deployed shape, or a lattice the build could not simulate (its
        // warnings say why).
        None => crate::drawing::picture::preview_captioned(
            &b.assembled,
            fab.material.width,
            name,
            Some(if crate::sim::needed(&b.lattice, &b.deployment) {
                "shown: the deployed shape as designed, not simulated (see the build's warnings)"
            } else {
                "shown: the deployed shape as designed: a true mechanism, its strips need not bend"
            }),
        ),
    };
    files.push((
        "preview.png".to_string(),
        png::write(&picture, PREVIEW_PX_PER_MM, 1.0),
    ));
    let solids: Vec<_> = b
        .parts
        .strips
        .iter()
        .map(|s| (s.id.clone(), solid(&b.lattice, s, fab)))
        .collect();
    files.push(("lattice.obj".to_string(), obj::write(name, &solids)));
    files.push((
        "viewer.html".to_string(),
        viewer::write(&scene_with(b, simulated.as_ref())),
    ));
    if let Some(run) = &b.simulation {
        files.extend(deployed_files(b, run));
    }
    if let Some(path) = &b.path {
        files.push((
            "path.png".to_string(),
            crate::write::path_png::write(
                path,
                b.design.simulation.material.eps_allow,
                &format!("{name}: the deployment path"),
            ),
        ));
    }
    files.push((
        "report.txt".to_string(),
        crate::report::build_text(b).into_bytes(),
    ));
    files
}

/// What the viewer page shows: the lattice as built and, where the
/// build simulated it, the simulated shape beside the designed one.
pub fn viewer_scene(b: &Build) -> viewer::Scene<'_> {
    scene_with(b, simulated_shape(b).as_ref())
}

/// The simulated deployed shape of a build that was simulated: the lattice
/// with its vertices and pivots where the simulation put them.
fn simulated_shape(b: &Build) -> Option<Lattice> {
    let run = b.simulation.as_ref()?;
    Some(crate::sim::placed_lattice(&b.lattice, &run.lm))
}

/// `viewer_scene` with the simulated shape already placed.
fn scene_with<'a>(b: &'a Build, simulated: Option<&Lattice>) -> viewer::Scene<'a> {
    let mut scene = viewer::Scene::new(
        &b.design,
        &b.lattice,
        &b.assembled,
        &b.parts,
        &b.layout,
        &b.deployment,
        &b.steps,
    );
    scene.path = b.path.as_ref();
    if let Some(placed) = simulated {
        let vertices = placed.vertices.iter().map(|v| v.pos);
        scene.simulated = Some(
            vertices
                .chain(placed.cells.iter().map(|c| c.pivot))
                .collect(),
        );
    }
    scene
}

/// deployed.json, deployed.obj and the solver's state for rebuilds
/// (`pipeline::STATE_FILE`) of a simulated build.
fn deployed_files(b: &Build, run: &crate::sim::Simulation) -> Vec<(String, Vec<u8>)> {
    use crate::write::deployed;
    let fab = &b.design.fabrication;
    let strips = crate::sim::results::deployed_strips(&run.lm.model);
    let eq = &run.equilibrium;
    let nv = b.lattice.vertices.len();
    let e = &eq.energy;
    let summary = deployed::Summary {
        design: &b.design.name,
        verdict: &b.deployment.verdict(&b.lattice),
        vertex_joint: b.design.simulation.vertex_joint.name(),
        theta_deg: run.theta.to_degrees(),
        energy: [e.stretch, e.bend, e.twist, e.external],
        eps_max: eq.strain.eps,
        eps_allow: b.design.simulation.material.eps_allow,
        eps_rod: &eq.strain.rod,
        eps_s: eq.strain.s,
        distance: eq.distance,
        iterations: run.iterations,
        fingerprint: b.simulation_key.map_or(0, |(key, _)| key),
        vertices: (0..nv)
            .map(|v| (b.lattice.vertex_name(v as u32), eq.points[v]))
            .collect(),
        pivots: b
            .lattice
            .cells
            .iter()
            .enumerate()
            .map(|(c, cell)| (b.lattice.cell_name(cell), eq.points[nv + c]))
            .collect(),
        supports: eq
            .supports
            .iter()
            .map(|r| (b.lattice.vertex_name(r.vertex), r.at, r.force))
            .collect(),
        support_span: crate::sim::supports::span(&eq.supports).map(|s| s.2),
    };
    vec![
        (
            "deployed.json".to_string(),
            deployed::json(&summary, &strips),
        ),
        (
            "deployed.obj".to_string(),
            deployed::obj(
                &b.design.name,
                &strips,
                fab.material.width,
                fab.material.thickness,
            ),
        ),
        (
            crate::pipeline::STATE_FILE.to_string(),
            crate::pipeline::simulation_state(run, b.path.as_ref(), summary.fingerprint),
        ),
    ]
}
