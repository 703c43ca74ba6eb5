#!/usr/bin/env bash
# Build ios/build/StridekitFFI.xcframework (release static libraries for iOS devices and
# the iOS simulator) and the Swift bindings the package in ios/Package.swift compiles.
# Runs on macOS with Xcode; see ios/README.md. `--headers-only` runs anywhere (CI).
set -euo pipefail

usage() {
    cat <<'USAGE'
Usage: ios/build-xcframework.sh [--zip] [--no-build] [--testing]
       ios/build-xcframework.sh --headers-only GENERATED_DIR OUT_DIR

Builds, from the repository root's workspace:
  1. libstridekit.a, release, for aarch64-apple-ios, aarch64-apple-ios-sim and
     x86_64-apple-ios (IPHONEOS_DEPLOYMENT_TARGET=15.0); the two simulator
     architectures are joined with lipo;
  2. uniffi-bindgen (host, dev profile, its own cargo invocation) and, from the
     device library, Stridekit.swift + StridekitFFI.h + the modulemap;
  3. the headers directory of the XCFramework:
       include/StridekitFFI/StridekitFFI.h
       include/StridekitFFI/module.modulemap   (module StridekitFFI)
  4. ios/build/StridekitFFI.xcframework with `xcodebuild -create-xcframework`, and
     copies Stridekit.swift to ios/Sources/Stridekit/ for Package.swift.

Options:
  --zip           also write ios/build/StridekitFFI.xcframework.zip and its SwiftPM
                  checksum (`swift package compute-checksum`) to
                  ios/build/StridekitFFI.xcframework.zip.checksum
  --no-build      reuse the three release libraries already in the target directory
  --testing       build with the bindings' `testing` feature (simulateRun,
                  simulateFootWalk, simulatePhoneWalk, pdrReferenceReplay), which the
                  package's XCTests need; never for an app or a release
  --headers-only GENERATED_DIR OUT_DIR
                  only step 3: lay out OUT_DIR/StridekitFFI/{StridekitFFI.h,
                  module.modulemap} from the output of `uniffi-bindgen generate
                  --language swift` in GENERATED_DIR (used by scripts/test; no macOS)
  -h, --help      this text

Prerequisites (checked): macOS, Xcode command line tools (xcodebuild, lipo, xcrun),
rustup with the three targets:
  rustup target add aarch64-apple-ios aarch64-apple-ios-sim x86_64-apple-ios
USAGE
}

die() { echo "error: $*" >&2; exit 1; }
step() { printf '\n==> %s\n' "$*"; }

FFI_MODULE=StridekitFFI        # [bindings.swift] ffi_module_name in bindings/uniffi.toml
SWIFT_MODULE=Stridekit         # [bindings.swift] module_name
XCFRAMEWORK_NAME=StridekitFFI  # must equal the binaryTarget name in Package.swift

# Step 3 on its own: the header layout Xcode and SwiftPM expect. Clang finds a module
# map either directly in a header search path or in a subdirectory named after the
# module; the subdirectory keeps our module.modulemap from colliding with another
# XCFramework's when Xcode copies all their headers into one include directory.
layout_headers() {
    local gen=$1 out=$2
    for f in "$FFI_MODULE.h" "$FFI_MODULE.modulemap"; do
        test -s "$gen/$f" || die "$gen/$f missing (run uniffi-bindgen generate --language swift)"
    done
    grep -q "^module $FFI_MODULE {" "$gen/$FFI_MODULE.modulemap" \
        || die "$gen/$FFI_MODULE.modulemap does not declare 'module $FFI_MODULE'"
    rm -rf "$out"
    mkdir -p "$out/$FFI_MODULE"
    cp "$gen/$FFI_MODULE.h" "$out/$FFI_MODULE/$FFI_MODULE.h"
    # Same content, the file name clang looks for.
    cp "$gen/$FFI_MODULE.modulemap" "$out/$FFI_MODULE/module.modulemap"
}

ZIP=0
BUILD=1
FEATURES=()
BINDGEN_FEATURES=cli
while [[ $# -gt 0 ]]; do
    case $1 in
        -h|--help) usage; exit 0 ;;
        --zip) ZIP=1; shift ;;
        --no-build) BUILD=0; shift ;;
        --testing) FEATURES=(--features testing); BINDGEN_FEATURES=cli,testing; shift ;;
        --headers-only)
            [[ $# -eq 3 ]] || { usage >&2; exit 2; }
            layout_headers "$2" "$3"
            echo "headers laid out in $3/$FFI_MODULE"
            exit 0 ;;
        *) echo "unknown argument: $1" >&2; usage >&2; exit 2 ;;
    esac
done

IOS_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=$(cd "$IOS_DIR/.." && pwd)
cd "$ROOT"

# ---- prerequisites -------------------------------------------------------------------
[[ $(uname -s) == Darwin ]] || die "needs macOS with Xcode (this is $(uname -s)); see ios/README.md"
for tool in cargo rustup xcodebuild lipo xcrun; do
    command -v "$tool" >/dev/null || die "'$tool' not found on PATH (install Rust via rustup and Xcode, then: sudo xcode-select -s /Applications/Xcode.app)"
done
xcrun --sdk iphoneos --show-sdk-path >/dev/null 2>&1 \
    || die "no iphoneos SDK: install Xcode (not only the command line tools) and run 'sudo xcode-select -s /Applications/Xcode.app'"
TARGETS=(aarch64-apple-ios aarch64-apple-ios-sim x86_64-apple-ios)
INSTALLED=$(rustup target list --installed)
for t in "${TARGETS[@]}"; do
    grep -qx "$t" <<<"$INSTALLED" || die "Rust target $t missing: rustup target add ${TARGETS[*]}"
done
if [[ $ZIP == 1 ]]; then
    command -v swift >/dev/null || die "--zip needs 'swift' (Xcode) for compute-checksum"
    command -v ditto >/dev/null || die "--zip needs 'ditto'"
fi

TARGET_DIR=$(cargo metadata --format-version 1 --no-deps \
    | sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p')
TARGET_DIR=${TARGET_DIR:-$ROOT/target}
BUILD_DIR=$IOS_DIR/build
GEN_DIR=$BUILD_DIR/generated
INCLUDE_DIR=$BUILD_DIR/include
SIM_LIB=$BUILD_DIR/ios-simulator/libstridekit.a
DEVICE_LIB=$TARGET_DIR/aarch64-apple-ios/release/libstridekit.a
XCFRAMEWORK=$BUILD_DIR/$XCFRAMEWORK_NAME.xcframework
BINDGEN=$TARGET_DIR/debug/uniffi-bindgen

# ---- 1. static libraries ---------------------------------------------------------------
# Must match `platforms: [.iOS(.v15)]` in Package.swift (else the linker warns about
# objects built for a newer iOS than the app's deployment target).
export IPHONEOS_DEPLOYMENT_TARGET=15.0
if [[ $BUILD == 1 ]]; then
    for t in "${TARGETS[@]}"; do
        step "cargo build -p stridekit --lib --release --target $t"
        # The release profile strips debug info only (Cargo.toml: strip = "debuginfo"),
        # so the uniffi metadata symbols stay in the archive.
        cargo build -p stridekit --lib --release --target "$t" ${FEATURES[@]+"${FEATURES[@]}"}
    done
fi
for t in "${TARGETS[@]}"; do
    test -f "$TARGET_DIR/$t/release/libstridekit.a" \
        || die "$TARGET_DIR/$t/release/libstridekit.a missing (run without --no-build)"
done

step "lipo: one simulator library (arm64 + x86_64)"
mkdir -p "$(dirname "$SIM_LIB")"
lipo -create \
    "$TARGET_DIR/aarch64-apple-ios-sim/release/libstridekit.a" \
    "$TARGET_DIR/x86_64-apple-ios/release/libstridekit.a" \
    -output "$SIM_LIB"
lipo -info "$SIM_LIB"

# ---- 2. bindings -----------------------------------------------------------------------
step "uniffi-bindgen (host, dev profile, own cargo invocation)"
cargo build -p stridekit --features "$BINDGEN_FEATURES" --bin uniffi-bindgen
step "generate Swift bindings from $DEVICE_LIB"
rm -rf "$GEN_DIR"
"$BINDGEN" generate "$DEVICE_LIB" --language swift --out-dir "$GEN_DIR" --no-format
for f in "$SWIFT_MODULE.swift" "$FFI_MODULE.h" "$FFI_MODULE.modulemap"; do
    test -s "$GEN_DIR/$f" || die "$GEN_DIR/$f missing: was the library stripped of its uniffi metadata?"
done
grep -q "class PaceTracker" "$GEN_DIR/$SWIFT_MODULE.swift" \
    || die "$GEN_DIR/$SWIFT_MODULE.swift has no PaceTracker: uniffi metadata missing from the library?"

# ---- 3. headers ------------------------------------------------------------------------
step "headers -> ${INCLUDE_DIR#"$ROOT"/}"
layout_headers "$GEN_DIR" "$INCLUDE_DIR"

# Same checks CI runs on the host-generated files (header/modulemap/Package.swift/adapters).
if command -v python3 >/dev/null; then
    python3 "$IOS_DIR/check-generated.py" --generated "$GEN_DIR" --include "$INCLUDE_DIR"
fi

# ---- 4. XCFramework --------------------------------------------------------------------
step "xcodebuild -create-xcframework -> ${XCFRAMEWORK#"$ROOT"/}"
rm -rf "$XCFRAMEWORK"
xcodebuild -create-xcframework \
    -library "$DEVICE_LIB" -headers "$INCLUDE_DIR" \
    -library "$SIM_LIB" -headers "$INCLUDE_DIR" \
    -output "$XCFRAMEWORK"

mkdir -p "$IOS_DIR/Sources/$SWIFT_MODULE"
cp "$GEN_DIR/$SWIFT_MODULE.swift" "$IOS_DIR/Sources/$SWIFT_MODULE/$SWIFT_MODULE.swift"

if [[ $ZIP == 1 ]]; then
    step "zip + SwiftPM checksum"
    rm -f "$XCFRAMEWORK.zip"
    (cd "$BUILD_DIR" && ditto -c -k --sequesterRsrc --keepParent \
        "$XCFRAMEWORK_NAME.xcframework" "$XCFRAMEWORK_NAME.xcframework.zip")
    (cd "$IOS_DIR" && swift package compute-checksum "$XCFRAMEWORK.zip") \
        | tee "$XCFRAMEWORK.zip.checksum"
fi

step "sizes"
ls -l "$DEVICE_LIB" "$SIM_LIB"
du -sh "$XCFRAMEWORK"
echo "done: $XCFRAMEWORK and Sources/$SWIFT_MODULE/$SWIFT_MODULE.swift; next: cd ios && swift build / xcodebuild test (ios/README.md)"
