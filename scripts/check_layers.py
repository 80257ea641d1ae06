#!/usr/bin/env python3
"""scripts/check_layers.py: the include rules of docs/architecture.md ("Who may include whom").

Reads every C, C++ and OpenCL source of the tree (host/, include/, kernels/, tests/, bench/,
python/src/), resolves each #include to the folder it reaches and fails, printing
`file:line: rule`, when an include crosses a boundary the architecture forbids:

- each folder includes only the folders below it (the table RULES, the doc's diagram written
  out folder by folder); host/gpu never includes host/dynamics;
- host/world/world_state.h, the world's state, is included by host/world alone;
- a kernel header (include/rubble/shared) or a kernel (kernels/) includes only the shared
  headers, and no system header outside cl_compat.h's host branch;
- the public API (include/rubble) includes no host code;
- OpenCL's headers are included in host/gpu alone, OpenGL's in host/viewer alone (the folder a
  file lives in says which stage it belongs to);
- every host folder of the tree is in the doc's folder list and in RULES, and the other way.

usage: scripts/check_layers.py [--root DIR]      check the tree at DIR (default: this checkout)
       scripts/check_layers.py --self-test       plant one violation of each rule in a copy of
                                                 the tree and check that each one fails
Exit status: 0 clean, 1 a rule is broken, 2 bad usage or a self-test failure.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

DOC = "docs/architecture.md"
WHERE = "(%s, Who may include whom)" % DOC

SOURCE_ROOTS = ["host", "include", "kernels", "tests", "bench", "python/src"]
SOURCE_SUFFIXES = (".h", ".hpp", ".c", ".cc", ".cpp", ".cl", ".inc")

PUBLIC = "include/rubble"
SHARED = "include/rubble/shared"
API = {PUBLIC, SHARED}
CORE = "host/core"

# Which folders each folder's files may include (besides its own folder), as the doc's diagram
# says: include/rubble <- host/core <- host/geometry <- host/collision <- host/dynamics, with
# host/scene on host/geometry; host/gpu on host/core and host/collision (and what is below it),
# never host/dynamics; host/io on the public API and host/core's helpers; host/world on all of
# them; host/tools (the tables of `rubble compare` and `rubble solvers`) on host/world;
# host/app and host/viewer on the public face, host/core's helpers, host/io and host/gpu (the
# device list); the command runs the viewer. Tests and benchmarks reach any stage, the Python
# bindings only the public API. The world's state header has a rule of its own (below).
RULES = {
    SHARED: set(),
    PUBLIC: {SHARED},
    "kernels": {SHARED},
    CORE: API,
    "host/geometry": API | {CORE},
    "host/collision": API | {CORE, "host/geometry"},
    "host/dynamics": API | {CORE, "host/geometry", "host/collision"},
    "host/scene": API | {CORE, "host/geometry"},
    "host/gpu": API | {CORE, "host/geometry", "host/collision"},
    "host/io": API | {CORE},
    "host/world": API | {CORE, "host/geometry", "host/collision", "host/dynamics",
                         "host/scene", "host/gpu", "host/io"},
    "host/tools": API | {CORE, "host/geometry", "host/collision", "host/dynamics", "host/scene",
                         "host/gpu", "host/io", "host/world"},
    "host/app": API | {CORE, "host/io", "host/gpu", "host/viewer"},
    "host/viewer": API | {CORE, "host/io", "host/gpu"},
    "python/src": API,
    "tests": None,  # any folder, but not the world's state header
    "bench": None,  # any folder (the tests' stage inputs too), but not the world's state header
}

# Why a folder's includes are limited, for the message.
REASONS = {
    "host/gpu": "host/gpu never includes host/dynamics: what the CPU twins and the device share "
                "is in host/core/step_params.h",
    "host/io": "host/io reads the world through the public API only",
    "host/app": "the command sees the world through rubble/world.h",
    "host/viewer": "the viewer sees the world through rubble/world.h",
    "python/src": "the Python bindings wrap the public API",
    PUBLIC: "the public API includes no host code",
    SHARED: "a kernel header includes no host code",
    "kernels": "a kernel includes only the shared headers",
}

WORLD_STATE = "host/world/world_state.h"

# Third-party headers that belong to one folder (and the tests and benchmarks of it).
OWNED_HEADERS = [
    (re.compile(r"^(CL/|OpenCL/|clblast)"), {"host/gpu", "tests", "bench"},
     "OpenCL's headers are host/gpu's (OpenCL context, program cache, buffers, dispatch)"),
    (re.compile(r"^(GL/|GLES|EGL/|epoxy/|GLFW/)"), {"host/viewer", "tests", "bench"},
     "OpenGL's headers are host/viewer's (OpenGL viewer and off-screen renderer)"),
]

# The one shared header with a host branch (#ifndef __OPENCL_C_VERSION__), which may include
# the C++ headers its host types need.
CL_COMPAT = "include/rubble/shared/cl_compat.h"

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def area_of(path):
    """The folder a repository path belongs to for the rules, or None when outside them."""
    parts = path.split("/")
    if path.startswith(SHARED + "/"):
        return SHARED
    if path.startswith(PUBLIC + "/"):
        return PUBLIC if len(parts) == 3 else None
    if parts[0] == "host" and len(parts) >= 3:
        return "host/" + parts[1]
    if parts[0] in ("kernels", "tests", "bench"):
        return parts[0]
    if path.startswith("python/src/"):
        return "python/src"
    return None


def resolve(root, source, name):
    """The repository path an include names, searched as the build does: the including file's
    folder, the root, include/ and tests/; a name found nowhere keeps its own spelling."""
    here = os.path.dirname(source)
    for base in (here, "", "include", "tests"):
        candidate = os.path.normpath(os.path.join(base, name))
        if not candidate.startswith("..") and os.path.isfile(os.path.join(root, candidate)):
            return candidate.replace(os.sep, "/")
    if name.startswith("rubble/"):
        return "include/" + name
    return os.path.normpath(os.path.join(here, name)).replace(os.sep, "/")


def includes(root, path):
    """(line number, delimiter, name) of each #include outside block comments."""
    out = []
    in_comment = False
    with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
        for number, line in enumerate(f, 1):
            if in_comment:
                if "*/" not in line:
                    continue
                line = line.split("*/", 1)[1]
                in_comment = False
            m = INCLUDE.match(line)
            if m:
                out.append((number, m.group(1), m.group(2)))
            elif "/*" in line and "*/" not in line.split("/*", 1)[1]:
                in_comment = True
    return out


def sources(root):
    for top in SOURCE_ROOTS:
        for folder, dirs, files in os.walk(os.path.join(root, top)):
            dirs[:] = sorted(d for d in dirs if not d.startswith(("build", ".")))
            for f in sorted(files):
                if f.endswith(SOURCE_SUFFIXES):
                    yield os.path.relpath(os.path.join(folder, f), root).replace(os.sep, "/")


def check_include(src_area, path, delim, name, target):
    """The broken rule, or None."""
    if delim == "<":
        for pattern, owners, why in OWNED_HEADERS:
            if pattern.match(name) and src_area not in owners:
                return "<%s> outside %s: %s" % (name, ", ".join(sorted(owners)), why)
        if src_area in (SHARED, "kernels") and path != CL_COMPAT:
            return ("<%s>: %s (system headers only in %s's host branch)"
                    % (name, REASONS[src_area], CL_COMPAT))
        return None
    if target == WORLD_STATE and src_area != "host/world":
        return ("%s is included by host/world alone: everything else asks the World through "
                "rubble/world.h %s" % (WORLD_STATE, WHERE))
    dst_area = area_of(target)
    if dst_area is None or dst_area == src_area:
        if src_area in (SHARED, "kernels") and dst_area != SHARED:
            return '"%s": %s %s' % (name, REASONS[src_area], WHERE)
        return None
    allowed = RULES.get(src_area)
    if allowed is None:  # tests and benchmarks
        return None
    if dst_area in allowed:
        return None
    reason = REASONS.get(src_area, "each folder includes only the folders below it")
    may = ", ".join(sorted(allowed)) or "nothing but itself"
    return '%s includes %s ("%s"): %s; %s may include %s %s' % (
        src_area, dst_area, name, reason, src_area, may, WHERE)


def doc_folders(root):
    """The host folders of the doc's folder list (the first code block)."""
    try:
        with open(os.path.join(root, DOC), encoding="utf-8") as f:
            text = f.read()
    except OSError:
        return None
    block = text.split("```", 2)[1] if text.count("```") >= 2 else ""
    return {"host/" + m for m in re.findall(r"^host/(\w+)/", block, re.M)}


def check(root):
    """Every broken rule of the tree at root, as `file:line: rule` lines."""
    problems = []
    tree = {area_of(p) for p in sources(root)} - {None}
    for area in sorted(a for a in tree if a.startswith("host/") and a not in RULES):
        problems.append("%s: a host folder without layering rules: add it to %s's diagram and "
                        "to RULES in scripts/check_layers.py" % (area, DOC))
    documented = doc_folders(root)
    if documented is not None:
        ruled = {a for a in RULES if a.startswith("host/")}
        for area in sorted(ruled - documented):
            problems.append("%s: %s is not in its folder list" % (DOC, area))
        for area in sorted(documented - ruled):
            problems.append("%s: %s has no rules in scripts/check_layers.py" % (DOC, area))
    for path in sources(root):
        src_area = area_of(path)
        if src_area is None:
            continue
        for number, delim, name in includes(root, path):
            if delim == "<" and name.startswith(("host/", "rubble/")):
                delim = '"'  # the project's own header, whichever way it is spelled
            target = resolve(root, path, name) if delim == '"' else name
            rule = check_include(src_area, path, delim, name, target)
            if rule:
                problems.append("%s:%d: %s" % (path, number, rule))
    return problems


# Each planted violation: the file it goes into (a real file of the tree), the line added, and
# a piece of the message that names the broken rule.
PLANTS = [
    ("host/gpu/buffer.cpp", '#include "host/dynamics/pgs.h"', "host/gpu includes host/dynamics"),
    ("host/gpu/buffer.cpp", '#include "../dynamics/pgs.h"', "host/gpu includes host/dynamics"),
    ("host/gpu/buffer.cpp", "#include <host/dynamics/pgs.h>", "host/gpu includes host/dynamics"),
    ("host/app/main.cpp", '#include "host/world/world_state.h"', "by host/world alone"),
    ("tests/unit/pgs_test.cpp", '#include "host/world/world_state.h"', "by host/world alone"),
    ("include/rubble/shared/body.h", '#include "host/core/math.h"', "a kernel header"),
    ("include/rubble/shared/body.h", "#include <vector>", "a kernel header"),
    ("kernels/pgs_sweep.cl", '#include "host/core/limits.h"', "a kernel includes only"),
    ("include/rubble/world.h", '#include "host/core/bodies.h"', "the public API includes"),
    ("host/core/integrate.cpp", '#include "host/dynamics/forces.h"',
     "host/core includes host/dynamics"),
    ("host/geometry/shape.cpp", '#include "host/collision/contact.h"',
     "host/geometry includes host/collision"),
    ("host/io/metrics.cpp", '#include "host/world/cpu_step.h"', "host/io includes host/world"),
    ("host/viewer/camera.cpp", '#include "host/geometry/shape.h"',
     "host/viewer includes host/geometry"),
    ("host/dynamics/pgs.cpp", "#include <CL/cl.h>", "OpenCL's headers"),
    ("python/src/module.cpp", '#include "host/core/math.h"', "Python bindings"),
]


def run_check(root):
    done = subprocess.run([sys.executable, os.path.abspath(__file__), "--root", root],
                          capture_output=True, text=True)
    return done.returncode, done.stdout + done.stderr


def self_test():
    """Copies the tree's sources into a temporary folder, checks the copy passes, then plants
    each violation of PLANTS in turn and checks that the script fails naming the file, the line
    and the rule; a new host folder without rules fails too."""
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    failures = []
    with tempfile.TemporaryDirectory(prefix="check_layers_") as tmp:
        for top in SOURCE_ROOTS:
            shutil.copytree(os.path.join(here, top), os.path.join(tmp, top),
                            ignore=shutil.ignore_patterns("build*", ".*", "*.pyc"))
        os.makedirs(os.path.join(tmp, "docs"))
        shutil.copy(os.path.join(here, DOC), os.path.join(tmp, DOC))
        status, out = run_check(tmp)
        if status != 0:
            failures.append("the copied tree does not pass:\n" + out)
        for path, line, rule in PLANTS:
            target = os.path.join(tmp, path)
            with open(target, encoding="utf-8") as f:
                original = f.read()
            planted = original.count("\n") + 1
            with open(target, "w", encoding="utf-8") as f:
                f.write(original + line + "\n")
            status, out = run_check(tmp)
            with open(target, "w", encoding="utf-8") as f:
                f.write(original)
            where = "%s:%d: " % (path, planted)
            if status != 1 or where not in out or rule not in out:
                failures.append("%s planted in %s: exit %d, expected 1 with '%s...%s':\n%s"
                                % (line, path, status, where, rule, out))
            else:
                print("self-test: %s in %s fails: %s" % (line, path, out.strip().splitlines()[0]))
        os.makedirs(os.path.join(tmp, "host", "extra"))
        with open(os.path.join(tmp, "host", "extra", "extra.cpp"), "w") as f:
            f.write('#include "host/core/math.h"\n')
        status, out = run_check(tmp)
        if status != 1 or "host/extra: a host folder without layering rules" not in out:
            failures.append("a host folder without rules passed: exit %d\n%s" % (status, out))
        else:
            print("self-test: a new folder host/extra fails: %s" % out.strip().splitlines()[0])
    for f in failures:
        print("self-test FAILED: " + f, file=sys.stderr)
    return 2 if failures else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(
        __file__))), help="the checkout to check (default: this one)")
    parser.add_argument("--self-test", action="store_true",
                        help="plant violations in a copy of the tree and check each one fails")
    args = parser.parse_args()
    if args.self_test:
        return self_test()
    if not os.path.isdir(os.path.join(args.root, "host")):
        print("check_layers: %s has no host/ folder" % args.root, file=sys.stderr)
        return 2
    problems = check(args.root)
    for p in problems:
        print(p)
    if problems:
        print("check_layers: %d include(s) cross a boundary of %s" % (len(problems), DOC),
              file=sys.stderr)
        return 1
    print("check_layers: every include of %s keeps %s's layering" % (args.root, DOC))
    return 0


if __name__ == "__main__":
    sys.exit(main())
