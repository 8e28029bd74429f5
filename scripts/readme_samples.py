#!/usr/bin/env python3
"""The README's sample outputs, made by the commands they name.

Prints each sample block as README.md shows it: the command line, then its
--json output cut to the fields worth showing, in the output's order. A run of
fields left out is written "...", and so is the value of a timing field (it
differs from run to run), so a block is the same on every run and machine.

  scripts/readme_samples.py [--exe build/breakables]
      prints the blocks, to paste into README.md;
  scripts/readme_samples.py --exe build/breakables --check README.md
      compares each block with the README's (the fenced block whose first
      line is the same command) and exits 1 naming the first line that
      differs, or a README block that no sample here makes.
"""

import argparse
import json
import subprocess
import sys

# The samples: the command (as the README shows it, run from the repository),
# the fields shown, and which of them are timings (shown as "...").
SAMPLES = [
    {
        "args": ["fracture", "--mesh", "cube", "--pieces", "4096", "--json"],
        "fields": ["mesh", "pieces", "pieces_requested", "pieces_made", "nodes", "max_depth", "ms", "leaf_triangles",
                   "bonds", "watertight", "volume_rel_error", "warnings"],
        "timings": ["ms"],
    },
    {
        "args": ["sim", "--scene", "wall", "--pieces", "1024", "--shots", "1", "--steps", "240", "--json"],
        "fields": ["scene", "pieces", "shots", "steps", "bodies_initial", "bodies_final", "break_events", "bonds_broken",
                   "colliders_initial", "colliders_final", "colliders_naive_final", "fragments_free", "step_ms_median",
                   "step_ms_max", "mass_rel_error", "nan", "pattern", "patterns"],
        "timings": ["step_ms_median", "step_ms_max"],
    },
    {
        "args": ["sim", "--scene", "wall", "--pieces", "64", "--refine", "--shots", "3", "--json"],
        "fields": ["scene", "pieces", "shots", "bodies_final", "bonds_broken", "colliders_final", "fragments_free",
                   "break_ms_max", "refined_leaves", "leaves_final", "refine_ms_p99", "refine_ms_max"],
        "timings": ["break_ms_max", "refine_ms_p99", "refine_ms_max"],
    },
]
# The README's blocks are 120 columns at most; a field is never split.
WIDTH = 120
PROMPT = "$ build/breakables "


def raw_fields(text):
    """The top-level fields of a JSON object as (key, value text as written)."""
    json.loads(text)  # valid JSON, or json's own error
    fields = []
    i = text.index("{") + 1
    n = len(text)
    while True:
        while i < n and text[i] in " \t\r\n,":
            i += 1
        if i >= n or text[i] == "}":
            return fields
        key_end = text.index('"', i + 1)  # our keys have no escapes
        key = text[i + 1:key_end]
        i = text.index(":", key_end) + 1
        while text[i] in " \t\r\n":
            i += 1
        start, depth, in_string = i, 0, False
        while i < n:
            c = text[i]
            if in_string:
                if c == "\\":
                    i += 1
                elif c == '"':
                    in_string = False
            elif c == '"':
                in_string = True
            elif c in "[{":
                depth += 1
            elif c in "]}":
                if depth == 0:
                    break
                depth -= 1
            elif c == "," and depth == 0:
                break
            i += 1
        fields.append((key, text[start:i].strip()))


def sample_block(exe, sample):
    """The lines of one sample's block."""
    try:
        run = subprocess.run([exe] + sample["args"], capture_output=True, text=True, check=False)
    except OSError as e:
        sys.exit(f"readme_samples: cannot run {exe}: {e.strerror}")
    if run.returncode != 0:
        sys.exit(f"readme_samples: '{' '.join(sample['args'])}' failed ({run.returncode}): {run.stderr.strip()}")
    fields = raw_fields(run.stdout)
    keys = [key for key, _ in fields]
    items = []
    previous = -1
    for name in sample["fields"]:
        if name not in keys:
            sys.exit(f"readme_samples: '{' '.join(sample['args'])}' printed no field '{name}'")
        index = keys.index(name)
        if index <= previous:
            sys.exit(f"readme_samples: field '{name}' is listed out of the output's order")
        if index > previous + 1:
            items.append("...")
        value = "..." if name in sample["timings"] else fields[index][1]
        items.append(f'"{name}": {value}')
        previous = index
    if previous < len(fields) - 1:
        items.append("...")
    lines = []
    line = "{"
    for k, item in enumerate(items):
        piece = item + ("," if k < len(items) - 1 else "}")
        if line not in ("{", " ") and len(line) + 1 + len(piece) > WIDTH:
            lines.append(line)
            line = " "
        line += ("" if line in ("{", " ") else " ") + piece
    lines.append(line)
    return [PROMPT + " ".join(sample["args"])] + lines


def readme_blocks(path):
    """The README's fenced blocks that start with a command of ours: {command line: lines}."""
    blocks = {}
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines):
        if lines[i].startswith("```"):
            j = i + 1
            while j < len(lines) and not lines[j].startswith("```"):
                j += 1
            body = lines[i + 1:j]
            if body and body[0].startswith(PROMPT):
                blocks[body[0]] = (i + 2, body)
            i = j
        i += 1
    return blocks


def main():
    parser = argparse.ArgumentParser(description="The README's sample outputs, from the commands they name.")
    parser.add_argument("--exe", default="build/breakables", help="the breakables executable to run")
    parser.add_argument("--check", metavar="README", help="compare with this README's blocks instead of printing")
    options = parser.parse_args()
    made = [sample_block(options.exe, sample) for sample in SAMPLES]
    if not options.check:
        for block in made:
            print("```")
            print("\n".join(block))
            print("```")
        return 0
    blocks = readme_blocks(options.check)
    for block in made:
        if block[0] not in blocks:
            print(f"readme_samples: {options.check} has no block for '{block[0]}'")
            return 1
        first_line, shown = blocks.pop(block[0])
        for k in range(max(len(block), len(shown))):
            want = block[k] if k < len(block) else "(nothing)"
            have = shown[k] if k < len(shown) else "(nothing)"
            if want != have:
                print(f"readme_samples: {options.check}:{first_line + k} differs from the command's output")
                print(f"  README: {have}")
                print(f"  output: {want}")
                print("readme_samples: scripts/readme_samples.py prints the blocks to paste")
                return 1
    for command, (first_line, _) in blocks.items():
        print(f"readme_samples: {options.check}:{first_line} '{command}' is a block no sample here makes")
        return 1
    print(f"readme_samples: {len(made)} README blocks match their commands' output")
    return 0


if __name__ == "__main__":
    sys.exit(main())
