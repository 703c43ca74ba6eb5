//! The walls of a floor plan in a uniform grid (compressed rows: each cell's wall
//! indices in one flat array): "does this step cross a wall" visits only the cells
//! the step passes through, "how far is the nearest wall" only the rings of cells
//! around the point. Neither allocates.

/// Side of a grid cell, m: about two steps, so a step visits one to four cells.
pub const DEFAULT_WALL_CELL_M: f64 = 2.0;
/// Most cells of a wall grid (the cell grows for larger plans): 1 MB of offsets.
const MAX_WALL_CELLS: usize = 1 << 18;
/// Walls are filed in every cell they come this close to, m, so that a crossing on
/// a cell's border is found from either side.
const FILING_MARGIN_M: f64 = 1e-6;

/// A wall: `[x0, y0, x1, y1]`, m.
pub type Wall = [f64; 4];

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct WallGrid {
    x0: f64,
    y0: f64,
    cell_m: f64,
    cols: usize,
    rows: usize,
    /// Cell c's walls are `items[start[c]..start[c + 1]]`.
    start: Vec<u32>,
    items: Vec<u32>,
    walls: Vec<Wall>,
}

impl WallGrid {
    /// File `walls` in a grid over `bounds` `[x0, y0, x1, y1]`.
    pub(crate) fn new(walls: Vec<Wall>, bounds: [f64; 4]) -> Self {
        let (w, h) = (
            (bounds[2] - bounds[0]).max(1.0),
            (bounds[3] - bounds[1]).max(1.0),
        );
        let mut cell_m = DEFAULT_WALL_CELL_M;
        while (w / cell_m).ceil() * (h / cell_m).ceil() > MAX_WALL_CELLS as f64 {
            cell_m *= 1.5;
        }
        let cols = (w / cell_m).ceil() as usize + 1;
        let rows = (h / cell_m).ceil() as usize + 1;
        let mut g = Self {
            x0: bounds[0],
            y0: bounds[1],
            cell_m,
            cols,
            rows,
            start: vec![0; cols * rows + 1],
            items: Vec::new(),
            walls,
        };
        // Two passes: count per cell, then fill (compressed rows).
        let mut counts = vec![0u32; cols * rows];
        for wall in &g.walls {
            g.cells_along(wall, FILING_MARGIN_M, |c| {
                counts[c] += 1;
                false
            });
        }
        let mut total = 0u32;
        for (c, n) in counts.iter().enumerate() {
            g.start[c] = total;
            total += n;
        }
        g.start[cols * rows] = total;
        let mut items = vec![0; total as usize];
        let mut fill = g.start.clone();
        for (i, wall) in g.walls.iter().enumerate() {
            g.cells_along(wall, FILING_MARGIN_M, |c| {
                items[fill[c] as usize] = i as u32;
                fill[c] += 1;
                false
            });
        }
        g.items = items;
        g
    }

    pub(crate) fn walls(&self) -> &[Wall] {
        &self.walls
    }

    pub(crate) fn cell_m(&self) -> f64 {
        self.cell_m
    }

    /// Heap bytes held.
    pub(crate) fn heap_bytes(&self) -> usize {
        self.start.len() * 4 + self.items.len() * 4 + self.walls.len() * 32
    }

    /// Calls `f` with every cell the segment comes within `margin` of (cells off the
    /// grid clamp to its border, which holds no wall beyond it); stops when `f` says
    /// so and returns whether it did.
    fn cells_along(&self, s: &Wall, margin: f64, mut f: impl FnMut(usize) -> bool) -> bool {
        let [ax, ay, bx, by] = *s;
        let row_of = |y: f64| ((y - self.y0) / self.cell_m).floor();
        let col_of = |x: f64| ((x - self.x0) / self.cell_m).floor();
        let clamp = |v: f64, n: usize| v.clamp(0.0, (n - 1) as f64) as usize;
        let (ylo, yhi) = (ay.min(by) - margin, ay.max(by) + margin);
        let (r0, r1) = (clamp(row_of(ylo), self.rows), clamp(row_of(yhi), self.rows));
        for r in r0..=r1 {
            // The part of the segment within this row's band (widened by the margin).
            let band0 = self.y0 + r as f64 * self.cell_m - margin;
            let band1 = band0 + self.cell_m + 2.0 * margin;
            let (xa, xb) = if (by - ay).abs() < 1e-12 {
                (ax, bx)
            } else {
                let t = |y: f64| ((y - ay) / (by - ay)).clamp(0.0, 1.0);
                let (ta, tb) = (t(band0), t(band1));
                (ax + ta * (bx - ax), ax + tb * (bx - ax))
            };
            let (c0, c1) = (
                clamp(col_of(xa.min(xb) - margin), self.cols),
                clamp(col_of(xa.max(xb) + margin), self.cols),
            );
            for c in c0..=c1 {
                if f(r * self.cols + c) {
                    return true;
                }
            }
        }
        false
    }

    /// Whether the segment from `a` to `b` crosses or touches a wall.
    pub(crate) fn crosses(&self, a: [f64; 2], b: [f64; 2]) -> bool {
        let s = [a[0], a[1], b[0], b[1]];
        self.cells_along(&s, 0.0, |c| {
            let (i0, i1) = (self.start[c] as usize, self.start[c + 1] as usize);
            self.items[i0..i1]
                .iter()
                .any(|&i| segments_meet(&s, &self.walls[i as usize]))
        })
    }

    /// Distance from `p` to the nearest wall, m, or `max_m` when none is closer.
    pub(crate) fn nearest_wall_m(&self, p: [f64; 2], max_m: f64) -> f64 {
        let col = ((p[0] - self.x0) / self.cell_m).floor();
        let row = ((p[1] - self.y0) / self.cell_m).floor();
        let mut best = max_m;
        let max_ring = (max_m / self.cell_m).ceil() as i64 + 1;
        for k in 0..=max_ring {
            // Cells of ring k are at least (k − 1) cells from p.
            if (k - 1) as f64 * self.cell_m >= best {
                break;
            }
            self.ring_cells(col as i64, row as i64, k, |c| {
                let (i0, i1) = (self.start[c] as usize, self.start[c + 1] as usize);
                for &i in &self.items[i0..i1] {
                    best = best.min(point_segment_m(p, &self.walls[i as usize]));
                }
            });
        }
        best
    }

    /// The cells of the square ring at Chebyshev distance `k` around `(col, row)` that
    /// lie on the grid.
    fn ring_cells(&self, col: i64, row: i64, k: i64, mut f: impl FnMut(usize)) {
        let (cols, rows) = (self.cols as i64, self.rows as i64);
        let mut visit = |c: i64, r: i64| {
            if (0..cols).contains(&c) && (0..rows).contains(&r) {
                f((r * cols + c) as usize);
            }
        };
        if k == 0 {
            visit(col, row);
            return;
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
}

/// Orientation of `c` against the line `a → b` (twice the signed triangle area).
#[inline]
fn orient(ax: f64, ay: f64, bx: f64, by: f64, cx: f64, cy: f64) -> f64 {
    (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
}

/// Whether two segments `[x0, y0, x1, y1]` cross or touch.
#[inline]
pub(crate) fn segments_meet(s: &Wall, w: &Wall) -> bool {
    let d1 = orient(w[0], w[1], w[2], w[3], s[0], s[1]);
    let d2 = orient(w[0], w[1], w[2], w[3], s[2], s[3]);
    if (d1 > 0.0 && d2 > 0.0) || (d1 < 0.0 && d2 < 0.0) {
        return false;
    }
    let d3 = orient(s[0], s[1], s[2], s[3], w[0], w[1]);
    let d4 = orient(s[0], s[1], s[2], s[3], w[2], w[3]);
    if (d3 > 0.0 && d4 > 0.0) || (d3 < 0.0 && d4 < 0.0) {
        return false;
    }
    if d1 != 0.0 || d2 != 0.0 || d3 != 0.0 || d4 != 0.0 {
        return true;
    }
    // Collinear: they meet when their extents overlap.
    let overlap =
        |a0: f64, a1: f64, b0: f64, b1: f64| a0.min(a1) <= b0.max(b1) && b0.min(b1) <= a0.max(a1);
    overlap(s[0], s[2], w[0], w[2]) && overlap(s[1], s[3], w[1], w[3])
}

/// Distance from a point to a segment, m.
#[inline]
pub(crate) fn point_segment_m(p: [f64; 2], w: &Wall) -> f64 {
    let (dx, dy) = (w[2] - w[0], w[3] - w[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p[0] - w[0]) * dx + (p[1] - w[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - w[0] - t * dx).hypot(p[1] - w[1] - t * dy)
}
