#!/usr/bin/env python3
"""The layering of DESIGN §2 one level down: which *files* of the crate name which.

`scripts/module-graph.sh` keeps the top-level modules acyclic; inside a module the same rule
holds between its files and between its sub-modules, and a newcomer reading bottom-up must
never meet a file that needs one they have not read yet. This script builds that graph from
the code itself (comments and strings left out: a doc link is not a dependency) and fails
when it has a cycle, so CI holds the order.

What counts as an edge: a path in a `use` (groups `{a, b::{c}}` expanded, `self`, `as`, `*`)
or in code (`crate::a::b::f()`, `super::x`, `self::x`, a child module's name, or a name a
`use` bound to a module), resolved to the longest prefix that is a module with a file of
its own (`a/b.rs`, `a/b/mod.rs`, or a `#[path]`). `mod x;` is not an edge: declaring a child
is how a parent owns it. Edges between a file and the file of one of its ancestor modules are
left out of the cycle search: a parent re-exports its children and a child reads its
parent's shared types, and neither makes the house harder to walk.

Two checks, both by default:
  files   no cycle between files (`config/options.rs -> config/preset.rs -> config/options.rs`);
  levels  for every module with sub-module files (`config`, `multiview::room`, ...), the
          graph between its direct children, each collapsed with its own descendants, is
          acyclic; its edges and a bottom-up order are printed.

Usage: file-graph.py [--files | --levels] [--edges] [--ignore MODULE]...
  --edges          print the file edges the cycle search counts too
  --ignore MODULE  report cycles lying wholly inside MODULE (`multiview`, `multiview::room`)
                   without failing: for a module being reorganised elsewhere.
Exits 1 on a cycle that is not ignored; cycles go to stderr, the rest to stdout.
"""

import os
import re
import sys
from collections import deque

SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src")
LIB_NAME = "holoinject"

IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*|::|[{}();,*#\[\]]|\S")
PATH_ATTR = re.compile(
    r'#\[path\s*=\s*"([^"]+)"\]\s*(?:#\[[^\]]*\]\s*)*(?:pub(?:\([^)]*\))?\s+)?mod\s+(\w+)\s*;'
)


def strip(text):
    """The code with comments, strings and char literals blanked (newlines kept)."""
    out, i, n = [], 0, len(text)

    def blank(a, b):
        out.append("".join(c if c == "\n" else " " for c in text[a:b]))

    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            blank(i, j)
            i = j
        elif text.startswith("/*", i):
            depth, j = 1, i + 2
            while j < n and depth:
                if text.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif text.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            blank(i, j)
            i = j
        elif c in "rb" and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")) and (
            m := re.match(r'b?r(#*)"', text[i:])
        ):
            close = '"' + m.group(1)
            j = text.find(close, i + m.end())
            j = n if j < 0 else j + len(close)
            blank(i, j)
            i = j
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            blank(i, j + 1)
            i = j + 1
        elif c == "'":
            # A char literal ('a', '\n', '\u{..}', '"'), else a lifetime ('a, 'static).
            if i + 1 < n and text[i + 1] == "\\":
                j = text.find("'", i + 2)
                j = n if j < 0 else j + 1
            elif i + 2 < n and text[i + 2] == "'":
                j = i + 3
            else:
                out.append(c)
                i += 1
                continue
            blank(i, j)
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


class Crate:
    """Modules (tuples of names under a crate tag) and the file each one's code is in."""

    def __init__(self):
        self.file_of = {}  # module -> file (inline modules: their file)
        self.own_file = {}  # module -> file, only modules that are a file themselves
        self.module_of_file = {}

    def load(self, tag, root):
        self._load_file((tag,), root, os.path.dirname(root))

    def _load_file(self, module, path, child_dir):
        if not os.path.isfile(path) or path in self.module_of_file:
            return
        self.file_of[module] = path
        self.own_file[module] = path
        self.module_of_file[path] = module
        raw = open(path, encoding="utf-8").read()
        attrs = {m.group(2): m.group(1) for m in PATH_ATTR.finditer(raw)}
        code = strip(raw)
        stack = []  # (name or None, own child dir) per open brace
        toks = TOKEN.findall(code)
        for k, t in enumerate(toks):
            if t == "mod" and k + 2 < len(toks) and IDENT.fullmatch(toks[k + 1]):
                name, after = toks[k + 1], toks[k + 2]
                inner = module + tuple(s[0] for s in stack if s[0])
                base = stack[-1][1] if stack and stack[-1][0] else child_dir
                if after == ";":
                    if name in attrs and not any(s[0] for s in stack):
                        target = os.path.join(os.path.dirname(path), attrs[name])
                        sub = os.path.splitext(target)[0]
                    else:
                        target = os.path.join(base, name + ".rs")
                        if not os.path.isfile(target):
                            target = os.path.join(base, name, "mod.rs")
                        sub = os.path.join(base, name)
                    if os.path.basename(target) == "mod.rs":
                        sub = os.path.dirname(target)
                    self._load_file(inner + (name,), os.path.normpath(target), sub)
                elif after == "{":
                    self.file_of[inner + (name,)] = path
                    stack.append((name, os.path.join(base, name)))
                    continue
            if t == "{":
                if not (k >= 2 and toks[k - 2] == "mod"):
                    stack.append((None, None))
            elif t == "}" and stack:
                stack.pop()

    def resolve_file(self, module):
        """The file of the longest prefix of `module` that is a module."""
        for end in range(len(module), 0, -1):
            if module[:end] in self.file_of:
                return self.file_of[module[:end]]
        return None


def use_leaves(toks, k):
    """The leaves of the `use` tree starting at toks[k]: (segments, kind, alias), and the
    index after its `;`. kind is `name`, `self` or `glob`."""
    leaves = []

    def tree(k, prefix):
        segs = list(prefix)
        while k < len(toks):
            t = toks[k]
            if t == "{":
                k += 1
                while toks[k] != "}":
                    k = tree(k, segs)
                    if toks[k] == ",":
                        k += 1
                return k + 1
            if t == "*":
                leaves.append((segs, "glob", None))
                return k + 1
            if IDENT.fullmatch(t):
                if t == "self" and segs and toks[k + 1] != "::":
                    alias = toks[k + 2] if toks[k + 1] == "as" else None
                    leaves.append((segs, "self", alias))
                    return k + 3 if alias else k + 1
                segs.append(t)
                if toks[k + 1] == "::":
                    k += 2
                    continue
                alias = toks[k + 2] if toks[k + 1] == "as" else None
                leaves.append((segs, "name", alias))
                return k + 3 if alias else k + 1
            return k + 1

    try:
        if toks[k] == "::":  # `use ::std::x`: an external crate
            return [], toks.index(";", k) + 1
        end = tree(k, [])
        return leaves, toks.index(";", end - 1) + 1
    except (IndexError, ValueError):
        return leaves, len(toks)


class Graph:
    def __init__(self, crate):
        self.crate = crate
        self.edges = {f: set() for f in crate.module_of_file}

    def scan(self, path):
        module = self.crate.module_of_file[path]
        toks = TOKEN.findall(strip(open(path, encoding="utf-8").read()))
        scopes, uses, inline = [], [], []  # brace scopes; (scope, leaves); (scope, segments)
        k = 0
        while k < len(toks):
            t = toks[k]
            scope = module + tuple(s for s in scopes if s)
            if t == "mod" and k + 2 < len(toks) and toks[k + 2] == "{":
                scopes.append(toks[k + 1])
                k += 3
                continue
            if t == "{":
                scopes.append(None)
            elif t == "}" and scopes:
                scopes.pop()
            elif t == "use":
                leaves, k = use_leaves(toks, k + 1)
                uses.append((scope, leaves))
                continue
            elif IDENT.fullmatch(t) and k + 1 < len(toks) and toks[k + 1] == "::" and (
                k == 0 or toks[k - 1] != "::"
            ):
                segs, j = [t], k + 1
                while j + 1 < len(toks) and toks[j] == "::" and IDENT.fullmatch(toks[j + 1]):
                    segs.append(toks[j + 1])
                    j += 2
                inline.append((scope, segs))
                k = j
                continue
            k += 1
        # Names a `use` binds to a module, and the modules a scope glob-imports; twice, so
        # that a `use` naming another's binding resolves whatever their order.
        aliases, globs = {}, {}
        for _ in range(2):
            for scope, leaves in uses:
                for segs, kind, alias in leaves:
                    target = self.resolve(scope, segs, aliases, globs)
                    if not target or target not in self.crate.file_of:
                        continue
                    if kind == "glob":
                        globs.setdefault(scope, set()).add(target)
                    else:
                        aliases.setdefault(scope, {})[alias or segs[-1]] = target
        for scope, leaves in uses:
            for segs, _, _ in leaves:
                self.add(path, self.resolve(scope, segs, aliases, globs))
        for scope, segs in inline:
            self.add(path, self.resolve(scope, segs, aliases, globs))

    def in_scope(self, scope, name, aliases, globs, depth=0):
        """The module `name` means in `scope`: a child module, a `use` binding, or either of
        those in a glob-imported module (`use super::*` in a test module)."""
        if scope + (name,) in self.crate.file_of:
            return scope + (name,)
        if name in aliases.get(scope, {}):
            return aliases[scope][name]
        for g in sorted(globs.get(scope, ())) if depth < 2 else ():
            found = self.in_scope(g, name, aliases, globs, depth + 1)
            if found:
                return found
        return None

    def resolve(self, scope, segs, aliases, globs):
        """The absolute module path `segs` names from `scope`, or None (external, local)."""
        if not segs:
            return None
        first, rest = segs[0], segs[1:]
        if first == "crate":
            return scope[:1] + tuple(rest)
        if first == "self":
            return scope + tuple(rest)
        if first == "super":
            up = scope
            while segs and segs[0] == "super":
                up, segs = up[:-1], segs[1:]
            return up + tuple(segs) if len(up) >= 1 else None
        if first == LIB_NAME and scope[0] != "lib":
            return ("lib",) + tuple(rest)
        found = self.in_scope(scope, first, aliases, globs)
        return found + tuple(rest) if found else None

    def add(self, src, module):
        if module is None:
            return
        dst = self.crate.resolve_file(module)
        if dst and dst != src:
            self.edges[src].add(dst)


def related(a, b):
    """Whether one module is the other's ancestor (its file may name it freely)."""
    return a[: len(b)] == b or b[: len(a)] == a


def cycles(nodes, edges):
    """One cycle per edge lying on a cycle (the shortest back), rotated and deduplicated."""
    found = set()
    for u in sorted(nodes):
        for v in sorted(edges.get(u, ())):
            prev, queue = {v: None}, deque([v])
            while queue and u not in prev:
                x = queue.popleft()
                for y in sorted(edges.get(x, ())):
                    if y not in prev:
                        prev[y] = x
                        queue.append(y)
            if u in prev:
                path, x = [], u
                while x is not None:
                    path.append(x)
                    x = prev[x]
                cyc = [u] + path[::-1]
                cyc = cyc[:-1]
                i = cyc.index(min(cyc))
                found.add(tuple(cyc[i:] + cyc[:i]))
    return sorted(found)


def bottom_up(nodes, edges):
    order, done = [], set()

    def visit(n):
        if n in done:
            return
        done.add(n)
        for m in sorted(edges.get(n, ())):
            visit(m)
        order.append(n)

    for n in sorted(nodes):
        visit(n)
    return order


def rel(path):
    return os.path.relpath(path, SRC)


def show(module):
    return "::".join(module[1:]) or module[0]


def load():
    """The crate's files (the library and each `src/bin/NAME.rs`) and what each names."""
    crate = Crate()
    crate.load("lib", os.path.normpath(os.path.join(SRC, "lib.rs")))
    bins = os.path.join(SRC, "bin")
    for name in sorted(os.listdir(bins)) if os.path.isdir(bins) else []:
        if name.endswith(".rs"):
            crate.load("bin:" + name[:-3], os.path.normpath(os.path.join(bins, name)))
    graph = Graph(crate)
    for f in sorted(crate.module_of_file):
        graph.scan(f)
    return crate, graph


def check_files(counted, mod, ignored):
    """Prints the file cycles; whether one is not ignored."""
    failed, skipped = False, 0
    for cyc in cycles(counted, counted):
        line = " -> ".join(rel(f) for f in cyc + (cyc[0],))
        if all(ignored(mod[f]) for f in cyc):
            print(f"ignored file cycle: {line}")
            skipped += 1
        else:
            print(f"file cycle: {line}", file=sys.stderr)
            failed = True
    if not failed:
        print("files: acyclic" + (f" but for {skipped} ignored cycle(s)" if skipped else ""))
    return failed


def child_edges(parent, edges, mod):
    """The edges between `parent`'s direct children, each with its descendants."""
    n, out = len(parent), {}
    for f, targets in edges.items():
        a = mod[f]
        if len(a) <= n or a[:n] != parent:
            continue
        for b in (mod[g] for g in targets):
            if len(b) > n and b[:n] == parent and a[n] != b[n]:
                out.setdefault(a[n], set()).add(b[n])
    return out


def check_levels(crate, edges, ignored):
    """Prints every level's edges and order, or its cycles; whether one is not ignored."""
    mod, failed = crate.module_of_file, False
    # Every module with sub-module files but the library's root: the top level is
    # `scripts/module-graph.sh`'s.
    parents = sorted({m[:-1] for m in crate.own_file if len(m) > 1 and m[:-1] != ("lib",)})
    for parent in parents:
        nodes = {m[len(parent)] for m in crate.own_file if len(m) > len(parent) and m[: len(parent)] == parent}
        level = child_edges(parent, edges, mod)
        name = show(parent)
        for a in sorted(level):
            for b in sorted(level[a]):
                print(f"{name}: {a} -> {b}")
        found = cycles(nodes, level)
        for cyc in found:
            line = f"{name}: child cycle: " + " -> ".join(cyc + (cyc[0],))
            if ignored(parent):
                print(f"ignored {line}")
            else:
                print(line, file=sys.stderr)
                failed = True
        if not found:
            print(f"{name}: acyclic; bottom-up order: " + " ".join(bottom_up(nodes, level)))
    return failed


def main(argv):
    do_files, do_levels, show_edges, ignore = True, True, False, []
    args = iter(argv)
    for a in args:
        if a == "--files":
            do_levels = False
        elif a == "--levels":
            do_files = False
        elif a == "--edges":
            show_edges = True
        elif a in ("-h", "--help"):
            print(__doc__)
            return 0
        elif a == "--ignore":
            ignore.append(tuple(re.split(r"::|/", next(args, "").strip("/"))))
        else:
            print(__doc__.split("\n\n")[-1], file=sys.stderr)
            return 2
    crate, graph = load()
    mod = crate.module_of_file

    def ignored(module):
        return module[0] == "lib" and any(module[1 : 1 + len(p)] == p for p in ignore)

    counted = {f: {g for g in graph.edges[f] if not related(mod[f], mod[g])} for f in graph.edges}
    if show_edges:
        for f in sorted(counted):
            for g in sorted(counted[f]):
                print(f"{rel(f)} -> {rel(g)}")
    failed = do_files and check_files(counted, mod, ignored)
    failed = (do_levels and check_levels(crate, graph.edges, ignored)) or failed
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
