#!/usr/bin/env python3
"""The layering of docs/DESIGN.md ("The map"), checked on every #include of the sources.

Each folder may include only the folders its rule names (its own always). core is pure: no
threads, files, LCM or TBB. Prints one line per include that breaks a rule, and the count;
exits 1 when there is any. `--self-test` shows that a breach is caught.
Usage: check_layering.py ROOT [--self-test]
"""
import pathlib
import re
import sys

# Folder -> the project folders it may include (besides itself). The longest folder that holds a
# file is its folder: io/sources/openni2 is io/sources.
ALLOWED = {
    "core": [],
    "attention": ["core"],
    "io/base": ["core"],
    "io/formats": ["core", "io/base"],
    "io/config": ["core", "io/base"],
    "io/sources": ["core", "io/base", "io/formats", "io/config"],
    "io/lcm": ["core", "io/base"],
    "io/viewer": ["core", "io/base", "io/lcm"],
    "io/ros2": ["core", "io/base", "io/lcm"],
    "daemon": ["core", "attention", "io"],
}
# System headers a folder must not include: core does no I/O, threads, LCM or TBB; only the LCM
# folders (and what wires them: daemon) speak LCM.
FORBIDDEN_SYSTEM = {
    "core": r"<(thread|fstream|filesystem|iostream|future|lcm/|tbb/|saccade/|oneapi/)",
    "attention": r"<(thread|fstream|filesystem|iostream|future|lcm/|tbb/|saccade/|oneapi/)",
    "io/base": r"<(lcm/|saccade/)",
    "io/formats": r"<(lcm/|saccade/)",
    "io/config": r"<(lcm/|saccade/)",
    "io/sources": r"<(lcm/|saccade/)",
}
INCLUDE = re.compile(r'^\s*#\s*include\s+([<"][^>"]+[>"])', re.M)
SOURCE_SUFFIXES = {".h", ".cc", ".hpp", ".cpp"}


def folder_of(path):
    """The rule's folder of a project path ("io/lcm/bus.h" -> "io/lcm"), or None."""
    best = None
    for f in ALLOWED:
        if path == f or path.startswith(f + "/"):
            if best is None or len(f) > len(best):
                best = f
    return best


def breaches(rel, text):
    """(include, why) for every include of file `rel` (a path under the root) that breaks a rule."""
    own = folder_of(rel)
    if own is None:
        return []
    out = []
    for inc in INCLUDE.findall(text):
        name = inc[1:-1]
        if inc.startswith('"'):
            target = folder_of(name)
            if target is None or target == own:
                continue
            if not any(target == a or target.startswith(a + "/") for a in ALLOWED[own]):
                out.append((inc, f"{own} may not include {target}"))
        elif own in FORBIDDEN_SYSTEM and re.match(FORBIDDEN_SYSTEM[own], inc):
            out.append((inc, f"{own} may not include {inc}"))
    return out


def check(root):
    found = 0
    for path in sorted(root.rglob("*")):
        if path.suffix not in SOURCE_SUFFIXES or not path.is_file():
            continue
        rel = path.relative_to(root).as_posix()
        for inc, why in breaches(rel, path.read_text(errors="replace")):
            print(f"{rel}: #include {inc}: {why}")
            found += 1
    return found


def self_test():
    cases = [
        ("io/formats/x.cc", '#include "io/lcm/bus.h"\n', 1),      # formats -> lcm
        ("io/viewer/x.cc", '#include "io/sources/frame_source.h"\n', 1),  # viewer -> sources
        ("io/lcm/x.cc", '#include "io/viewer/viewer.h"\n', 1),     # upward
        ("core/x.cc", '#include "io/base/log.h"\n#include <thread>\n', 2),
        ("io/sources/openni2/x.cc", '#include "io/formats/images.h"\n', 0),
        ("daemon/x.cc", '#include "io/lcm/bus.h"\n#include <lcm/lcm-cpp.hpp>\n', 0),
    ]
    bad = [c for c in cases if len(breaches(c[0], c[1])) != c[2]]
    for c in bad:
        print(f"self-test: {c[0]} with {c[1]!r}: expected {c[2]} breach(es), got "
              f"{len(breaches(c[0], c[1]))}")
    return len(bad)


def main():
    if len(sys.argv) < 2:
        print(__doc__.strip().splitlines()[-1])
        return 2
    if self_test():
        return 1
    root = pathlib.Path(sys.argv[1])
    if not (root / "core").is_dir():
        print(f"{root}: not Saccade's source folder (no core/)")
        return 2
    found = check(root)
    print(f"layering: {found} include(s) against docs/DESIGN.md's map")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
