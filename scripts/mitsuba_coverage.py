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
`includes` or `fragments`, which Mitsuba's test data keeps for inclusion, and files under
`__MACOSX` (macOS archive metadata that public copies sometimes carry: not XML).

With -D name=value (repeatable), every scene is read with that parameter, as Mitsuba's command
line gives it (`tessera-worker convert -D`, and `mi.load_file(..., name=value)`): public scenes
use `$spp` without declaring it.

With --mitsuba PYTHON, each scene is also loaded by Mitsuba 3 (`PYTHON -c "mi.load_file(...)"`
with the scalar_rgb variant) and the table shows which refused scenes Mitsuba itself loads.

With --xml-only, a scene refused only because a mesh or image it names is missing (public copies
often leave their assets out) is converted again in a scratch copy of its FOLDER in which each
missing file is an explicit STAND-IN (a one-triangle mesh, a 4 x 4 grey image), until Tessera
accepts it or refuses it for another reason: that reason is the scene's first refusal at the
XML level. The stand-ins exist only in that scratch copy (hard links to the real files, deleted
at exit), never in the FOLDER; scenes measured so are marked `[N stand-ins: FILES]`, and counted apart
in the figure: their XML converts, their images cannot be rendered. With --mitsuba, Mitsuba
loads the same copy, so both renderers are asked about the XML alone.

Usage:
  scripts/mitsuba_coverage.py [--worker build/worker/tessera-worker] [--root DIR]
                              [-D name=value ...] [--mitsuba /path/to/python] [--jobs N]
                              [--xml-only] FOLDER...
"""

import argparse
import collections
import concurrent.futures
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import threading
import xml.etree.ElementTree as ElementTree

FRAGMENT_FOLDERS = {"include", "includes", "fragments"}
# macOS archive metadata (AppleDouble `._name.xml` files beside copies of the scenes): not XML.
NOT_SCENE_FOLDERS = {"__MACOSX"}


def find_scenes(folders):
    """Every scene file under the folders, sorted; fragments left out (see the module doc)."""
    return [scene for scene, _ in find_scenes_in_folders(folders)]


def find_scenes_in_folders(folders):
    """(scene file, the FOLDER it was found under) for each of find_scenes."""
    scenes = []
    for folder in folders:
        for directory, subfolders, files in os.walk(folder):
            subfolders.sort()
            if (FRAGMENT_FOLDERS | NOT_SCENE_FOLDERS) & set(directory.split(os.sep)):
                continue
            for name in sorted(files):
                if name.lower().endswith(".xml") and is_scene(os.path.join(directory, name)):
                    scenes.append((os.path.join(directory, name), folder))
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
    key = re.sub(r'"[^"]*\.(xml|obj|ply|serialized|exr|hdr|pfm|png|jpg|jpeg)"', '"FILE"', key,
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


# A missing file in a refusal: "...: models/m.obj: no such file in the scene's folder", also as
# the first of several folders searched ("...; first: models/m.obj: no such file ...").
MISSING_FILE = re.compile(r"(?:>: |first: )([^()]+?): no such file in the scene's folder")

STAND_IN_MESHES = {
    ".obj": "# STAND-IN written by mitsuba_coverage.py --xml-only for a missing file\n"
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n",
    ".ply": "ply\nformat ascii 1.0\ncomment STAND-IN written by mitsuba_coverage.py --xml-only\n"
            "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
            "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
}
STAND_IN_IMAGES = {".png", ".jpg", ".jpeg", ".bmp", ".tga", ".exr", ".hdr", ".pfm", ".tif",
                   ".tiff"}


class StandIns:
    """Scratch copies of FOLDERs (hard links) in which missing meshes and images get stand-ins;
    only for --xml-only (see the module doc)."""

    def __init__(self):
        self.scratch = tempfile.mkdtemp(prefix="mitsuba-coverage-")
        self.copies = {}
        self.lock = threading.Lock()

    def close(self):
        shutil.rmtree(self.scratch, ignore_errors=True)

    def copy_of(self, folder):
        with self.lock:
            if folder not in self.copies:
                copy = os.path.join(self.scratch, str(len(self.copies)))
                shutil.copytree(folder, copy, symlinks=True, copy_function=os.link)
                self.copies[folder] = copy
            return self.copies[folder]

    def add(self, copy, relative):
        """Writes a stand-in for `relative` below `copy`; False if its kind has none."""
        path = os.path.normpath(os.path.join(copy, relative))
        extension = os.path.splitext(path)[1].lower()
        if not path.startswith(copy + os.sep):
            return False
        with self.lock:
            if os.path.exists(path):
                return False  # not missing here: some other trouble
            os.makedirs(os.path.dirname(path), exist_ok=True)
            if extension in STAND_IN_MESHES:
                with open(path, "w") as out:
                    out.write(STAND_IN_MESHES[extension])
                return True
            if extension == ".pfm":
                # OpenImageIO reads PFM but has no writer for it: 4 x 4 RGB 0.5, little-endian.
                with open(path, "wb") as out:
                    out.write(b"PF\n4 4\n-1.0\n" + struct.pack("<48f", *[0.5] * 48))
                return True
            if extension in STAND_IN_IMAGES:
                depth = "float" if extension in (".exr", ".hdr") else "uint8"
                return subprocess.run(["oiiotool", "--pattern", "constant:color=0.5,0.5,0.5",
                                       "4x4", "3", "-d", depth, "-o", path],
                                      capture_output=True).returncode == 0
        return False


def convert_xml_only(worker, defines, scene, folder, stand_ins):
    """(reason or None, the files stood in, the scene file converted last) for `scene` with its
    missing files stood in. The files are those this scene lacked, relative to FOLDER; a scene
    whose missing files another scene of the FOLDER stood in first counts one, "(shared)"."""
    reason = convert(worker, None, defines, scene)
    missing = set()  # every file this scene lacks, whether this scene or another stood it in
    copy = None
    while reason is not None and len(missing) < 200:
        match = MISSING_FILE.search(reason)
        if not match:
            break
        if copy is None:
            # Paths in messages are relative to the bundle root: the copy is the root from now.
            copy = stand_ins.copy_of(folder)
            scene = os.path.join(copy, os.path.relpath(scene, folder))
            reason = convert(worker, copy, defines, scene)
            continue
        if match.group(1) in missing:
            break  # stood in, and still refused: some other trouble with the file
        if not stand_ins.add(copy, match.group(1)):
            break  # a kind of file without a stand-in
        missing.add(match.group(1))
        reason = convert(worker, copy, defines, scene)
    # A scene that lacked files counts as stood in even when another scene of the same FOLDER
    # wrote the stand-ins it needed.
    return reason, (sorted(missing) or ["(shared)"]) if copy else [], scene


# Mitsuba's load_file refuses a parameter the scene never uses ("Found unused parameters"),
# where its command line and Tessera's -D change nothing: such parameters are left out.
MITSUBA_LOAD = """
import re
import sys
import mitsuba as mi
mi.set_variant('scalar_rgb')
parameters = dict(d.split('=', 1) for d in sys.argv[2:])
try:
    mi.load_file(sys.argv[1], **parameters)
except RuntimeError as error:
    unused = re.findall(r"- \\$(\\w+)=", str(error))
    if "unused parameters" not in str(error) or not unused:
        raise
    mi.load_file(sys.argv[1], **{k: v for k, v in parameters.items() if k not in unused})
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
    parser.add_argument("--xml-only", action="store_true",
                        help="stand in for missing meshes and images (see the module doc)")
    args = parser.parse_args()
    if args.xml_only and args.root:
        sys.exit("--xml-only takes each FOLDER as the root; leave out --root")

    found = find_scenes_in_folders(args.folders)
    if not found:
        sys.exit("no Mitsuba scene under " + ", ".join(args.folders))
    scenes = [scene for scene, _ in found]
    stand_ins = StandIns() if args.xml_only else None
    try:
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            if args.xml_only:
                results = list(pool.map(
                    lambda f: convert_xml_only(args.worker, args.defines, f[0], f[1], stand_ins),
                    found))
            else:
                results = list(pool.map(
                    lambda s: (convert(args.worker, args.root, args.defines, s), [], s), scenes))
            # With stand-ins, Mitsuba loads the same copy (its XML, not the published assets).
            loads = list(pool.map(lambda r: mitsuba_loads(args.mitsuba, args.defines, r[2]),
                                  results)) if args.mitsuba else [None] * len(scenes)
    finally:
        if stand_ins:
            stand_ins.close()
    reasons = [reason for reason, _, _ in results]
    stood_in = [len(files) for _, files, _ in results]
    stood_in_files = [files for _, files, _ in results]

    by_key = collections.Counter()
    by_key_mitsuba = collections.Counter()
    example = {}
    for scene, reason, loaded, files in zip(scenes, reasons, loads, stood_in_files):
        mark = "" if loaded is None else ("  [mitsuba loads]" if loaded else "  [mitsuba fails]")
        if files:
            mark += f"  [{len(files)} stand-ins: {', '.join(files)}]"
        if reason is None:
            print(f"accepted  {scene}{mark}")
            continue
        print(f"refused   {scene}: {reason}{mark}")
        key = reason_key(reason)
        by_key[key] += 1
        by_key_mitsuba[key] += 1 if loaded else 0
        example.setdefault(key, scene)

    accepted = sum(r is None and not n for r, n in zip(reasons, stood_in))
    accepted_xml = sum(r is None and n > 0 for r, n in zip(reasons, stood_in))
    print()
    print("scenes | mitsuba loads | first refusal reason (example scene)")
    for key, count in by_key.most_common():
        loaded = str(by_key_mitsuba[key]) if args.mitsuba else "-"
        print(f"{count:6d} | {loaded:>13} | {key}  ({example[key]})")
    print()
    print(f"accepted {accepted} of {len(scenes)} scenes")
    if args.xml_only:
        print(f"and {accepted_xml} more at the XML level only, with STAND-INS for missing "
              "meshes and images (not renderable as published)")
    if args.mitsuba:
        loaded = sum(bool(x) for x in loads)
        both = sum(bool(x) and r is None for x, r in zip(loads, reasons))
        print(f"Mitsuba 3 loads {loaded} of {len(scenes)}; Tessera accepts {both} of those")


if __name__ == "__main__":
    main()
