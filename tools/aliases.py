#!/usr/bin/env python3
"""aliases.py: object-like macros that name a variable's member, element or their address (one name, one
meaning: `#define x (y.z)` makes two names for one object and hides the data flow).

Usage: tools/aliases.py DIR..  prints each alias `file:line: name -> body`; exit 1 if any.
A macro whose body is a constant, an expression with an operator or a call is not an alias."""
import os
import re
import sys

# the body, its outer parentheses stripped: an optional & or *, then a name followed by at least
# one member access or subscript
PATH = re.compile(r"^[&*]?\s*\(?\s*([A-Za-z_]\w*)\s*((\.|->)\s*[A-Za-z_]\w*|\[[^\]]*\])+\s*\)?$")
DEFINE = re.compile(r"^\s*#\s*define\s+([A-Za-z_]\w*)\s+(.*?)\s*(/\*.*)?$")


def strip(body):
    while body.startswith("(") and body.endswith(")"):
        depth = 0
        for i, ch in enumerate(body):
            depth += ch == "("
            depth -= ch == ")"
            if depth == 0 and i < len(body) - 1:
                return body
        body = body[1:-1].strip()
    return body


def aliases(paths):
    out = []
    for top in paths:
        for root, _, files in os.walk(top):
            for name in sorted(files):
                if not name.endswith((".c", ".h")):
                    continue
                path = os.path.join(root, name)
                with open(path, encoding="utf-8", errors="replace") as f:
                    for n, line in enumerate(f, 1):
                        m = DEFINE.match(line)
                        if m and PATH.match(strip(m.group(2))):
                            out.append("%s:%d: %s -> %s" % (path, n, m.group(1), m.group(2)))
    return out


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__.strip().splitlines()[2])
    found = aliases(sys.argv[1:])
    for a in found:
        print(a)
    print("aliases: %d in %s" % (len(found), " ".join(sys.argv[1:])))
    sys.exit(1 if found else 0)


if __name__ == "__main__":
    main()
