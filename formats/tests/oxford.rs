//! The Oxford Step Counter reader on the real traces (skips without the shared data).

use stridekit_formats::{data_dir, list_oxford_traces, read_oxford_trace, OxfordPosition};

#[test]
fn reads_every_trace_and_matches_the_published_step_totals() {
    let Some(root) = data_dir() else {
        eprintln!("SKIPPED: shared data folder not found (../shared/data; set STRIDEKIT_DATA)");
        return;
    };
    let dir = root.join("steps/oxford");
    if !dir.is_dir() {
        eprintln!("SKIPPED: {} not found", dir.display());
        return;
    }
    let stats = std::fs::read_to_string(dir.join("_stats.csv")).unwrap();
    let traces = list_oxford_traces(&dir).unwrap();
    assert_eq!(traces.len(), 48);
    let mut positions = std::collections::BTreeSet::new();
    for path in &traces {
        let t = read_oxford_trace(path).unwrap();
        positions.insert(t.position);
        // `_stats.csv`: dir, user, phone, position, surface, duration(s), steps
        let row = stats
            .lines()
            .find(|l| l.split(',').next() == Some(t.name.as_str()))
            .unwrap_or_else(|| panic!("{} not in _stats.csv", t.name));
        let cols: Vec<&str> = row.split(',').map(str::trim).collect();
        assert_eq!(cols[1], t.user);
        assert_eq!(cols[2], t.phone);
        assert_eq!(cols[4], t.surface);
        assert_eq!(
            OxfordPosition::parse(cols[3]),
            Some(t.position),
            "{}",
            t.name
        );
        let steps: usize = cols[6].parse().unwrap();
        assert_eq!(t.heel_strikes_t_s.len(), steps, "{}", t.name);
        let rate = t.rate_hz();
        assert!((90.0..=420.0).contains(&rate), "{}: {rate} Hz", t.name);
        assert!(t.accel.windows(2).all(|w| w[1].t_s > w[0].t_s));
        assert!(t.heel_strikes_t_s.windows(2).all(|w| w[1] >= w[0]));
        // m/s² with gravity: the mean magnitude is near 9.8.
        let mean = t
            .accel
            .iter()
            .map(|a| a.accel_mps2.iter().map(|v| v * v).sum::<f64>().sqrt())
            .sum::<f64>()
            / t.accel.len() as f64;
        assert!((9.0..=12.0).contains(&mean), "{}: {mean}", t.name);
        // Reference and accelerometer share a clock.
        let (a0, a1) = (t.accel[0].t_s, t.accel.last().unwrap().t_s);
        let inside = t
            .heel_strikes_t_s
            .iter()
            .filter(|&&s| s >= a0 && s <= a1)
            .count();
        assert!(inside * 10 >= steps * 9, "{}", t.name);
    }
    assert_eq!(positions.len(), 7);
}

#[test]
fn missing_files_are_errors_and_folders_named_otherwise_are_read() {
    let dir = std::env::temp_dir().join(format!("stridekit-oxford-{}", std::process::id()));
    let bad = dir.join("not_a_trace");
    std::fs::create_dir_all(&bad).unwrap();
    assert!(read_oxford_trace(&bad).is_err());
    let missing = dir.join("Pixel_Jamie_Hard_InHand_9");
    std::fs::create_dir_all(&missing).unwrap();
    assert!(read_oxford_trace(&missing).is_err());
    std::fs::write(
        missing.join("accelerometer.csv"),
        "1000000000,3,0,0,9.8\n2000000000,3,0,0,9.8\n",
    )
    .unwrap();
    std::fs::write(
        missing.join("stepcounter.csv"),
        "1000000000,0,0\n1500000000,1,0\n1600000000,1,1\n",
    )
    .unwrap();
    let t = read_oxford_trace(&missing).unwrap();
    assert_eq!(t.accel.len(), 2);
    assert_eq!(t.heel_strikes_t_s, vec![1.5, 1.6]);
    assert_eq!(t.position, OxfordPosition::InHand);
    assert_eq!(list_oxford_traces(&dir).unwrap(), vec![missing.clone()]);
    // A folder named outside the set's pattern (a recording of your own) is read:
    // the samples and the reference are what count.
    let own = dir.join("my_walk");
    std::fs::create_dir_all(&own).unwrap();
    for f in ["accelerometer.csv", "stepcounter.csv"] {
        std::fs::copy(missing.join(f), own.join(f)).unwrap();
    }
    let t = read_oxford_trace(&own).unwrap();
    assert_eq!(t.heel_strikes_t_s, vec![1.5, 1.6]);
    assert_eq!((t.user.as_str(), t.position), ("?", OxfordPosition::Other));
    std::fs::remove_dir_all(&dir).unwrap();
}
