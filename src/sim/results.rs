//! What an equilibrium says (docs/physics.md, "Strain and what is allowed"): strains and where they
//! are, joint reactions, distance from the design after the best rigid
//! fit, and a discrete curvature measure of the deployed shape.

use super::model::{Model, Stencil, bend_measures};
use glam::{DMat3, DVec3};
use std::collections::{BTreeMap, HashMap};

/// The largest corner-fibre strain of the strips, and where.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StrainPeak {
    /// (t/2)|k_flat| + (w/2)|k_edge| + axial.
    pub eps: f64,
    /// ID of the strip where the peak occurs.
    pub rod: String,
    /// Arc length from the rod's start hole (mm).
    pub s: f64,
    /// "flatwise bending", "edgewise bending" or "stretch".
    pub term: &'static str,
    /// Largest surface shear strain from twist t|m|/lbar, anywhere.
    pub gamma: f64,
    /// Largest von Mises equivalent strain, anywhere.
    pub eps_eq: f64,
}

/// Per-node strains of one rod: (s, eps, gamma).
pub(crate) fn rod_strains(m: &Model, rod: usize, nu: f64) -> Vec<(f64, f64, f64)> {
    let _ = nu;
    let path = &m.rods[rod];
    let sec = &m.section;
    let axial = |e: usize| -> f64 {
        let ed = &m.edges[e];
        if ed.is_arm() {
            return 0.0;
        }
        (m.pos(ed.b).distance(m.pos(ed.a)) / ed.rest - 1.0).abs()
    };
    let mut out = vec![(0.0, 0.0, 0.0); path.nodes.len()];
    for (k, s) in path.s.iter().enumerate() {
        out[k].0 = *s;
    }
    let interior = path.nodes.len().saturating_sub(1);
    for (k, o) in out.iter_mut().enumerate().take(interior).skip(1) {
        let (e0, e1) = (path.edges[k - 1], path.edges[k]);
        let lbar = (m.edges[e0].rest + m.edges[e1].rest) / 2.0;
        let (kf, ke, tw) = bend_measures(m, e0, e1);
        let eps = sec.thickness / 2.0 * (kf / lbar).abs()
            + sec.width / 2.0 * (ke / lbar).abs()
            + axial(e0).max(axial(e1));
        o.1 = eps;
        o.2 = sec.thickness * tw.abs() / lbar;
    }
    out
}

/// Relative difference below which two strains or reactions are a tie.
const TIE: f64 = 1e-6;

/// The strain peak over every rod.
pub(crate) fn strain_peak(m: &Model, e: f64, g: f64) -> StrainPeak {
    let sec = &m.section;
    let mut peak = StrainPeak::default();
    for path in &m.rods {
        for k in 1..path.nodes.len().saturating_sub(1) {
            let (e0, e1) = (path.edges[k - 1], path.edges[k]);
            let lbar = (m.edges[e0].rest + m.edges[e1].rest) / 2.0;
            let (kf, ke, tw) = bend_measures(m, e0, e1);
            let axial = [e0, e1]
                .iter()
                .filter(|&&x| !m.edges[x].is_arm())
                .map(|&x| {
                    let ed = &m.edges[x];
                    (m.pos(ed.b).distance(m.pos(ed.a)) / ed.rest - 1.0).abs()
                })
                .fold(0.0, f64::max);
            let terms = [
                (sec.thickness / 2.0 * (kf / lbar).abs(), "flatwise bending"),
                (sec.width / 2.0 * (ke / lbar).abs(), "edgewise bending"),
                (axial, "stretch"),
            ];
            let eps = terms.iter().map(|t| t.0).sum::<f64>();
            let gamma = sec.thickness * tw.abs() / lbar;
            let eq = (eps * eps + 3.0 * (g * gamma / e).powi(2)).sqrt();
            peak.gamma = peak.gamma.max(gamma);
            peak.eps_eq = peak.eps_eq.max(eq);
            // Strips alike by symmetry strain alike to within the solver's
            // tolerance: the first of them is named, not whichever round-off
            // favours (labels that moved with every change of the solver).
            if eps > peak.eps * (1.0 + TIE) {
                peak.eps = eps;
                peak.rod = path.name.clone();
                peak.s = path.s[k];
                peak.term = terms
                    .iter()
                    .max_by(|a, b| a.0.total_cmp(&b.0))
                    .map_or("", |t| t.1);
            }
        }
    }
    peak
}

/// Each stencil's energy gradient on the position variables `owner` maps
/// (variable -> its owner and axis), handed to `each` with the stencil:
/// the forces at joints and at supports are sums of these.
pub(crate) fn owned_gradients<T: Copy>(
    m: &Model,
    owner: &HashMap<usize, (T, usize)>,
    mut each: impl FnMut(&Stencil, T, usize, f64),
) {
    if owner.is_empty() {
        return;
    }
    for st in &m.stencils {
        let vars = m.stencil_vars(st);
        if !vars.iter().any(|v| owner.contains_key(v)) {
            continue;
        }
        let (_, g, _) = m.stencil_derivatives(st, &vars);
        for (k, v) in vars.iter().enumerate() {
            if let Some(&(o, a)) = owner.get(v) {
                each(st, o, a, g[k]);
            }
        }
    }
}

/// The largest force any joint exerts on one of its rods (N), with the
/// joint and the rod: F = -dE_rod/dX_J.
pub(crate) fn largest_reaction(m: &Model) -> (f64, usize, String) {
    let mut forces: BTreeMap<(usize, usize), DVec3> = BTreeMap::new();
    // Position variable -> (joint, axis).
    let mut owner = HashMap::new();
    for (j, jt) in m.joints.iter().enumerate() {
        for a in 0..3 {
            owner.insert(jt.x + a, (j, a));
        }
    }
    owned_gradients(m, &owner, |st, j, a, g| {
        if let Some(rod) = st.rod() {
            forces.entry((j, rod)).or_default()[a] -= g;
        }
    });
    // The first of equal reactions (to `TIE`), as for the strain.
    forces
        .into_iter()
        .map(|((j, r), f)| (f.length(), j, r))
        .fold(None, |best: Option<(f64, usize, usize)>, x| match best {
            Some(b) if !(x.0 > b.0 * (1.0 + TIE)) => Some(b),
            _ => Some(x),
        })
        .map_or((0.0, 0, String::new()), |(f, j, r)| {
            (f, j, m.rods[r].name.clone())
        })
}

/// The proper rotation and translation taking `a` onto `b` in the least
/// squares sense (Horn's quaternion method), applied to `a`.
pub(crate) fn kabsch_fit(a: &[DVec3], b: &[DVec3]) -> Vec<DVec3> {
    let n = a.len().max(1) as f64;
    let ca = a.iter().sum::<DVec3>() / n;
    let cb = b.iter().sum::<DVec3>() / n;
    let mut s = [[0.0f64; 3]; 3];
    for (p, q) in a.iter().zip(b) {
        let (p, q) = (*p - ca, *q - cb);
        for i in 0..3 {
            for j in 0..3 {
                s[i][j] += p[i] * q[j];
            }
        }
    }
    let rot = crate::rigid::horn_rotation(s);
    let m = DMat3::from_quat(rot);
    a.iter().map(|p| cb + m * (*p - ca)).collect()
}

/// Largest point distance after the best proper rigid fit of `a` onto `b`.
pub fn kabsch_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    shape_distance(a, b).max
}

/// How far one shape lies from another after the best proper rigid fit:
/// the root mean square and the largest of the point distances, and the
/// point of the largest (the first of equal ones).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShapeDistance {
    /// Root mean square of the point distances (mm).
    pub rms: f64,
    /// Largest point distance (mm).
    pub max: f64,
    /// Index of the point at the largest distance.
    pub at: usize,
}

/// `ShapeDistance` of `a` fitted onto `b`, point by point.
pub fn shape_distance(a: &[DVec3], b: &[DVec3]) -> ShapeDistance {
    let d: Vec<f64> = kabsch_fit(a, b)
        .iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q))
        .collect();
    let mut out = ShapeDistance::default();
    for (i, &x) in d.iter().enumerate() {
        if x > out.max {
            (out.max, out.at) = (x, i);
        }
    }
    let n = d.len().max(1) as f64;
    out.rms = (d.iter().map(|x| x * x).sum::<f64>() / n).sqrt();
    out
}

/// One strip of an equilibrium, node by node, for deployed.json/.obj.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct DeployedStrip {
    /// The engraved strip id.
    pub(crate) id: String,
    /// Arc length from the first hole (mm).
    pub(crate) s: Vec<f64>,
    pub(crate) centre: Vec<DVec3>,
    /// Width direction and face normal at each node (mean of its edges).
    pub(crate) d1: Vec<DVec3>,
    pub(crate) d2: Vec<DVec3>,
    /// Corner-fibre strain and twist shear strain at each node.
    pub(crate) strain: Vec<f64>,
    pub(crate) gamma: Vec<f64>,
}

/// Every strip of the model as it is now.
pub(crate) fn deployed_strips(m: &Model) -> Vec<DeployedStrip> {
    (0..m.rods.len())
        .map(|r| {
            let path = &m.rods[r];
            let frames: Vec<(DVec3, DVec3, DVec3)> =
                path.edges.iter().map(|&e| m.edge_frame(e)).collect();
            let at = |k: usize, pick: fn(&(DVec3, DVec3, DVec3)) -> DVec3| {
                let before = k.checked_sub(1).map(|i| pick(&frames[i]));
                let after = frames.get(k).map(pick);
                let sum = before.unwrap_or(DVec3::ZERO) + after.unwrap_or(DVec3::ZERO);
                sum.try_normalize().unwrap_or(sum)
            };
            let strains = rod_strains(m, r, 0.0);
            DeployedStrip {
                id: path.name.clone(),
                s: path.s.clone(),
                centre: path.nodes.iter().map(|&n| m.pos(n)).collect(),
                d1: (0..path.nodes.len()).map(|k| at(k, |f| f.1)).collect(),
                d2: (0..path.nodes.len()).map(|k| at(k, |f| f.2)).collect(),
                strain: strains.iter().map(|x| x.1).collect(),
                gamma: strains.iter().map(|x| x.2).collect(),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_distance_is_rigid_invariant_and_finds_the_farthest_point() {
        let a: Vec<DVec3> = (0..12)
            .map(|k| DVec3::new((k % 4) as f64 * 10.0, (k / 4) as f64 * 10.0, 0.0))
            .collect();
        // Turned and moved: no distance at all.
        let turn = DMat3::from_rotation_z(0.3) * DMat3::from_rotation_x(0.2);
        let b: Vec<DVec3> = a
            .iter()
            .map(|p| turn * *p + DVec3::new(5.0, -2.0, 7.0))
            .collect();
        let d = shape_distance(&a, &b);
        assert!(d.max < 1e-9 && d.rms < 1e-9, "{d:?}");
        // One point lifted 3 mm: it is the farthest, the rms below the largest.
        let mut c = a.clone();
        c[5].z += 3.0;
        let d = shape_distance(&c, &a);
        assert_eq!(d.at, 5);
        assert!(d.max > 2.0 && d.max <= 3.0 && d.rms < d.max, "{d:?}");
        assert_eq!(kabsch_distance(&c, &a), d.max);
    }
}
