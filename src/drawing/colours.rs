//! Colour presets for the cut layers. Laser software maps colours to
//! operations, so the same file must be readable with the mapping a maker's
//! library already uses. Presets change colours only, never geometry.

use super::{Layer, Page};
use crate::fabrication::ColourPreset;

/// The colour of a layer under a preset.
pub(crate) fn rgb(preset: ColourPreset, layer: Layer) -> [u8; 3] {
    match (preset, layer) {
        (ColourPreset::Karigami, l) => l.rgb(),
        // boxes.py: outer cut black, inner cut blue, etching green,
        // annotations red.
        (ColourPreset::Boxes, Layer::Holes) => [0, 0, 255],
        (ColourPreset::Boxes, Layer::Outlines) => [0, 0, 0],
        (ColourPreset::Boxes, Layer::Labels) => [0, 255, 0],
        (ColourPreset::Boxes, Layer::Reference) => [255, 0, 0],
        (ColourPreset::Boxes, Layer::Art) => Layer::Art.rgb(),
    }
}

pub(crate) fn hex(preset: ColourPreset, layer: Layer) -> String {
    super::hex(rgb(preset, layer))
}

/// Recolour a cut sheet's layers (and its "layers" metadata) to `preset`.
pub(crate) fn apply(page: &mut Page, preset: ColourPreset) {
    if preset == ColourPreset::Karigami {
        return;
    }
    for item in page.groups.iter_mut().flat_map(|g| g.items.iter_mut()) {
        if item.layer != Layer::Art && item.ink.stroke == Some(item.layer.rgb()) {
            item.ink.stroke = Some(rgb(preset, item.layer));
        }
    }
    for (k, v) in &mut page.metadata {
        if k == "layers" {
            *v = Layer::ALL
                .iter()
                .map(|l| format!("{} {} = {}", l.name(), hex(preset, *l), l.operation()))
                .collect::<Vec<_>>()
                .join("; ");
        }
    }
    page.metadata
        .push(("colours".into(), preset.name().to_string()));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_preset_gives_the_cut_layers_distinct_colours() {
        for p in ColourPreset::ALL {
            let mut c: Vec<[u8; 3]> = Layer::ALL.iter().map(|&l| rgb(p, l)).collect();
            c.sort();
            c.dedup();
            assert_eq!(c.len(), Layer::ALL.len(), "{}", p.name());
        }
        assert_eq!(rgb(ColourPreset::Boxes, Layer::Outlines), [0, 0, 0]);
        assert_eq!(rgb(ColourPreset::Boxes, Layer::Reference), [255, 0, 0]);
    }
}
