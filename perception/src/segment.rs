//! Labelling (Kakiuchi et al. 2010, §IV-C): occupied cells that touch form one cluster.
//!
//! Connectivity is 8-neighbour by default: a thin diagonal object (a chair rail seen at 45°) occupies
//! cells that touch only at corners, and 4-connectivity would shatter it. The price is that objects
//! closer than one cell (40 mm) merge — the paper's own limitation ("segmentation with simple labeling
//! fails when objects are located too close").
//!
//! Cells of different colours never join (see [`crate::hue`]): the elevation map keeps the returns of
//! a place that differ in chromaticity in cells of their own, and neighbours join only when their
//! colours are one surface's. A red box flush against a grey wall, or two chairs of different
//! colours abreast, are two clusters however close they stand.
//!
//! Cells are split into two height classes before labelling: *low* cells (highest point at most
//! [`SegmentConfig::low_height`] above the floor: mats, cables, floor noise) only join low cells, and
//! tall cells only tall ones. A mat touching a chair therefore stays a flat, traversable cluster instead
//! of lending the chair its area, and a trail of floor-noise cells cannot bridge two objects.

use crate::elevation::ElevationMap;

/// Which neighbours of a cell count as touching.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Connectivity {
    /// Edge neighbours only (4).
    Four,
    /// Edge and corner neighbours (8). Default.
    #[default]
    Eight,
}

/// Parameters of labelling.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentConfig {
    /// Neighbourhood. Default [`Connectivity::Eight`].
    pub connectivity: Connectivity,
    /// Cells whose highest point is at most this high (m) are *low* and only join low cells. Default 0.05.
    pub low_height: f32,
    /// Clusters with fewer occupied cells are dropped. Default 1 (keep all).
    pub min_cells: usize,
}

impl Default for SegmentConfig {
    fn default() -> Self {
        Self {
            connectivity: Connectivity::Eight,
            low_height: 0.05,
            min_cells: 1,
        }
    }
}

/// A connected set of occupied cells (indices into [`ElevationMap::cells`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Cluster {
    /// The cluster's cells, in discovery order.
    pub cells: Vec<u32>,
}

/// Labels the occupied cells of `map` into clusters (deterministic: discovery follows cell order).
pub fn label(map: &ElevationMap, config: &SegmentConfig) -> Vec<Cluster> {
    let cells = map.cells();
    let mut seen = vec![false; cells.len()];
    let mut clusters = Vec::new();
    let mut stack = Vec::new();
    for start in 0..cells.len() {
        if seen[start] || !map.is_occupied(start) {
            continue;
        }
        let low = cells[start].z_max <= config.low_height;
        seen[start] = true;
        stack.push(start as u32);
        let mut members = Vec::new();
        while let Some(k) = stack.pop() {
            members.push(k);
            let c = &cells[k as usize];
            for (dc, dr) in neighbours(config.connectivity) {
                for n in map.layers_at(i64::from(c.col) + dc, i64::from(c.row) + dr) {
                    let nu = n as usize;
                    if !seen[nu]
                        && map.is_occupied(nu)
                        && (cells[nu].z_max <= config.low_height) == low
                        && map.same_colour(k, n)
                    {
                        seen[nu] = true;
                        stack.push(n);
                    }
                }
            }
        }
        if members.len() >= config.min_cells {
            clusters.push(Cluster { cells: members });
        }
    }
    clusters
}

/// Splits a set of cells into its connected components (same connectivity rule, no height classes:
/// the input is one class already). Components come in order of their first cell in `cells`.
pub fn components(map: &ElevationMap, cells: &[u32], connectivity: Connectivity) -> Vec<Vec<u32>> {
    let mut member: std::collections::HashMap<u32, bool> =
        cells.iter().map(|&k| (k, false)).collect();
    let all = map.cells();
    let mut out = Vec::new();
    let mut stack = Vec::new();
    for &start in cells {
        if member.get(&start).copied().unwrap_or(true) {
            continue;
        }
        member.insert(start, true);
        stack.push(start);
        let mut comp = Vec::new();
        while let Some(k) = stack.pop() {
            comp.push(k);
            let c = &all[k as usize];
            for (dc, dr) in neighbours(connectivity) {
                for n in map.layers_at(i64::from(c.col) + dc, i64::from(c.row) + dr) {
                    if member.get(&n) == Some(&false) {
                        member.insert(n, true);
                        stack.push(n);
                    }
                }
            }
        }
        out.push(comp);
    }
    out
}

fn neighbours(connectivity: Connectivity) -> &'static [(i64, i64)] {
    const FOUR: [(i64, i64); 4] = [(1, 0), (-1, 0), (0, 1), (0, -1)];
    const EIGHT: [(i64, i64); 8] = [
        (1, 0),
        (-1, 0),
        (0, 1),
        (0, -1),
        (1, 1),
        (1, -1),
        (-1, 1),
        (-1, -1),
    ];
    match connectivity {
        Connectivity::Four => &FOUR,
        Connectivity::Eight => &EIGHT,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::{CloudFrame, ColourCloud};
    use crate::elevation::ElevationConfig;
    use nalgebra::{Isometry3, Point2, Point3};

    fn map_of(cells: &[(f32, f32, f32)]) -> ElevationMap {
        let mut c = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
        for &(x, y, z) in cells {
            for _ in 0..3 {
                c.push(Point3::new(x, y, z), [0, 0, 0]);
            }
        }
        ElevationMap::build(&c, 0.0, Point2::origin(), &ElevationConfig::default())
            .expect("valid input")
    }

    #[test]
    fn diagonal_cells_join_under_eight_connectivity_only() {
        // Invariant: corner-touching cells are one cluster with 8-connectivity and two with 4.
        let map = map_of(&[(0.02, 0.02, 0.5), (0.06, 0.06, 0.5)]);
        let eight = label(&map, &SegmentConfig::default());
        assert_eq!(eight.len(), 1);
        let four = label(
            &map,
            &SegmentConfig {
                connectivity: Connectivity::Four,
                ..SegmentConfig::default()
            },
        );
        assert_eq!(four.len(), 2);
    }

    #[test]
    fn low_cells_do_not_join_tall_neighbours() {
        // Invariant: a mat-height cell next to a tall cell forms its own cluster.
        let map = map_of(&[(0.02, 0.02, 0.01), (0.06, 0.02, 0.5), (0.10, 0.02, 0.6)]);
        let clusters = label(&map, &SegmentConfig::default());
        assert_eq!(clusters.len(), 2);
        let sizes: Vec<usize> = clusters.iter().map(|c| c.cells.len()).collect();
        assert_eq!(sizes, vec![1, 2]);
    }
}
