"""The Cornell box of raylab's lab 12 rendered by Mitsuba 3 (`scalar_rgb`), and the comparison
of raylab's renders with Mitsuba's. Run through `labs/raylab/scripts/mitsuba.sh`, which makes
the virtual environment.

  render  --out DIR --spp N --depth D --size S --seeds K [--threads T]
          K renders of the box, DIR/mitsuba-<seed>.exr, each with N samples per pixel and paths
          of at most D bounces (raylab's max_depth; Mitsuba's max_depth is D + 1, since it
          counts the camera vertex); prints the seconds of each and the samples per second.
  compare --a 'DIR/raylab-*.exr' --b 'DIR/mitsuba-*.exr' [--blocks B] [--reference FILE]
          the mean radiance of B × B blocks of the image over each side's renders, with the
          standard error from the spread between renders; the largest |z| against the Šidák
          limit of a family-wise 1e-3, the ratio of the two images' means, and, with a
          reference, each render's MSE against it.

The scene is raylab's built-in `cornell` (framework/core/scenes): the same OBJ files in
millimetres scaled by 0.001, the same RGB reflectances and the light's radiance (17, 12, 4), a
pinhole camera at (0.278, 0.273, −0.8) looking along +z with raylab's focal distance of 1.4
image heights (a vertical field of view of 2·atan(0.5/1.4) = 39.3°), a box pixel filter.
"""

import argparse
import glob
import math
import os
import sys
import time

import mitsuba as mi

mi.set_variant("scalar_rgb")
import drjit as dr  # noqa: E402  (after the variant)
import numpy as np  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
SCENES = os.path.join(ROOT, "framework", "core", "scenes")

# framework/core/scenes/cornell.mtl
MATERIALS = {
    "white": (0.725, 0.71, 0.68),
    "red": (0.63, 0.065, 0.05),
    "green": (0.14, 0.45, 0.091),
    "light": (0.78, 0.78, 0.78),
}
LIGHT_RADIANCE = (17.0, 12.0, 4.0)


def split_obj(path, out_dir):
    """The OBJ file `path` as one file per material (Mitsuba gives a shape one BSDF)."""
    vertices, groups, current = [], {}, None
    with open(path) as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] == "v":
                vertices.append(line)
            elif words[0] == "usemtl":
                current = words[1]
                groups.setdefault(current, [])
            elif words[0] == "f":
                groups.setdefault(current, []).append(line)
    files = {}
    base = os.path.splitext(os.path.basename(path))[0]
    for material, faces in groups.items():
        name = os.path.join(out_dir, f"{base}_{material}.obj")
        with open(name, "w") as f:
            f.write("".join(vertices) + "".join(faces))
        files[material] = name
    return files


def scene(spp, depth, size, work):
    """The Cornell box as a Mitsuba scene dictionary."""
    fov = 2.0 * math.degrees(math.atan(0.5 / 1.4))
    d = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": depth + 1, "rr_depth": 3},
        "sensor": {
            "type": "perspective",
            "fov": fov,
            "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=[0.278, 0.273, -0.8], target=[0.278, 0.273, 0.0], up=[0, 1, 0]
            ),
            "film": {
                "type": "hdrfilm",
                "width": size,
                "height": size,
                "rfilter": {"type": "box"},
            },
            "sampler": {"type": "independent", "sample_count": spp},
        },
    }
    k = 0
    for obj in ["cornell_room.obj", "cornell_blocks.obj"]:
        for material, file in split_obj(os.path.join(SCENES, obj), work).items():
            shape = {
                "type": "obj",
                "filename": file,
                "face_normals": True,
                "to_world": mi.ScalarTransform4f().scale(0.001),
                "bsdf": {
                    "type": "diffuse",
                    "reflectance": {"type": "rgb", "value": list(MATERIALS[material])},
                },
            }
            if material == "light":
                shape["emitter"] = {
                    "type": "area",
                    "radiance": {"type": "rgb", "value": list(LIGHT_RADIANCE)},
                }
            d[f"shape{k}"] = shape
            k += 1
    return d


def render(args):
    os.makedirs(args.out, exist_ok=True)
    if args.threads == 1:
        # Dr.Jit's pool of 1 (or 0) workers stopped the scalar renderer of Mitsuba 3.9.1 here
        # (no progress for ten minutes at 0.8 % of a core); say so rather than hang.
        sys.exit("error: --threads 1 hangs Mitsuba 3.9.1's scalar renderer on this machine; use 2 or more")
    if args.threads:
        dr.set_thread_count(args.threads)
    sc = mi.load_dict(scene(args.spp, args.depth, args.size, args.out))
    seconds = []
    for seed in range(args.seeds):
        start = time.perf_counter()
        image = mi.render(sc, seed=seed)
        seconds.append(time.perf_counter() - start)
        mi.Bitmap(image).write(os.path.join(args.out, f"mitsuba-{seed}.exr"))
        samples = args.size * args.size * args.spp
        print(
            f"seed {seed}: {seconds[-1]:.3f} s, {samples / seconds[-1] / 1e6:.3f} M samples/s",
            flush=True,
        )
    median = sorted(seconds)[len(seconds) // 2]
    print(
        f"median {median:.3f} s for {args.size}x{args.size} at {args.spp} spp, "
        f"{args.depth} bounces, {args.threads or 'all'} thread(s)"
    )


def load(pattern):
    files = sorted(glob.glob(pattern))
    if not files:
        sys.exit(f"error: no file matches {pattern}")
    return files, np.stack([np.array(mi.Bitmap(f), dtype=np.float64)[..., :3] for f in files])


def block_means(images, blocks):
    n, h, w, c = images.shape
    return images.reshape(n, blocks, h // blocks, blocks, w // blocks, c).mean(axis=(2, 4))


def normal_quantile(p):
    """The z with P(|Z| >= z) = p, by bisection on erfc."""
    lo, hi = 0.0, 40.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if math.erfc(mid / math.sqrt(2.0)) > p:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def compare(args):
    files_a, a = load(args.a)
    files_b, b = load(args.b)
    if a.shape[1:] != b.shape[1:]:
        sys.exit(f"error: images of {a.shape[1:3]} and {b.shape[1:3]} pixels")
    ba, bb = block_means(a, args.blocks), block_means(b, args.blocks)
    mean_a, mean_b = ba.mean(axis=0), bb.mean(axis=0)
    se_a = ba.std(axis=0, ddof=1) / math.sqrt(len(files_a))
    se_b = bb.std(axis=0, ddof=1) / math.sqrt(len(files_b))
    z = (mean_a - mean_b) / np.sqrt(se_a**2 + se_b**2 + 1e-30)
    tests = z.size
    limit = normal_quantile(1.0 - (1.0 - 1e-3) ** (1.0 / tests))
    worst = np.unravel_index(np.argmax(np.abs(z)), z.shape)
    print(f"{len(files_a)} renders of {args.a} against {len(files_b)} of {args.b}")
    print(
        f"{args.blocks}x{args.blocks} blocks x 3 channels: max |z| = {np.abs(z).max():.2f} "
        f"at block {worst[:2]} channel {worst[2]} (Sidak limit for a family-wise 1e-3: {limit:.2f}); "
        f"{int((np.abs(z) > limit).sum())} beyond it"
    )
    ratio = a.mean(axis=0).mean(axis=(0, 1)) / b.mean(axis=0).mean(axis=(0, 1))
    print(f"image mean, first over second, per channel: {np.array2string(ratio, precision=4)}")
    if args.reference:
        ref = np.array(mi.Bitmap(args.reference), dtype=np.float64)[..., :3]
        for name, images in [(args.a, a), (args.b, b)]:
            mse = ((images - ref) ** 2).mean(axis=(1, 2, 3))
            print(f"MSE against {args.reference}, {name}: median {np.median(mse):.4e}")
    return 0 if np.abs(z).max() <= limit else 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser("render")
    r.add_argument("--out", required=True)
    r.add_argument("--spp", type=int, default=64)
    r.add_argument("--depth", type=int, default=10)
    r.add_argument("--size", type=int, default=256)
    r.add_argument("--seeds", type=int, default=1)
    r.add_argument("--threads", type=int, default=0)
    c = sub.add_parser("compare")
    c.add_argument("--a", required=True)
    c.add_argument("--b", required=True)
    c.add_argument("--blocks", type=int, default=16)
    c.add_argument("--reference")
    args = parser.parse_args()
    if args.command == "render":
        render(args)
    else:
        sys.exit(compare(args))


if __name__ == "__main__":
    main()
