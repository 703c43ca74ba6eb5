//! Where people can walk, as a bit per cell (a cell is walkable when its centre is):
//! "is this point walkable", "the nearest walkable point" and "the k-th walkable cell"
//! (uniform draws over the walkable area) without allocating. Built by a scanline over
//! every ring, so overlapping obstacles and holes inside obstacles come out right.

use super::geometry::{PlanGeometry, RingRole};

/// Side of a raster cell, m.
pub const DEFAULT_RASTER_CELL_M: f64 = 0.25;
/// Most cells of a raster (the cell grows for larger plans): 2 MB of bits.
const MAX_RASTER_CELLS: f64 = 16.0e6;

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct WalkRaster {
    x0: f64,
    y0: f64,
    cell_m: f64,
    cols: usize,
    rows: usize,
    words_per_row: usize,
    bits: Vec<u64>,
    /// Walkable cells in the rows before each row (`rows + 1` entries).
    before_row: Vec<u32>,
}

impl WalkRaster {
    /// The raster of `g` over `bounds` `[x0, y0, x1, y1]`.
    pub(crate) fn new(g: &PlanGeometry, bounds: [f64; 4]) -> Self {
        let (w, h) = (
            (bounds[2] - bounds[0]).max(1.0),
            (bounds[3] - bounds[1]).max(1.0),
        );
        let mut cell_m = DEFAULT_RASTER_CELL_M;
        while (w / cell_m).ceil() * (h / cell_m).ceil() > MAX_RASTER_CELLS {
            cell_m *= 1.5;
        }
        let cols = (w / cell_m).ceil() as usize;
        let rows = (h / cell_m).ceil() as usize;
        let words_per_row = cols.div_ceil(64);
        let mut r = Self {
            x0: bounds[0],
            y0: bounds[1],
            cell_m,
            cols,
            rows,
            words_per_row,
            bits: vec![0; words_per_row * rows],
            before_row: vec![0; rows + 1],
        };
        r.scan(g);
        r
    }

    /// Fill the bits row by row: the crossings of the row's centre line with every
    /// ring, sorted, then each ring's inside/outside state swept from west to east.
    fn scan(&mut self, g: &PlanGeometry) {
        // Edges: (y_min, y_max, x at y_min, dx/dy, ring).
        let mut edges: Vec<(f64, f64, f64, f64, u32)> = Vec::new();
        let mut roles = Vec::new();
        for (ring_i, (ring, role, _)) in g.rings().enumerate() {
            roles.push(role);
            for w in ring.windows(2) {
                let (a, b) = if w[0][1] <= w[1][1] {
                    (w[0], w[1])
                } else {
                    (w[1], w[0])
                };
                if a[1] < b[1] {
                    edges.push((
                        a[1],
                        b[1],
                        a[0],
                        (b[0] - a[0]) / (b[1] - a[1]),
                        ring_i as u32,
                    ));
                }
            }
        }
        edges.sort_by(|p, q| p.0.total_cmp(&q.0));
        let mut inside = vec![false; roles.len()];
        let mut active: Vec<usize> = Vec::new();
        let mut cross: Vec<(f64, u32)> = Vec::new();
        let mut next = 0;
        let mut total = 0u32;
        for row in 0..self.rows {
            let y = self.y0 + (row as f64 + 0.5) * self.cell_m;
            while next < edges.len() && edges[next].0 <= y {
                active.push(next);
                next += 1;
            }
            // Half-open in y, so a vertex on the line is crossed once.
            active.retain(|&e| edges[e].1 > y);
            cross.clear();
            cross.extend(active.iter().map(|&e| {
                let (y0, _, x0, k, ring) = edges[e];
                (x0 + (y - y0) * k, ring)
            }));
            cross.sort_by(|p, q| p.0.total_cmp(&q.0));
            let (mut walk, mut obstacle) = (0i32, 0i32);
            for (i, &(x, ring)) in cross.iter().enumerate() {
                let now = !inside[ring as usize];
                inside[ring as usize] = now;
                let d = if now { 1 } else { -1 };
                match roles[ring as usize] {
                    RingRole::Walkable => walk += d,
                    RingRole::WalkableHole => walk -= d,
                    RingRole::Obstacle => obstacle += d,
                    RingRole::ObstacleHole => obstacle -= d,
                }
                if walk > 0 && obstacle <= 0 {
                    if let Some(&(x1, _)) = cross.get(i + 1) {
                        self.fill(row, x, x1);
                    }
                }
            }
            self.before_row[row] = total;
            let words = &self.bits[row * self.words_per_row..(row + 1) * self.words_per_row];
            total += words.iter().map(|w| w.count_ones()).sum::<u32>();
        }
        self.before_row[self.rows] = total;
    }

    /// Set the cells of `row` whose centres lie in `[xa, xb)`.
    fn fill(&mut self, row: usize, xa: f64, xb: f64) {
        let first = ((xa - self.x0) / self.cell_m - 0.5).ceil().max(0.0) as usize;
        let end = (((xb - self.x0) / self.cell_m - 0.5).ceil().max(0.0) as usize).min(self.cols);
        for c in first..end {
            self.bits[row * self.words_per_row + c / 64] |= 1 << (c % 64);
        }
    }

    pub(crate) fn cell_m(&self) -> f64 {
        self.cell_m
    }

    /// Walkable cells.
    pub(crate) fn count(&self) -> u32 {
        self.before_row[self.rows]
    }

    pub(crate) fn heap_bytes(&self) -> usize {
        self.bits.len() * 8 + self.before_row.len() * 4
    }

    fn get(&self, col: i64, row: i64) -> bool {
        if col < 0 || row < 0 || col >= self.cols as i64 || row >= self.rows as i64 {
            return false;
        }
        let (c, r) = (col as usize, row as usize);
        self.bits[r * self.words_per_row + c / 64] >> (c % 64) & 1 == 1
    }

    fn cell_of(&self, p: [f64; 2]) -> (i64, i64) {
        (
            ((p[0] - self.x0) / self.cell_m).floor() as i64,
            ((p[1] - self.y0) / self.cell_m).floor() as i64,
        )
    }

    fn centre(&self, col: i64, row: i64) -> [f64; 2] {
        [
            self.x0 + (col as f64 + 0.5) * self.cell_m,
            self.y0 + (row as f64 + 0.5) * self.cell_m,
        ]
    }

    /// Whether the cell holding `p` is walkable.
    pub(crate) fn walkable(&self, p: [f64; 2]) -> bool {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return false;
        }
        let (c, r) = self.cell_of(p);
        self.get(c, r)
    }

    /// The centre of the walkable cell nearest to `p` within `max_m`, if any.
    pub(crate) fn nearest(&self, p: [f64; 2], max_m: f64) -> Option<[f64; 2]> {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return None;
        }
        let (col, row) = self.cell_of(p);
        let mut best: Option<([f64; 2], f64)> = None;
        let max_ring = (max_m / self.cell_m).ceil() as i64 + 1;
        for k in 0..=max_ring {
            if let Some((_, d)) = best {
                if (k - 1) as f64 * self.cell_m >= d {
                    break;
                }
            }
            let mut visit = |c: i64, r: i64| {
                if self.get(c, r) {
                    let q = self.centre(c, r);
                    let d = (q[0] - p[0]).hypot(q[1] - p[1]);
                    if d <= max_m && best.is_none_or(|b| d < b.1) {
                        best = Some((q, d));
                    }
                }
            };
            if k == 0 {
                visit(col, row);
                continue;
            }
            for c in col - k..=col + k {
                visit(c, row - k);
                visit(c, row + k);
            }
            for r in row - k + 1..row + k {
                visit(col - k, r);
                visit(col + k, r);
            }
        }
        best.map(|b| b.0)
    }

    /// The centre of the `k`-th walkable cell (row by row from the south-west),
    /// `k < count()`.
    pub(crate) fn nth(&self, k: u32) -> [f64; 2] {
        let row = self.before_row.partition_point(|&n| n <= k) - 1;
        let mut left = k - self.before_row[row];
        let words = &self.bits[row * self.words_per_row..(row + 1) * self.words_per_row];
        for (i, &w) in words.iter().enumerate() {
            let n = w.count_ones();
            if left < n {
                let mut w = w;
                for _ in 0..left {
                    w &= w - 1;
                }
                let col = i * 64 + w.trailing_zeros() as usize;
                return self.centre(col as i64, row as i64);
            }
            left -= n;
        }
        // Not reached for k < count(); the raster's corner keeps it total.
        self.centre(0, 0)
    }
}
