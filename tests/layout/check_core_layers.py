#!/usr/bin/env python3
"""The include rule of core/ (core/README.md): each folder is a layer, listed lowest first in
core/CMakeLists.txt's CORE_LAYERS, and a file may include only headers of its own layer or a
lower one, named by folder ("plans/planned_cage.h"). Nothing in core/ includes the renderer, the
plugins, the editor or the Python module (those are not on the core library's include path, so
such an include names no core header and is reported too).

Usage: check_core_layers.py REPO_ROOT      exit 0 when the rule holds, 1 with each violation
       check_core_layers.py --self-test    checks that violations are found, on a made-up tree
"""
import os
import re
import sys
import tempfile

INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.MULTILINE)
LAYERS = re.compile(r'set\(CORE_LAYERS([^)]*)\)')


def layers_of(core):
    with open(os.path.join(core, "CMakeLists.txt"), encoding="utf-8") as f:
        found = LAYERS.search(f.read())
    if not found:
        raise SystemExit("core/CMakeLists.txt has no set(CORE_LAYERS ...)")
    return found.group(1).split()


def violations(root):
    core = os.path.join(root, "core")
    layers = layers_of(core)
    rank = {name: i for i, name in enumerate(layers)}
    found = []
    for entry in sorted(os.listdir(core)):
        path = os.path.join(core, entry)
        if os.path.isfile(path):
            if entry not in ("CMakeLists.txt", "README.md"):
                found.append(f"core/{entry}: every source file belongs in a layer folder")
        elif entry not in rank:
            found.append(f"core/{entry}/: not a layer in CORE_LAYERS")
    for layer in layers:
        folder = os.path.join(core, layer)
        if not os.path.isfile(os.path.join(folder, "README.md")):
            found.append(f"core/{layer}/: no README.md saying what it holds and may include")
        if not os.path.isdir(folder):
            continue
        for name in sorted(os.listdir(folder)):
            if not name.endswith((".h", ".cpp")):
                continue
            with open(os.path.join(folder, name), encoding="utf-8") as f:
                text = f.read()
            for header in INCLUDE.findall(text):
                where = f"core/{layer}/{name}: #include \"{header}\""
                parts = header.split("/")
                if len(parts) != 2 or parts[0] not in rank:
                    found.append(f"{where}: core includes core headers only, by layer folder")
                elif not os.path.isfile(os.path.join(core, header)):
                    found.append(f"{where}: no such core header")
                elif rank[parts[0]] > rank[layer]:
                    found.append(f"{where}: {parts[0]}/ is above {layer}/")
    return found


def self_test():
    with tempfile.TemporaryDirectory() as root:
        def write(path, text):
            os.makedirs(os.path.dirname(os.path.join(root, path)), exist_ok=True)
            with open(os.path.join(root, path), "w", encoding="utf-8") as f:
                f.write(text)
        write("core/CMakeLists.txt", "set(CORE_LAYERS low high)\n")
        write("core/low/README.md", "")
        write("core/high/README.md", "")
        write("core/low/a.h", '#include "low/b.h"\n')
        write("core/low/b.h", "")
        write("core/high/c.cpp", '#include "low/a.h"\n#include "high/c.h"\n')
        write("core/high/c.h", "")
        assert violations(root) == [], violations(root)
        write("core/low/b.cpp", '#include "high/c.h"\n')          # upward
        write("core/low/d.cpp", '#include "a.h"\n')               # bare name
        write("core/low/e.cpp", '#include "plan_pass.h"\n')       # the renderer
        write("core/high/f.cpp", '#include "low/missing.h"\n')    # no such header
        write("core/stray.cpp", "")
        os.makedirs(os.path.join(root, "core/unlisted"))
        found = violations(root)
        expected = ["core/stray.cpp", "core/unlisted/", "core/high/f.cpp", "core/low/b.cpp",
                    "core/low/d.cpp", "core/low/e.cpp"]
        for part in expected:
            assert any(v.startswith(part) for v in found), (part, found)
        assert len(found) == len(expected), found
    print("self-test: the checker finds upward, bare, outside and unknown includes, stray files")


if __name__ == "__main__":
    if sys.argv[1:] == ["--self-test"]:
        self_test()
        sys.exit(0)
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    problems = violations(sys.argv[1])
    for problem in problems:
        print(problem)
    if problems:
        sys.exit(1)
    print(f"core/ layers {' < '.join(layers_of(os.path.join(sys.argv[1], 'core')))}: every include goes down or across")
