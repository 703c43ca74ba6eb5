//! The polygons a floor plan is built from, in metres of the plan's frame (x east,
//! y north): walkable outlines with their holes, and obstacles (shops, rooms, pillars)
//! to walk around. Validated before anything is built: finite, closed, with area, of a
//! building's size.

use super::error::PlanError;

/// Largest extent of a floor plan, m (the largest buildings are about 1 km across).
pub const MAX_PLAN_EXTENT_M: f64 = 5_000.0;
/// Most points of all rings of a plan (a detailed mall floor has about 5 000).
pub const MAX_PLAN_POINTS: usize = 2_000_000;

/// A closed ring of points `[x_m, y_m]` (the last point repeats the first).
pub type Ring = Vec<[f64; 2]>;

/// A polygon: an exterior ring and the holes in it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Polygon {
    pub exterior: Ring,
    pub holes: Vec<Ring>,
}

impl Polygon {
    /// A polygon without holes.
    pub fn new(exterior: Ring) -> Self {
        Self {
            exterior,
            holes: Vec::new(),
        }
    }

    /// An axis-aligned rectangle (closed ring, anticlockwise).
    pub fn rectangle(x0: f64, y0: f64, x1: f64, y1: f64) -> Self {
        Self::new(vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1], [x0, y0]])
    }
}

/// What a floor plan is made of: where people can walk is inside a `walkable`
/// polygon (outside its holes) and outside every `obstacle`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlanGeometry {
    /// The floor this plan is of (the app's numbering: −1 a basement, 0 or 1 the
    /// ground floor, ...).
    pub floor: i32,
    pub walkable: Vec<Polygon>,
    pub obstacles: Vec<Polygon>,
}

/// The role a ring plays in the walkable area.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum RingRole {
    Walkable,
    WalkableHole,
    Obstacle,
    ObstacleHole,
}

impl PlanGeometry {
    /// Every ring with its role, in order (walkable polygons first).
    pub(crate) fn rings(&self) -> impl Iterator<Item = (&Ring, RingRole, String)> + '_ {
        let walk = self.walkable.iter().enumerate().flat_map(|(i, p)| {
            std::iter::once((
                &p.exterior,
                RingRole::Walkable,
                format!("walkable polygon {i}"),
            ))
            .chain(p.holes.iter().enumerate().map(move |(j, h)| {
                (
                    h,
                    RingRole::WalkableHole,
                    format!("walkable polygon {i}, hole {j}"),
                )
            }))
        });
        let obst = self.obstacles.iter().enumerate().flat_map(|(i, p)| {
            std::iter::once((&p.exterior, RingRole::Obstacle, format!("obstacle {i}"))).chain(
                p.holes.iter().enumerate().map(move |(j, h)| {
                    (h, RingRole::ObstacleHole, format!("obstacle {i}, hole {j}"))
                }),
            )
        });
        walk.chain(obst)
    }

    /// Check every ring; returns the bounding box `[x0, y0, x1, y1]` of the walkable
    /// outlines.
    pub(crate) fn validate(&self) -> Result<[f64; 4], PlanError> {
        if self.walkable.is_empty() {
            return Err(PlanError::NoWalkableArea {
                reason: "no walkable outline".into(),
            });
        }
        let points: usize = self.rings().map(|(r, _, _)| r.len()).sum();
        if points > MAX_PLAN_POINTS {
            return Err(PlanError::TooManyPoints {
                points,
                max: MAX_PLAN_POINTS,
            });
        }
        let mut all = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        let mut walk = all;
        for (ring, role, what) in self.rings() {
            check_ring(ring, &what)?;
            for p in ring {
                grow(&mut all, p);
                if role == RingRole::Walkable {
                    grow(&mut walk, p);
                }
            }
        }
        let extent = (all[2] - all[0]).max(all[3] - all[1]);
        let far = all.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if extent > MAX_PLAN_EXTENT_M || far > 10.0 * MAX_PLAN_EXTENT_M {
            return Err(PlanError::TooLarge {
                extent_m: extent.max(far),
                max_m: MAX_PLAN_EXTENT_M,
            });
        }
        Ok(walk)
    }
}

fn grow(b: &mut [f64; 4], p: &[f64; 2]) {
    b[0] = b[0].min(p[0]);
    b[1] = b[1].min(p[1]);
    b[2] = b[2].max(p[0]);
    b[3] = b[3].max(p[1]);
}

/// Twice the signed area of a closed ring (anticlockwise positive), m².
pub(crate) fn ring_area2(ring: &[[f64; 2]]) -> f64 {
    ring.windows(2)
        .map(|w| w[0][0] * w[1][1] - w[1][0] * w[0][1])
        .sum()
}

fn check_ring(ring: &[[f64; 2]], what: &str) -> Result<(), PlanError> {
    if ring.iter().any(|p| !(p[0].is_finite() && p[1].is_finite())) {
        return Err(PlanError::NonFinite { what: what.into() });
    }
    if ring.len() < 4 {
        return Err(PlanError::TooFewPoints {
            what: what.into(),
            points: ring.len(),
        });
    }
    if ring[0] != ring[ring.len() - 1] {
        return Err(PlanError::OpenRing { what: what.into() });
    }
    // Area against the ring's own size, so that a sliver is not taken for a room.
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    ring.iter().for_each(|p| grow(&mut b, p));
    let size2 = ((b[2] - b[0]).powi(2) + (b[3] - b[1]).powi(2)).max(f64::MIN_POSITIVE);
    if ring_area2(ring).abs() <= 1e-9 * size2 || ring_area2(ring).is_nan() {
        return Err(PlanError::NoArea { what: what.into() });
    }
    Ok(())
}
