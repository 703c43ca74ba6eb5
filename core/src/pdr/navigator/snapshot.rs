//! Snapshot and restore of the [`PhoneNavigator`]: the sub-engines' own snapshots,
//! the position, the walking direction, the steps waiting or placed and the personal
//! calibration, versioned and checksummed. `snapshot` destructures the navigator
//! exhaustively and `restore` builds it field by field, so a field that is not
//! serialised is a compile error.

use super::*;

impl PhoneNavigator {
    /// The whole state (sub-engines included) as bytes.
    pub fn snapshot(&self) -> Vec<u8> {
        // Exhaustive on purpose: a new field must be written (or said to be derived);
        // `restore` builds the navigator field by field, so it cannot miss one either.
        let PhoneNavigator {
            config: _, // the sub-engines' configurations, rebuilt from them at restore
            ahrs,
            detector,
            lengths,
            direction,
            vertical,
            frame,
            east_m,
            north_m,
            pos_var_m2,
            distance_m,
            steps,
            last_step_length_m,
            last_t_s,
            imu_time,
            fix_time,
            dr_east_m,
            dr_north_m,
            course_anchor,
            deferred,
            recent,
            placed,
            calibration,
            scale,
            merger,
        } = self;
        let mut w = Writer::new(SNAPSHOT_KIND, SNAPSHOT_VERSION);
        w.bytes(&ahrs.snapshot());
        w.bytes(&detector.snapshot());
        w.bytes(&lengths.snapshot());
        direction.write(&mut w);
        vertical.write(&mut w);
        crate::geo::write_frame(&mut w, frame.as_ref());
        w.f64s(&[
            *east_m,
            *north_m,
            *pos_var_m2,
            *distance_m,
            *last_step_length_m,
            *last_t_s,
            *dr_east_m,
            *dr_north_m,
        ]);
        imu_time.write(&mut w);
        fix_time.write(&mut w);
        let CourseAnchor {
            t_s,
            fix_east_m,
            fix_north_m,
            dr_east_m,
            dr_north_m,
        } = course_anchor;
        w.f64s(&[*t_s, *fix_east_m, *fix_north_m, *dr_east_m, *dr_north_m]);
        w.u64(*steps);
        w.u64(deferred.len() as u64);
        for p in deferred.iter() {
            let PendingStep {
                t0_s,
                t1_s,
                length_m,
                vertical_displacement_m,
                origin,
            } = p;
            w.f64s(&[t0_s, t1_s, length_m, vertical_displacement_m]);
            origin.write(&mut w);
        }
        w.u64(recent.len() as u64);
        for p in recent.iter() {
            let NavStep {
                t_s,
                east_m,
                north_m,
                length_m,
                azimuth_rad,
                vertical_displacement_m,
                origin,
            } = p;
            w.f64s(&[
                t_s,
                east_m,
                north_m,
                length_m,
                azimuth_rad,
                vertical_displacement_m,
            ]);
            origin.write(&mut w);
        }
        w.u64(*placed);
        match calibration {
            Some(c) => {
                w.bool(true);
                w.bytes(c.to_text(&[]).as_bytes());
            }
            None => w.bool(false),
        }
        scale.write(&mut w);
        w.bytes(&merger.snapshot());
        w.finish()
    }

    /// A navigator continuing exactly where the snapshot was taken.
    pub fn restore(bytes: &[u8]) -> Result<Self, NavError> {
        // The reader refuses any other version than this build writes.
        let (mut r, _) = Reader::new(bytes, SNAPSHOT_KIND, SNAPSHOT_VERSION)?;
        let ahrs = Ahrs::restore(r.bytes()?)?;
        let detector = StepDetector::restore(r.bytes()?)?;
        let lengths = StepLengthEstimator::restore(r.bytes()?)?;
        let direction = WalkingDirection::read(&mut r)?;
        let vertical = VerticalHistory::read(&mut r)?;
        let frame = crate::geo::read_frame(&mut r)?;
        let [east_m, north_m, pos_var_m2, distance_m] = [r.f64()?, r.f64()?, r.f64()?, r.f64()?];
        // NaN before the first step / the first input.
        let last_step_length_m = r.f64_or_nan()?;
        let last_t_s = r.f64_or_nan()?;
        let [dr_east_m, dr_north_m] = [r.f64()?, r.f64()?];
        let imu_time = TimeGuard::read(&mut r, Stream::Imu)?;
        let fix_time = TimeGuard::read(&mut r, Stream::Gnss)?;
        // All NaN before the first stretch.
        let anchor = [(); 5].map(|_| r.f64_or_nan());
        let [t_s, fix_east_m, fix_north_m, anchor_dr_east_m, anchor_dr_north_m] = anchor;
        let course_anchor = CourseAnchor {
            t_s: t_s?,
            fix_east_m: fix_east_m?,
            fix_north_m: fix_north_m?,
            dr_east_m: anchor_dr_east_m?,
            dr_north_m: anchor_dr_north_m?,
        };
        let steps = r.u64()?;
        let deferred = read_deferred(&mut r)?;
        let recent = read_recent(&mut r)?;
        let placed = r.u64()?;
        let calibration = if r.bool()? {
            let text = std::str::from_utf8(r.bytes()?)
                .map_err(|_| SnapshotError::Invalid("calibration"))?;
            Some(PdrCalibration::parse(text).map_err(|_| SnapshotError::Invalid("calibration"))?)
        } else {
            None
        };
        let scale = StepScale::read(&mut r)?;
        let merger = ImuMerger::restore(r.bytes()?)?;
        r.end()?;
        let newest = imu_time
            .last_t_s()
            .into_iter()
            .chain(fix_time.last_t_s())
            .reduce(f64::max);
        // Generous: garbage fixes may teleport across the globe for days.
        let pos_ok = |v: f64| v.abs() <= 1e12;
        let ok = pos_ok(east_m)
            && pos_ok(north_m)
            && pos_ok(dr_east_m)
            && pos_ok(dr_north_m)
            && (0.0..=1e25).contains(&pos_var_m2)
            && (0.0..=1e13).contains(&distance_m)
            && (last_step_length_m.is_nan() || (0.0..=10.0).contains(&last_step_length_m))
            && course_anchor_ok(&course_anchor)
            && newest.map_or(last_t_s.is_nan(), |t| t == last_t_s)
            && !(frame.is_none() && fix_time.last_t_s().is_some());
        if !ok {
            return Err(SnapshotError::Invalid("navigator state").into());
        }
        let config = NavigatorConfig {
            ahrs: *ahrs.settings(),
            detector: *detector.config(),
            step_length_model: lengths.model(),
            step_length: *lengths.config(),
            gyro_calibrated: direction.gyro_calibrated(),
            merge: *merger.config(),
        };
        Ok(Self {
            config,
            ahrs,
            detector,
            lengths,
            direction,
            vertical,
            frame,
            east_m,
            north_m,
            pos_var_m2,
            distance_m,
            last_step_length_m,
            last_t_s,
            imu_time,
            fix_time,
            dr_east_m,
            dr_north_m,
            course_anchor,
            steps,
            deferred,
            recent,
            placed,
            calibration,
            scale,
            merger,
        })
    }
}

/// A step's vertical displacement: NaN (not measured) or within the input limit.
fn read_vertical(r: &mut Reader) -> Result<f64, SnapshotError> {
    let h = r.f64_or_nan()?;
    if h.is_nan() || (0.0..=crate::input::limits::MAX_STEP_VERTICAL_M).contains(&h) {
        Ok(h)
    } else {
        Err(SnapshotError::Invalid("vertical displacement"))
    }
}

/// A stretch start: all NaN (none yet) or all set, within generous bounds.
fn course_anchor_ok(a: &CourseAnchor) -> bool {
    let CourseAnchor {
        t_s,
        fix_east_m,
        fix_north_m,
        dr_east_m,
        dr_north_m,
    } = *a;
    let v = [t_s, fix_east_m, fix_north_m, dr_east_m, dr_north_m];
    v.iter().all(|v| v.is_nan() || v.abs() <= 1e11 + 1.0)
        && v.iter().all(|v| v.is_nan()) == t_s.is_nan()
}

/// The steps waiting for the carrying.
fn read_deferred(r: &mut Reader) -> Result<Ring<PendingStep, DEFERRED_STEPS>, SnapshotError> {
    let mut deferred = Ring::new();
    for _ in 0..r.len(DEFERRED_STEPS)? {
        let mut v = [0.0; 3];
        r.f64s(&mut v)?;
        let [t0_s, t1_s, length_m] = v;
        deferred.push(PendingStep {
            t0_s,
            t1_s,
            length_m,
            vertical_displacement_m: read_vertical(r)?,
            origin: StepOrigin::read(r)?,
        });
    }
    Ok(deferred)
}

/// The latest placed steps.
fn read_recent(r: &mut Reader) -> Result<Ring<NavStep, RECENT_STEPS>, SnapshotError> {
    let mut recent = Ring::new();
    for _ in 0..r.len(RECENT_STEPS)? {
        let mut v = [0.0; 5];
        r.f64s(&mut v)?;
        let [t_s, east_m, north_m, length_m, azimuth_rad] = v;
        recent.push(NavStep {
            t_s,
            east_m,
            north_m,
            length_m,
            azimuth_rad,
            vertical_displacement_m: read_vertical(r)?,
            origin: StepOrigin::read(r)?,
        });
    }
    Ok(recent)
}
