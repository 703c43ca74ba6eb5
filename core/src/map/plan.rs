//! [`FloorPlan`]: one floor's walls and walkable area, built once from its polygons
//! and then queried per step without allocating: wall crossings, the nearest wall,
//! walkability, the nearest walkable point, uniform draws over the walkable area.

use super::error::PlanError;
use super::geometry::{PlanGeometry, Polygon};
use super::georef::GeoReference;
use super::grid::{Wall, WallGrid};
use super::raster::WalkRaster;

/// Margin around the walls of the grids, m (a step leaving the plan still meets its
/// outline in a cell of the grid).
const GRID_MARGIN_M: f64 = 2.0;

/// One floor's plan, in metres of its own frame (x east, y north).
#[derive(Clone, Debug, PartialEq)]
pub struct FloorPlan {
    floor: i32,
    /// Bounding box of the walkable outlines `[x0, y0, x1, y1]`, m.
    bounds: [f64; 4],
    walls: WallGrid,
    raster: WalkRaster,
    geo: Option<GeoReference>,
    fingerprint: u64,
}

impl FloorPlan {
    /// Build the plan of `geometry` (polygons in metres), optionally tied to WGS84.
    pub fn new(geometry: &PlanGeometry, geo: Option<GeoReference>) -> Result<Self, PlanError> {
        let bounds = geometry.validate()?;
        if let Some(g) = &geo {
            g.validate()?;
        }
        let walls: Vec<Wall> = geometry
            .rings()
            .flat_map(|(r, _, _)| r.windows(2).map(|w| [w[0][0], w[0][1], w[1][0], w[1][1]]))
            .filter(|w| w[0] != w[2] || w[1] != w[3])
            .collect();
        let mut all = bounds;
        for w in &walls {
            all = [
                all[0].min(w[0]).min(w[2]),
                all[1].min(w[1]).min(w[3]),
                all[2].max(w[0]).max(w[2]),
                all[3].max(w[1]).max(w[3]),
            ];
        }
        let grid_bounds = [
            all[0] - GRID_MARGIN_M,
            all[1] - GRID_MARGIN_M,
            all[2] + GRID_MARGIN_M,
            all[3] + GRID_MARGIN_M,
        ];
        let raster = WalkRaster::new(geometry, bounds);
        if raster.count() == 0 {
            return Err(PlanError::NoWalkableArea {
                reason: "the holes and obstacles cover every walkable outline".into(),
            });
        }
        let walls = WallGrid::new(walls, grid_bounds);
        let fingerprint = fingerprint(geometry.floor, &walls, &geo);
        Ok(Self {
            floor: geometry.floor,
            bounds,
            walls,
            raster,
            geo,
            fingerprint,
        })
    }

    /// A plan with one rectangular walkable area and rectangular obstacles
    /// `[x0, y0, x1, y1]` (tests, examples).
    pub fn rectangles(
        floor: i32,
        outline: [f64; 4],
        obstacles: &[[f64; 4]],
    ) -> Result<Self, PlanError> {
        let r = |b: &[f64; 4]| Polygon::rectangle(b[0], b[1], b[2], b[3]);
        Self::new(
            &PlanGeometry {
                floor,
                walkable: vec![r(&outline)],
                obstacles: obstacles.iter().map(r).collect(),
            },
            None,
        )
    }

    pub fn floor(&self) -> i32 {
        self.floor
    }

    /// Bounding box of the walkable outlines `[x0, y0, x1, y1]`, m.
    pub fn bounds(&self) -> [f64; 4] {
        self.bounds
    }

    pub fn geo_reference(&self) -> Option<&GeoReference> {
        self.geo.as_ref()
    }

    /// Every wall `[x0, y0, x1, y1]` (ring edges), m.
    pub fn walls(&self) -> &[Wall] {
        self.walls.walls()
    }

    /// Whether the straight step from `from` to `to` crosses (or touches) a wall.
    pub fn crosses_wall(&self, from: [f64; 2], to: [f64; 2]) -> bool {
        self.walls.crosses(from, to)
    }

    /// Distance from `p` to the nearest wall, m; `max_m` when none is that close.
    pub fn distance_to_wall_m(&self, p: [f64; 2], max_m: f64) -> f64 {
        if !(p[0].is_finite() && p[1].is_finite() && max_m > 0.0) {
            return max_m.max(0.0);
        }
        self.walls
            .nearest_wall_m(p, max_m.min(super::geometry::MAX_PLAN_EXTENT_M))
    }

    /// Whether `p` is in the walkable area (to the raster's cell, see
    /// [`raster_cell_m`](Self::raster_cell_m)).
    pub fn is_walkable(&self, p: [f64; 2]) -> bool {
        self.raster.walkable(p)
    }

    /// The walkable point nearest to `p` (a cell centre) within `max_m`, if any.
    pub fn nearest_walkable(&self, p: [f64; 2], max_m: f64) -> Option<[f64; 2]> {
        self.raster
            .nearest(p, max_m.min(super::geometry::MAX_PLAN_EXTENT_M))
    }

    /// The walkable area, m².
    pub fn walkable_area_m2(&self) -> f64 {
        f64::from(self.raster.count()) * self.raster.cell_m().powi(2)
    }

    /// Side of the walkability raster's cells, m.
    pub fn raster_cell_m(&self) -> f64 {
        self.raster.cell_m()
    }

    /// Side of the wall grid's cells, m.
    pub fn wall_cell_m(&self) -> f64 {
        self.walls.cell_m()
    }

    /// A point drawn uniformly over the walkable area from two uniforms in [0, 1):
    /// a walkable cell, then a point within it.
    pub fn walkable_point(&self, u_cell: f64, u_x: f64, u_y: f64) -> [f64; 2] {
        let n = self.raster.count();
        let k = ((u_cell * f64::from(n)) as u32).min(n - 1);
        let c = self.raster.nth(k);
        let h = self.raster.cell_m();
        [c[0] + (u_x - 0.5) * h, c[1] + (u_y - 0.5) * h]
    }

    /// Heap memory the plan holds, bytes.
    pub fn heap_bytes(&self) -> usize {
        self.walls.heap_bytes() + self.raster.heap_bytes()
    }

    /// A number that identifies the plan (its floor, walls and geographic
    /// reference): snapshots carry it so that they are restored with the same plans.
    pub fn fingerprint(&self) -> u64 {
        self.fingerprint
    }
}

/// FNV-1a over the floor, the walls' bits and the geographic reference's.
fn fingerprint(floor: i32, walls: &WallGrid, geo: &Option<GeoReference>) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let mut eat = |v: u64| {
        for b in v.to_le_bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    };
    eat(floor as u64);
    for w in walls.walls() {
        w.iter().for_each(|v| eat(v.to_bits()));
    }
    match geo {
        None => eat(0),
        Some(GeoReference::BoundingBox {
            west_deg,
            south_deg,
            east_deg,
            north_deg,
            width_m,
            height_m,
        }) => {
            eat(1);
            for v in [west_deg, south_deg, east_deg, north_deg, width_m, height_m] {
                eat(v.to_bits());
            }
        }
        Some(GeoReference::Local { lat_deg, lon_deg }) => {
            eat(2);
            eat(lat_deg.to_bits());
            eat(lon_deg.to_bits());
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shop_plan() -> FloorPlan {
        // A 40 × 20 m hall with a 10 × 10 m shop in the middle and a pillar beside it
        // that overlaps the shop (overlapping obstacles stay obstacles).
        FloorPlan::rectangles(
            2,
            [0.0, 0.0, 40.0, 20.0],
            &[[15.0, 5.0, 25.0, 15.0], [24.0, 9.0, 27.0, 11.0]],
        )
        .unwrap()
    }

    #[test]
    fn steps_through_walls_are_found_and_steps_beside_them_are_not() {
        let p = shop_plan();
        assert_eq!(p.floor(), 2);
        assert!(p.crosses_wall([14.5, 10.0], [15.5, 10.0]), "into the shop");
        assert!(p.crosses_wall([10.0, 10.0], [30.0, 10.0]), "through it");
        assert!(
            p.crosses_wall([39.5, 10.0], [40.5, 10.0]),
            "out of the hall"
        );
        assert!(
            !p.crosses_wall([10.0, 2.0], [30.0, 2.0]),
            "along the corridor below"
        );
        assert!(!p.crosses_wall([14.0, 4.0], [14.9, 4.9]));
        // On a grid line (the grid's cells are 2 m): found from either side.
        assert!(p.crosses_wall([15.0 - 1e-3, 6.0], [15.0 + 1e-3, 6.0]));
        assert!(p.crosses_wall([16.0, 4.0], [16.0, 6.0]));
    }

    #[test]
    fn walkable_area_and_nearest_points() {
        let p = shop_plan();
        assert!(p.is_walkable([5.0, 5.0]));
        assert!(!p.is_walkable([20.0, 10.0]), "in the shop");
        assert!(
            !p.is_walkable([26.0, 10.0]),
            "in the pillar beyond the shop"
        );
        assert!(!p.is_walkable([-1.0, 5.0]) && !p.is_walkable([f64::NAN, 1.0]));
        let area = 40.0 * 20.0 - 100.0 - 2.0 * 2.0;
        assert!(
            (p.walkable_area_m2() - area).abs() < 0.02 * area,
            "{}",
            p.walkable_area_m2()
        );
        let q = p.nearest_walkable([20.0, 14.0], 3.0).unwrap();
        assert!(p.is_walkable(q) && (q[1] - 15.1).abs() < 0.3, "{q:?}");
        assert!(
            p.nearest_walkable([20.0, 10.0], 3.0).is_none(),
            "5 m from any corridor"
        );
        assert!((p.distance_to_wall_m([10.0, 10.0], 20.0) - 5.0).abs() < 1e-9);
        assert!((p.distance_to_wall_m([2.0, 3.0], 20.0) - 2.0).abs() < 1e-9);
        assert_eq!(p.distance_to_wall_m([200.0, 200.0], 1.0), 1.0);
        for u in [0.0, 0.3, 0.999_999] {
            let w = p.walkable_point(u, 0.5, 0.5);
            assert!(p.is_walkable(w), "{w:?}");
        }
        assert!(p.heap_bytes() > 0 && p.fingerprint() != shop_plan_other().fingerprint());
    }

    fn shop_plan_other() -> FloorPlan {
        FloorPlan::rectangles(2, [0.0, 0.0, 40.0, 20.0], &[[15.0, 5.0, 25.0, 15.1]]).unwrap()
    }

    #[test]
    fn bad_geometry_is_a_typed_error() {
        let ring = |pts: &[[f64; 2]]| Polygon::new(pts.to_vec());
        let build = |walkable: Vec<Polygon>, obstacles: Vec<Polygon>| {
            FloorPlan::new(
                &PlanGeometry {
                    floor: 0,
                    walkable,
                    obstacles,
                },
                None,
            )
        };
        let square = ring(&[[0.0, 0.0], [5.0, 0.0], [5.0, 5.0], [0.0, 5.0], [0.0, 0.0]]);
        let open = ring(&[[0.0, 0.0], [5.0, 0.0], [5.0, 5.0], [0.0, 5.0]]);
        let line = ring(&[[0.0, 0.0], [5.0, 0.0], [10.0, 0.0], [0.0, 0.0]]);
        let nan = ring(&[[0.0, 0.0], [f64::NAN, 0.0], [5.0, 5.0], [0.0, 0.0]]);
        let short = ring(&[[0.0, 0.0], [5.0, 0.0], [0.0, 0.0]]);
        let huge = Polygon::rectangle(0.0, 0.0, 1.0e6, 10.0);
        assert!(matches!(
            build(vec![open], vec![]),
            Err(PlanError::OpenRing { .. })
        ));
        assert!(matches!(
            build(vec![line], vec![]),
            Err(PlanError::NoArea { .. })
        ));
        assert!(matches!(
            build(vec![nan], vec![]),
            Err(PlanError::NonFinite { .. })
        ));
        assert!(matches!(
            build(vec![short], vec![]),
            Err(PlanError::TooFewPoints { .. })
        ));
        assert!(matches!(
            build(vec![huge], vec![]),
            Err(PlanError::TooLarge { .. })
        ));
        assert!(matches!(
            build(vec![], vec![]),
            Err(PlanError::NoWalkableArea { .. })
        ));
        let cover = Polygon::rectangle(-1.0, -1.0, 6.0, 6.0);
        assert!(matches!(
            build(vec![square.clone()], vec![cover]),
            Err(PlanError::NoWalkableArea { .. })
        ));
        let bad_geo = GeoReference::Local {
            lat_deg: 95.0,
            lon_deg: 0.0,
        };
        assert!(matches!(
            FloorPlan::new(
                &PlanGeometry {
                    floor: 0,
                    walkable: vec![square],
                    obstacles: vec![],
                },
                Some(bad_geo)
            ),
            Err(PlanError::GeoReference { .. })
        ));
    }

    #[test]
    fn a_hole_is_not_walkable_and_a_courtyard_in_it_is() {
        let outline = Polygon {
            exterior: Polygon::rectangle(0.0, 0.0, 30.0, 30.0).exterior,
            holes: vec![Polygon::rectangle(5.0, 5.0, 25.0, 25.0).exterior],
        };
        let island = Polygon::rectangle(10.0, 10.0, 20.0, 20.0);
        let p = FloorPlan::new(
            &PlanGeometry {
                floor: 0,
                walkable: vec![outline, island],
                obstacles: vec![],
            },
            None,
        )
        .unwrap();
        assert!(p.is_walkable([2.0, 2.0]) && p.is_walkable([15.0, 15.0]));
        assert!(!p.is_walkable([7.0, 15.0]));
        assert!(p.crosses_wall([2.0, 15.0], [15.0, 15.0]));
    }

    #[test]
    fn geographic_references_round_trip() {
        let b = GeoReference::BoundingBox {
            west_deg: 120.0,
            south_deg: 30.0,
            east_deg: 120.003,
            north_deg: 30.002,
            width_m: 288.0,
            height_m: 222.0,
        };
        let l = GeoReference::Local {
            lat_deg: 30.0,
            lon_deg: 120.0,
        };
        for g in [b, l] {
            g.validate().unwrap();
            let (lat, lon) = g.to_geodetic(100.0, 50.0);
            let (x, y) = g.to_plan(lat, lon);
            assert!(
                (x - 100.0).abs() < 1e-6 && (y - 50.0).abs() < 1e-6,
                "{g:?}: {x} {y}"
            );
        }
        assert_eq!(b.to_plan(30.0, 120.0), (0.0, 0.0));
    }
}
