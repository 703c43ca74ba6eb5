//! The evaluations on small folders of real recordings, as held-out recordings of
//! another session, user or building may come: one session of foot trials, one
//! user's step traces. They must run and print no "NaN" (skips without the data).

use std::path::{Path, PathBuf};
use std::process::Command;

use stridekit_formats::data_dir;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("stridekit-small-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `rel` under the shared data folder, or `None` (the test skips, saying why).
fn shared(rel: &str) -> Option<PathBuf> {
    let d = data_dir().map(|d| d.join(rel));
    if d.is_none() {
        eprintln!("skipping: ../shared/data not found (set STRIDEKIT_DATA)");
    }
    d
}

/// Link `names` from `from` into a new folder.
fn subset(from: &Path, names: &[&str], name: &str) -> PathBuf {
    let d = temp_dir(name);
    for n in names {
        std::os::unix::fs::symlink(from.join(n), d.join(n)).unwrap();
    }
    d
}

fn eval(args: &[&str], dir: &Path) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_stridekit"))
        .arg("eval")
        .args(args)
        .arg("--data")
        .arg(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn eval_foot_on_one_session() {
    let Some(root) = shared("foot/pyshoe-vicon") else {
        return;
    };
    let dir = subset(
        &root,
        &["2017-11-22-11-22-46.csv", "2017-11-22-11-27-30.csv"],
        "foot",
    );
    let out = eval(&["foot"], &dir);
    assert!(!out.contains("NaN"), "{out}");
    // One session: nothing to leave out.
    assert!(!out.contains("leave one session out) |"), "{out}");
    assert!(out.contains("| adaptive shoe | "), "{out}");
    assert!(out.contains("are not in this folder"), "{out}");
}

#[test]
fn eval_steps_on_one_user() {
    let Some(root) = shared("steps/oxford") else {
        return;
    };
    let dir = subset(
        &root,
        &[
            "Samsung_Carmelo_Hard_InHand_2",
            "Samsung_Carmelo_Hard_Purse_1",
        ],
        "steps",
    );
    let out = eval(&["steps"], &dir);
    assert!(!out.contains("NaN"), "{out}");
    assert!(out.contains("| user Carmelo | 2 | "), "{out}");
    assert!(!out.contains("user Jamie"), "{out}");
}
