//! Colour maps for quantities on a mesh, shared by the editor's view and the command line's
//! export, so a value has the same colour in both.
//!
//! - [`ColorMap::Viridis`], perceptually uniform and readable in grey and by most colour-blind
//!   viewers (van der Walt & Smith's matplotlib default), for quantities of one sign.
//! - [`ColorMap::Diverging`], blue through white to red (Moreland's "cool to warm", 2009), for
//!   signed quantities such as curvature: white is zero, so the sign reads at a glance.
//!
//! [`Range::robust`] clamps at percentiles so that one outlier (a near-degenerate triangle's
//! huge curvature) does not wash the rest of the map out; a diverging range is made symmetric
//! about zero.

/// A colour map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorMap {
    /// Dark blue → green → yellow: for values of one sign.
    Viridis,
    /// Blue → white → red, white at zero: for signed values.
    Diverging,
}

/// Viridis sampled at nine even steps (sRGB, 0–255), interpolated linearly between them.
const VIRIDIS: [[f32; 3]; 9] = [
    [68.0, 1.0, 84.0],
    [71.0, 44.0, 122.0],
    [59.0, 81.0, 139.0],
    [44.0, 113.0, 142.0],
    [33.0, 144.0, 141.0],
    [39.0, 173.0, 129.0],
    [92.0, 200.0, 99.0],
    [170.0, 220.0, 50.0],
    [253.0, 231.0, 37.0],
];

/// Moreland's cool-to-warm map sampled at five steps (sRGB, 0–255).
const COOL_WARM: [[f32; 3]; 5] = [
    [59.0, 76.0, 192.0],
    [141.0, 176.0, 254.0],
    [221.0, 221.0, 221.0],
    [244.0, 154.0, 123.0],
    [180.0, 4.0, 38.0],
];

fn sample(table: &[[f32; 3]], t: f32) -> [u8; 3] {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (table.len() - 1) as f32;
    let i = (x.floor() as usize).min(table.len() - 2);
    let f = x - i as f32;
    let (a, b) = (table[i], table[i + 1]);
    [0, 1, 2].map(|k| (a[k] + f * (b[k] - a[k])).round() as u8)
}

impl ColorMap {
    /// The colour at `t` in [0, 1] (clamped; NaN gives the low end).
    pub fn at(self, t: f32) -> [u8; 3] {
        match self {
            ColorMap::Viridis => sample(&VIRIDIS, t),
            ColorMap::Diverging => sample(&COOL_WARM, t),
        }
    }
}

/// The values a colour map spans: below `low` is the low colour, above `high` the high one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// The value at the low end.
    pub low: f64,
    /// The value at the high end.
    pub high: f64,
}

impl Range {
    /// The range from the `percentile`-th to the `(100 − percentile)`-th percentile of the
    /// finite `values` (symmetric about zero for a diverging map). `[0, 1]` when there are none.
    pub fn robust(values: &[f64], percentile: f64, map: ColorMap) -> Self {
        let mut sorted: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
        if sorted.is_empty() {
            return Self {
                low: 0.0,
                high: 1.0,
            };
        }
        sorted.sort_unstable_by(f64::total_cmp);
        let at = |p: f64| sorted[((p / 100.0) * (sorted.len() - 1) as f64).round() as usize];
        let (mut low, mut high) = (at(percentile), at(100.0 - percentile));
        if map == ColorMap::Diverging {
            let mut reach = low.abs().max(high.abs());
            if reach == 0.0 {
                reach = 1.0;
            }
            (low, high) = (-reach, reach);
        }
        if high <= low {
            high = low + 1.0;
        }
        Self { low, high }
    }

    /// Where `value` falls in the range, 0 to 1 (clamped).
    pub fn fraction(self, value: f64) -> f32 {
        (((value - self.low) / (self.high - self.low)) as f32).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_and_middle_are_the_tables_and_nan_is_safe() {
        assert_eq!(ColorMap::Viridis.at(0.0), [68, 1, 84]);
        assert_eq!(ColorMap::Viridis.at(1.0), [253, 231, 37]);
        assert_eq!(ColorMap::Diverging.at(0.5), [221, 221, 221]);
        assert_eq!(ColorMap::Viridis.at(f32::NAN), [68, 1, 84]);
        assert_eq!(ColorMap::Viridis.at(7.0), [253, 231, 37]);
    }

    #[test]
    fn a_robust_range_ignores_outliers_and_centres_signed_maps() {
        let mut values: Vec<f64> = (0..1000).map(|i| i as f64 / 1000.0).collect();
        values.push(1e9);
        values.push(f64::NAN);
        let r = Range::robust(&values, 1.0, ColorMap::Viridis);
        assert!(r.low < 0.02 && r.high < 1.0, "{r:?}");
        let signed = Range::robust(&[-1.0, 0.5, 2.0], 0.0, ColorMap::Diverging);
        assert_eq!((signed.low, signed.high), (-2.0, 2.0));
        assert_eq!(signed.fraction(0.0), 0.5);
        assert_eq!(Range::robust(&[], 5.0, ColorMap::Viridis).high, 1.0);
        // All zero on a signed map: zero stays in the middle.
        let flat = Range::robust(&[0.0, 0.0], 1.0, ColorMap::Diverging);
        assert_eq!(flat.fraction(0.0), 0.5);
    }
}
