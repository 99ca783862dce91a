#!/usr/bin/python3
"""The file-level dependency graph of sinew's C sources, and its cycles.

  tools/include_graph.py [ROOT] [--edges] [--quiet] [--self-test]

Reads every .c and .h file under ROOT/models, ROOT/solvers and ROOT/sim (ROOT defaults to the
source tree this script lives in): its `#include "..."` lines, the sw_* functions it defines
and the sw_* functions it calls (or names, as an operations table does) that another file
defines.  A file depends on the headers it includes and on the files whose functions it uses.

Reported:
  - every file-level cycle: a strongly connected set of two or more files of the use graph
    (a file calls into another that, directly or through others, calls back into it);
  - every file of models/ that includes a header of solvers/ or sim/ other than the floor
    headers (FLOOR_HEADERS), or uses a function defined in solvers/ or sim/ other than the
    floor's (FLOOR_SOURCES).

The layering is one way (docs/architecture.md): sim/cli -> the run loop (sim/sim.c, run.c) with
its readers and writers (sim/input, sim/output) -> solvers/ -> the state and the model
(sim/data.c, model.c) -> models/ -> the floor (sim/util.c).
Exit 0 when no cycle among the files of models/ exists and no models/ file reaches up, 1
otherwise (cycles elsewhere are printed but do not fail), 2 on bad arguments.  --edges prints
every dependency with its reasons; --self-test first checks the checker on small made-up trees
(a clean one, a models/ cycle, a models/ call into sim/, a models/ include of solvers/) and
exits 3 if it misjudges one.

Limits: a plain scanner, not a C parser.  Comments, strings and preprocessor lines other than
#include are dropped first; a function's definition is `name(...) {` at brace depth 0, an
object's (an operations table, a flag) a non-static `... name =`, `name[` or `name;` at depth 0
with one of the prefixes of OBJECT; calls made only from inside macro bodies are not seen;
static functions resolve to their own file first. """
import os
import re
import sys
from collections import defaultdict

ROOMS = ("models", "solvers", "sim")
# The shared helpers (allocation, errors, hashing, the names table) that every room uses.
# They live in sim/ for history; util.h's other declarations are not used below sim/.
FLOOR_HEADERS = {"sim/sinew.h", "sim/util.h"}
FLOOR_SOURCES = {"sim/util.c"}

IDENT = re.compile(r"\b[A-Za-z_]\w*\b")
# Objects other files may name (operations tables, lists, flags) are sought by these prefixes.
OBJECT = re.compile(r"(sw|sc|sy|out)_\w+$")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def strip(text):
    """text without comments, string and character literals and preprocessor lines (each
    replaced by blanks of the same length, newlines kept)."""
    out, i, n = [], 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and c in " \t":
            out.append(c)
            i += 1
            continue
        if line_start and c == "#":  # a preprocessor line, with its continuations
            j = i
            while j < n and (text[j] != "\n" or text[j - 1] == "\\"):
                j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
            continue
        line_start = False
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        else:
            out.append(c)
            if c == "\n":
                line_start = True
            i += 1
    return "".join(out)


def scan(code):
    """(defined, used): the sw_ functions defined in code (name -> static?), and every sw_
    identifier used anywhere else in it."""
    defined, used = {}, set()
    depth, n = 0, len(code)
    depth_at = []  # the brace depth at each character
    for ch in code:
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        depth_at.append(depth)
    for m in IDENT.finditer(code):
        name, s, e = m.group(0), m.start(), m.end()
        j = e
        while j < n and code[j] in " \t\n":
            j += 1
        is_def = False  # at depth 0, `name (...) {`
        if depth_at[s] == 0 and j < n and code[j] == "(":
            k, par = j, 0
            while k < n:
                if code[k] == "(":
                    par += 1
                elif code[k] == ")":
                    par -= 1
                    if par == 0:
                        break
                k += 1
            k += 1
            while k < n and code[k] in " \t\n":
                k += 1
            if k < n and code[k] == "{":
                is_def = True
                line = code.rfind("\n", 0, s) + 1
                defined[name] = bool(re.search(r"\bstatic\b", code[line:s]))
            elif k < n and code[k] in ";,":
                continue  # a prototype
        elif depth_at[s] == 0 and OBJECT.match(name) and j < n and code[j] in "=[;":
            line = code[code.rfind("\n", 0, s) + 1:s]
            if not re.search(r"\b(static|extern|typedef)\b", line) and line.strip():
                defined[name] = False  # an object: an operations table, a flag
                continue
        if not is_def:
            used.add(name)
    return defined, used


def files_of(root):
    for room in ROOMS:
        for base, _, names in os.walk(os.path.join(root, room)):
            for f in sorted(names):
                if f.endswith((".c", ".h")):
                    yield os.path.relpath(os.path.join(base, f), root)


def build(root):
    """(deps, why): file -> files it depends on, and (a, b) -> the reasons (headers, names)."""
    paths = sorted(files_of(root))
    by_base = defaultdict(list)
    for p in paths:
        by_base[os.path.basename(p)].append(p)
    text = {p: open(os.path.join(root, p), encoding="utf-8", errors="replace").read()
            for p in paths}
    defs, uses = {}, {}
    for p in paths:
        defs[p], uses[p] = scan(strip(text[p]))
    extern = defaultdict(set)  # name -> files defining it non-static
    for p in paths:
        for name, static in defs[p].items():
            if not static:
                extern[name].add(p)
    deps, why = defaultdict(set), defaultdict(set)
    for p in paths:
        for inc in INCLUDE.findall(text[p]):
            cands = [q for q in by_base.get(os.path.basename(inc), [])]
            same = [q for q in cands if os.path.dirname(q) == os.path.dirname(p)]
            for q in same or cands[:1]:
                if q != p:
                    deps[p].add(q)
                    why[p, q].add("#include \"%s\"" % inc)
        for name in uses[p]:
            if name in defs[p]:
                continue
            for q in extern.get(name, ()):
                if q != p and q.endswith(".c"):
                    deps[p].add(q)
                    why[p, q].add(name)
    return paths, deps, why


def sccs(nodes, edges):
    """Tarjan's strongly connected components with two or more nodes."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]
    sys.setrecursionlimit(10000)

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in nodes:
        if v not in index:
            visit(v)
    return out


# The made-up trees of --self-test: files and the exit status the check must give.
FIXTURES = [
    ("clean", {"models/a.c": '#include "util.h"\nint sw_a(void) { return sw_b() + sw_u(); }\n',
               "models/b.c": "static int helper(void) { return 1; }\nint sw_b(void) { return helper(); }\n",
               "sim/util.c": "int sw_u(void) { return 0; }\n", "sim/util.h": "int sw_u(void);\n",
               "sim/s.c": "/* sw_s(); */\nint sw_s(void) { return sw_a(); }\n"}, 0),
    ("models cycle", {"models/a.c": "int sw_a(void) { return sw_b(); }\n",
                      "models/b.c": "int sw_b(int k) {\n  return k ? sw_a() : 0;\n}\n"}, 1),
    ("models call up", {"models/a.c": "int sw_a(void) { return sw_interrupted(); }\n",
                        "sim/s.c": "int sw_interrupted(void) { return 0; }\n"}, 1),
    ("models include up", {"models/a.c": '#include "solver.h"\n',
                           "solvers/solver.h": "int sw_x(void);\n"}, 1),
    ("models name a table", {"models/a.c": "int sw_a(void) { return sw_tab.n; }\n",
                             "sim/s.c": "const struct t sw_tab = {1};\n"}, 1),
]


def self_test():
    import tempfile
    bad = 0
    for name, files, want in FIXTURES:
        with tempfile.TemporaryDirectory() as root:
            for room in ROOMS:
                os.makedirs(os.path.join(root, room), exist_ok=True)
            for path, text in files.items():
                os.makedirs(os.path.dirname(os.path.join(root, path)), exist_ok=True)
                with open(os.path.join(root, path), "w", encoding="utf-8") as f:
                    f.write(text)
            got = check(root, set(), out=lambda *a: None)
        if got != want:
            print("self-test %s: exit %d; expected %d" % (name, got, want))
            bad = 1
    return bad


def main(argv):
    args = [a for a in argv if not a.startswith("--")]
    flags = {a for a in argv if a.startswith("--")}
    if flags - {"--edges", "--quiet", "--self-test"} or len(args) > 1:
        print(__doc__, file=sys.stderr)
        return 2
    if "--self-test" in flags and self_test():
        return 3
    root = args[0] if args else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    if not os.path.isdir(os.path.join(root, "models")):
        print("include_graph: %s has no models/ folder" % root, file=sys.stderr)
        return 2
    return check(root, flags)


def check(root, flags, out=print):
    """Print the cycles and upward reaches of the tree at root; 1 when the layering is broken."""
    paths, deps, why = build(root)
    if "--edges" in flags:
        for p in paths:
            for q in sorted(deps[p]):
                out("%s -> %s: %s" % (p, q, ", ".join(sorted(why[p, q]))))
    bad = 0
    # Cycles are sought among the sources (.c) through the functions and objects they use; a
    # header only declares what a source defines.
    src = [p for p in paths if p.endswith(".c")]
    edges = {p: {q for q in deps[p] if q.endswith(".c")} for p in src}
    for comp in sccs(src, edges):
        in_models = [p for p in comp if p.startswith("models/")]
        fails = len(in_models) > 1
        bad |= fails
        out("cycle%s: %s" % (" (models/)" if fails else "", " <-> ".join(comp)))
        for a in comp:
            for b in comp:
                if b in edges[a]:
                    out("  %s -> %s: %s" % (a, b, ", ".join(sorted(why[a, b]))))
    for p in paths:
        if not p.startswith("models/"):
            continue
        for q in sorted(deps[p]):
            if q.startswith("models/") or q in FLOOR_HEADERS or q in FLOOR_SOURCES:
                continue
            bad = 1
            out("models reach up: %s -> %s: %s" % (p, q, ", ".join(sorted(why[p, q]))))
    if "--quiet" not in flags:
        out("%d files; %s" % (len(paths), "layering broken" if bad else
                                "no cycle among models/, no models/ file reaches up"))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
