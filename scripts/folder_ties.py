#!/usr/bin/env python3
"""Counts pairs of folders that include each other.

A folder A depends on folder B when a file directly in A includes (#include "...") a file
directly in B. Two folders are tied when each depends on the other, whether B lies inside A
(an upward include) or beside it. Quoted includes resolve as the compiler does: first beside
the including file, then under each include root.

Usage: scripts/folder_ties.py TREE [INCLUDE_ROOT...]
  TREE          the folder whose files are counted (e.g. worker)
  INCLUDE_ROOT  folders the build puts on the include path (default: TREE and core)
Prints each tie with one include of each direction, then the count.
"""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.M)
SUFFIXES = ('.h', '.cpp', '.inc', '.hpp', '.cc')


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    tree = os.path.abspath(sys.argv[1])
    roots = [os.path.abspath(r) for r in sys.argv[2:]] or [tree, os.path.join(root, 'core')]
    edges = {}  # (folder A, folder B) -> one include "file -> target"
    for dirpath, _, names in os.walk(tree):
        for name in sorted(names):
            if not name.endswith(SUFFIXES):
                continue
            path = os.path.join(dirpath, name)
            with open(path, encoding='utf-8', errors='replace') as f:
                text = f.read()
            for target in INCLUDE.findall(text):
                for base in [dirpath] + roots:
                    resolved = os.path.normpath(os.path.join(base, target))
                    if os.path.isfile(resolved):
                        break
                else:
                    continue
                a, b = dirpath, os.path.dirname(resolved)
                if a != b:
                    edges.setdefault((a, b), f'{os.path.relpath(path, root)} -> '
                                             f'{os.path.relpath(resolved, root)}')
    ties = sorted({tuple(sorted(pair)) for pair in edges if pair[::-1] in edges})
    for a, b in ties:
        print(f'{os.path.relpath(a, root)} <-> {os.path.relpath(b, root)}')
        print(f'  {edges[(a, b)]}')
        print(f'  {edges[(b, a)]}')
    print(f'{len(ties)} tied folder pairs under {os.path.relpath(tree, root)}')


if __name__ == '__main__':
    main()
