//! Histograms of the active mesh in the panel (`egui_plot`): vertex valences, corner angles, edge
//! lengths, and the quantity the mesh is coloured by. Counted when the mesh changes (with the
//! statistics, after a drag ends), drawn from the counts every frame.

use bevy::prelude::World;
use bevy_egui::egui;
use egui_plot::{Bar, BarChart, Plot};

use crate::mesh::MeshId;
use crate::mesh::tables::{Connectivity, extract};
use crate::ops::geometry::Quantity;
use crate::ops::geometry::quantity::corner_angles_deg;

use crate::editor::view::colouring::VertexValues;

/// One histogram: equal bins from `start`, `width` wide.
#[derive(Clone, Debug, PartialEq)]
pub struct Histogram {
    /// What is counted (and its unit).
    pub title: String,
    /// Where the first bin starts.
    pub start: f64,
    /// The width of each bin.
    pub width: f64,
    /// The count in each bin.
    pub counts: Vec<u32>,
}

impl Histogram {
    /// `bins` equal bins over `[low, high]` (values outside go to the end bins; non-finite ones
    /// are not counted).
    pub fn of(title: impl Into<String>, values: &[f64], low: f64, high: f64, bins: usize) -> Self {
        let bins = bins.max(1);
        let width = if high > low {
            (high - low) / bins as f64
        } else {
            1.0
        };
        let mut counts = vec![0u32; bins];
        for &v in values.iter().filter(|v| v.is_finite()) {
            let i = ((v - low) / width).floor().clamp(0.0, (bins - 1) as f64) as usize;
            counts[i] += 1;
        }
        Self {
            title: title.into(),
            start: low,
            width,
            counts,
        }
    }
}

/// The panel's histograms of `mesh`: valence (one bin per value), corner angles (5° bins),
/// edge lengths (30 bins up to the 99th percentile), and `shown`'s values over its colour range.
pub fn histograms(world: &World, mesh: MeshId, shown: Option<&VertexValues>) -> Vec<Histogram> {
    histograms_of_tables(&extract(world, mesh).tables, shown)
}

/// [`histograms`] of a mesh's tables (computable away from the world).
pub fn histograms_of_tables(t: &Connectivity, shown: Option<&VertexValues>) -> Vec<Histogram> {
    let valence = Quantity::VALENCE.per_vertex(t, &Default::default());
    let most = valence.iter().copied().fold(3.0, f64::max).min(16.0);
    let angles: Vec<f64> = t.faces().flat_map(|f| corner_angles_deg(t, f)).collect();
    let mut lengths: Vec<f64> = t.edges().map(|e| f64::from(t.edge_length(e))).collect();
    let mut out = vec![
        Histogram::of("valence", &valence, 0.5, most + 0.5, most as usize),
        Histogram::of("corner angles (°)", &angles, 0.0, 180.0, 36),
    ];
    if !lengths.is_empty() {
        lengths.sort_unstable_by(f64::total_cmp);
        let high = lengths[(lengths.len() - 1) * 99 / 100];
        out.push(Histogram::of("edge lengths", &lengths, 0.0, high, 30));
    }
    if let Some(shown) = shown {
        let values: Vec<f64> = shown.values.values().copied().collect();
        out.push(Histogram::of(
            shown.quantity.label(),
            &values,
            shown.range.low,
            shown.range.high,
            30,
        ));
    }
    out
}

/// Draws one histogram as a small bar chart.
pub fn draw(ui: &mut egui::Ui, histogram: &Histogram) {
    ui.label(egui::RichText::new(&histogram.title).small());
    let bars: Vec<Bar> = histogram
        .counts
        .iter()
        .enumerate()
        .map(|(i, &n)| {
            Bar::new(
                histogram.start + (i as f64 + 0.5) * histogram.width,
                f64::from(n),
            )
            .width(histogram.width * 0.9)
        })
        .collect();
    Plot::new(histogram.title.as_str())
        .height(70.0)
        .allow_zoom(false)
        .allow_drag(false)
        .allow_scroll(false)
        .show_axes([true, false])
        .show(ui, |plot| {
            plot.bar_chart(BarChart::new(histogram.title.as_str(), bars));
        });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{MeshInfo, build_mesh, shapes};

    #[test]
    fn a_cube_counts_exactly() {
        let mut world = World::new();
        let built = build_mesh(&mut world, &shapes::cube(), MeshInfo::default()).unwrap();
        let h = histograms(&world, built.mesh, None);
        // Eight vertices of valence 3; 24 right angles; 12 edges of one length.
        assert_eq!(h[0].counts[2], 8);
        assert_eq!(h[1].counts[18], 24, "90° falls in the bin [90, 95)");
        assert_eq!(h[2].counts.iter().sum::<u32>(), 12);
    }

    #[test]
    fn values_outside_go_to_the_end_bins() {
        let h = Histogram::of("x", &[-5.0, 0.5, 99.0, f64::NAN], 0.0, 1.0, 2);
        assert_eq!(h.counts, vec![1, 2]);
    }
}
