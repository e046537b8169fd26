#!/usr/bin/env bash
# The dependencies between rasm's module libraries, from CMake's --graphviz: writes
# docs/modules.dot (rasm targets only, sorted, so that it diffs) and, with Graphviz's dot,
# docs/images/modules.svg. --check compares docs/modules.dot with the code instead (the ctest
# module_graph). Configures a scratch build folder (BUILD, default build/graphviz-scratch).
set -euo pipefail
cd "$(dirname "$0")/.."
check=0
scratch=build/graphviz-scratch
for a in "$@"; do
  case $a in --check) check=1 ;; *) scratch=$a ;; esac
done
mkdir -p "$scratch"
cmake -S . -B "$scratch" -DRASM_BUILD_BENCH=OFF --graphviz="$scratch/graph/deps.dot" >/dev/null
/usr/bin/env python3 - "$scratch/graph/deps.dot" "$scratch/modules.dot" <<'PY'
import re, sys
src, dst = sys.argv[1], sys.argv[2]
names, edges = {}, set()
for line in open(src):
    m = re.match(r'\s*"(node\d+)"\s*\[\s*label\s*=\s*"([^"]+)"', line)
    if m:
        names[m.group(1)] = m.group(2)
        continue
    m = re.match(r'\s*"(node\d+)"\s*->\s*"(node\d+)"', line)
    if m:
        edges.add((m.group(1), m.group(2)))
import os
modules = set(os.listdir("modules"))
def module(label):
    # The library of a folder of modules/ (label "rasm_io\\n(rasm::io)"), not its CUDA or
    # helper targets; "app" is the rasm executable with its commands (app/).
    if label in ("rasm", "rasm_app"):  # the executable and its commands' object library
        return "app"
    m = re.match(r'rasm_([a-z_]+)(?:\\n|$)', label)
    return m.group(1) if m and m.group(1) in modules else None
mods = {n: module(l) for n, l in names.items()}
keep = sorted({m for m in mods.values() if m})
deps = sorted({(mods[a], mods[b]) for a, b in edges if mods.get(a) and mods.get(b) and mods[a] != mods[b]})
with open(dst, "w") as f:
    f.write("// rasm module dependencies (scripts/module-graph.sh; an arrow points to what a module links)\n")
    f.write("digraph rasm_modules {\n  rankdir=BT;\n  node [shape=box, fontname=Helvetica];\n")
    for m in keep:
        f.write(f'  "{m}";\n')
    for a, b in deps:
        f.write(f'  "{a}" -> "{b}";\n')
    f.write("}\n")
PY
if [[ $check -eq 1 ]]; then
  if ! diff -u docs/modules.dot "$scratch/modules.dot"; then
    echo "module-graph: docs/modules.dot differs from the code's dependencies; run scripts/module-graph.sh" >&2
    exit 1
  fi
  echo "module-graph: docs/modules.dot matches the code"
  exit 0
fi
cp "$scratch/modules.dot" docs/modules.dot
if command -v dot >/dev/null; then
  dot -Tsvg docs/modules.dot -o docs/images/modules.svg
  echo "module-graph: docs/modules.dot and docs/images/modules.svg written"
else
  echo "module-graph: docs/modules.dot written (no Graphviz dot: apt-get install graphviz for the picture)"
fi
