#!/usr/bin/env python3
"""Give the generated Kotlin exceptions a readable `message`.

uniffi 0.32 writes `message` of an error variant with fields as a field dump
(`field=lat_deg`); the SDK's own sentence ("lat_deg is not a finite number") is only in
`toString()`, which every stridekit error exports from its Rust `Display`. This rewrites
each variant's `message` getter to return `toString()`, so `e.message`, logs and crash
reports read the SDK's words. Used by scripts/test (JVM bindings) and android/ (the
AAR's bindings, same rewrite in build.gradle.kts). Fails when an exception class has no
`toString()` (a new error type without `#[uniffi::export(Display)]`) or when the
generated code no longer has the expected shape.

    python3 bindings/kotlin-messages.py path/to/stridekit.kt
"""
import re
import sys

GETTER = re.compile(r'override val message\n(\s+)get\(\) = "[^"\n]*"')


def rewrite(text: str) -> tuple[str, int]:
    classes = list(re.finditer(r"^sealed class (\w+Exception)\b", text, flags=re.M))
    if not classes:
        raise SystemExit("kotlin-messages: no exception classes found (generated code changed?)")
    for i, m in enumerate(classes):
        end = classes[i + 1].start() if i + 1 < len(classes) else len(text)
        body = text[m.start():end]
        if "override fun toString(): String" not in body:
            raise SystemExit(f"kotlin-messages: {m.group(1)} has no toString(): export Display for it")
    return GETTER.subn(r"override val message: String\n\1get() = toString()", text)


def main() -> None:
    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    path = sys.argv[1]
    with open(path, encoding="utf-8") as f:
        text = f.read()
    new, n = rewrite(text)
    if n == 0:
        raise SystemExit(f"kotlin-messages: no message getter rewritten in {path}")
    with open(path, "w", encoding="utf-8") as f:
        f.write(new)
    print(f"kotlin-messages: {n} exception messages now read the SDK's Display text ({path})")


if __name__ == "__main__":
    main()
