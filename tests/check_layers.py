#!/usr/bin/env python3
"""The architecture's rules, checked on the #include lines of src/ and tools/.

1. The libraries are layers: base <- geom <- fracture <- runtime <- bullet.
   A library file includes its own layer's headers and those below, never
   an upper layer's, nor a program's.
2. A program (src/shared, src/scenes, src/tools, src/bench, src/game, the
   texture generator in tools/) includes the libraries' public headers only
   (<breakables/*.h>), never a header under src/lib/.
3. No circle among the modules of a folder: a module is a file's stem
   (game.c and game.h are the module "game"), and module A depends on B
   when a file of A includes B's header or A's source calls a function
   B's source defines (not static), as through a header the folder shares.
4. The libraries' C code allocates through the allocator of
   <breakables/base.h> (bk_alloc, bk_free, ...): no malloc, calloc,
   realloc, free or strdup outside src/lib/base/alloc.c.

Known exceptions are listed in tests/layer_allowlist.txt, one a line:
"circle <folder>: <modules>", "include <file> -> <header>" (an include
rules 1 and 2 refuse) or "call <file>: <function>" (rule 4). One not listed fails, and so does a listed one that
is gone (delete its line then); an empty list is the goal.

Usage: check_layers.py [source dir] (default: this file's project).
Prints one line per problem and exits 1 if any, else prints a summary.
"""
import os
import re
import sys

LAYERS = ["base", "geom", "fracture", "runtime", "bullet"]
SOURCE_EXTENSIONS = (".c", ".h", ".cpp", ".hpp")
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')
DIRECT_ALLOCATION = re.compile(r"(?<![\w.>])(malloc|calloc|realloc|free|strdup|strndup|aligned_alloc|posix_memalign)\s*\(")
ALLOCATOR = os.path.join("src", "lib", "base", "alloc.c")


def source_files(root):
    """Every C/C++ file of src/ and tools/, as paths relative to root."""
    found = []
    for top in ("src", "tools"):
        for folder, _, names in os.walk(os.path.join(root, top)):
            for name in names:
                if name.endswith(SOURCE_EXTENSIONS):
                    found.append(os.path.relpath(os.path.join(folder, name), root))
    return sorted(found)


def quoted_includes(root, path):
    """(line number, name) of each #include "name" of a file."""
    with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
        return [(n, m.group(1)) for n, line in enumerate(f, 1) for m in [INCLUDE.match(line)] if m]


def layer_of(path):
    """A library file's layer index, or None for a program's file."""
    parts = path.split(os.sep)
    if len(parts) > 3 and parts[0] == "src" and parts[1] == "lib" and parts[2] in LAYERS:
        return LAYERS.index(parts[2])
    return None


def resolve(path, name, by_name):
    """The file an include names: beside the includer first (as the compiler
    looks), else the one file of that name in the tree; None for a name not
    in the tree (a system or third-party header)."""
    beside = os.path.normpath(os.path.join(os.path.dirname(path), name))
    if beside in by_name.get(os.path.basename(name), []):
        return beside
    candidates = [c for c in by_name.get(os.path.basename(name), []) if c.endswith(os.path.normpath(name))]
    return candidates[0] if len(candidates) == 1 else None


STRIPPED = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S)
IDENTIFIER = re.compile(r"[A-Za-z_]\w*")
DEFINITION = re.compile(r"\b([A-Za-z_]\w*)\s*\([^;{}]*\)\s*$", re.S)


def code_of(root, path):
    """A file's text without comments, strings and preprocessor lines."""
    def blank(m):  # keeps the line breaks, so line numbers stay right
        return " " + "\n" * m.group(0).count("\n")

    with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
        text = STRIPPED.sub(blank, f.read())
    return re.sub(r"^\s*#.*?(?<!\\)$", blank, text, flags=re.M | re.S)


def defined_functions(code):
    """Names of the functions a source file defines that other files can call
    (top-level definitions not declared static)."""
    names, depth, start = set(), 0, 0
    for i, c in enumerate(code):
        if c == "{":
            if depth == 0:
                head = code[start:i]
                m = DEFINITION.search(head)
                if m and not re.search(r"\b(static|typedef|struct|enum|union)\b", head[: m.start()]) and "=" not in head:
                    names.add(m.group(1))
            depth += 1
        elif c == "}":
            depth = max(0, depth - 1)
            if depth == 0:
                start = i + 1
        elif c == ";" and depth == 0:
            start = i + 1
    return names


def module_of(path):
    return os.path.splitext(os.path.basename(path))[0]


def circles(edges):
    """Strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(edges.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(tuple(sorted(component)))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return found


def read_allowlist(path):
    """{entry: line number}: ("circle", folder, modules) or ("include", file, header)."""
    allowed = {}
    if not os.path.exists(path):
        return allowed
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            line = line.split("#", 1)[0].strip()
            kind, _, rest = line.partition(" ")
            if kind == "circle":
                folder, _, modules = rest.partition(":")
                allowed[("circle", folder.strip(), tuple(sorted(modules.split())))] = n
            elif kind == "call":
                source, _, function = rest.partition(":")
                allowed[("call", source.strip(), function.strip())] = n
            elif kind == "include":
                source, _, header = rest.partition("->")
                allowed[("include", source.strip(), header.strip())] = n
            elif line:
                allowed[("unknown", line, "")] = n
    return allowed


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    files = source_files(root)
    by_name = {}
    for f in files:
        by_name.setdefault(os.path.basename(f), []).append(f)
    found = {}  # entry -> its problem, before the allowlist
    includes = 0
    folder_edges = {}  # folder -> module -> set of modules
    for path in files:
        layer = layer_of(path)
        for line, name in quoted_includes(root, path):
            target = resolve(path, name, by_name)
            if target is None:
                continue
            includes += 1
            target_layer = layer_of(target)
            why = None
            if layer is not None:
                if target_layer is None:
                    why = "a library includes a program's header"
                elif target_layer > layer:
                    why = f"{LAYERS[layer]} includes the upper layer {LAYERS[target_layer]}"
            elif target.startswith(os.path.join("src", "lib") + os.sep):
                why = "a program includes a library's private header (use <breakables/*.h>)"
            if why:
                found[("include", path, target)] = f"{path}:{line}: includes {target}: {why}"
            if os.path.dirname(target) == os.path.dirname(path) and module_of(target) != module_of(path):
                edges = folder_edges.setdefault(os.path.dirname(path), {})
                edges.setdefault(module_of(path), set()).add(module_of(target))
    # Calls between the sources of a folder (through any header).
    sources = [f for f in files if f.endswith((".c", ".cpp"))]
    code = {f: code_of(root, f) for f in sources}
    definer = {}  # (folder, function) -> module
    for f in sources:
        for name in defined_functions(code[f]):
            definer[(os.path.dirname(f), name)] = module_of(f)
    for f in sources:
        folder = os.path.dirname(f)
        for name in set(IDENTIFIER.findall(code[f])):
            callee = definer.get((folder, name))
            if callee is not None and callee != module_of(f):
                folder_edges.setdefault(folder, {}).setdefault(module_of(f), set()).add(callee)
    for f in files:
        if layer_of(f) is not None and f.endswith((".c", ".h")) and f != ALLOCATOR:
            for n, line in enumerate(code_of(root, f).split("\n"), 1):
                for m in DIRECT_ALLOCATION.finditer(line):
                    key = ("call", f, m.group(1))
                    where = found[key].split(": calls")[0] + f",{n}" if key in found else f"{f}:{n}"
                    found[key] = f"{where}: calls {m.group(1)} (allocate with base.h's bk_alloc, bk_realloc, bk_free)"
    for folder in sorted(folder_edges):
        for circle in circles(folder_edges[folder]):
            found[("circle", folder, circle)] = f"{folder}: circle among {', '.join(circle)}"
    allowed = read_allowlist(os.path.join(root, "tests", "layer_allowlist.txt"))
    problems = [text for entry, text in found.items() if entry not in allowed]
    for entry, n in sorted(allowed.items(), key=lambda item: item[1]):
        if entry[0] == "unknown":
            problems.append(f"tests/layer_allowlist.txt:{n}: not \"circle <folder>: <modules>\", "
                            f"\"include <file> -> <header>\" nor \"call <file>: <function>\": {entry[1]}")
        elif entry not in found:
            detail = " ".join(entry[2]) if entry[0] == "circle" else entry[2]
            problems.append(f"tests/layer_allowlist.txt:{n}: {entry[0]} {entry[1]}: {detail} is gone: delete the line")
    for p in problems:
        print(p)
    if problems:
        return 1
    print(f"check_layers: {len(files)} files, {includes} includes of the tree: nothing but the "
          f"{len(allowed)} allowlisted exception(s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
