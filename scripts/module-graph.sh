#!/usr/bin/env bash
# Prints the dependency edges between the crate's top-level modules (`src/NAME.rs` or
# `src/NAME/`), one `from -> to` per line, as found by `crate::NAME` paths in the code
# (unit tests included: they are part of a module too), then whether the graph has a cycle.
# Exits 1 on a cycle, so CI can hold the layering (DESIGN §2).
set -euo pipefail
cd "$(dirname "$0")/../src"
modules=$(ls | sed -n 's/\.rs$//p; /\./!p' | grep -v -x -e lib -e main -e bin | sort -u)
edges=$(for m in $modules; do
  files=$( { [ -f "$m.rs" ] && echo "$m.rs"; [ -d "$m" ] && find "$m" -name '*.rs'; } || true)
  # `crate::NAME` anywhere, including inside `use crate::{a, b}` groups.
  grep -ohE 'crate::[a-z_]+|crate::\{[^}]*\}' $files \
    | sed -E 's/crate::\{//; s/[{}]//g; s/crate:://' | tr ',' '\n' | sed -E 's/^ *([a-z_]+).*/\1/' \
    | grep -x -F "$modules" | grep -v -x "$m" | sort -u | sed "s/^/$m -> /"
done)
echo "$edges"
python3 - "$edges" <<'PY'
import sys
edges = [l.split(" -> ") for l in sys.argv[1].splitlines() if " -> " in l]
graph = {}
for a, b in edges:
    graph.setdefault(a, set()).add(b)
    graph.setdefault(b, set())
state, order = {}, []
def visit(n, path):
    if state.get(n) == 1:
        cycle = path[path.index(n):] + [n]
        print("module graph has a cycle: " + " -> ".join(cycle), file=sys.stderr)
        sys.exit(1)
    if state.get(n) == 2:
        return
    state[n] = 1
    for m in sorted(graph[n]):
        visit(m, path + [n])
    state[n] = 2
    order.append(n)
for n in sorted(graph):
    visit(n, [])
print("acyclic; bottom-up order: " + " ".join(order))
PY
