#!/usr/bin/env python3
"""pointray's path integrator against Mitsuba 3 on matched mesh scenes, and pointray's
point-set versions of the same scenes against its mesh versions.

    python3 -m venv target/mitsuba-venv && target/mitsuba-venv/bin/pip install mitsuba numpy
    cargo build -p pointray-cli      # or --release, with --pointray target/release/pointray
    target/mitsuba-venv/bin/python scripts/mitsuba-compare.py [--spp 256] [--size 128]

Each scene is written once as PLY meshes; pointray (a generated scene file) and Mitsuba
(`scalar_rgb`, a scene dictionary) load the same files. How they are matched:

- camera: the same pinhole (position, look-at, up, vertical field of view), square images,
  a box pixel filter in Mitsuba (pointray jitters uniformly inside each pixel);
- geometry: the same triangles with flat face normals (`face_normals` in Mitsuba);
- materials: pointray's `diffuse` is Mitsuba's `diffuse` wrapped in `twosided` (pointray's
  opaque surfaces are two-sided); `dielectric` (smooth, ior 1.5 inside, 1 outside, the
  outside where the face normals point) is Mitsuba's `dielectric`;
- lights: a quad light (emitting on one side, black and opaque on the other) is Mitsuba's
  `rectangle` with an `area` emitter of the same radiance and a black BSDF; the uniform sky
  is Mitsuba's `constant` emitter, and an environment map (an EXR that Mitsuba writes) is
  Mitsuba's `envmap` of the same file (pointray holds each texel constant, Mitsuba
  interpolates between them: the map's sun is blurred over a few texels so that this barely
  matters);
- integrator: Mitsuba's `path` with the same `max_depth` (path segments, 2 = direct light).

Distances are over linear RGB: the mean relative error |a - b| / (b + 0.05) over pixels and
channels, and the ratio of the images' means (energy). The noise floor is Mitsuba against
itself with another seed: two renders of one scene differ by that much from noise alone.
The point-set versions sample each mesh with `pointray sample --blue-noise` and prep the
points (normals estimated and oriented by prep, not taken from the meshes).

Writes the table to docs/MITSUBA_COMPARISON.md and the images to docs/mitsuba/.
"""

import argparse
import datetime
import math
import os
import platform
import struct
import subprocess
import sys
import time
from pathlib import Path

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")

ROOT = Path(__file__).resolve().parent.parent
DARK_FLOOR = 0.05
# pointray agrees with Mitsuba when its mean relative error is within this many times the
# noise floor (two independent renders differ by about the floor) and its energy within
# ENERGY_TOLERANCE.
NOISE_FACTOR = 1.5
ENERGY_TOLERANCE = 0.02


def write_ply(path, vertices, faces):
    """A binary little-endian PLY mesh: float x, y, z and uchar/int vertex_indices."""
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(vertices)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    with open(path, "wb") as out:
        out.write(header.encode())
        for v in vertices:
            out.write(struct.pack("<3f", *v))
        for f in faces:
            out.write(struct.pack("<B3i", 3, *f))


def read_ply(path):
    """Vertices and triangles of a binary little-endian PLY mesh whose vertices start with
    three floats and whose faces are `uchar` counts of `int` indices."""
    data = Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    counts = {line.split()[1]: int(line.split()[2]) for line in header if line.startswith("element")}
    sizes = {"float": 4, "double": 8, "uchar": 1, "int": 4, "uint": 4, "short": 2, "ushort": 2}
    stride, in_vertex = 0, False
    for line in header:
        if line.startswith("element"):
            in_vertex = line.startswith("element vertex")
        elif line.startswith("property") and in_vertex:
            stride += sizes[line.split()[1]]
    vertex_bytes = counts["vertex"] * stride
    raw = np.frombuffer(data[end:end + vertex_bytes], dtype=np.uint8).reshape(counts["vertex"], stride)
    vertices = raw[:, :12].copy().view("<f4").reshape(-1, 3)
    face_records = np.frombuffer(data[end + vertex_bytes:end + vertex_bytes + counts["face"] * 13], dtype=np.uint8)
    faces = face_records.reshape(-1, 13)[:, 1:].copy().view("<i4").reshape(-1, 3)
    return vertices, faces


def quad(corner, edge_u, edge_v):
    """Two triangles over corner + a edge_u + b edge_v, facing edge_u x edge_v."""
    c, u, v = (np.array(x, dtype=float) for x in (corner, edge_u, edge_v))
    return [c, c + u, c + u + v, c + v], [(0, 1, 2), (0, 2, 3)]


def merge(parts):
    vertices, faces = [], []
    for part_vertices, part_faces in parts:
        base = len(vertices)
        vertices += [tuple(v) for v in part_vertices]
        faces += [tuple(i + base for i in f) for f in part_faces]
    return vertices, faces


def box(center, size, turn_degrees):
    """A closed box turned about y, faces outward."""
    cx, cy, cz = center
    sx, sy, sz = (s / 2 for s in size)
    a = math.radians(turn_degrees)

    def place(x, y, z):
        return (cx + x * math.cos(a) + z * math.sin(a), cy + y, cz - x * math.sin(a) + z * math.cos(a))

    corners = [place(x, y, z) for x in (-sx, sx) for y in (-sy, sy) for z in (-sz, sz)]
    # Index = 4 ix + 2 iy + iz; each face wound counterclockwise seen from outside.
    faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
             (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    return corners, faces


def uv_sphere(center, radius, rings=48, segments=96):
    """A closed sphere, faces outward."""
    vertices = []
    for ring in range(rings + 1):
        polar = math.pi * ring / rings
        for segment in range(segments):
            azimuth = 2 * math.pi * segment / segments
            d = (math.sin(polar) * math.cos(azimuth), math.cos(polar), math.sin(polar) * math.sin(azimuth))
            vertices.append(tuple(c + radius * x for c, x in zip(center, d)))
    faces = []
    for ring in range(rings):
        for segment in range(segments):
            a, b = ring * segments + segment, ring * segments + (segment + 1) % segments
            c, d = a + segments, b + segments
            faces += [(a, b, d), (a, d, c)]
    return vertices, faces


def area(vertices, faces):
    v = np.array(vertices)
    f = np.array(faces)
    return float(0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1).sum())


WHITE = [0.725, 0.71, 0.68]
RED = [0.63, 0.065, 0.05]
GREEN = [0.14, 0.45, 0.091]


def cornell_box(folder):
    """Mitsuba's Cornell box layout ([-1, 1]³, camera on +z), walls facing in."""
    objects = []
    walls = {
        "floor": (quad((-1, -1, -1), (0, 0, 2), (2, 0, 0)), WHITE),
        "ceiling": (quad((-1, 1, -1), (2, 0, 0), (0, 0, 2)), WHITE),
        "back": (quad((-1, -1, -1), (2, 0, 0), (0, 2, 0)), WHITE),
        "red": (quad((-1, -1, -1), (0, 2, 0), (0, 0, 2)), RED),
        "green": (quad((1, -1, -1), (0, 0, 2), (0, 2, 0)), GREEN),
        "small_box": (box((0.335, -0.7, 0.38), (0.6, 0.6, 0.6), -18), WHITE),
        "large_box": (box((-0.36, -0.4, -0.28), (0.6, 1.2, 0.6), 20), WHITE),
    }
    for name, ((vertices, faces), color) in walls.items():
        path = folder / f"cornell_{name}.ply"
        write_ply(path, vertices, faces)
        objects.append({"name": name, "path": path, "bsdf": "diffuse", "color": color, "area": area(vertices, faces),
                        "density": 15_000})
    light = {"corner": (-0.25, 0.99, -0.25), "edge_u": (0.5, 0, 0), "edge_v": (0, 0, 0.5),
             "radiance": (18.387, 13.9873, 6.75357)}
    camera = {"position": (0, 0, 3.9), "look_at": (0, 0, 0), "up": (0, 1, 0), "fov": 40.0}
    return {"name": "cornell box", "camera": camera, "objects": objects, "lights": [light], "sky": None,
            "max_depth": 8}


def bunny_on_plane(folder):
    """The bunny mesh on a plane, under a quad light and a dim sky."""
    bunny = ROOT / "data/meshes/bunny.ply"
    vertices, faces = read_ply(bunny)
    low, high = vertices.min(axis=0), vertices.max(axis=0)
    center = (low + high) / 2
    plane_y = float(low[1])
    vertices_plane, faces_plane = quad((-0.5, plane_y, -0.5), (0, 0, 1.0), (1.0, 0, 0))
    plane = folder / "bunny_plane.ply"
    write_ply(plane, vertices_plane, faces_plane)
    objects = [
        {"name": "bunny", "path": bunny, "bsdf": "diffuse", "color": [0.8, 0.75, 0.7], "area": area(vertices, faces),
         "density": 1_500_000},
        {"name": "plane", "path": plane, "bsdf": "diffuse", "color": [0.5, 0.5, 0.5],
         "area": area(vertices_plane, faces_plane), "density": 100_000},
    ]
    top = plane_y + 0.45
    light = {"corner": (center[0] - 0.1, top, center[2] - 0.1), "edge_u": (0.2, 0, 0), "edge_v": (0, 0, 0.2),
             "radiance": (20.0, 20.0, 20.0)}
    camera = {"position": (float(center[0]) + 0.05, float(center[1]) + 0.12, float(center[2]) + 0.38),
              "look_at": (float(center[0]), float(center[1]) - 0.01, float(center[2])), "up": (0, 1, 0), "fov": 35.0}
    return {"name": "bunny on a plane", "camera": camera, "objects": objects, "lights": [light], "sky": 0.1,
            "max_depth": 6}


def glass_sphere(folder):
    """A glass sphere on a white plane, under a quad light and a sky."""
    sphere_vertices, sphere_faces = uv_sphere((0, 0.5, 0), 0.5)
    plane_vertices, plane_faces = quad((-1.5, 0, -1.5), (0, 0, 3), (3, 0, 0))
    sphere, plane = folder / "glass_sphere.ply", folder / "glass_plane.ply"
    write_ply(sphere, sphere_vertices, sphere_faces)
    write_ply(plane, plane_vertices, plane_faces)
    objects = [
        {"name": "sphere", "path": sphere, "bsdf": "dielectric", "color": [1, 1, 1],
         "area": area(sphere_vertices, sphere_faces), "density": 12_000},
        {"name": "plane", "path": plane, "bsdf": "diffuse", "color": [0.7, 0.7, 0.7],
         "area": area(plane_vertices, plane_faces), "density": 12_000},
    ]
    light = {"corner": (-0.5, 2.5, -0.5), "edge_u": (1.0, 0, 0), "edge_v": (0, 0.3, 1.0), "radiance": (8.0, 8.0, 8.0)}
    camera = {"position": (0, 1.4, 3.2), "look_at": (0, 0.45, 0), "up": (0, 1, 0), "fov": 35.0}
    return {"name": "glass sphere", "camera": camera, "objects": objects, "lights": [light], "sky": 0.3,
            "max_depth": 10}


def sun_and_sky_map(path, width=512, height=256):
    """An equirectangular sky written as EXR by Mitsuba's own Bitmap: a blue gradient, a dark
    ground, and a sun off every axis (so that a map read turned or mirrored shows), blurred
    over a few texels because Mitsuba interpolates texels where pointray holds them constant."""
    theta = np.pi * (np.arange(height) + 0.5) / height
    phi = 2 * np.pi * (np.arange(width) + 0.5) / width
    theta, phi = np.meshgrid(theta, phi, indexing="ij")
    # Mitsuba's envmap: u = atan2(x, -z) / 2π, v = acos(y) / π.
    d = np.stack([np.sin(phi) * np.sin(theta), np.cos(theta), -np.cos(phi) * np.sin(theta)], axis=-1)
    up = np.clip(d[..., 1:2], 0, 1)
    sky = np.where(d[..., 1:2] > 0, (1 - np.sqrt(up)) * [0.8, 0.87, 1.0] + np.sqrt(up) * [0.22, 0.4, 0.85],
                   [0.12, 0.1, 0.09])
    elevation, azimuth = np.radians(40.0), np.radians(62.0)
    sun = np.array([np.cos(elevation) * np.sin(azimuth), np.sin(elevation), -np.cos(elevation) * np.cos(azimuth)])
    angle = np.arccos(np.clip(d @ sun, -1, 1))
    sky = sky + 400.0 * np.exp(-0.5 * (angle / np.radians(2.0)) ** 2)[..., None] * [1.0, 0.93, 0.82]
    mi.Bitmap(np.ascontiguousarray(sky.astype(np.float32))).write(str(path))
    return path


def bunny_under_sun_and_sky(folder):
    """The bunny mesh on a plane, lit by an environment map alone."""
    scene = bunny_on_plane(folder)
    scene.update({"name": "bunny under a sky map", "lights": [], "sky": {"map": sun_and_sky_map(folder / "sky.exr")},
                  "max_depth": 5})
    return scene


def toml_list(values):
    return "[" + ", ".join(f"{float(v):.9g}" for v in values) + "]"


def pointray_scene(scene, folder, size, spp, objects_kind):
    """The scene file for pointray: meshes, or the points sampled from them."""
    c = scene["camera"]
    sky = scene["sky"]
    background = f'{{ map = "{sky["map"]}" }}' if isinstance(sky, dict) else toml_list([sky or 0.0] * 3)
    lines = [
        f"background = {background}",
        "[render]",
        f"width = {size}\nheight = {size}\nspp = {spp}\nmax_depth = {scene['max_depth']}",
        'integrator = "path"\nseed = 1',
        "[camera]",
        f"position = {toml_list(c['position'])}\nlook_at = {toml_list(c['look_at'])}",
        f"up = {toml_list(c['up'])}\nvfov_degrees = {c['fov']}",
    ]
    for light in scene["lights"]:
        lines += ["[[lights]]", 'type = "quad"', f"corner = {toml_list(light['corner'])}",
                  f"edge_u = {toml_list(light['edge_u'])}", f"edge_v = {toml_list(light['edge_v'])}",
                  f"color = {toml_list(light['radiance'])}", "intensity = 1.0"]
    for item in scene["objects"]:
        path = item["path"] if objects_kind == "mesh" else item["points"]
        kind = "mesh" if objects_kind == "mesh" else "points"
        lines += ["[[objects]]", f'name = "{item["name"]}"', f'type = "{kind}"', f'path = "{path}"',
                  "[objects.material]", f'bsdf = "{item["bsdf"]}"', f"diffuse = {toml_list(item['color'])}",
                  "roughness = 0.0", "ior = 1.5"]
    path = folder / f"{scene['name'].replace(' ', '_')}_{objects_kind}.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def mitsuba_scene(scene, size, spp, seed):
    c = scene["camera"]
    to_world = mi.ScalarTransform4f().look_at(origin=c["position"], target=c["look_at"], up=c["up"])
    sensor = {"type": "perspective", "fov": c["fov"], "fov_axis": "y", "to_world": to_world,
              "film": {"type": "hdrfilm", "width": size, "height": size, "rfilter": {"type": "box"},
                       "pixel_format": "rgb"},
              "sampler": {"type": "independent", "sample_count": spp, "seed": seed}}
    description = {"type": "scene", "integrator": {"type": "path", "max_depth": scene["max_depth"]},
                   "sensor": sensor}
    for item in scene["objects"]:
        color = {"type": "rgb", "value": item["color"]}
        if item["bsdf"] == "dielectric":
            bsdf = {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0}
        else:
            bsdf = {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": color}}
        description[item["name"]] = {"type": "ply", "filename": str(item["path"]), "face_normals": True,
                                     "bsdf": bsdf}
    for index, light in enumerate(scene["lights"]):
        u, v = np.array(light["edge_u"], float), np.array(light["edge_v"], float)
        normal = np.cross(u, v)
        normal /= np.linalg.norm(normal)
        center = np.array(light["corner"], float) + 0.5 * (u + v)
        # Mitsuba's rectangle spans [-1, 1]² in x, y and faces +z.
        matrix = np.identity(4)
        matrix[:3, 0], matrix[:3, 1], matrix[:3, 2], matrix[:3, 3] = 0.5 * u, 0.5 * v, normal, center
        description[f"light_{index}"] = {
            "type": "rectangle", "to_world": mi.ScalarTransform4f(matrix.tolist()),
            "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0, 0, 0]}},
            "emitter": {"type": "area", "radiance": {"type": "rgb", "value": list(light["radiance"])}}}
    if isinstance(scene["sky"], dict):
        description["sky"] = {"type": "envmap", "filename": str(scene["sky"]["map"])}
    elif scene["sky"]:
        description["sky"] = {"type": "constant", "radiance": {"type": "rgb", "value": [scene["sky"]] * 3}}
    return mi.load_dict(description)


def render_mitsuba(scene, size, spp, seed):
    started = time.time()
    image = np.array(mi.render(mitsuba_scene(scene, size, spp, seed), spp=spp, seed=seed))[:, :, :3]
    return image, time.time() - started


def render_pointray(binary, scene_file, output):
    started = time.time()
    subprocess.run([str(binary), "render", str(scene_file), "-o", str(output), "--backend", "cpu"], check=True,
                   stdout=subprocess.DEVNULL)
    return np.array(mi.Bitmap(str(output)))[:, :, :3], time.time() - started


def sample_points(binary, scene, folder):
    for item in scene["objects"]:
        count = max(2000, int(item["area"] * item["density"]))
        item["points"] = folder / f"{scene['name'].replace(' ', '_')}_{item['name']}_points.ply"
        subprocess.run([str(binary), "sample", str(item["path"]), "-o", str(item["points"]), "--count", str(count),
                        "--seed", "1", "--blue-noise"], check=True, stdout=subprocess.DEVNULL)


def mean_relative_error(a, b):
    return float(np.mean(np.abs(a - b) / (b + DARK_FLOOR)))


def energy_ratio(a, b):
    return float(a.mean() / b.mean())


def write_png(image, path):
    bitmap = mi.Bitmap(np.ascontiguousarray(image.astype(np.float32)))
    bitmap.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, srgb_gamma=True).write(str(path))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--pointray", default=ROOT / "target/debug/pointray", type=Path)
    parser.add_argument("--spp", default=256, type=int)
    parser.add_argument("--size", default=128, type=int)
    parser.add_argument("--work", default=ROOT / "target/mitsuba-compare", type=Path)
    parser.add_argument("--docs", default=ROOT / "docs", type=Path)
    args = parser.parse_args()
    args.work = args.work.resolve()
    args.work.mkdir(parents=True, exist_ok=True)
    images = args.docs / "mitsuba"
    images.mkdir(parents=True, exist_ok=True)
    rows = []
    for make in (cornell_box, bunny_on_plane, glass_sphere, bunny_under_sun_and_sky):
        scene = make(args.work)
        slug = scene["name"].replace(" ", "_")
        print(f"{scene['name']}: rendering", file=sys.stderr)
        reference, mitsuba_seconds = render_mitsuba(scene, args.size, args.spp, 1)
        other, _ = render_mitsuba(scene, args.size, args.spp, 2)
        mesh_file = pointray_scene(scene, args.work, args.size, args.spp, "mesh")
        mesh, pointray_seconds = render_pointray(args.pointray, mesh_file, args.work / f"{slug}_mesh.exr")
        sample_points(args.pointray, scene, args.work)
        points_file = pointray_scene(scene, args.work, args.size, args.spp, "points")
        points, _ = render_pointray(args.pointray, points_file, args.work / f"{slug}_points.exr")
        for image, name in ((reference, "mitsuba"), (mesh, "pointray_mesh"), (points, "pointray_points")):
            write_png(image, images / f"{slug}_{name}.png")
        rows.append({
            "scene": scene["name"],
            "noise": mean_relative_error(other, reference),
            "mesh": mean_relative_error(mesh, reference),
            "mesh_energy": energy_ratio(mesh, reference),
            "points": mean_relative_error(points, mesh),
            "points_energy": energy_ratio(points, mesh),
            "mitsuba_s": mitsuba_seconds,
            "pointray_s": pointray_seconds,
        })
        print(rows[-1], file=sys.stderr)
    write_report(args, rows)


def write_report(args, rows):
    command = f"target/mitsuba-venv/bin/python scripts/mitsuba-compare.py --spp {args.spp} --size {args.size}"
    lines = [
        "# pointray's path integrator against Mitsuba 3",
        "",
        f"Measured {datetime.date.today()} on {platform.machine()} with {os.cpu_count()} cores (Mitsuba "
        f"{mi.__version__} `scalar_rgb`, pointray's CPU backend from its {args.pointray.parent.name} build), "
        f"{args.size}x{args.size} pixels, {args.spp} samples per pixel:",
        "",
        "```sh",
        command,
        "```",
        "",
        "How the scenes are matched, and what the numbers mean, is in the script's docstring "
        "(`scripts/mitsuba-compare.py`). MRE is the mean relative error |a - b| / (b + 0.05) over "
        "pixels and channels; energy is the ratio of the images' means. The noise floor is Mitsuba "
        "against Mitsuba with another seed. pointray's mesh render agrees with Mitsuba's when its "
        f"MRE is within {NOISE_FACTOR} times the noise floor and its energy within "
        f"{100 * ENERGY_TOLERANCE:.0f}%. The point-set and mesh renders share pointray's seed, so "
        "their noise is correlated and their MRE is mostly what the surfaces change. Times are wall "
        "seconds for one render (pointray's include loading the scene and building its BVHs).",
        "",
        "| scene | noise floor (MRE) | pointray mesh vs Mitsuba (MRE) | energy | points vs mesh (MRE) "
        "| energy | agrees | Mitsuba s | pointray s |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        agrees = r["mesh"] <= NOISE_FACTOR * r["noise"] and abs(r["mesh_energy"] - 1) <= ENERGY_TOLERANCE
        lines.append(
            f"| {r['scene']} | {r['noise']:.4f} | {r['mesh']:.4f} | {r['mesh_energy']:.4f} | {r['points']:.4f} "
            f"| {r['points_energy']:.4f} | {'yes' if agrees else 'no'} | {r['mitsuba_s']:.1f} "
            f"| {r['pointray_s']:.1f} |")
    lines += ["", "Images (Mitsuba, pointray's mesh, pointray's points), sRGB:", ""]
    for r in rows:
        slug = r["scene"].replace(" ", "_")
        lines.append(" ".join(f"![{r['scene']}: {n}](mitsuba/{slug}_{n}.png)"
                              for n in ("mitsuba", "pointray_mesh", "pointray_points")))
        lines.append("")
    (args.docs / "MITSUBA_COMPARISON.md").write_text("\n".join(lines))


if __name__ == "__main__":
    main()
