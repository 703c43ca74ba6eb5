//! Replays every input that ever failed a fuzz target (`fuzz/regressions/<target>/`),
//! plus each target's seeds and a few fixed inputs, with stable Rust: a fix that
//! regresses fails CI without a fuzzer.

use std::path::PathBuf;

use stridekit_fuzz_harness::{run, seeds, TARGETS};

fn regressions_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fuzz/regressions")
}

#[test]
fn every_recorded_failure_is_fixed() {
    let dir = regressions_dir();
    let mut replayed = 0;
    for entry in std::fs::read_dir(&dir).expect("fuzz/regressions exists") {
        let entry = entry.unwrap();
        if !entry.file_type().unwrap().is_dir() {
            continue;
        }
        let target = entry.file_name().to_string_lossy().into_owned();
        assert!(
            TARGETS.iter().any(|t| t.name == target),
            "fuzz/regressions/{target}: no such target"
        );
        for input in std::fs::read_dir(entry.path()).unwrap() {
            let path = input.unwrap().path();
            let data = std::fs::read(&path).unwrap();
            eprintln!("replaying {}", path.display());
            run(&target, &data);
            replayed += 1;
        }
    }
    assert!(replayed > 0, "no regression inputs under {}", dir.display());
}

#[test]
fn every_target_takes_empty_fixed_and_seed_inputs() {
    let fixed: [&[u8]; 4] = [b"", &[0xFF; 64], &[0; 200], b"t_s,acc_x\n1,2\n"];
    for t in TARGETS {
        for data in fixed {
            (t.run)(data);
        }
        for s in seeds(t.name) {
            (t.run)(&s);
        }
    }
}

#[test]
fn restore_seeds_are_accepted_snapshots() {
    // The sealed seeds must decode, or the restore campaigns would start from nothing.
    use stridekit_fuzz_harness::engines::{sealed, seed_body, Engine, Navigator, Pace};
    assert!(Pace::restore(&sealed::<Pace>(&seed_body::<Pace>(1, 300))).is_ok());
    assert!(Navigator::restore(&sealed::<Navigator>(&seed_body::<Navigator>(1, 300))).is_ok());
}

#[test]
fn every_target_has_a_cargo_fuzz_binary() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fuzz");
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).unwrap();
    for t in TARGETS {
        let file = root.join(format!("fuzz_targets/{}.rs", t.name));
        let src = std::fs::read_to_string(&file)
            .unwrap_or_else(|_| panic!("{} is missing", file.display()));
        assert!(
            src.contains(&format!("run(\"{}\"", t.name)),
            "{}",
            file.display()
        );
        assert!(
            manifest.contains(&format!("name = \"{}\"", t.name)),
            "fuzz/Cargo.toml has no [[bin]] {}",
            t.name
        );
    }
}
