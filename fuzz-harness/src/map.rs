//! The map engine's targets: the GeoJSON plan readers (any text: no panic, and a plan
//! that builds answers every query), and `MapNavigator` as an [`Engine`] over a fixed
//! plan (restores of any bytes, sample and fix sequences with snapshot swaps).

use std::sync::{Arc, OnceLock};

use stridekit_core::map::{FixPosition, FloorPlan, MapConfig, MapEstimate, MapFix, MapNavigator};

use crate::bytes::Bytes;
use crate::engines::{imu, Engine};

/// A floor plan's text, read both ways; a plan that builds answers queries.
pub fn geojson_plan(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let info = r#"{"map_info": {"width": 120.0, "height": 80.0}}"#;
    let files = [
        stridekit_formats::parse_competition_plan(&text, info),
        stridekit_formats::parse_geojson_plan(&text, None, None),
    ];
    for f in files.into_iter().flatten() {
        let Ok(p) = f.build() else { continue };
        let b = p.bounds();
        let c = [0.5 * (b[0] + b[2]), 0.5 * (b[1] + b[3])];
        let _ = p.crosses_wall([b[0], b[1]], c);
        let _ = p.is_walkable(c);
        assert!(p.distance_to_wall_m(c, 50.0) <= 50.0);
        if let Some(q) = p.nearest_walkable(c, 20.0) {
            assert!(p.is_walkable(q), "the nearest walkable point is walkable");
        }
        let w = p.walkable_point(0.5, 0.5, 0.5);
        assert!(w[0].is_finite() && w[1].is_finite());
        assert!(p.walkable_area_m2() > 0.0);
    }
}

/// The plan every `Map` engine runs on: a 100 × 100 m hall with two shops.
fn plan() -> Arc<FloorPlan> {
    static PLAN: OnceLock<Arc<FloorPlan>> = OnceLock::new();
    Arc::clone(PLAN.get_or_init(|| {
        Arc::new(
            FloorPlan::rectangles(
                0,
                [0.0, 0.0, 100.0, 100.0],
                &[[20.0, 20.0, 40.0, 40.0], [60.0, 10.0, 70.0, 90.0]],
            )
            .expect("a valid plan"),
        )
    }))
}

pub struct Map {
    e: MapNavigator,
    t: f64,
    t_fix: f64,
}

fn check_map(e: &MapEstimate) {
    for (v, what) in [
        (e.t_s, "t_s"),
        (e.x_m, "x"),
        (e.y_m, "y"),
        (e.position_std_m, "position std"),
        (e.step_scale, "step scale"),
        (e.distance_m, "distance"),
    ] {
        assert!(v.is_finite(), "{what} is not finite: {v}");
    }
    if let Some(a) = e.walking_azimuth_rad {
        assert!(a.is_finite(), "azimuth {a}");
    }
}

impl Engine for Map {
    fn fresh() -> Self {
        let config = MapConfig {
            particles: 64,
            smoothing_lag_steps: 8,
            ..MapConfig::default()
        };
        let mut e = MapNavigator::new(config, vec![plan()]).expect("default config");
        e.start_at(10.0, 10.0, Some(1.0), None)
            .expect("a walkable start");
        Self {
            e,
            t: 0.0,
            t_fix: 0.0,
        }
    }
    fn feed(&mut self, b: &mut Bytes) {
        match b.u8() {
            0..=9 => {
                let t = b.time(&mut self.t_fix, 5.0);
                let position = if b.bool() {
                    FixPosition::Plan {
                        x_m: b.value(50.0, 15.0),
                        y_m: b.value(50.0, 15.0),
                    }
                } else {
                    FixPosition::LatLon {
                        lat_deg: b.value(47.0, 1e-4),
                        lon_deg: b.value(8.0, 1e-4),
                    }
                };
                let fix = MapFix {
                    t_s: t,
                    position,
                    accuracy_m: b.value(4.0, 1.0),
                    floor: b.bool().then_some(0),
                };
                if let Ok(Some(e)) = self.e.push_fix(&fix) {
                    check_map(&e);
                }
            }
            10..=11 => {
                let _ = self.e.start_at(
                    b.value(50.0, 15.0),
                    b.value(50.0, 15.0),
                    Some(b.value(1.0, 0.3)),
                    None,
                );
            }
            _ => {
                let t = b.time(&mut self.t, 0.01);
                if let Ok(Some(e)) = self.e.push(&imu(b, t)) {
                    check_map(&e);
                }
            }
        }
    }
    fn check(&self) {
        if let Some(e) = self.e.estimate() {
            check_map(&e);
        }
        self.e.smoothed_window(|p| {
            assert!(p.x_m.is_finite() && p.y_m.is_finite(), "smoothed {p:?}");
        });
    }
    fn snapshot(&self) -> Vec<u8> {
        self.e.snapshot()
    }
    fn restore(bytes: &[u8]) -> Result<Self, String> {
        MapNavigator::restore(bytes, vec![plan()])
            .map(|e| Self {
                t: e.estimate().map_or(0.0, |x| x.t_s),
                t_fix: e.estimate().map_or(0.0, |x| x.t_s),
                e,
            })
            .map_err(|e| e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engines::{sealed, seed_body};

    #[test]
    fn the_seeds_are_accepted_and_the_plan_seed_builds() {
        for (seed, n) in [(1, 300), (2, 2_000)] {
            let body = seed_body::<Map>(seed, n);
            assert!(Map::restore(&sealed::<Map>(&body)).is_ok(), "seed {seed}");
        }
        let f = stridekit_formats::parse_competition_plan(
            std::str::from_utf8(crate::seeds("format_geojson_plan")[0].as_slice()).unwrap(),
            r#"{"map_info": {"width": 96.0, "height": 78.0}}"#,
        )
        .unwrap();
        assert!(f.build().unwrap().walkable_area_m2() > 5000.0);
    }
}
