"""Reads every point file in the given folders with pointray and with the format's own Python
library (laspy, pypcd4, plyfile, pye57), compares point counts and coordinates, and runs
`pointray prep` on each file. Prints one markdown row a file.

A file passes when both read it alike (same count, coordinates within 1e-6 of the file's
extent) and prep either makes patches or refuses it with an error naming the file; or when
pointray refuses to read it with such an error. A mismatch or a panic fails, and the script
exits 1.

    pip install laspy[lazrs] pypcd4 plyfile pye57 numpy   # and the pointray package
    POINTRAY_BIN=target/release/pointray python bench/peer_files.py FOLDER...
"""

import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

import pointray

PRINTED_ERROR_CHARACTERS = 90


def read_with_laspy(path):
    import laspy

    las = laspy.read(path)
    return np.column_stack([las.x, las.y, las.z])


def read_with_pypcd4(path):
    from pypcd4 import PointCloud

    points = PointCloud.from_path(path).numpy(("x", "y", "z")).astype(np.float64)
    # PCL marks a missing return by NaN coordinates; pointray drops those points.
    return points[~np.isnan(points).any(axis=1)]


def read_with_plyfile(path):
    from plyfile import PlyData

    vertex = PlyData.read(path)["vertex"]
    return np.column_stack([vertex["x"], vertex["y"], vertex["z"]]).astype(np.float64)


def read_with_pye57(path):
    import pye57

    e57 = pye57.E57(str(path))
    scans = [e57.read_scan(i, ignore_missing_fields=True, transform=True) for i in range(e57.scan_count)]
    return np.concatenate([np.column_stack([s["cartesianX"], s["cartesianY"], s["cartesianZ"]])
                           for s in scans])


PEER_READERS = {".las": ("laspy", read_with_laspy), ".laz": ("laspy", read_with_laspy),
                ".pcd": ("pypcd4", read_with_pypcd4), ".ply": ("plyfile", read_with_plyfile),
                ".e57": ("pye57", read_with_pye57)}


def first_line(text, path):
    line = next((line for line in text.splitlines() if line.startswith("error")), text.strip())
    return line.replace(str(path), path.name)[:PRINTED_ERROR_CHARACTERS]


def peer_points(path):
    name, reader = PEER_READERS[path.suffix.lower()]
    try:
        return name, reader(path), None
    except Exception as error:  # noqa: BLE001 - any failure of the peer is a result to report
        return name, None, f"refuses ({type(error).__name__}: {str(error).splitlines()[0][:50]})"


def compare(ours, theirs):
    if theirs is None:
        return "peer refuses"
    if len(ours) != len(theirs):
        return f"MISMATCH: {len(ours)} points, peer {len(theirs)}"
    if len(ours) == 0:
        return "alike (0 points)"
    extent = max(float(np.ptp(theirs, axis=0).max()), 1.0)
    difference = float(np.abs(ours - theirs).max())
    if difference > 1e-6 * extent:
        return f"MISMATCH: coordinates differ by {difference:.3g}"
    return "alike"


def prep_outcome(binary, path):
    with tempfile.TemporaryDirectory() as folder:
        run = subprocess.run([binary, "prep", str(path), "-o", str(Path(folder) / "out.patches")],
                             capture_output=True, text=True, timeout=600)
    if "panicked" in run.stderr or run.returncode not in (0, 1):
        return f"PANIC (status {run.returncode})"
    if run.returncode == 0:
        patches = next((line.split(",")[-1].strip() for line in run.stdout.splitlines()
                        if "points in," in line), "written")
        return f"ok, {patches}"
    named = path.name in run.stderr
    return f"refused{'' if named else ' WITHOUT THE FILE NAME'}: {first_line(run.stderr, path)}"


def row(binary, path):
    peer, theirs, peer_error = peer_points(path)
    try:
        ours = pointray.read(str(path)).positions
        reading = compare(ours, theirs)
        prep = prep_outcome(binary, path)
    except pointray.PointrayError as error:
        reading = f"refused: {first_line(str(error), path)}" if path.name in str(error) else "REFUSED UNNAMED"
        prep = "-"
    peer_count = peer_error or len(theirs)
    failed = any(word in reading + prep for word in ("MISMATCH", "PANIC", "UNNAMED", "WITHOUT"))
    return failed, f"| {path.name} | {peer} | {peer_count} | {reading} | {prep} |"


def main(folders):
    binary = os.environ.get("POINTRAY_BIN", "pointray")
    files = sorted(p for folder in folders for p in Path(folder).iterdir() if p.suffix.lower() in PEER_READERS)
    print("| file | peer | peer's points | pointray's read | pointray prep |")
    print("|---|---|---|---|---|")
    failures = 0
    for path in files:
        failed, line = row(binary, path)
        failures += failed
        print(line, flush=True)
    print(f"\n{len(files)} files, {failures} failing")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
