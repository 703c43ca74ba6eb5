#!/usr/bin/env python3
"""Fail unless every LOAD segment of the given ELF shared libraries is aligned to at
least 16 KB (Google Play's requirement for apps targeting Android 15+, devices with
16 KB pages). Python 3 standard library only.

    python3 android/check-alignment.py android/src/main/jniLibs/*/libstridekit.so
    python3 android/check-alignment.py --jnilibs android/src/main/jniLibs   # every <abi>/libstridekit.so
"""
import struct
import sys
from pathlib import Path

MIN_ALIGN = 16 * 1024
PT_LOAD = 1
ABIS = ("arm64-v8a", "armeabi-v7a", "x86_64", "x86")


def load_alignments(path):
    """(offset, vaddr, align) of every PT_LOAD program header of an ELF file."""
    data = Path(path).read_bytes()
    if data[:4] != b"\x7fELF":
        raise ValueError("not an ELF file")
    cls, enc = data[4], data[5]
    if cls not in (1, 2) or enc not in (1, 2):
        raise ValueError(f"unknown ELF class {cls} / data encoding {enc}")
    e = "<" if enc == 1 else ">"
    if cls == 2:  # ELF64
        phoff, = struct.unpack_from(e + "Q", data, 0x20)
        phentsize, phnum = struct.unpack_from(e + "HH", data, 0x36)
        fmt = e + "IIQQQQQQ"  # type, flags, offset, vaddr, paddr, filesz, memsz, align
        pick = lambda h: (h[0], h[2], h[3], h[7])
    else:  # ELF32
        phoff, = struct.unpack_from(e + "I", data, 0x1C)
        phentsize, phnum = struct.unpack_from(e + "HH", data, 0x2A)
        fmt = e + "IIIIIIII"  # type, offset, vaddr, paddr, filesz, memsz, flags, align
        pick = lambda h: (h[0], h[1], h[2], h[7])
    out = []
    for i in range(phnum):
        kind, offset, vaddr, align = pick(struct.unpack_from(fmt, data, phoff + i * phentsize))
        if kind == PT_LOAD:
            out.append((offset, vaddr, align))
    if not out:
        raise ValueError("no LOAD segment")
    return out


def check(path):
    """Error lines for one library (empty: fine)."""
    try:
        segments = load_alignments(path)
    except (OSError, ValueError, struct.error) as e:
        return [f"{path}: {e}"]
    errors = []
    for offset, vaddr, align in segments:
        if align < MIN_ALIGN:
            errors.append(f"{path}: LOAD segment at offset {offset:#x} aligned to {align} bytes, needs >= {MIN_ALIGN} "
                          "(link with -Wl,-z,max-page-size=16384: bindings/build.rs)")
        elif offset % MIN_ALIGN != vaddr % MIN_ALIGN:
            errors.append(f"{path}: LOAD segment offset {offset:#x} and address {vaddr:#x} differ modulo 16 KB")
    return errors


def main(argv):
    if len(argv) == 2 and argv[0] == "--jnilibs":
        libs = [Path(argv[1]) / abi / "libstridekit.so" for abi in ABIS]
    elif argv and not argv[0].startswith("-"):
        libs = [Path(a) for a in argv]
    else:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    errors = [line for lib in libs for line in check(lib)]
    for line in errors:
        print(f"error: {line}", file=sys.stderr)
    if not errors:
        for lib in libs:
            aligns = sorted({a for _, _, a in load_alignments(lib)})
            print(f"{lib}: every LOAD segment aligned to >= 16 KB ({', '.join(map(str, aligns))})")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
