//! Link flags of the shipped library: 16 KB page alignment on every ELF target.
//!
//! Google Play requires the native libraries of apps targeting Android 15+ to have
//! their LOAD segments aligned to 16 KB (devices with 16 KB pages); NDK r27c's linker
//! defaults to 4 KB. Set here, not in `.cargo/config.toml`, because a `RUSTFLAGS`
//! in the environment (cargo-ndk users, CI) would silently replace config rustflags;
//! a build script's link argument always applies. Only the cdylib is affected;
//! `android/check-alignment.py` checks the result (Android libraries in the Gradle
//! recipe, the host library in scripts/test).

/// Page size the LOAD segments are aligned to, bytes (16 KB).
const MAX_PAGE_SIZE: u32 = 16 * 1024;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    // ELF targets (GNU ld, lld, the NDK's clang); Apple's linker has no `-z`.
    if matches!(os.as_str(), "android" | "linux") {
        println!("cargo:rustc-link-arg-cdylib=-Wl,-z,max-page-size={MAX_PAGE_SIZE}");
    }
}
