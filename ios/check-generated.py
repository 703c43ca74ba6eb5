#!/usr/bin/env python3
"""Cheap checks of the iOS packaging that need no Swift compiler (run by scripts/test).

Given the output of `uniffi-bindgen generate --language swift` (Stridekit.swift,
StridekitFFI.h, StridekitFFI.modulemap) and, optionally, the header directory that
`build-xcframework.sh --headers-only` laid out from it, check that:

 1. every C function the generated Swift calls is declared in StridekitFFI.h (and the
    C types it uses are defined there);
 2. the module names agree: bindings/uniffi.toml, the modulemap (module + header),
    `import StridekitFFI` in the Swift, the binaryTarget / target names and paths in
    ios/Package.swift and the names in build-xcframework.sh; the laid-out headers
    directory has StridekitFFI/module.modulemap next to the header it names;
 3. the hand-written Swift (ios/Sources/StridekitKit, ios/Sources/StridekitPacking,
    ios/Tests) only uses member / call / type names that are declared in the
    generated Stridekit.swift, declared by the hand-written files themselves, or are
    Apple-SDK / Swift-standard-library names listed below (a renamed Rust API then
    fails here instead of on a Mac); argument labels are not checked;
 4. the packed layouts in ios/Sources/StridekitPacking/Packing.swift match the Rust
    constants and decoders in bindings/src/packed.rs (sizes 16/32/56/80/56 and field
    order; the 80-byte IMU record is the 56-byte one followed by the magnetometer).

Python 3 standard library only. Exit status 1 with a list of problems on failure.
"""

import argparse
import re
import sys
from pathlib import Path

IOS = Path(__file__).resolve().parent
ROOT = IOS.parent
BINDINGS_SRC = ROOT / "bindings" / "src"

problems = []


def fail(msg):
    problems.append(msg)


def read(p):
    return Path(p).read_text(encoding="utf-8")


def strip_c_comments(text):
    return re.sub(r"//[^\n]*|/\*.*?\*/", " ", text, flags=re.S)


def strip_swift(text):
    """Swift source without comments and string literals (interpolations included)."""
    out, i, n = [], 0, len(text)
    while i < n:
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            depth, i = 1, i + 2
            while i < n and depth:
                if text.startswith("/*", i):
                    depth, i = depth + 1, i + 2
                elif text.startswith("*/", i):
                    depth, i = depth - 1, i + 2
                else:
                    i += 1
        elif text.startswith('"""', i):
            j = text.find('"""', i + 3)
            i = n if j < 0 else j + 3
            out.append('""')
        elif text[i] == '"':
            i += 1
            while i < n and text[i] != '"' and text[i] != "\n":
                i += 2 if text[i] == "\\" else 1
            i += 1
            out.append('""')
        else:
            out.append(text[i])
            i += 1
    return "".join(out)


# ---------------------------------------------------------------------------------
# 1. header vs generated Swift
# ---------------------------------------------------------------------------------
def check_header(swift, header):
    hdr = strip_c_comments(header)
    declared = set(re.findall(r"\b((?:uniffi|ffi)_stridekit_\w+)\s*\(", hdr))
    used = set(re.findall(r"\b((?:uniffi|ffi)_stridekit_\w+)\b", strip_swift(swift)))
    if not declared:
        fail("StridekitFFI.h declares no uniffi_stridekit_* / ffi_stridekit_* functions")
    for name in sorted(used - declared):
        fail(f"generated Swift calls {name}, which StridekitFFI.h does not declare")
    for ctype in ("RustBuffer", "ForeignBytes", "RustCallStatus"):
        if not re.search(r"typedef struct " + ctype + r"\b", hdr):
            fail(f"StridekitFFI.h does not define {ctype}")
    checksums = sorted(n for n in used if "_checksum_" in n)
    if not checksums:
        fail("generated Swift checks no API checksums (omit_checksums set?)")
    return len(used), len(declared), len(checksums)


# ---------------------------------------------------------------------------------
# 2. module names and layout
# ---------------------------------------------------------------------------------
def toml_swift_section(text):
    m = re.search(r"^\[bindings\.swift\]\s*$(.*?)(?=^\[|\Z)", text, flags=re.M | re.S)
    if not m:
        fail("bindings/uniffi.toml has no [bindings.swift] section")
        return {}
    return dict(re.findall(r'^\s*(\w+)\s*=\s*"([^"]*)"', m.group(1), flags=re.M))


def check_modules(gen_dir, swift, include_dir):
    cfg = toml_swift_section(read(ROOT / "bindings" / "uniffi.toml"))
    module = cfg.get("module_name", "")
    ffi = cfg.get("ffi_module_name", "")
    ffi_file = cfg.get("ffi_module_filename", ffi)
    if not module or not ffi:
        fail("bindings/uniffi.toml must set module_name and ffi_module_name")
        return
    for f in (f"{module}.swift", f"{ffi_file}.h", f"{ffi_file}.modulemap"):
        if not (gen_dir / f).is_file():
            fail(f"{gen_dir / f} missing (uniffi.toml names {f})")
    mm_path = gen_dir / f"{ffi_file}.modulemap"
    if mm_path.is_file():
        check_modulemap(read(mm_path), ffi, f"{ffi_file}.h", mm_path, framework_ok=False)
    if not re.search(r"^#if canImport\(" + ffi + r"\)\s*\nimport " + ffi + r"\b", swift, flags=re.M):
        fail(f"generated Swift does not `import {ffi}` under `#if canImport({ffi})`")

    pkg = strip_swift_keep_strings(read(IOS / "Package.swift"))
    m = re.search(r'\.binaryTarget\(\s*name:\s*"(\w+)"\s*,\s*path:\s*"([^"]+)"', pkg)
    if not m:
        fail("ios/Package.swift has no .binaryTarget(name:path:)")
    else:
        name, path = m.groups()
        if name != ffi:
            fail(f"Package.swift binaryTarget is {name!r}; the clang module is {ffi!r}")
        if Path(path).name != f"{name}.xcframework":
            fail(f"Package.swift binaryTarget path {path!r}: SwiftPM wants {name}.xcframework")
        if path != f"build/{name}.xcframework":
            fail(f"Package.swift binaryTarget path {path!r} is not where build-xcframework.sh writes it")
    m = re.search(r'\.target\(\s*name:\s*"' + module + r'"\s*,\s*dependencies:\s*\[([^\]]*)\]\s*,\s*path:\s*"([^"]+)"', pkg)
    if not m:
        fail(f"Package.swift has no target {module!r} (with dependencies and path) for the generated {module}.swift")
    else:
        if f'"{ffi}"' not in m.group(1):
            fail(f"Package.swift target {module} does not depend on {ffi}")
        if m.group(2) != f"Sources/{module}":
            fail(f"Package.swift target {module} path {m.group(2)!r} != Sources/{module}")
    if "swift-tools-version:5.9" not in read(IOS / "Package.swift").splitlines()[0]:
        fail("Package.swift must start with // swift-tools-version:5.9")
    if ".iOS(.v15)" not in pkg:
        fail("Package.swift must declare platforms: [.iOS(.v15)]")

    script = read(IOS / "build-xcframework.sh")
    for var, want in (("FFI_MODULE", ffi), ("SWIFT_MODULE", module), ("XCFRAMEWORK_NAME", ffi)):
        m = re.search(r"^" + var + r"=(\w+)", script, flags=re.M)
        if not m or m.group(1) != want:
            fail(f"build-xcframework.sh: {var} should be {want} (found {m.group(1) if m else 'nothing'})")
    if "IPHONEOS_DEPLOYMENT_TARGET=15.0" not in script:
        fail("build-xcframework.sh must build with IPHONEOS_DEPLOYMENT_TARGET=15.0 (Package.swift: iOS 15)")

    if include_dir is not None:
        mm = include_dir / ffi / "module.modulemap"
        if not mm.is_file():
            fail(f"{mm} missing: Xcode looks for <headers>/{ffi}/module.modulemap")
        else:
            check_modulemap(read(mm), ffi, f"{ffi_file}.h", mm, framework_ok=False)
        extra = [p for p in include_dir.rglob("*") if p.is_file()
                 and p.relative_to(include_dir).as_posix() not in (f"{ffi}/module.modulemap", f"{ffi}/{ffi_file}.h")]
        if extra:
            fail(f"unexpected files in the headers directory: {[str(p) for p in extra]}")


def strip_swift_keep_strings(text):
    return re.sub(r"//[^\n]*", "", text)


def check_modulemap(text, ffi, header, path, framework_ok):
    m = re.search(r"^\s*(framework\s+)?module\s+(\w+)\s*\{", text, flags=re.M)
    if not m:
        fail(f"{path}: no module declaration")
        return
    if m.group(1) and not framework_ok:
        fail(f"{path}: `framework module` is for .framework bundles; a library XCFramework needs `module {ffi}`")
    if m.group(2) != ffi:
        fail(f"{path}: module {m.group(2)!r}, expected {ffi!r}")
    headers = re.findall(r'\bheader\s+"([^"]+)"', text)
    if headers != [header]:
        fail(f"{path}: headers {headers}, expected [{header!r}]")
    for h in headers:
        if not (path.parent / h).is_file():
            fail(f"{path}: header {h!r} not found next to the modulemap")


# ---------------------------------------------------------------------------------
# 3. identifiers of the hand-written Swift
# ---------------------------------------------------------------------------------
SWIFT_KEYWORDS = set("""
as associatedtype async await break case catch class continue default defer deinit do
else enum extension fallthrough false fileprivate final for func guard if import in init
inout internal is lazy let mutating nil nonmutating open operator override precedencegroup
private protocol public repeat rethrows return self Self some static struct subscript super
switch throw throws true try typealias var weak unowned where while convenience any
""".split())

# Names from Apple's SDKs and the Swift standard library the hand-written code uses.
# Keep this list to such names: a stridekit name added here would defeat the check.
PLATFORM = set("""
Array Bool Data Date Double Error Int Int64 String UInt64 UInt8 TimeInterval Sendable Void Never
Optional Equatable CustomStringConvertible NSObject NSLock OperationQueue ProcessInfo
AsyncStream Continuation BufferingPolicy bufferingNewest unbounded yield finish
append reserveCapacity removeAll map compactMap allSatisfy contains isEmpty count prefix
bitPattern littleEndian isNaN nan startIndex timeIntervalSince timeIntervalSince1970
addingTimeInterval processInfo systemUptime lock unlock max min abs description
x y z first last
XCTestCase XCTAssertEqual XCTAssertNil XCTAssertNotNil XCTAssertTrue XCTAssertFalse
XCTFail XCTAssertThrowsError XCTUnwrap
CMMotionManager CMPedometer CMPedometerData CMAttitudeReferenceFrame CMDeviceMotion
CMAccelerometerData CMGyroData CMMagnetometerData
isAccelerometerAvailable isGyroAvailable isMagnetometerAvailable isDeviceMotionAvailable
accelerometerUpdateInterval gyroUpdateInterval magnetometerUpdateInterval
deviceMotionUpdateInterval startAccelerometerUpdates startGyroUpdates
startMagnetometerUpdates startDeviceMotionUpdates stopAccelerometerUpdates stopGyroUpdates
stopMagnetometerUpdates stopDeviceMotionUpdates availableAttitudeReferenceFrames
xMagneticNorthZVertical xArbitraryZVertical acceleration rotationRate magneticField
gravity userAcceleration field accuracy uncalibrated timestamp
isStepCountingAvailable startUpdates stopUpdates numberOfSteps endDate int64Value
name maxConcurrentOperationCount qualityOfService userInitiated
CLLocation CLLocationManager CLLocationManagerDelegate coordinate latitude longitude
altitude verticalAccuracy horizontalAccuracy speed speedAccuracy delegate
desiredAccuracy distanceFilter activityType fitness authorizationStatus notDetermined
requestWhenInUseAuthorization startUpdatingLocation stopUpdatingLocation locationManager
kCLLocationAccuracyBest kCLDistanceFilterNone
canImport os precondition withUnsafeBytes sin cos pi
""".split())


def generated_vocabulary(swift):
    s = strip_swift(swift)
    names = set(re.findall(r"\b(?:func|class|struct|enum|protocol|typealias|case|let|var)\s+`?(\w+)", s))
    names |= set(re.findall(r"\b(\w+)\s*:", s))          # fields, labels, enum payloads
    names |= set(re.findall(r"\bcase\s+(\w+)", s))
    return names


def declared_by(s):
    names = set(re.findall(r"\b(?:func|class|struct|enum|protocol|typealias|case|let|var)\s+`?(\w+)", s))
    names |= set(re.findall(r"\bcase\s+(?:let\s+)?\.?(\w+)", s))
    # parameters of own declarations: func f(label name: T), init(...)
    for params in re.findall(r"\b(?:func\s+\w+|init)\s*(?:<[^>]*>)?\(([^)]*)\)", s, flags=re.S):
        names |= set(re.findall(r"(\w+)(?:\s+\w+)?\s*:", params))
        names |= set(re.findall(r"\b\w+\s+(\w+)\s*:", params))
    # closure parameters `{ a, b in`, `{ [weak self] data, _ in`
    for params in re.findall(r"\{\s*(?:\[[^\]]*\]\s*)?([\w\s,]+?)\s+in\b", s):
        names |= set(re.findall(r"\w+", params))
    # bindings in patterns: `for (n, fields) in`, `case .fix(let f)`, `case let .count(tS, steps)`
    names |= set(re.findall(r"\blet\s+(\w+)", s))
    for group in re.findall(r"\bfor\s+\(([^)]*)\)\s+in", s):
        names |= set(re.findall(r"\w+", group))
    for group in re.findall(r"\bcase\s+let\s+\.?\w+\(([^)]*)\)", s):
        names |= set(re.findall(r"\w+", group))
    return names


def used_names(s):
    s = re.sub(r"^\s*(?:@testable\s+)?import\s+\w+", "", s, flags=re.M)
    s = re.sub(r"canImport\(\w+\)", "", s)
    s = re.sub(r"@\w+", "", s)
    used = set(re.findall(r"\.\s*([A-Za-z_]\w*)", s))       # members, enum cases
    used |= set(re.findall(r"\b([A-Za-z_]\w*)\s*\(", s))     # calls, initialisers
    used |= set(re.findall(r"\b([A-Z]\w*)\b", s))             # type names
    return used


def check_identifiers(swift):
    gen = generated_vocabulary(swift)
    files = sorted((IOS / "Sources" / "StridekitKit").glob("*.swift")) \
        + sorted((IOS / "Sources" / "StridekitPacking").glob("*.swift")) \
        + sorted((IOS / "Tests").rglob("*.swift"))
    stripped = {f: strip_swift(read(f)) for f in files}
    own = set()
    for s in stripped.values():
        own |= declared_by(s)
    api_used = set()
    for f, s in stripped.items():
        for name in sorted(used_names(s) - SWIFT_KEYWORDS):
            if name.isdigit() or name in own or name in PLATFORM:
                continue
            if name in gen:
                api_used.add(name)
                continue
            fail(f"{f.relative_to(ROOT)}: `{name}` is neither in the generated Stridekit.swift, "
                 "declared in ios/, nor a listed Apple/stdlib name")
    # Names both stridekit and ios/ declare (FixRecord fields...) count as stridekit uses
    # only when not declared here; report the stridekit API names seen.
    for f, s in stripped.items():
        api_used |= {n for n in used_names(s) if n in gen and n not in own and n not in PLATFORM}
    return len(files), sorted(api_used)


# ---------------------------------------------------------------------------------
# 4. packed layouts
# ---------------------------------------------------------------------------------
def rust_fn_body(text, signature):
    i = text.find(signature)
    if i < 0:
        fail(f"bindings/src: `{signature}` not found")
        return ""
    indent = text[text.rfind("\n", 0, i) + 1:i]
    end = text.find("\n" + indent + "}\n", i)
    return text[i:end if end > 0 else len(text)]


def rust_consts():
    consts = {}
    for f in ("packed.rs",):
        for name, v in re.findall(r"pub const (\w+_BYTES): usize = (\d+);", read(BINDINGS_SRC / f)):
            consts[name] = int(v)
    return consts


def expand_slots(body, call, first=0):
    """Field names in slot order (8-byte slots from `first`) from `name: CALL(offset)`
    and `name: [CALL(a), CALL(b), CALL(c)]` (also `let name = [...]` feeding `name_unit:`)."""
    slots = {}
    idx = call + r"(\d+)\)"
    for name, i in re.findall(r"(\w+):\s*" + idx, body):
        slots[int(i)] = name
    arrays = re.findall(r"(?:(\w+):|let\s+(\w+)\s*=)\s*\[\s*" + idx + r",\s*" + idx + r",\s*" + idx
                        + r"\s*\]", body)
    for field, let_name, a, b, c in arrays:
        group = field or let_name
        base, _, unit = group.partition("_")
        if not unit:  # `let mag = [...]` feeding `mag_ut: ...`
            m = re.search(r"\b(" + group + r"_\w+):", body)
            unit = m.group(1).partition("_")[2] if m else ""
        for axis, idx in zip("xyz", (a, b, c)):
            slots[int(idx)] = f"{base}_{axis}_{unit}" if unit else f"{base}_{axis}"
    return [slots.get(first + 8 * i, "?") for i in range(len(slots))] if slots else []


def swift_layouts(text):
    layouts = {}
    for name, body in re.findall(r"public enum (\w+Layout) \{(.*?)\n\}", text, flags=re.S):
        m = re.search(r"recordBytes = (\d+)", body)
        f = re.search(r"fields = \[(.*?)\]", body, flags=re.S)
        layouts[name] = {
            "bytes": int(m.group(1)) if m else None,
            "fields": re.findall(r'"(\w+)"', f.group(1)) if f else [],
            "appends": re.findall(r"appendLittleEndian\(([^,]+), to:", body),
            "nested": re.findall(r"\b(\w+Layout)\.append\(", body),
        }
    return layouts


def camel(snake):
    head, *rest = snake.split("_")
    return head + "".join(w[:1].upper() + w[1:] for w in rest)


def check_layouts():
    consts = rust_consts()
    packed = read(BINDINGS_SRC / "packed.rs")
    types = read(BINDINGS_SRC / "pace" / "types.rs")

    fix_body = rust_fn_body(packed, "pub fn fixes(")
    fix_fields = [n for _, n in sorted((int(o), n) for n, o in
                                       re.findall(r"(\w+):\s*(?:opt_)?f64_at\(c,\s*(\d+)\)", fix_body))]
    accel_body = rust_fn_body(packed, "pub fn accel(")
    accel_offsets = [int(o) for o in re.findall(r"f64_at\(c,\s*(\d+)\)", accel_body)]
    m = re.search(r"pub struct AccelSample \{(.*?)\n\}", types, flags=re.S)
    accel_fields = re.findall(r"pub (\w+):", m.group(1)) if m else []
    if accel_offsets != [8 * i for i in range(len(accel_fields))]:
        fail(f"packed::accel reads offsets {accel_offsets}, not t_s, x, y, z in AccelSample order")
    steps_body = rust_fn_body(packed, "pub fn step_counts(")
    step_fields = []
    if re.search(r"t_s:\s*f64_at\(c,\s*0\)", steps_body) and "c[8..16]" in steps_body:
        step_fields = ["t_s", "steps"]
    # The IMU family: the 6-axis record, and the 9-axis record = the 6-axis one + mag.
    at = r"f64_at\(c,\s*"
    imu6_fields = expand_slots(rust_fn_body(packed, "fn imu6_record("), at)
    imu9_body = rust_fn_body(packed, "fn imu_record(")
    if "imu6_record(c)" not in imu9_body:
        fail("packed.rs: imu_record does not start with imu6_record (one layout family)")
    imu_fields = imu6_fields + expand_slots(imu9_body, at, first=8 * len(imu6_fields))
    # The pack side writes the 6-axis fields in the same order (`s.accel_mps2[0]` ...).
    pack6 = [f"{n.partition('_')[0]}_{'xyz'[int(i)]}_{n.partition('_')[2]}" if i else n
             for n, i in re.findall(r"\bs\.(\w+)(?:\[(\d)\])?,", rust_fn_body(packed, "fn imu6_values("))]
    if pack6 != imu6_fields:
        fail(f"packed.rs: imu6_values order {pack6} != decode order {imu6_fields}")

    # Other engines taking 32-byte accelerometer records must decode them with packed::accel.
    for f in sorted(BINDINGS_SRC.rglob("*.rs")):
        text = read(f)
        for sig in re.findall(r"pub fn (push_accel_packed)\(", text):
            if "packed::accel(" not in rust_fn_body(text, f"pub fn {sig}("):
                fail(f"{f.name}: {sig} does not decode with packed::accel (AccelLayout)")

    rust = {
        "AccelLayout": ("ACCEL_RECORD_BYTES", accel_fields),
        "StepCountLayout": ("STEP_COUNT_RECORD_BYTES", step_fields),
        "FixLayout": ("FIX_RECORD_BYTES", fix_fields),
        "ImuLayout": ("IMU_RECORD_BYTES", imu_fields),
        "FootImuLayout": ("IMU6_RECORD_BYTES", imu6_fields),
    }
    swift = swift_layouts(read(IOS / "Sources" / "StridekitPacking" / "Packing.swift"))
    report = []
    for layout, (const, fields) in rust.items():
        if const not in consts:
            fail(f"bindings/src: no constant {const}")
            continue
        if not fields:
            fail(f"could not read the Rust field order for {layout} ({const})")
        s = swift.get(layout)
        if s is None:
            fail(f"Packing.swift has no enum {layout}")
            continue
        if s["bytes"] != consts[const]:
            fail(f"Packing.swift {layout}.recordBytes = {s['bytes']}, Rust {const} = {consts[const]}")
        if 8 * len(s["fields"]) != consts[const]:
            fail(f"Packing.swift {layout}.fields has {len(s['fields'])} 8-byte fields for {consts[const]} bytes")
        if s["fields"] != fields:
            fail(f"Packing.swift {layout}.fields {s['fields']} != Rust order {fields}")
        # A layout of the family may write a leading record with its layout's append.
        nested = [swift.get(n, {}).get("fields", []) for n in s["nested"]]
        if sum(map(len, nested)) + len(s["appends"]) != len(s["fields"]):
            fail(f"Packing.swift {layout}.append writes {len(s['appends'])} values and "
                 f"{' + '.join(s['nested']) or 'no nested layout'} for {len(s['fields'])} fields")
        if any(n != s["fields"][:len(n)] for n in nested):
            fail(f"Packing.swift {layout}.fields does not start with the fields of {s['nested']}")
        report.append(f"{layout}={consts[const]}")
    fix = swift.get("FixLayout")
    if fix:
        for k, (arg, field) in enumerate(zip(fix["appends"], fix["fields"])):
            if f".{camel(field)}" not in arg:
                fail(f"Packing.swift FixLayout.append writes `{arg.strip()}` at field {k} ({field})")
    return report


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--generated", required=True, type=Path,
                    help="output dir of uniffi-bindgen generate --language swift")
    ap.add_argument("--include", type=Path,
                    help="headers dir laid out by build-xcframework.sh --headers-only")
    args = ap.parse_args()

    swift_path = args.generated / "Stridekit.swift"
    header_path = args.generated / "StridekitFFI.h"
    if not swift_path.is_file() or not header_path.is_file():
        print(f"error: {swift_path} or {header_path} missing", file=sys.stderr)
        return 1
    swift = read(swift_path)
    used, declared, checksums = check_header(swift, read(header_path))
    check_modules(args.generated, swift, args.include)
    nfiles, api = check_identifiers(swift)
    layouts = check_layouts()

    if problems:
        print(f"ios/check-generated.py: {len(problems)} problem(s):", file=sys.stderr)
        for p in problems:
            print(f"  - {p}", file=sys.stderr)
        return 1
    print(f"ok: Swift calls {used} FFI symbols, all among the header's {declared} "
          f"({checksums} checksums); module names agree (uniffi.toml, modulemap, Package.swift, "
          f"build script{', headers layout' if args.include else ''}); {nfiles} hand-written Swift "
          f"files use {len(api)} generated API names, all present; layouts {' '.join(layouts)} match bindings/src")
    return 0


if __name__ == "__main__":
    sys.exit(main())
