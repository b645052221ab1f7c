#!/usr/bin/env python3
"""How many Mitsuba 3 scenes of a folder Tessera imports (docs/mitsuba.md, "Coverage").

Runs `tessera-worker convert SCENE.xml -o OUT.json` on every .xml file under each FOLDER and
prints one line per scene, `accepted` or `refused` with the first reason Tessera gave, then a
table of the refusal reasons by the number of scenes each one stops and the figure
`accepted N of M`.

A reason is the refusal message with the place and the identifiers taken out (file, line,
id="...", name="...", numbers), so that the same blocker in many scenes counts as one row.

Files that are no scene are left out of the figure: an XML file whose root element is not
<scene> (a fragment meant for <include>), and files under a folder named `include`,
`includes` or `fragments`, which Mitsuba's test data keeps for inclusion.

With -D name=value (repeatable), every scene is read with that parameter, as Mitsuba's command
line gives it (`tessera-worker convert -D`, and `mi.load_file(..., name=value)`): public scenes
use `$spp` without declaring it.

With --mitsuba PYTHON, each scene is also loaded by Mitsuba 3 (`PYTHON -c "mi.load_file(...)"`
with the scalar_rgb variant) and the table shows which refused scenes Mitsuba itself loads.

Usage:
  scripts/mitsuba_coverage.py [--worker build/worker/tessera-worker] [--root DIR]
                              [-D name=value ...] [--mitsuba /path/to/python] [--jobs N]
                              FOLDER...
"""

import argparse
import collections
import concurrent.futures
import os
import re
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ElementTree

FRAGMENT_FOLDERS = {"include", "includes", "fragments"}


def find_scenes(folders):
    """Every scene file under the folders, sorted; fragments left out (see the module doc)."""
    scenes = []
    for folder in folders:
        for directory, subfolders, files in os.walk(folder):
            subfolders.sort()
            if FRAGMENT_FOLDERS & set(directory.split(os.sep)):
                continue
            for name in sorted(files):
                if name.lower().endswith(".xml") and is_scene(os.path.join(directory, name)):
                    scenes.append(os.path.join(directory, name))
    return scenes


def is_scene(path):
    try:
        for _, element in ElementTree.iterparse(path, events=("start",)):
            return element.tag == "scene"
    except ElementTree.ParseError:
        return True  # malformed XML is a scene that Tessera must refuse, not a fragment
    return False


def first_reason(stderr):
    """The first line of tessera-worker's error, without its `error: ` prefix."""
    for line in stderr.splitlines():
        line = line.strip()
        if line:
            return re.sub(r"^(tessera-worker: )?(error: )?", "", line)
    return "(no message)"


def reason_key(reason):
    """The reason without place, identifiers and numbers (see the module doc)."""
    key = re.sub(r"^.*?: line \d+: ", "", reason)  # "<file>: line <L>: "
    key = re.sub(r' (id|name)="[^"]*"', "", key)
    key = re.sub(r'"[^"]*\.(xml|obj|ply|serialized|exr|hdr|png|jpg|jpeg)"', '"FILE"', key,
                 flags=re.IGNORECASE)
    key = re.sub(r"-?\d+(\.\d+)?(e-?\d+)?", "N", key)
    return key[:200]


def convert(worker, root, defines, scene):
    with tempfile.TemporaryDirectory() as out:
        command = [worker, "convert", scene, "-o", os.path.join(out, "scene.json")]
        if root:
            command += ["--root", root]
        for define in defines:
            command += ["-D", define]
        result = subprocess.run(command, capture_output=True, text=True, timeout=600)
    if result.returncode == 0:
        return None
    return first_reason(result.stderr)


MITSUBA_LOAD = """
import sys
import mitsuba as mi
mi.set_variant('scalar_rgb')
mi.load_file(sys.argv[1], **dict(d.split('=', 1) for d in sys.argv[2:]))
"""


def mitsuba_loads(python, defines, scene):
    try:
        result = subprocess.run([python, "-c", MITSUBA_LOAD, scene, *defines],
                                capture_output=True, text=True, timeout=600)
    except subprocess.TimeoutExpired:
        return False
    return result.returncode == 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folders", nargs="+", metavar="FOLDER")
    parser.add_argument("--worker", default="build/worker/tessera-worker")
    parser.add_argument("--root", help="passed to convert as --root DIR")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE",
                        help="a scene parameter, as Mitsuba's -D (repeatable)")
    parser.add_argument("--mitsuba", metavar="PYTHON", help="also load each scene in Mitsuba 3")
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()

    scenes = find_scenes(args.folders)
    if not scenes:
        sys.exit("no Mitsuba scene under " + ", ".join(args.folders))
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        reasons = list(pool.map(lambda s: convert(args.worker, args.root, args.defines, s),
                                scenes))
        loads = list(pool.map(lambda s: mitsuba_loads(args.mitsuba, args.defines, s), scenes)) \
            if args.mitsuba else [None] * len(scenes)

    by_key = collections.Counter()
    by_key_mitsuba = collections.Counter()
    example = {}
    for scene, reason, loaded in zip(scenes, reasons, loads):
        mark = "" if loaded is None else ("  [mitsuba loads]" if loaded else "  [mitsuba fails]")
        if reason is None:
            print(f"accepted  {scene}{mark}")
            continue
        print(f"refused   {scene}: {reason}{mark}")
        key = reason_key(reason)
        by_key[key] += 1
        by_key_mitsuba[key] += 1 if loaded else 0
        example.setdefault(key, scene)

    accepted = sum(r is None for r in reasons)
    print()
    print("scenes | mitsuba loads | first refusal reason (example scene)")
    for key, count in by_key.most_common():
        loaded = str(by_key_mitsuba[key]) if args.mitsuba else "-"
        print(f"{count:6d} | {loaded:>13} | {key}  ({example[key]})")
    print()
    print(f"accepted {accepted} of {len(scenes)} scenes")
    if args.mitsuba:
        loaded = sum(bool(x) for x in loads)
        both = sum(bool(x) and r is None for x, r in zip(loads, reasons))
        print(f"Mitsuba 3 loads {loaded} of {len(scenes)}; Tessera accepts {both} of those")


if __name__ == "__main__":
    main()
