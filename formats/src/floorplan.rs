//! Floor plans from GeoJSON, into the core's [`PlanGeometry`] in metres:
//!
//! - **the indoor-location competition's plans** (`geojson_map.json` +
//!   `floor_info.json`, [`parse_competition_plan`]): a FeatureCollection in
//!   longitude/latitude whose first feature is the floor's outline (a Polygon or
//!   MultiPolygon) and every other feature a unit to walk around (a shop, a room). The
//!   outline's bounding box maps linearly onto `[0, width] × [0, height]` metres of
//!   `floor_info.json` (`map_info.width`, `map_info.height`), x with longitude (east),
//!   y with latitude (north): the frame of the competition's waypoints.
//! - **plain GeoJSON in WGS84** ([`parse_geojson_plan`]), as map tools export it: the
//!   same roles (the first feature the outline, the others obstacles) unless features
//!   say `"walkable": true` or `false` in their properties; metres are East-North-Up
//!   around a reference point (by default the south-west corner of the walkable
//!   outlines' bounding box, so x and y are positive like an image's).
//!
//! Features that are not polygons (points, lines: labels, doors) are skipped and
//! counted; the outline must be a polygon. The geometry's own checks (closed rings,
//! area, size) are the core's ([`FloorPlan::new`]). `read_floor_plan` reads a floor
//! folder (the two competition files) or one GeoJSON file.

use std::path::Path;

use serde_json::Value;
use stridekit_core::map::{FloorPlan, GeoReference, PlanError, PlanGeometry, Polygon, Ring};

/// Most bytes of a plan's GeoJSON (the largest competition plan is 0.5 MB).
pub const MAX_PLAN_BYTES: usize = 64 << 20;

/// Why a floor plan file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum PlanFileError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    /// Not JSON, or not a GeoJSON FeatureCollection.
    #[error("invalid GeoJSON: {0}")]
    Json(String),
    /// A feature that cannot be used (the outline is not a polygon, coordinates that
    /// are not numbers...).
    #[error("GeoJSON feature {index}: {reason}")]
    Feature { index: usize, reason: String },
    /// `floor_info.json` lacks a positive `map_info.width` / `height`.
    #[error("floor_info.json: {0}")]
    FloorInfo(String),
    /// The polygons do not make a floor plan.
    #[error(transparent)]
    Plan(#[from] PlanError),
}

/// A plan read from GeoJSON: its polygons in metres and how they tie to WGS84.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanFile {
    pub geometry: PlanGeometry,
    pub geo: GeoReference,
    /// Features skipped because they are not polygons.
    pub skipped_features: usize,
}

impl PlanFile {
    /// Build the core's plan (validates the geometry).
    pub fn build(&self) -> Result<FloorPlan, PlanError> {
        FloorPlan::new(&self.geometry, Some(self.geo))
    }
}

/// The polygons of one feature, in degrees: `[[ring], ...]` per polygon.
type DegPolygons = Vec<Vec<Vec<[f64; 2]>>>;

/// A feature: its polygons (None: not a polygon), its `walkable` property, its
/// properties.
type Feature = (Option<DegPolygons>, Option<bool>, Value);

/// The features of a FeatureCollection.
fn features(text: &str) -> Result<Vec<Feature>, PlanFileError> {
    if text.len() > MAX_PLAN_BYTES {
        return Err(PlanFileError::Json(format!(
            "{} bytes, more than the {MAX_PLAN_BYTES} a plan may have",
            text.len()
        )));
    }
    let v: Value = serde_json::from_str(text).map_err(|e| PlanFileError::Json(e.to_string()))?;
    if v.get("type").and_then(Value::as_str) != Some("FeatureCollection") {
        return Err(PlanFileError::Json("not a FeatureCollection".into()));
    }
    let Some(feats) = v.get("features").and_then(Value::as_array) else {
        return Err(PlanFileError::Json("no \"features\" array".into()));
    };
    feats
        .iter()
        .enumerate()
        .map(|(index, f)| {
            let geometry = f.get("geometry").filter(|g| !g.is_null());
            let props = f.get("properties").cloned().unwrap_or(Value::Null);
            let walkable = props.get("walkable").and_then(Value::as_bool);
            let polys = match geometry {
                Some(g) => {
                    polygons(g).map_err(|reason| PlanFileError::Feature { index, reason })?
                }
                None => None,
            };
            Ok((polys, walkable, props))
        })
        .collect()
}

/// A geometry's polygons (None: not a polygon).
fn polygons(g: &Value) -> Result<Option<DegPolygons>, String> {
    let kind = g.get("type").and_then(Value::as_str).unwrap_or("");
    let coords = g.get("coordinates");
    match kind {
        "Polygon" => Ok(Some(vec![polygon(coords.ok_or("no coordinates")?)?])),
        "MultiPolygon" => coords
            .and_then(Value::as_array)
            .ok_or_else(|| "MultiPolygon coordinates are not an array".to_string())?
            .iter()
            .map(polygon)
            .collect::<Result<Vec<_>, _>>()
            .map(Some),
        _ => Ok(None),
    }
}

fn polygon(v: &Value) -> Result<Vec<Vec<[f64; 2]>>, String> {
    v.as_array()
        .ok_or("polygon coordinates are not an array of rings")?
        .iter()
        .map(|ring| {
            ring.as_array()
                .ok_or_else(|| "a ring is not an array of positions".to_string())?
                .iter()
                .map(|p| {
                    let a = p.as_array().filter(|a| a.len() >= 2);
                    match a.map(|a| (a[0].as_f64(), a[1].as_f64())) {
                        Some((Some(x), Some(y))) => Ok([x, y]),
                        _ => Err("a position is not [longitude, latitude]".to_string()),
                    }
                })
                .collect()
        })
        .collect()
}

fn bbox(polys: &DegPolygons) -> [f64; 4] {
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in polys.iter().flatten().flatten() {
        b = [
            b[0].min(p[0]),
            b[1].min(p[1]),
            b[2].max(p[0]),
            b[3].max(p[1]),
        ];
    }
    b
}

/// The feature's floor number (`floor_num`, else 0).
fn floor_of(props: &Value) -> i32 {
    props
        .get("floor_num")
        .and_then(Value::as_i64)
        .and_then(|f| i32::try_from(f).ok())
        .unwrap_or(0)
}

/// Degrees → metres through `geo`, polygon by polygon.
fn to_metres(polys: &DegPolygons, geo: &GeoReference) -> Vec<Polygon> {
    let ring = |r: &Vec<[f64; 2]>| -> Ring {
        r.iter()
            .map(|p| {
                let (x, y) = geo.to_plan(p[1], p[0]);
                [x, y]
            })
            .collect()
    };
    polys
        .iter()
        .filter(|p| !p.is_empty())
        .map(|p| Polygon {
            exterior: ring(&p[0]),
            holes: p[1..].iter().map(ring).collect(),
        })
        .collect()
}

fn outline_of(feats: &[Feature]) -> Result<(&DegPolygons, &Value), PlanFileError> {
    match feats.first() {
        None => Err(PlanFileError::Json("no features".into())),
        Some((Some(p), _, props)) if !p.is_empty() => Ok((p, props)),
        Some(_) => Err(PlanFileError::Feature {
            index: 0,
            reason: "the floor outline (the first feature) is not a polygon".into(),
        }),
    }
}

/// The competition's plan: `geojson_map.json`'s text and `floor_info.json`'s.
pub fn parse_competition_plan(geojson: &str, floor_info: &str) -> Result<PlanFile, PlanFileError> {
    let info: Value =
        serde_json::from_str(floor_info).map_err(|e| PlanFileError::FloorInfo(e.to_string()))?;
    let size = |k: &str| {
        info.get("map_info")
            .and_then(|m| m.get(k))
            .and_then(Value::as_f64)
            .filter(|v| v.is_finite() && *v > 0.0)
            .ok_or_else(|| PlanFileError::FloorInfo(format!("no positive map_info.{k}")))
    };
    let (width_m, height_m) = (size("width")?, size("height")?);
    let feats = features(geojson)?;
    let (outline, props) = outline_of(&feats)?;
    let b = bbox(outline);
    let geo = GeoReference::BoundingBox {
        west_deg: b[0],
        south_deg: b[1],
        east_deg: b[2],
        north_deg: b[3],
        width_m,
        height_m,
    };
    geo.validate()?;
    let mut geometry = PlanGeometry {
        floor: floor_of(props),
        walkable: to_metres(outline, &geo),
        obstacles: Vec::new(),
    };
    let mut skipped = 0;
    for (p, _, _) in &feats[1..] {
        match p {
            Some(p) => geometry.obstacles.extend(to_metres(p, &geo)),
            None => skipped += 1,
        }
    }
    Ok(PlanFile {
        geometry,
        geo,
        skipped_features: skipped,
    })
}

/// A plain GeoJSON plan in WGS84 (see the module docs for the roles); metres are
/// East-North-Up around `reference` `(lat, lon)` (default: the south-west corner of
/// the walkable outlines' bounding box); `floor` overrides the outline's `floor_num`.
pub fn parse_geojson_plan(
    geojson: &str,
    reference: Option<(f64, f64)>,
    floor: Option<i32>,
) -> Result<PlanFile, PlanFileError> {
    let feats = features(geojson)?;
    let marked = feats.iter().any(|f| f.1.is_some());
    let (first, props) = outline_of(&feats)?;
    let walkable: Vec<&DegPolygons> = if marked {
        feats
            .iter()
            .filter(|f| f.1 == Some(true))
            .filter_map(|f| f.0.as_ref())
            .collect()
    } else {
        vec![first]
    };
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for w in &walkable {
        let c = bbox(w);
        b = [
            b[0].min(c[0]),
            b[1].min(c[1]),
            b[2].max(c[2]),
            b[3].max(c[3]),
        ];
    }
    let (lat, lon) = reference.unwrap_or((b[1], b[0]));
    let geo = GeoReference::Local {
        lat_deg: lat,
        lon_deg: lon,
    };
    geo.validate()?;
    let mut geometry = PlanGeometry {
        floor: floor.unwrap_or_else(|| floor_of(props)),
        walkable: Vec::new(),
        obstacles: Vec::new(),
    };
    let mut skipped = 0;
    for (i, (p, w, _)) in feats.iter().enumerate() {
        let Some(p) = p else {
            skipped += 1;
            continue;
        };
        let is_walkable = if marked { *w == Some(true) } else { i == 0 };
        let target = if is_walkable {
            &mut geometry.walkable
        } else {
            &mut geometry.obstacles
        };
        target.extend(to_metres(p, &geo));
    }
    Ok(PlanFile {
        geometry,
        geo,
        skipped_features: skipped,
    })
}

fn read(path: &Path) -> Result<String, PlanFileError> {
    std::fs::read_to_string(path).map_err(|source| PlanFileError::Io {
        path: path.display().to_string(),
        source,
    })
}

/// A floor folder (`geojson_map.json` and `floor_info.json`: the competition's plan),
/// a competition `geojson_map.json` with its `floor_info.json` beside it, or one plain
/// GeoJSON file in WGS84.
pub fn read_floor_plan(path: &Path) -> Result<PlanFile, PlanFileError> {
    let (geojson, info) = if path.is_dir() {
        (
            path.join("geojson_map.json"),
            Some(path.join("floor_info.json")),
        )
    } else {
        let info = path.with_file_name("floor_info.json");
        (path.to_path_buf(), info.is_file().then_some(info))
    };
    let text = read(&geojson)?;
    match info {
        Some(info) => parse_competition_plan(&text, &read(&info)?),
        None => parse_geojson_plan(&text, None, None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A competition-style plan: a 0.001° × 0.001° outline and one shop in it.
    const PLAN: &str = r#"{"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"category": "floor", "floor_num": -1},
         "geometry": {"type": "MultiPolygon", "coordinates": [[[[120.0, 30.0], [120.001, 30.0],
            [120.001, 30.001], [120.0, 30.001], [120.0, 30.0]]]]}},
        {"type": "Feature", "properties": {"name": "shop"},
         "geometry": {"type": "Polygon", "coordinates": [[[120.0004, 30.0004], [120.0006, 30.0004],
            [120.0006, 30.0006], [120.0004, 30.0006], [120.0004, 30.0004]]]}},
        {"type": "Feature", "properties": {"name": "label"},
         "geometry": {"type": "Point", "coordinates": [120.0005, 30.0005]}}
    ]}"#;
    const INFO: &str = r#"{"map_info": {"height": 111.0, "width": 96.0}}"#;

    #[test]
    fn a_competition_plan_maps_its_outline_box_onto_width_and_height() {
        let f = parse_competition_plan(PLAN, INFO).unwrap();
        assert_eq!(f.geometry.floor, -1);
        assert_eq!(f.skipped_features, 1);
        assert_eq!(
            (f.geometry.walkable.len(), f.geometry.obstacles.len()),
            (1, 1)
        );
        let corner = f.geometry.walkable[0].exterior[2];
        assert!((corner[0] - 96.0).abs() < 1e-9 && (corner[1] - 111.0).abs() < 1e-9);
        let p = f.build().unwrap();
        assert!(p.is_walkable([10.0, 10.0]) && !p.is_walkable([48.0, 55.5]));
        let (lat, lon) = p.geo_reference().unwrap().to_geodetic(48.0, 55.5);
        assert!((lat - 30.0005).abs() < 1e-9 && (lon - 120.0005).abs() < 1e-9);
    }

    #[test]
    fn a_plain_plan_is_in_metres_around_its_south_west_corner_or_a_reference() {
        let f = parse_geojson_plan(PLAN, None, Some(3)).unwrap();
        assert_eq!(f.geometry.floor, 3);
        let ring = &f.geometry.walkable[0].exterior;
        // 0.001° of longitude at 30° N is 96.5 m, of latitude 110.9 m.
        assert!(
            ring[0][0].abs() < 1e-6 && ring[0][1].abs() < 1e-6,
            "{:?}",
            ring[0]
        );
        assert!(
            (ring[2][0] - 96.5).abs() < 0.5 && (ring[2][1] - 110.9).abs() < 0.5,
            "{:?}",
            ring[2]
        );
        let f = parse_geojson_plan(PLAN, Some((30.0005, 120.0005)), None).unwrap();
        assert!((f.geometry.walkable[0].exterior[0][0] + 48.2).abs() < 0.5);
        f.build().unwrap();
        // Features that say which they are.
        let marked = PLAN
            .replace(r#""name": "shop""#, r#""walkable": false"#)
            .replace(r#""category": "floor""#, r#""walkable": true"#);
        let f = parse_geojson_plan(&marked, None, None).unwrap();
        assert_eq!(
            (f.geometry.walkable.len(), f.geometry.obstacles.len()),
            (1, 1)
        );
    }

    #[test]
    fn what_is_not_a_plan_is_a_typed_error() {
        let cases = [
            ("", "invalid GeoJSON"),
            ("[1, 2]", "not a FeatureCollection"),
            (r#"{"type": "FeatureCollection"}"#, "no \"features\""),
            (
                r#"{"type": "FeatureCollection", "features": []}"#,
                "no features",
            ),
            (
                r#"{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "Point", "coordinates": [1, 2]}}]}"#,
                "not a polygon",
            ),
            (
                r#"{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[1, "a"]]]}}]}"#,
                "[longitude, latitude]",
            ),
        ];
        for (text, says) in cases {
            let e = parse_competition_plan(text, INFO).unwrap_err().to_string();
            assert!(e.contains(says), "{text:?}: {e}");
        }
        let e = parse_competition_plan(PLAN, r#"{"map_info": {"width": -1}}"#).unwrap_err();
        assert!(matches!(e, PlanFileError::FloorInfo(_)), "{e}");
        // Open rings are the core's to refuse, when the plan is built.
        let open = PLAN.replace(
            "[120.0004, 30.0006], [120.0004, 30.0004]]]",
            "[120.0004, 30.0006]]]",
        );
        let e = parse_competition_plan(&open, INFO)
            .unwrap()
            .build()
            .unwrap_err();
        assert!(matches!(e, PlanError::OpenRing { .. }), "{e}");
        // Deep nesting is refused by the parser, not a stack overflow.
        let deep = format!("{}{}", "[".repeat(100_000), "]".repeat(100_000));
        assert!(parse_competition_plan(&deep, INFO).is_err());
    }

    #[test]
    fn the_shared_plans_are_read_and_hold_their_waypoints() {
        let Some(dir) = crate::data_dir().map(|d| d.join("phone-indoor/site1")) else {
            eprintln!("skipping: the shared data folder is absent (set STRIDEKIT_DATA)");
            return;
        };
        if !dir.is_dir() {
            eprintln!("skipping: {} is absent", dir.display());
            return;
        }
        for floor in ["B1", "F1", "F2", "F3", "F4"] {
            let f = read_floor_plan(&dir.join(floor)).unwrap();
            let p = f.build().unwrap();
            assert!(
                p.walkable_area_m2() > 3000.0,
                "{floor}: {}",
                p.walkable_area_m2()
            );
            assert!(
                p.heap_bytes() < 5_000_000,
                "{floor}: {} bytes",
                p.heap_bytes()
            );
            assert_eq!(
                p.floor(),
                if floor == "B1" {
                    -1
                } else {
                    floor[1..].parse().unwrap()
                }
            );
        }
    }
}
