#!/usr/bin/env python3
"""Score an acuity frame dump with FovVideoVDP (PyPI `pyfvvdp`).

Each sequence of the dump is compared with the full-detail reference
sequence (`full_1`), foveated at the dumped gaze point of every frame.
`acuity run --metric fvvdp` runs this script (its copy built into the
binary, on the interpreter `$ACUITY_PYTHON`, else `python3`).

Usage:
    fvvdp_score.py DUMP_DIR [--reference full_1] [--device cpu|cuda]
    fvvdp_score.py --check          exit 0 if pyfvvdp imports, else 3

DUMP_DIR is what `acuity run --dump-frames DIR` writes:
    display.json     {"resolution": [w, h], "fov_deg": [h, v], "fps": F,
                      "peak_cd_m2": .., "contrast": .., "ambient_lux": ..,
                      "sequences": ["full_1", ...]}
    <seq>/NNNN.png   RGB frames (sRGB), NNNN the frame index
    <seq>/gaze.csv   frame,x_px,y_px: the gaze in pixels, origin at the
                     top-left corner of the image, x right, y down
                     (the display centre is (w/2, h/2))

Output: one line of JSON on stdout, {"<policy>_<knob>": jod,
"<policy>_<knob>:local_p999": local, ...}, every sequence including the
reference itself (10 and 0: identical by construction; a sequence whose
frames equal the reference's byte for byte also gets them without running
the metric). `local` is the most visible local difference: the 99.9th
percentile over pixels and frames of FovVideoVDP's per-pixel distortion
map (`heatmap="raw"`: the JOD loss each pixel's difference would cost if
the whole image had it), so that one bright pop in a large image shows
even where the global JOD hides it.
JOD: 10 = identical to the reference, one JOD less = 75% of observers
prefer the reference. Progress and warnings go to stderr.

The display: photometry from display.json (the scene's [display] keys:
sRGB EOTF, peak luminance, contrast, ambient light; screen reflectivity
pyfvvdp's default 0.5%); geometry from the resolution
and the horizontal field of view (pyfvvdp assumes square pixels, so the
vertical field of view follows from the aspect ratio).

Foveation: pyfvvdp 1.2 takes a fixation point per frame (a tensor of
shape [frames, 2], pixel indices x, y from the top-left pixel), so each
frame is foveated at its own gaze point (gaze.csv's x_px - 0.5, y_px -
0.5: pyfvvdp adds half a pixel to reach the pixel centre).

Frame rates of 4 Hz or less: pyfvvdp's temporal filter then has a single
tap and fails, so each frame is scored as a still image (foveated at its
gaze) and the per-frame quality is pooled over frames as pyfvvdp pools a
video (sustained channel only; there is no temporal channel to speak of
at such rates). A warning on stderr says so.
"""

import argparse
import csv
import json
import math
import os
import sys
import time

EXIT_NO_PYFVVDP = 3


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def import_pyfvvdp():
    try:
        import pyfvvdp  # noqa: F401
        import torch  # noqa: F401
        import imageio.v2  # noqa: F401
    except ImportError as e:
        log(
            f"error: FovVideoVDP needs the Python package pyfvvdp, which "
            f"{sys.executable} cannot import ({e}); install it with "
            f"`{sys.executable} -m pip install pyfvvdp`"
        )
        sys.exit(EXIT_NO_PYFVVDP)


def read_gaze(path):
    frames, points = [], []
    with open(path, newline="") as f:
        rows = csv.reader(f)
        header = next(rows, None)
        if header != ["frame", "x_px", "y_px"]:
            raise SystemExit(f"error: {path}: header is not frame,x_px,y_px")
        for row in rows:
            if not row:
                continue
            frames.append(int(row[0]))
            points.append((float(row[1]), float(row[2])))
    return frames, points


def load_sequence(dump, name, frames):
    import imageio.v2 as iio
    import numpy as np

    imgs = []
    for k in frames:
        img = iio.imread(os.path.join(dump, name, f"{k:04d}.png"))
        if img.ndim == 2:
            img = np.stack([img] * 3, axis=-1)
        imgs.append(img[:, :, :3])
    return np.stack(imgs).astype(np.uint8)  # F, H, W, C


def top_percentile(maps, percent, pixels):
    """The `percent` percentile (nearest rank) over every value of the
    heatmaps (tensors whose elements are frames x `pixels`), found from each
    frame's largest values so that no float32 copy of the whole video is
    made."""
    import torch

    frames = [m.reshape(-1, pixels) for m in maps]
    n = sum(f.shape[0] for f in frames) * pixels
    rank = math.ceil(percent / 100.0 * n)  # ascending, 1-based
    largest = n - rank + 1
    tops = [
        torch.topk(row.float(), min(largest, pixels)).values
        for f in frames
        for row in f
    ]
    return float(torch.topk(torch.cat(tops), largest).values.min())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dump", nargs="?", help="the dump folder")
    ap.add_argument("--reference", default="full_1")
    ap.add_argument("--device", default=None, help="torch device (default: cuda if available)")
    ap.add_argument("--check", action="store_true", help="only check that pyfvvdp imports")
    args = ap.parse_args()

    import_pyfvvdp()
    if args.check:
        return
    if not args.dump:
        ap.error("DUMP_DIR is required")

    import numpy as np
    import torch
    import pyfvvdp

    with open(os.path.join(args.dump, "display.json")) as f:
        display = json.load(f)
    w, h = display["resolution"]
    fov_h, fov_v = display["fov_deg"]
    fps = float(display["fps"])
    sequences = display.get("sequences") or sorted(
        d for d in os.listdir(args.dump)
        if os.path.isfile(os.path.join(args.dump, d, "gaze.csv"))
    )
    if args.reference not in sequences:
        raise SystemExit(f"error: {args.dump}: no reference sequence `{args.reference}`")

    square_v = 2 * math.degrees(math.atan(math.tan(math.radians(fov_h / 2)) * h / w))
    if abs(square_v - fov_v) > 0.05 * fov_v:
        log(
            f"warning: pyfvvdp assumes square pixels: a {fov_h} deg wide, {w}x{h} display "
            f"is {square_v:.1f} deg high, not {fov_v}"
        )
    photometry = pyfvvdp.fvvdp_display_photo_eotf(
        display["peak_cd_m2"],
        contrast=display["contrast"],
        EOTF="sRGB",
        E_ambient=display["ambient_lux"],
    )
    geometry = pyfvvdp.fvvdp_display_geometry((w, h), fov_horizontal=fov_h)
    device = torch.device(args.device) if args.device else None
    metric = pyfvvdp.fvvdp(
        display_photometry=photometry,
        display_geometry=geometry,
        color_space="sRGB",
        foveated=True,
        heatmap="raw",
        quiet=True,
        device=device,
        temp_padding="replicate",
    )

    ref_frames, gaze = read_gaze(os.path.join(args.dump, args.reference, "gaze.csv"))
    reference = load_sequence(args.dump, args.reference, ref_frames)
    if reference.shape[1:3] != (h, w):
        raise SystemExit(f"error: frames are {reference.shape[2]}x{reference.shape[1]}, display.json says {w}x{h}")
    # Pixel indices for pyfvvdp, which adds half a pixel.
    fixation = torch.tensor([[x - 0.5, y - 0.5] for x, y in gaze], dtype=torch.float32)
    video = len(ref_frames) > 1
    # pyfvvdp's temporal filter has ceil(fps / 4) taps and needs two.
    stills = video and math.ceil(250.0 / (1000.0 / fps)) < 2
    if stills:
        log(
            f"warning: {fps:.2f} Hz is too low for FovVideoVDP's temporal filter; "
            "scoring each frame as a still image and pooling over frames"
        )

    scores = {}
    for name in sequences:
        if name == args.reference:
            scores[name] = 10.0
            scores[f"{name}:local_p999"] = 0.0
            continue
        started = time.time()
        frames, _ = read_gaze(os.path.join(args.dump, name, "gaze.csv"))
        if frames != ref_frames:
            raise SystemExit(f"error: {name}: frames differ from the reference's")
        test = load_sequence(args.dump, name, frames)
        if np.array_equal(test, reference):
            # No difference scores 10 exactly; skip the metric's work.
            scores[name] = 10.0
            scores[f"{name}:local_p999"] = 0.0
            log(f"{name}: identical to the reference, 10 JOD")
            continue
        with torch.no_grad():
            if stills:
                q, maps = [], []
                for k in range(len(frames)):
                    _, stats = metric.predict(
                        test[k], reference[k], dim_order="HWC", fixation_point=fixation[k]
                    )
                    q.append(torch.as_tensor(stats["Q_per_ch"], device=metric.device))
                    maps.append(stats["heatmap"])
                jod = metric.do_pooling_and_jods(torch.cat(q, dim=2), metric.lpyr.get_freqs()[0:-1])
            elif video:
                jod, stats = metric.predict(
                    test, reference, dim_order="FHWC", frames_per_second=fps, fixation_point=fixation
                )
                maps = [stats["heatmap"]]
            else:
                jod, stats = metric.predict(
                    test[0], reference[0], dim_order="HWC", fixation_point=fixation[0]
                )
                maps = [stats["heatmap"]]
        scores[name] = float(jod)
        scores[f"{name}:local_p999"] = top_percentile(maps, 99.9, h * w)
        log(
            f"{name}: {scores[name]:.4f} JOD, local 99.9th percentile "
            f"{scores[f'{name}:local_p999']:.4f} ({time.time() - started:.1f} s)"
        )
    print(json.dumps(scores))


if __name__ == "__main__":
    main()
