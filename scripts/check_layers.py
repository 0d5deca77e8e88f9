#!/usr/bin/env python3
"""Checks that the source files of a library call each other in layers:
file A depends on file B when A calls a function B defines (not static),
and those dependencies must form no cycle, so no file calls back into a file
that called it. Prints the files from the top layer down.

    scripts/check_layers.py DIR [DIR...]     (default: sam_runtime/src)

Exits 1 and names the cycle when there is one."""
import os
import re
import sys

DEFINITION = re.compile(r'^(?!static\b)[A-Za-z_][\w \t\*]*?\b([a-z_][a-z0-9_]*)\s*\([^;{}]*?\)\s*\{', re.M)
CALL = re.compile(r'\b([a-z_][a-z0-9_]*)\s*\(')
COMMENT = re.compile(r'/\*.*?\*/|//[^\n]*', re.S)


def main():
    dirs = sys.argv[1:] or [os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sam_runtime", "src")]
    files = {}
    for d in dirs:
        for name in sorted(os.listdir(d)):
            if name.endswith(".c"):
                files[name] = COMMENT.sub("", open(os.path.join(d, name), encoding="utf-8").read())
    owner = {}
    for name, text in files.items():
        for m in DEFINITION.finditer(text):
            owner.setdefault(m.group(1), name)
    deps = {name: set() for name in files}
    for name, text in files.items():
        for m in CALL.finditer(text):
            other = owner.get(m.group(1))
            if other and other != name:
                deps[name].add(other)
    # Depth-first search for a cycle; the finishing order is the layering.
    state, order, stack = {}, [], []

    def visit(n):
        state[n] = 1
        stack.append(n)
        for m in sorted(deps[n]):
            if state.get(m) == 1:
                cycle = stack[stack.index(m):] + [m]
                print("check_layers: cycle: " + " -> ".join(cycle), file=sys.stderr)
                sys.exit(1)
            if m not in state:
                visit(m)
        stack.pop()
        state[n] = 2
        order.append(n)

    for n in sorted(files):
        if n not in state:
            visit(n)
    for n in reversed(order):
        print("%-32s calls %s" % (n, ", ".join(sorted(deps[n])) or "-"))
    print("check_layers: %d files, no cycle" % len(files))


if __name__ == "__main__":
    main()
