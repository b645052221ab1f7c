#!/usr/bin/env python3
"""Where a change moved the variance: pixel classes of two seed_variance.py maps.

Reads DIR/SCENE_old_variance.exr and DIR/SCENE_new_variance.exr (bench/seed_variance.py --maps
DIR with builds named old and new), ranks the pixels by the sum of both maps (ranked by one
build alone, noise would make that build's calm pixels look calmer than they are and the other
build look worse there), and prints for the calmest half, the 50th-90th and 90th-99th
percentiles and the top 1 %: their share of old's variance and new's variance over old's there.

With --old NAME and --new NAME, compares the builds so named instead (seed_variance.py --build
NAME=...): DIR/SCENE_NAME_variance.exr.

Usage (repository root; PY is a Python with Mitsuba 3, e.g. .venv-bench/bin/python of
bench/README.md):
  $PY bench/variance_classes.py out/maps hexroom cornell-sphere \
      [--old old] [--new new]
"""
import sys
from pathlib import Path

import numpy as np

sys.dont_write_bytecode = True
sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_exr import read_rgb  # noqa: E402


def main():
    args = sys.argv[1:]
    names = {"--old": "old", "--new": "new"}
    for flag in names:
        if flag in args:
            i = args.index(flag)
            if i + 1 >= len(args):
                raise SystemExit(f"{flag} needs a build name\n{__doc__}")
            names[flag] = args[i + 1]
            del args[i:i + 2]
    if len(args) < 2:
        raise SystemExit(__doc__)
    maps = Path(args[0])
    for scene in args[1:]:
        old = read_rgb(maps / f"{scene}_{names['--old']}_variance.exr")[..., 0].ravel()
        new = read_rgb(maps / f"{scene}_{names['--new']}_variance.exr")[..., 0].ravel()
        order = np.argsort(old + new)
        n = len(old)
        print(f"{scene}: {names['--new']} against {names['--old']}")
        for name, lo, hi in [("calmest half", 0, .5), ("50th-90th percentile", .5, .9),
                             ("90th-99th percentile", .9, .99), ("top 1 %", .99, 1.0)]:
            idx = order[int(lo * n):int(hi * n)]
            print(f"  {name}: {100 * old[idx].sum() / old.sum():.1f} % of old's variance, "
                  f"new / old x{new[idx].sum() / old[idx].sum():.3f}")


if __name__ == "__main__":
    main()
