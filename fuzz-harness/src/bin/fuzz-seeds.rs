//! `fuzz-seeds DIR`: writes each target's generated seeds (see `seeds`) into
//! `DIR/<target>/seed-<n>` and lists the targets (scripts/fuzz uses both).

use stridekit_fuzz_harness::{seeds, TARGETS};

fn main() -> std::io::Result<()> {
    let Some(dir) = std::env::args().nth(1) else {
        for t in TARGETS {
            println!("{}", t.name);
        }
        return Ok(());
    };
    for t in TARGETS {
        let d = std::path::Path::new(&dir).join(t.name);
        std::fs::create_dir_all(&d)?;
        for (i, s) in seeds(t.name).iter().enumerate() {
            std::fs::write(d.join(format!("seed-{i}")), s)?;
        }
    }
    Ok(())
}
