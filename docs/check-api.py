#!/usr/bin/env python3
"""docs/api.md covers the whole generated Kotlin API: every public object, its
methods and constructors, every record (with its fields), enum, sealed class and
top-level function of the uniffi bindings. Python 3 standard library only.

    python3 docs/check-api.py KOTLIN_FILE            # fails listing what api.md lacks
    python3 docs/check-api.py KOTLIN_FILE --write    # rewrite the generated reference
                                                      # section of docs/api.md

A name counts as documented when it appears in backticks in docs/api.md (`pushFix`,
`PhoneNavigator.pushFix(fix)`, ...). The section between the markers
<!-- api-reference:start --> and <!-- api-reference:end --> is generated from the
bindings' own doc comments by --write; the hand-written sections above it explain.
A new FFI object, method or record fails scripts/test until it is documented: run
--write after scripts/test generated the bindings (then review the diff), or
document it by hand.
"""
import re
import sys
from pathlib import Path

API_MD = Path(__file__).resolve().parent / "api.md"
# In the bindings of the tests only (feature `testing`), never in an app's build.
TESTING = {"simulateRun", "simulateFootWalk", "simulatePhoneWalk", "pdrReferenceReplay",
           "SimulatedRun", "SimulatedFootWalk", "SimulatedPhoneWalk", "PdrReplay"}
TESTING_NOTE = " (test builds only: feature `testing`)"
START, END = "<!-- api-reference:start -->", "<!-- api-reference:end -->"
FUN = re.compile(r"\bfun `(\w+)`\((.*?)\)\s*(?::\s*([^{=]+?))?\s*(?:\{|$|=)")
PARAM = re.compile(r"`(\w+)`:\s*")


def strip_code(line):
    """A line without string literals and comments (to count braces)."""
    line = re.sub(r'"(?:\\.|[^"\\])*"', '""', line)
    line = re.sub(r"//.*", "", line)
    return line


def signature(args, ret):
    args = PARAM.sub(lambda m: m.group(1) + ": ", args).replace("kotlin.", "")
    ret = (ret or "").strip().replace("kotlin.", "")
    return f"({args})" + (f": {ret}" if ret and ret != "Unit" else "")


def first_sentence(doc):
    text = " ".join(l.strip().lstrip("*").strip() for l in doc).strip()
    text = re.sub(r"\s+", " ", text)
    m = re.match(r"(.+?\.)(\s|$)", text)
    s = m.group(1) if m else text
    return s.replace("|", "\\|")


class Api:
    def __init__(self):
        self.objects = {}  # name -> {"doc", "methods": [(name, sig, doc)], "ctors": [...]}
        self.records = {}  # name -> (fields, doc)
        self.enums = {}  # name -> (values, doc)
        self.sealed = {}  # name -> (variants, doc)
        self.functions = []  # (name, sig, doc)


def parse(path):
    lines = Path(path).read_text(encoding="utf-8").splitlines()
    api = Api()
    depth = 0
    doc, in_doc = [], False
    scope = []  # [kind, name, depth of its body, body entered]
    header = None  # the record whose fields (between its parentheses) are being read
    for line in lines:
        s = line.strip()
        if s.startswith("/**"):
            in_doc, doc = True, []
        if in_doc:
            body = s.replace("/**", "").replace("*/", "")
            if body.strip() and not body.strip() == "*":
                doc.append(body)
            if "*/" in s:
                in_doc = False
                rest = s.split("*/", 1)[1].strip()
                if not rest:
                    continue
                s = rest
            else:
                continue
        top = depth == 0
        m = re.match(r"public interface (\w+)Interface\b", s)
        if top and m:
            api.objects.setdefault(m.group(1), {"doc": first_sentence(doc), "methods": [], "ctors": []})
            scope.append(["interface", m.group(1), depth + 1, False])
        m = re.match(r"open class (\w+)\s*:\s*Disposable", s)
        if top and m:
            scope.append(["class", m.group(1), depth + 1, False])
        m = re.match(r"data class (\w+)\s*\(", s)
        if top and m:
            api.records[m.group(1)] = ([], first_sentence(doc))
            header = m.group(1)
        m = re.match(r"enum class (\w+)", s)
        if top and m:
            api.enums[m.group(1)] = ([], first_sentence(doc))
            scope.append(["enum", m.group(1), depth + 1, False])
        m = re.match(r"sealed class (\w+)", s)
        if top and m:
            api.sealed[m.group(1)] = ([], first_sentence(doc))
            scope.append(["sealed", m.group(1), depth + 1, False])
        cur = scope[-1] if scope else None
        f = FUN.search(s)
        if f and not s.startswith(("internal", "private", "override fun lower", "override fun lift")):
            name, sig = f.group(1), signature(f.group(2), f.group(3))
            entry = (name, sig, first_sentence(doc))
            if top:
                api.functions.append(entry)
            elif cur and cur[0] == "interface" and depth == cur[2]:
                api.objects[cur[1]]["methods"].append(entry)
            elif cur and cur[0] == "class" and "override" not in s and depth == cur[2] + 1:
                api.objects.setdefault(cur[1], {"doc": "", "methods": [], "ctors": []})["ctors"].append(entry)
        if cur and cur[0] == "class" and depth == cur[2] and re.match(r"constructor\(`", s):
            sig = signature(re.search(r"constructor\((.*?)\)", s).group(1), None)
            api.objects[cur[1]]["ctors"].insert(0, ("constructor", sig, first_sentence(doc)))
        if header:
            m = re.match(r"(?:var|val) `(\w+)`", s)
            if m:
                api.records[header][0].append(m.group(1))
            if s.startswith(")"):
                header = None
        if cur and cur[0] == "enum" and depth == cur[2]:
            m = re.match(r"([A-Z][A-Z0-9_]*)\s*[,;]?\s*$", s)
            if m:
                api.enums[cur[1]][0].append(m.group(1))
        if cur and cur[0] == "sealed" and depth == cur[2]:
            m = re.match(r"(?:data )?(?:class|object) (\w+)", s)
            if m:
                api.sealed[cur[1]][0].append(m.group(1))
        doc = [] if s and not s.startswith("@") else doc
        code = strip_code(line)
        depth += code.count("{") - code.count("}")
        # A scope opens when its brace is reached (the class line may end without
        # it) and closes when the depth falls below its body again.
        if scope and depth >= scope[-1][2]:
            scope[-1][3] = True
        while scope and scope[-1][3] and depth < scope[-1][2]:
            scope.pop()
    return api


def required(api):
    """Every name a reader must find in api.md."""
    names = set(api.objects) | set(api.records) | set(api.enums) | set(api.sealed)
    for o in api.objects.values():
        names |= {m[0] for m in o["methods"]} | {c[0] for c in o["ctors"] if c[0] != "constructor"}
    names |= {f[0] for f in api.functions}
    return names - {"uniffiEnsureInitialized"}


def documented(text, name):
    return re.search(r"`[^`\n]*\b" + re.escape(name) + r"\b[^`\n]*`", text) is not None


def reference(api):
    out = [START, "", "## Reference (generated from the bindings' doc comments)", "",
           "Generated by `python3 docs/check-api.py tests/src/main/generated/kotlin/io/stridekit/stridekit.kt --write`",
           "after `scripts/test`; Kotlin names (Swift: the same in Swift's style). Sizes of packed",
           "records and units are in the doc sentences and in the sections above.", ""]
    out += ["### Objects", ""]
    for name in sorted(api.objects):
        o = api.objects[name]
        out += [f"#### `{name}`", "", o["doc"], "", "| member | what |", "|---|---|"]
        for n, sig, d in o["ctors"]:
            label = f"`{name}{sig}`" if n == "constructor" else f"`{name}.{n}{sig}`"
            out.append(f"| {label} | {d} |")
        for n, sig, d in sorted(o["methods"]):
            out.append(f"| `{n}{sig}` | {d} |")
        out += ["", ]
    out += ["### Records", "", "| record | fields | what |", "|---|---|---|"]
    for name in sorted(api.records):
        fields, d = api.records[name]
        note = TESTING_NOTE if name in TESTING else ""
        out.append(f"| `{name}` | {', '.join(f'`{f}`' for f in fields)} | {d}{note} |")
    out += ["", "### Enums and sealed classes", "", "| type | values | what |", "|---|---|---|"]
    for name in sorted(set(api.enums) | set(api.sealed)):
        values, d = api.enums.get(name) or api.sealed.get(name)
        out.append(f"| `{name}` | {', '.join(f'`{v}`' for v in values)} | {d} |")
    out += ["", "### Functions", "", "| function | what |", "|---|---|"]
    for n, sig, d in sorted(api.functions):
        if n != "uniffiEnsureInitialized":
            note = TESTING_NOTE if n in TESTING else ""
            out.append(f"| `{n}{sig}` | {d}{note} |")
    out += ["", END]
    return "\n".join(out)


def main(argv):
    if not argv or argv[0].startswith("-"):
        print(__doc__.strip(), file=sys.stderr)
        return 2
    api = parse(argv[0])
    if len(api.objects) < 5 or len(api.records) < 20:
        print(f"error: {argv[0]}: found {len(api.objects)} objects, {len(api.records)} records: "
              "not the generated bindings, or their layout changed (fix docs/check-api.py)", file=sys.stderr)
        return 1
    text = API_MD.read_text(encoding="utf-8")
    if "--write" in argv[1:]:
        section = reference(api)
        if START in text:
            head, rest = text.split(START, 1)
            text = head + section + rest.split(END, 1)[1]
        else:
            text = text.rstrip("\n") + "\n\n" + section + "\n"
        API_MD.write_text(text, encoding="utf-8")
        print(f"wrote the reference section of {API_MD}")
    missing = sorted(n for n in required(api) if not documented(text, n))
    if missing:
        print(f"error: docs/api.md does not mention {len(missing)} public name(s) of the bindings: "
              + ", ".join(missing), file=sys.stderr)
        print("  document them, or run: python3 docs/check-api.py " + argv[0] + " --write", file=sys.stderr)
        return 1
    n = len(required(api))
    print(f"docs/api.md covers all {n} public names ({len(api.objects)} objects, {len(api.records)} records, "
          f"{len(api.enums) + len(api.sealed)} enums/sealed classes, {len(api.functions)} functions)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
