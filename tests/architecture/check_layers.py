#!/usr/bin/env python3
"""The house's layer rule, checked on every #include of the production code.

The rule is written once, in docs/architecture.md, as a fenced block marked `layers`; this program
reads it from there, so the document and the check cannot disagree. Each line of the block is

    <area>: <areas it may include> | <third-party libraries it may include>

where an area is a folder of src/ (its public headers are include/hrgbench/<area>/) or a driver
(drivers/<name>), `*` means any, and the C++ standard library is always allowed. POSIX and Linux
headers are the library `posix`. A file may include its own area's private headers ("<area>/x.hpp"
from src/, or a file beside it); nobody else may, and a public header may include no private one.

Usage: check_layers.py [--root DIR] [--rules FILE]   (exit 0: clean; 1: violations, one per line;
2: the rule block or the tree cannot be read)
"""
import argparse
import os
import re
import sys

SOURCE_EXT = (".cpp", ".hpp", ".h", ".cc")
INCLUDE_RE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)
# Headers of the C and C++ standard libraries (the ones without a path).
STD_HEADERS = set(
    """algorithm any array atomic barrier bit bitset cassert cctype cerrno cfenv cfloat charconv
    chrono cinttypes climits clocale cmath codecvt compare complex concepts condition_variable
    coroutine csetjmp csignal cstdarg cstddef cstdint cstdio cstdlib cstring ctime cuchar cwchar
    cwctype deque exception execution expected filesystem format forward_list fstream functional
    future initializer_list iomanip ios iosfwd iostream istream iterator latch limits list locale
    map memory memory_resource mutex new numbers numeric optional ostream queue random ranges ratio
    regex scoped_allocator semaphore set shared_mutex source_location span sstream stack stdexcept
    stop_token streambuf string string_view syncstream system_error thread tuple type_traits
    typeindex typeinfo unordered_map unordered_set utility valarray variant vector version
    assert.h limits.h math.h stddef.h stdint.h stdio.h stdlib.h string.h errno.h""".split())
POSIX_PREFIXES = ("sys/", "linux/", "net/", "netinet/", "arpa/")
POSIX_HEADERS = {"unistd.h", "fcntl.h", "poll.h", "signal.h", "spawn.h", "sched.h", "pthread.h",
                 "netdb.h", "time.h", "dirent.h", "termios.h", "pwd.h", "grp.h"}
# The C library's own extensions (glibc): mallopt for the programs' allocator policy.
GLIBC_HEADERS = {"malloc.h"}
# Third-party libraries by the first component of the include, or the whole name.
LIBRARIES = {"Eigen": "Eigen", "unsupported": "Eigen", "nlohmann": "nlohmann", "toml++": "toml++",
             "CLI": "CLI11", "spdlog": "spdlog", "httplib.h": "httplib", "modbus.h": "modbus",
             "modbus": "modbus", "sqlite3.h": "sqlite3", "libpq-fe.h": "libpq", "gtest": "gtest"}


def read_rules(path):
    text = open(path, encoding="utf-8").read()
    m = re.search(r"^```layers\n(.*?)^```", text, re.M | re.S)
    if not m:
        raise ValueError(f"{path}: no ```layers block")
    rules = {}
    for number, line in enumerate(m.group(1).splitlines(), 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        area, sep, rest = line.partition(":")
        areas, bar, libs = rest.partition("|")
        if not sep or not bar:
            raise ValueError(f"{path}: layers line {number}: '{line}': want 'area: areas | libraries'")
        rules[area.strip()] = (set(areas.split()), set(libs.split()))
    return rules


def area_of(rel):
    """The area a repository path belongs to, or None outside the production code."""
    parts = rel.split("/")
    if parts[0] == "src" and len(parts) > 2:
        return parts[1]
    if parts[0] == "include" and len(parts) > 3 and parts[1] == "hrgbench":
        return parts[2]
    if parts[0] == "drivers" and len(parts) > 2:
        return "drivers/" + parts[1]
    return None


def classify(root, rel, kind, target):
    """(what, name): ('area', a) public header, ('private', a), ('library', lib), ('std', ''),
    or ('unknown', target)."""
    here = os.path.dirname(rel)
    if kind == '"':
        if os.path.isfile(os.path.join(root, here, target)):
            resolved = os.path.normpath(os.path.join(here, target))
            area = area_of(resolved)
            return ("private" if resolved.startswith(("src/", "drivers/")) else "area", area)
        if target.startswith("hrgbench/") and os.path.isfile(os.path.join(root, "include", target)):
            return ("area", target.split("/")[1])
        first = target.split("/")[0]
        if os.path.isfile(os.path.join(root, "drivers", target)):
            return ("area", "drivers/" + first)
        if os.path.isfile(os.path.join(root, "src", target)):
            return ("private", first)
        return ("unknown", target)
    if target in STD_HEADERS:
        return ("std", "")
    if target in POSIX_HEADERS or target in GLIBC_HEADERS or target.startswith(POSIX_PREFIXES):
        return ("library", "posix")
    first = target.split("/")[0]
    if first in LIBRARIES:
        return ("library", LIBRARIES[first])
    return ("unknown", target)


def check(root, rules):
    problems = []
    for top in ("src", "include", "drivers"):
        for dirpath, _, files in os.walk(os.path.join(root, top)):
            for name in sorted(files):
                if not name.endswith(SOURCE_EXT):
                    continue
                path = os.path.join(dirpath, name)
                rel = os.path.relpath(path, root)
                area = area_of(rel)
                if area is None:
                    problems.append(f"{rel}: outside every area of the rule")
                    continue
                if area not in rules:
                    problems.append(f"{rel}: area '{area}' has no line in the rule")
                    continue
                may_areas, may_libs = rules[area]
                is_public = rel.startswith("include/")
                text = open(path, encoding="utf-8", errors="replace").read()
                for m in INCLUDE_RE.finditer(text):
                    line = text.count("\n", 0, m.start()) + 1
                    what, other = classify(root, rel, m.group(1), m.group(2))
                    closing = ">" if m.group(1) == "<" else '"'
                    where = f"{rel}:{line}: #include {m.group(1)}{m.group(2)}{closing}"
                    if what == "std":
                        continue
                    if what == "unknown":
                        problems.append(f"{where}: not a header of this tree, the standard "
                                        "library or a known library")
                    elif what == "private":
                        if other != area or is_public:
                            problems.append(f"{where}: a private header of '{other}'")
                    elif what == "area":
                        if other != area and "*" not in may_areas and other not in may_areas:
                            problems.append(f"{where}: '{area}' may not depend on '{other}'")
                    elif what == "library":
                        if "*" not in may_libs and other not in may_libs:
                            problems.append(f"{where}: '{area}' may not use {other}")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    here = os.path.dirname(os.path.abspath(__file__))
    parser.add_argument("--root", default=os.path.normpath(os.path.join(here, "..", "..")))
    parser.add_argument("--rules", help="default: ROOT/docs/architecture.md")
    args = parser.parse_args()
    try:
        rules = read_rules(args.rules or os.path.join(args.root, "docs", "architecture.md"))
    except (OSError, ValueError) as error:
        print(f"check_layers: {error}", file=sys.stderr)
        return 2
    problems = check(args.root, rules)
    for p in problems:
        print(p)
    print(f"check_layers: {len(problems)} violation(s) of the layer rule", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
