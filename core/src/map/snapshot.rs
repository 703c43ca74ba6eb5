//! Snapshot and restore of the map engine: the navigator's own snapshot, then the
//! particles, their ancestry (the smoothed path's window), the random state, the
//! waiting fixes and the counters, with the plans' fingerprints so that a snapshot is
//! only restored over the plans it was taken with (the plans themselves are not in
//! it: the app keeps them). Writers destructure exhaustively; `restore` checks ranges.

use std::sync::Arc;

use crate::pdr::PhoneNavigator;
use crate::signal::Ring;
use crate::snapshot::{Reader, SnapshotError, Writer};

use super::config::{
    Declination, MapConfig, MAX_PARTICLES, MAX_SMOOTHING_LAG_STEPS, MIN_PARTICLES,
};
use super::error::MapError;
use super::fix::PendingFix;
use super::matcher::{MapFlags, MapMatcher, MAX_PLAN_COORD_M, PENDING_FIXES};
use super::navigator::MapNavigator;
use super::particles::{Cloud, Summary};
use super::plan::FloorPlan;
use super::smoother::{History, SmoothedPoint};
use crate::rng::Rng;

/// Snapshot kind of the map engine (docs/architecture.md lists every kind).
const SNAPSHOT_KIND: u8 = 9;
const SNAPSHOT_VERSION: u16 = 1;
/// Largest |position| a restored particle may hold, m (a plan is at most 5 km across;
/// steps taken through walls may leave it, never this far).
const MAX_POSITION_M: f64 = 1.0e6;
/// Largest |heading offset| (wrapped to ±π), rad, with rounding.
const MAX_OFFSET_RAD: f64 = std::f64::consts::PI + 1e-9;

impl MapNavigator {
    /// The whole state as bytes (the plans are identified, not stored).
    pub fn snapshot(&self) -> Vec<u8> {
        let MapNavigator {
            nav,
            matcher,
            config: _, // the navigator's from its snapshot, the rest from the matcher's
            placed,
            last_fix_t_s,
            origin,
            fixes_used,
        } = self;
        let mut w = Writer::new(SNAPSHOT_KIND, SNAPSHOT_VERSION);
        w.bytes(&nav.snapshot());
        write_config(&mut w, &self.config);
        w.u64(*placed);
        w.opt_f64(*last_fix_t_s);
        w.f64s(origin);
        w.u64(*fixes_used);
        match matcher {
            Some(m) => {
                w.bool(true);
                write_matcher(&mut w, m);
            }
            None => w.bool(false),
        }
        w.finish()
    }

    /// An engine continuing exactly where the snapshot was taken, over the same
    /// `plans` (the same floors and walls, in the same order; others are refused).
    pub fn restore(bytes: &[u8], plans: Vec<Arc<FloorPlan>>) -> Result<Self, MapError> {
        let (mut r, _) = Reader::new(bytes, SNAPSHOT_KIND, SNAPSHOT_VERSION)?;
        let nav = PhoneNavigator::restore(r.bytes()?)?;
        let mut config = read_config(&mut r)?;
        config.navigator = *nav.config();
        let placed = r.u64()?;
        let last_fix_t_s = r.opt_f64()?;
        let origin = [
            r.f64_in(-1e5, 1e5, "origin")?,
            r.f64_in(-1e5, 1e5, "origin")?,
        ];
        let fixes_used = r.u64()?;
        let matcher = if r.bool()? {
            Some(read_matcher(&mut r, config, plans)?)
        } else {
            if !plans.is_empty() {
                return Err(SnapshotError::Invalid("plans given for a snapshot without").into());
            }
            None
        };
        r.end()?;
        if placed > nav.recent_steps().1 {
            return Err(SnapshotError::Invalid("steps handed to the particles").into());
        }
        Ok(Self {
            nav,
            matcher,
            config,
            placed,
            last_fix_t_s,
            origin,
            fixes_used,
        })
    }
}

fn write_config(w: &mut Writer, c: &MapConfig) {
    let MapConfig {
        navigator: _, // in the navigator's snapshot
        particles,
        seed,
        start_sigma_m,
        heading_sigma_rad,
        heading_walk_rad_per_sqrt_m,
        step_heading_sigma_rad,
        scale_sigma,
        scale_walk_per_sqrt_m,
        step_length_sigma,
        wall_crossing_weight,
        roughen_heading_rad,
        roughen_scale,
        smoothing_lag_steps,
        declination,
    } = *c;
    w.u64(particles as u64);
    w.u64(seed);
    w.f64s(&[
        start_sigma_m,
        heading_sigma_rad,
        heading_walk_rad_per_sqrt_m,
        step_heading_sigma_rad,
        scale_sigma,
        scale_walk_per_sqrt_m,
        step_length_sigma,
        wall_crossing_weight,
        roughen_heading_rad,
        roughen_scale,
    ]);
    w.u64(smoothing_lag_steps as u64);
    match declination {
        Declination::Auto => w.u8(0),
        Declination::Fixed(d) => {
            w.u8(1);
            w.f64(d);
        }
        Declination::Off => w.u8(2),
    }
}

fn read_config(r: &mut Reader) -> Result<MapConfig, MapError> {
    let particles = r.len(MAX_PARTICLES)?;
    let seed = r.u64()?;
    let mut v = [0.0; 10];
    r.f64s(&mut v)?;
    let smoothing_lag_steps = r.len(MAX_SMOOTHING_LAG_STEPS)?;
    let declination = match r.u8()? {
        0 => Declination::Auto,
        1 => Declination::Fixed(r.f64()?),
        2 => Declination::Off,
        _ => return Err(SnapshotError::Invalid("declination").into()),
    };
    let c = MapConfig {
        navigator: Default::default(),
        particles,
        seed,
        start_sigma_m: v[0],
        heading_sigma_rad: v[1],
        heading_walk_rad_per_sqrt_m: v[2],
        step_heading_sigma_rad: v[3],
        scale_sigma: v[4],
        scale_walk_per_sqrt_m: v[5],
        step_length_sigma: v[6],
        wall_crossing_weight: v[7],
        roughen_heading_rad: v[8],
        roughen_scale: v[9],
        smoothing_lag_steps,
        declination,
    };
    c.validate()
        .map_err(|_| SnapshotError::Invalid("map configuration"))?;
    Ok(c)
}

fn write_pending(w: &mut Writer, f: &PendingFix) {
    let PendingFix {
        t_s,
        x_m,
        y_m,
        sigma_m,
    } = *f;
    w.f64s(&[t_s, x_m, y_m, sigma_m]);
}

fn read_pending(r: &mut Reader) -> Result<PendingFix, SnapshotError> {
    let t_s = r.f64_in(-1e11, 1e11, "fix time")?;
    let x_m = r.f64_in(-MAX_PLAN_COORD_M, MAX_PLAN_COORD_M, "fix position")?;
    let y_m = r.f64_in(-MAX_PLAN_COORD_M, MAX_PLAN_COORD_M, "fix position")?;
    let sigma_m = r.f64_in(super::fix::MIN_FIX_SIGMA_M, 1e5, "fix sigma")?;
    Ok(PendingFix {
        t_s,
        x_m,
        y_m,
        sigma_m,
    })
}

fn write_matcher(w: &mut Writer, m: &MapMatcher) {
    let MapMatcher {
        config: _, // written with the engine's
        plans,
        floor,
        cloud,
        history,
        rng,
        declination_rad,
        absolute_heading,
        offsets_pending,
        pending,
        last_fix_t_s,
        conflict,
        flags,
        steps_since_recovery,
        recoveries,
        fixes_used,
        fixes_rejected,
        summary,
    } = m;
    w.u64(plans.len() as u64);
    plans.iter().for_each(|p| w.u64(p.fingerprint()));
    w.u64(*floor as u64);
    write_cloud(w, cloud);
    write_history(w, history);
    rng.write(w);
    w.f64(*declination_rad);
    w.bool(*absolute_heading);
    w.bool(*offsets_pending);
    w.u64(pending.len() as u64);
    pending.iter().for_each(|f| write_pending(w, &f));
    w.opt_f64(*last_fix_t_s);
    match conflict {
        Some((f, walked)) => {
            w.bool(true);
            write_pending(w, f);
            w.f64(*walked);
        }
        None => w.bool(false),
    }
    let MapFlags {
        converged,
        ambiguous,
        recovered,
        start_snapped,
        global,
    } = *flags;
    for b in [converged, ambiguous, recovered, start_snapped, global] {
        w.bool(b);
    }
    w.u64(*steps_since_recovery);
    w.u64(*recoveries);
    w.u64(*fixes_used);
    w.u64(*fixes_rejected);
    // The summary follows from the cloud, but its heading mean from the one before:
    // kept as it is.
    let Summary {
        x,
        y,
        std_m,
        off,
        off_std,
        scale,
        near_share,
    } = *summary;
    w.f64s(&[x, y, std_m, off, off_std, scale, near_share]);
}

fn read_matcher(
    r: &mut Reader,
    config: MapConfig,
    plans: Vec<Arc<FloorPlan>>,
) -> Result<MapMatcher, MapError> {
    let n_plans = r.len(1 << 16)?;
    if n_plans != plans.len() {
        return Err(SnapshotError::Invalid("the snapshot was taken with other plans").into());
    }
    for p in &plans {
        if r.u64()? != p.fingerprint() {
            return Err(SnapshotError::Invalid("the snapshot was taken with other plans").into());
        }
    }
    let floor = r.len(n_plans.saturating_sub(1))?;
    let cloud = read_cloud(r, config.particles)?;
    let history = read_history(r, config.smoothing_lag_steps, config.particles)?;
    let rng = Rng::read(r)?;
    let declination_rad = r.f64_in(-std::f64::consts::PI, std::f64::consts::PI, "declination")?;
    let absolute_heading = r.bool()?;
    let offsets_pending = r.bool()?;
    let mut pending = Ring::new();
    for _ in 0..r.len(PENDING_FIXES)? {
        pending.push(read_pending(r)?);
    }
    let last_fix_t_s = r.opt_f64()?;
    let conflict = if r.bool()? {
        let f = read_pending(r)?;
        Some((f, r.f64_in(0.0, 1e13, "distance walked")?))
    } else {
        None
    };
    let mut b = [false; 5];
    for v in &mut b {
        *v = r.bool()?;
    }
    let flags = MapFlags {
        converged: b[0],
        ambiguous: b[1],
        recovered: b[2],
        start_snapped: b[3],
        global: b[4],
    };
    let steps_since_recovery = r.u64()?;
    let (recoveries, fixes_used, fixes_rejected) = (r.u64()?, r.u64()?, r.u64()?);
    let summary = Summary {
        x: r.f64_in(-MAX_POSITION_M, MAX_POSITION_M, "mean position")?,
        y: r.f64_in(-MAX_POSITION_M, MAX_POSITION_M, "mean position")?,
        std_m: r.f64_in(0.0, MAX_POSITION_M, "position spread")?,
        off: r.f64_in(-MAX_OFFSET_RAD, MAX_OFFSET_RAD, "heading offset")?,
        off_std: r.f64_in(0.0, 2.0 * MAX_OFFSET_RAD, "heading spread")?,
        scale: r.f64_in(0.5, 1.5, "step scale")?,
        near_share: r.f64_in(0.0, 1.0 + 1e-9, "weight share")?,
    };
    Ok(MapMatcher {
        config,
        plans,
        floor,
        cloud,
        history,
        rng,
        declination_rad,
        absolute_heading,
        offsets_pending,
        pending,
        last_fix_t_s,
        conflict,
        flags,
        steps_since_recovery,
        recoveries,
        fixes_used,
        fixes_rejected,
        summary,
    })
}

fn write_cloud(w: &mut Writer, c: &Cloud) {
    // `pick` and the gather scratch are not state.
    for a in [&c.x, &c.y, &c.off, &c.scale, &c.w] {
        w.f64s(a);
    }
}

fn read_cloud(r: &mut Reader, n: usize) -> Result<Cloud, SnapshotError> {
    if !(MIN_PARTICLES..=MAX_PARTICLES).contains(&n) {
        return Err(SnapshotError::Invalid("particles"));
    }
    let mut c = Cloud::new(n);
    for (a, lim, what) in [
        (&mut c.x, MAX_POSITION_M, "particle position"),
        (&mut c.y, MAX_POSITION_M, "particle position"),
        (&mut c.off, MAX_OFFSET_RAD, "heading offset"),
    ] {
        for v in a.iter_mut() {
            *v = r.f64_in(-lim, lim, what)?;
        }
    }
    for v in c.scale.iter_mut() {
        *v = r.f64_in(0.5, 1.5, "step scale")?;
    }
    for v in c.w.iter_mut() {
        *v = r.f64_in(0.0, 1.0, "weight")?;
    }
    let total: f64 = c.w.iter().sum();
    if !(total > 0.0 && total <= 1.0 + 1e-6) {
        return Err(SnapshotError::Invalid("weights"));
    }
    Ok(c)
}

fn write_history(w: &mut Writer, h: &History) {
    let History {
        lag,
        n,
        head,
        len,
        t_s,
        xy,
        parent,
        link,
        fixed,
        fixed_total,
        ..
    } = h;
    let _ = (lag, n); // from the configuration
    w.u64(*head as u64);
    w.u64(*len as u64);
    w.f64s(t_s);
    // The slots in use, packed: x, y as f32 bits and the parent index.
    let mut packed = Vec::with_capacity(*len * *n * 12);
    for k in 0..*len {
        let s = (*head + k) % *lag;
        for i in 0..*n {
            let j = s * *n + i;
            packed.extend_from_slice(&xy[j][0].to_bits().to_le_bytes());
            packed.extend_from_slice(&xy[j][1].to_bits().to_le_bytes());
            packed.extend_from_slice(&parent[j].to_le_bytes());
        }
    }
    w.bytes(&packed);
    let links: Vec<u8> = link.iter().flat_map(|l| l.to_le_bytes()).collect();
    w.bytes(&links);
    w.u64(fixed.len() as u64);
    for p in fixed {
        let SmoothedPoint { t_s, x_m, y_m } = *p;
        w.f64s(&[t_s, x_m, y_m]);
    }
    w.u64(*fixed_total);
}

fn read_history(r: &mut Reader, lag: usize, n: usize) -> Result<History, SnapshotError> {
    let mut h = History::new(lag, n);
    h.head = r.len(lag - 1)?;
    h.len = r.len(lag)?;
    for v in h.t_s.iter_mut() {
        *v = r.f64_in(-1e11, 1e11, "step time")?;
    }
    let packed = r.bytes()?;
    if packed.len() != h.len * n * 12 {
        return Err(SnapshotError::Invalid("smoothing window"));
    }
    let u32_at = |b: &[u8]| u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    for (k, chunk) in packed.chunks_exact(n * 12).enumerate() {
        let s = (h.head + k) % lag;
        for (i, e) in chunk.chunks_exact(12).enumerate() {
            let x = f32::from_bits(u32_at(&e[0..4]));
            let y = f32::from_bits(u32_at(&e[4..8]));
            let p = u32_at(&e[8..12]);
            if !(x.is_finite() && y.is_finite() && (p as usize) < n) {
                return Err(SnapshotError::Invalid("smoothing window"));
            }
            h.xy[s * n + i] = [x, y];
            h.parent[s * n + i] = p;
        }
    }
    let links = r.bytes()?;
    if links.len() != n * 4 {
        return Err(SnapshotError::Invalid("ancestry links"));
    }
    for (l, b) in h.link.iter_mut().zip(links.chunks_exact(4)) {
        *l = u32_at(b);
        if *l as usize >= n {
            return Err(SnapshotError::Invalid("ancestry links"));
        }
    }
    for _ in 0..r.len(lag)? {
        h.fixed.push(SmoothedPoint {
            t_s: r.f64_in(-1e11, 1e11, "smoothed time")?,
            x_m: r.f64_in(-MAX_POSITION_M, MAX_POSITION_M, "smoothed position")?,
            y_m: r.f64_in(-MAX_POSITION_M, MAX_POSITION_M, "smoothed position")?,
        });
    }
    h.fixed_total = r.u64()?;
    if (h.fixed.len() as u64) > h.fixed_total {
        return Err(SnapshotError::Invalid("smoothed points"));
    }
    Ok(h)
}
