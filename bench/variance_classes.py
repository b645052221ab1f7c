#!/usr/bin/env python3
"""Where a change moved the variance: pixel classes of two seed_variance.py maps.

Reads DIR/SCENE_old_variance.exr and DIR/SCENE_new_variance.exr (bench/seed_variance.py --maps
DIR with builds named old and new), ranks the pixels by the sum of both maps (ranked by one
build alone, noise would make that build's calm pixels look calmer than they are and the other
build look worse there), and prints for the calmest half, the 50th-90th and 90th-99th
percentiles and the top 1 %: their share of old's variance and new's variance over old's there.

Usage (repository root):
  /work/venv-mitsuba/bin/python bench/variance_classes.py out/maps hexroom cornell-sphere
"""
import sys
from pathlib import Path

import numpy as np

sys.dont_write_bytecode = True
sys.path.insert(0, str(Path(__file__).resolve().parent))
from compare_exr import read_rgb  # noqa: E402


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    maps = Path(sys.argv[1])
    for scene in sys.argv[2:]:
        old = read_rgb(maps / f"{scene}_old_variance.exr")[..., 0].ravel()
        new = read_rgb(maps / f"{scene}_new_variance.exr")[..., 0].ravel()
        order = np.argsort(old + new)
        n = len(old)
        print(scene)
        for name, lo, hi in [("calmest half", 0, .5), ("50th-90th percentile", .5, .9),
                             ("90th-99th percentile", .9, .99), ("top 1 %", .99, 1.0)]:
            idx = order[int(lo * n):int(hi * n)]
            print(f"  {name}: {100 * old[idx].sum() / old.sum():.1f} % of old's variance, "
                  f"new / old x{new[idx].sum() / old[idx].sum():.3f}")


if __name__ == "__main__":
    main()
