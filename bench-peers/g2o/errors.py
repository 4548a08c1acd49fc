"""Errors of a solved g2o graph against the simulator's ground truth.

    python3 errors.py ESTIMATES.g2o TRUTH.g2o

ESTIMATES holds the optimised vertices (solve_g2o --estimates), TRUTH the
true ones (data/g2o-addons/*_truth.g2o). Prints one JSON line: over the
poses both files hold, the RMS and largest translation error (m) and the
RMS and largest rotation error (degrees), with no alignment (the graphs fix
their first pose at its true value); per line landmark the angle between
the directions (degrees) and the difference of the distances from the
origin (m); per plane the angle between the normals (degrees) and the
difference of the offsets (m, for unit normals); for the sensor offset
(vertex 0, when both hold it) its translation and rotation errors.
"""

import json
import math
import sys


def read(path):
    vertices = {}
    with open(path) as f:
        for line in f:
            fields = line.split()
            if fields and fields[0].startswith("VERTEX"):
                vertices[int(fields[1])] = (fields[0], [float(x) for x in fields[2:]])
    return vertices


def quaternion_angle(a, b):
    """Angle (degrees) of the rotation between unit quaternions [x, y, z, w]."""
    na, nb = math.sqrt(sum(x * x for x in a)), math.sqrt(sum(x * x for x in b))
    dot = abs(sum(x * y for x, y in zip(a, b))) / (na * nb)
    return math.degrees(2.0 * math.acos(min(1.0, dot)))


def angle(u, v):
    nu, nv = math.sqrt(sum(x * x for x in u)), math.sqrt(sum(x * x for x in v))
    c = sum(x * y for x, y in zip(u, v)) / (nu * nv)
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def norm(v):
    return math.sqrt(sum(x * x for x in v))


def main(estimates_path, truth_path):
    estimates, truth = read(estimates_path), read(truth_path)
    translation, rotation = [], []
    lines, planes, offset = {}, {}, None
    for vid, (tag, true) in sorted(truth.items()):
        if vid not in estimates:
            continue
        est = estimates[vid][1]
        if tag == "VERTEX_SE3:QUAT":
            t = norm([a - b for a, b in zip(est[:3], true[:3])])
            r = quaternion_angle(est[3:7], true[3:7])
            if vid == 0:
                offset = {"translation": t, "rotation_deg": r}
            else:
                translation.append(t)
                rotation.append(r)
        elif tag == "VERTEX_LINE3D":
            # [w, d]: distance |w| / |d|.
            lines[vid] = {
                "direction_deg": angle(est[3:6], true[3:6]),
                "distance": norm(est[:3]) / norm(est[3:6]) - norm(true[:3]) / norm(true[3:6]),
            }
        elif tag == "VERTEX_PLANE":
            ne, nt = norm(est[:3]), norm(true[:3])
            planes[vid] = {
                "normal_deg": angle(est[:3], true[:3]),
                "offset": est[3] / ne - true[3] / nt,
            }
    rms = lambda xs: math.sqrt(sum(x * x for x in xs) / len(xs))
    print(
        json.dumps(
            {
                "estimates": estimates_path,
                "poses": len(translation),
                "translation_rms": rms(translation),
                "translation_max": max(translation),
                "rotation_rms_deg": rms(rotation),
                "rotation_max_deg": max(rotation),
                "lines": lines,
                "planes": planes,
                "sensor_offset": offset,
            }
        )
    )


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: errors.py ESTIMATES.g2o TRUTH.g2o")
    main(sys.argv[1], sys.argv[2])
